"""Misuse is refused with fmi2Error (status 3) and a log message, and the process survives."""

import math

import pytest
from fmpy.fmi1 import FMICallException

from damper_tools.fmu import Slave

FMI2_ERROR = 3
STEP = 1e-3


@pytest.fixture
def slave(damper_unit, request):
    s = Slave(damper_unit, request.node.name)
    yield s
    s.fmu.freeInstance()


def refused(s, call, *args, **kwargs):
    """Runs call, which must raise FMICallException with fmi2Error and log an error message."""
    before = len(s.errors())
    with pytest.raises(FMICallException) as info:
        call(*args, **kwargs)
    assert info.value.status == FMI2_ERROR, info.value
    assert len(s.errors()) > before, "no error message was logged"
    return info.value


def test_nan_input_is_refused_and_the_process_survives(slave, damper_unit):
    slave.initialize()
    slave.step(STEP, v_damper=0.1, F_demand=1e3)
    refused(slave, slave.fmu.setReal, [slave.vr("v_damper")], [math.nan])
    # The process lives on: a new instance runs normally.
    other = Slave(damper_unit, "after_nan")
    try:
        other.initialize()
        other.step(STEP, v_damper=0.1, F_demand=1e3)
        assert math.isfinite(other.get(["F_damper"])[0])
    finally:
        other.free()


def test_infinite_input_is_refused(slave):
    slave.initialize()
    refused(slave, slave.fmu.setReal, [slave.vr("F_demand")], [math.inf])


def test_do_step_before_initialisation_is_a_call_sequence_error(slave):
    refused(slave, slave.fmu.doStep, currentCommunicationPoint=0.0, communicationStepSize=STEP)


def test_parameters_are_fixed_after_initialisation(slave):
    slave.initialize()
    refused(slave, slave.fmu.setReal, [slave.vr("air_fraction")], [0.03])
    refused(slave, slave.fmu.setInteger, [slave.vr("control_mode")], [1])
    slave.step(STEP)
    refused(slave, slave.fmu.setReal, [slave.vr("h_max")], [1e-4])


def test_out_of_range_parameter_is_refused(slave):
    refused(slave, slave.fmu.setReal, [slave.vr("air_fraction")], [-1.0])
    refused(slave, slave.fmu.setInteger, [slave.vr("control_mode")], [3])


def test_out_of_range_input_is_refused(slave):
    slave.initialize()
    refused(slave, slave.fmu.setReal, [slave.vr("v_damper")], [50.0])


def test_outputs_cannot_be_set(slave):
    slave.initialize()
    refused(slave, slave.fmu.setReal, [slave.vr("F_damper")], [1.0])


@pytest.mark.parametrize("offset, step", [(0.5, STEP), (-STEP, STEP), (0.0, 0.0), (0.0, -STEP), (0.0, math.nan)],
                         ids=["wrong_point", "point_in_the_past", "zero_step", "negative_step", "nan_step"])
def test_bad_do_step_arguments_are_refused(slave, offset, step):
    """currentCommunicationPoint must be the slave's time; the step must be positive."""
    slave.initialize()
    slave.step(STEP)  # the slave is at t = 1 ms now
    refused(slave, slave.fmu.doStep, currentCommunicationPoint=slave.time + offset, communicationStepSize=step)
