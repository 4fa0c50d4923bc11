"""The FMI 3.0 FMUs beside the FMI 2.0 ones: the same Rust model behind the other standard's C API
(crates/fmi_slave), with a model description generated from the FMI 2.0 one (crates/fmi_codegen).

- fmpy validates all three (schema and structure) without a problem;
- their variables are the FMI 2.0 ones, value reference for value reference, plus the independent
  variable `time`;
- fmpy simulates them, and the damper's force, the coupled quarter truck's and the full truck's
  outputs equal the FMI 2.0 FMUs' bit for bit on the same inputs;
- what FMI 3.0 does otherwise: a discarded step leaves the FMU in Step Mode, ready to retry;
  instantiation asking for Event Mode is refused; an FMU state serialized by the FMI 2.0 FMU
  restores in the FMI 3.0 one (one byte format, one GUID); log messages arrive with '#' escaped.
"""

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from damper_tools import REPO, cosim, roads
from damper_tools.fmu import FmuUnit, Slave

PAIRS = {"damper": ("fmu", "fmu3"), "truck": ("truck_fmu", "truck_fmu3"),
         "full_truck": ("full_truck_fmu", "full_truck_fmu3")}
TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}


@pytest.mark.parametrize("which", PAIRS)
def test_fmpy_validates_the_fmi3_fmu(which, request):
    path = request.getfixturevalue(PAIRS[which][1])
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == "3.0"
    assert md.coSimulation is not None and md.modelExchange is None


@pytest.mark.parametrize("which", PAIRS)
def test_the_fmi3_variables_are_the_fmi2_ones_and_time(which, request):
    md2, md3 = (read_model_description(str(request.getfixturevalue(f))) for f in PAIRS[which])
    assert md3.guid == md2.guid, "the instantiation token is the variable table's fingerprint"
    (time,) = [v for v in md3.modelVariables if v.causality == "independent"]
    assert time.name == "time" and time.type == "Float64"
    rest = [v for v in md3.modelVariables if v is not time]
    assert len(rest) == len(md2.modelVariables)
    for v2, v3 in zip(md2.modelVariables, rest, strict=True):
        assert (v3.name, v3.valueReference, v3.type, v3.causality, v3.variability) == \
            (v2.name, v2.valueReference, TYPES[v2.type], v2.causality, v2.variability)
        assert (v3.start, v3.min, v3.max, v3.unit, v3.description) == \
            (v2.start, v2.min, v2.max, v2.unit, v2.description)
    named = {v.name for u in md2.outputs for v in u.dependencies}
    assert {v.name for u in md3.outputs for v in u.dependencies} == named


def test_the_damper_s_force_is_the_fmi2_fmu_s_bit_for_bit(fmu, fmu3):
    """fmpy's own master on the README's input file: every output at every communication point."""
    inputs = np.genfromtxt(REPO / "tests" / "python" / "resources" / "damper_input.csv", delimiter=",", names=True)
    outputs = [u.variable.name for u in read_model_description(str(fmu)).outputs]
    runs = [simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=1.5, output_interval=1e-3, input=inputs,
                         start_values={"x_damper_start": -0.03}, output=outputs) for path in (fmu, fmu3)]
    assert len(runs[0]) == len(runs[1]) == 1501
    assert np.array_equal(runs[0]["time"], runs[1]["time"])
    for name in outputs:
        assert np.array_equal(runs[0][name], runs[1][name]), name
    assert np.ptp(runs[0]["F_damper"]) > 1e3  # the run moved the damper


def test_the_coupled_quarter_truck_is_the_fmi2_one_bit_for_bit(fmu, truck_fmu, fmu3, truck_fmu3):
    case = roads.road_case("minor", 14.0, 2.0, 3, step=1e-3)
    fmi2, fmi3 = (cosim.simulate_one(case.z_road, case.v_road, 1e-3, case.t.size - 1, truck_fmu=t, damper_fmu=d)
                  for t, d in ((truck_fmu, fmu), (truck_fmu3, fmu3)))
    assert set(fmi2) == set(fmi3)
    for name in fmi2:
        assert np.array_equal(fmi2[name], fmi3[name]), name


def test_the_full_truck_is_the_fmi2_one_bit_for_bit(full_truck_fmu, full_truck_fmu3):
    runs = []
    for path in (full_truck_fmu, full_truck_fmu3):
        truck = Slave(FmuUnit.load(path), "full truck")
        truck.initialize(0.0, damper_mode=2, pitch_start=0.002)
        rows = []
        for k in range(500):
            truck.step(1e-3, k * 1e-3, **{"front_left.z_road": 0.01 * np.sin(20e-3 * k), "drive2_right.v_road": 0.05})
            rows.append(truck.get())
        truck.free()
        runs.append(np.array(rows))
    assert np.array_equal(runs[0], runs[1])


def test_a_discarded_fmi3_step_leaves_the_fmu_in_step_mode_to_retry(fmu3):
    """A step that needs more integration steps in one controller sample than the damper allows
    (h_max 1e-7 s in a 10 ms sample) is discarded with its state kept; a shorter step from the same
    point then runs, with no fmi3SetFMUState (FMI 3.0: the FMU is as it was before the call; FMI
    2.0 would be in stepFailed, where fmi2DoStep is refused)."""
    damper = Slave(FmuUnit.load(fmu3), "retry", echo=False)
    damper.initialize(0.0, T_sample=0.01, h_max=1e-7)
    assert isinstance(damper.fmu, FMU3Slave)
    with pytest.raises(FMICallException, match="status 2"):
        damper.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
    assert any(status == 2 and "state kept at 0 s" in text for status, _, text in damper.messages), damper.messages
    event, terminate, early, last = damper.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-4)
    assert (event, terminate, early, last) == (False, False, False, 1e-4)
    assert np.isfinite(damper.get(["F_damper"])[0])
    damper.free()


def test_fmi3_instantiation_refuses_what_the_model_description_rules_out(fmu3):
    unit = FmuUnit.load(fmu3)
    fmu = FMU3Slave(guid=unit.md.guid, unzipDirectory=str(unit.unzipdir),
                    modelIdentifier=unit.md.coSimulation.modelIdentifier, instanceName="event mode")
    messages = []
    with pytest.raises(Exception, match="Failed to instantiate"):
        fmu.instantiate(eventModeUsed=True, logMessage=lambda env, status, cat, msg: messages.append(msg.decode()))
    assert any("hasEventMode = false" in m for m in messages), messages
    wrong = FMU3Slave(guid="{not-this-one}", unzipDirectory=str(unit.unzipdir),
                      modelIdentifier=unit.md.coSimulation.modelIdentifier, instanceName="token")
    with pytest.raises(Exception, match="Failed to instantiate"):
        wrong.instantiate(logMessage=lambda env, status, cat, msg: messages.append(msg.decode()))
    assert any("instantiationToken" in m for m in messages), messages


def test_an_fmi2_state_restores_in_the_fmi3_fmu(fmu, fmu3):
    """One state format and GUID: a damper saved by the FMI 2.0 FMU goes on in the FMI 3.0 one."""
    two, three = Slave(FmuUnit.load(fmu), "two"), Slave(FmuUnit.load(fmu3), "three")
    for s in (two, three):
        s.initialize(0.0)
    for k in range(200):
        two.step(1e-3, k * 1e-3, v_damper=0.2 * np.sin(0.03 * k), F_demand=4e3)
    state = two.fmu.getFMUstate()
    blob = two.fmu.serializeFMUstate(state)
    restored = three.fmu.deserializeFMUState(blob)
    three.fmu.setFMUState(restored)
    three.time = two.time
    for k in range(200, 300):
        inputs = {"v_damper": 0.2 * np.sin(0.03 * k), "F_demand": 4e3}
        two.step(1e-3, k * 1e-3, **inputs)
        three.step(1e-3, k * 1e-3, **inputs)
        assert np.array_equal(two.get(), three.get()), k
    two.free()
    three.free()


def test_fmi3_log_messages_escape_the_value_reference_character(fmu3):
    """FMI 3.0 reads '#' in a message as a value reference's delimiter, so the FMU doubles it; the
    wrapper's logger reads it back."""
    damper = Slave(FmuUnit.load(fmu3), "log", echo=False)
    damper.fmu.setDebugLogging(True, [])
    with pytest.raises(FMICallException):
        damper.fmu.setDebugLogging(True, ["#nonsense"])
    assert any('"#nonsense"' in text for _, _, text in damper.messages), damper.messages
    damper.fmu.freeInstance()  # never initialised: nothing to terminate
