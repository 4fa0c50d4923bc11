"""The FMU in a second importer: libcosim (Open Simulation Platform) through libcosimpy."""

import numpy as np
from fmpy import simulate_fmu
from libcosimpy.CosimEnums import CosimVariableType
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

STEP_NS = 1_000_000          # communication step: 1 ms
STOP_NS = 300_000_000        # 0.3 s
V_DAMPER = 0.15              # m/s, extension
F_DEMAND = 10e3              # N
SETTLED_AFTER = 0.2          # s
SETTLED_REL_TOL = 0.05       # |F_damper - F_demand| / F_demand after SETTLED_AFTER
MATCH_FMPY_TOL_N = 1.0       # largest |F_damper(libcosim) - F_damper(fmpy)| on the common time grid


def run_libcosim(fmu, vr):
    log_output_level(CosimLogLevel.WARNING)
    execution = CosimExecution.from_step_size(step_size=STEP_NS)
    slave = CosimLocalSlave(fmu_path=str(fmu), instance_name="damper")
    index = execution.add_local_slave(local_slave=slave)
    assert index == 0
    names = {v.name.decode() for v in execution.slave_variables(index)}
    assert {"v_damper", "F_demand", "F_damper"} <= names

    manipulator = CosimManipulator.create_override()
    assert execution.add_manipulator(manipulator=manipulator)
    observer = CosimObserver.create_time_series()
    assert execution.add_observer(observer=observer)
    assert observer.start_time_series(index, vr["F_damper"], CosimVariableType.REAL)

    assert execution.integer_initial_value(index, vr["control_mode"], 0)
    assert execution.real_initial_value(index, vr["v_damper"], V_DAMPER)
    assert execution.real_initial_value(index, vr["F_demand"], F_DEMAND)
    assert manipulator.slave_real_values(index, [vr["v_damper"], vr["F_demand"]], [V_DAMPER, F_DEMAND])

    assert execution.simulate_until(target_time=STOP_NS)
    n = STOP_NS // STEP_NS
    times_ns, _, values = observer.time_series_real_samples(index, vr["F_damper"], from_step=0, sample_count=n + 1)
    return np.array(times_ns) * 1e-9, np.array(values)


def test_libcosim_runs_the_fmu_and_agrees_with_fmpy(fmu, model_description):
    vr = {v.name: v.valueReference for v in model_description.modelVariables}
    t_cosim, f_cosim = run_libcosim(fmu, vr)
    # The time-series observer keeps a sample per step (the one after the last step may be missing).
    assert t_cosim[0] == 0.0 and t_cosim[-1] >= STOP_NS * 1e-9 - 2 * STEP_NS * 1e-9

    settled = f_cosim[t_cosim >= SETTLED_AFTER]
    assert np.all(np.abs(settled - F_DEMAND) < SETTLED_REL_TOL * F_DEMAND), settled

    result = simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=STOP_NS * 1e-9,
                          output_interval=STEP_NS * 1e-9, output=["F_damper"],
                          start_values={"control_mode": 0, "v_damper": V_DAMPER, "F_demand": F_DEMAND})
    t_fmpy, f_fmpy = result["time"], result["F_damper"]
    # Compare on the time points both have.
    idx = np.rint(t_cosim / (STEP_NS * 1e-9)).astype(int)
    assert np.allclose(t_fmpy[idx], t_cosim, atol=1e-9)
    assert np.max(np.abs(f_fmpy[idx] - f_cosim)) < MATCH_FMPY_TOL_N
