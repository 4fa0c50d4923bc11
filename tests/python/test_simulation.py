"""A user's session: simulate the FMU with fmpy from an input file and check the physics."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_csv, simulate_fmu
from fmpy.fmi1 import FMICallException

from damper_tools.fmu import Slave, drive

RESOURCES = Path(__file__).resolve().parent / "resources"
INPUT_CSV = RESOURCES / "damper_input.csv"
FMPY_CLI = Path(sys.executable).parent / "fmpy"
OUTPUT_INTERVAL = 1e-3        # s, communication step
X_DAMPER_START = -0.03        # m, the input file's stroke stays within +-35 mm of mid-stroke
STEADY_REL_TOL = 0.05         # |F_damper - F_demand| / |F_demand| at constant velocity and demand
SIGN_SPEED = 0.125            # m/s: where |v_damper| exceeds this, F_damper has the sign of v_damper
X_INTEGRAL_TOL = 1e-9         # m, x_damper against the integral of the held velocity
CLIPPED_FORCE_RANGE = (-1.5e3, 0.5e3)   # N, valve wide open at 0.15 m/s: gas offset (-1 kN) + ~0.1 kN
CLIP_TOL_N = 1e-6             # N, F_demand_clipped against a dissipative F_demand
VARIABLE_STEP_TOL_N = 60.0    # N, alternating 0.5/1.5 ms steps against 1 ms steps (1 % of 6 kN)
FINE_SOLVER = {"h_max": 2.5e-5, "rtol": 1e-5}   # internal integration 20x finer than the defaults
CONVERGED_RMS_REL_TOL = 0.01  # RMS(F_default - F_fine) / RMS(F_fine)


def simulate_input_file(fmu):
    signals = read_csv(INPUT_CSV)
    return simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=float(signals["time"][-1]),
                        output_interval=OUTPUT_INTERVAL, input=signals,
                        start_values={"x_damper_start": X_DAMPER_START},
                        output=["F_damper", "F_demand", "F_demand_clipped", "v_damper", "x_damper", "x_spool",
                                "p_ext", "p_comp", "p_reservoir"])


def between(result, t0, t1):
    return (result["time"] >= t0) & (result["time"] <= t1)


def test_input_file_run_is_physical(fmu):
    r = simulate_input_file(fmu)
    t, f, v = r["time"], r["F_damper"], r["v_damper"]
    assert np.all(np.isfinite(f))

    # Constant 0.15 m/s with +6 kN (extension), then -0.15 m/s with -6 kN (compression): settled.
    for t0, t1, demand in ((0.30, 0.40, 6e3), (0.72, 0.82, -6e3)):
        window = between(r, t0, t1)
        assert np.all(np.abs(f[window] - demand) < STEADY_REL_TOL * abs(demand)), f[window]

    # 3 Hz velocity with a dissipative demand (24 kNs/m): the force opposes the motion...
    fast = between(r, 0.9, 1.5) & (np.abs(v) > SIGN_SPEED)
    assert np.all(np.sign(f[fast]) == np.sign(v[fast]))
    # ...and the damper absorbs energy over the run (the gas force alone would give ~0).
    sine = between(r, 0.84, 1.5)
    assert np.trapezoid(f[sine] * v[sine], t[sine]) > 0.0
    assert np.trapezoid(f * v, t) > 0.0

    # Dissipative demands pass the semi-active clip unchanged.
    assert np.allclose(r["F_demand_clipped"][1:], r["F_demand"][1:], rtol=0.0, atol=CLIP_TOL_N)
    # The extension chamber carries the force in extension, both chambers in compression.
    ext = between(r, 0.30, 0.40)
    assert np.all(r["p_ext"][ext] > 5 * r["p_comp"][ext])
    comp = between(r, 0.72, 0.82)
    assert np.allclose(r["p_ext"][comp], r["p_comp"][comp], rtol=0.05)


def test_x_damper_is_the_integral_of_the_velocity(fmu):
    r = simulate_input_file(fmu)
    # fmpy holds the input sampled at the start of each step, and the recorded v_damper at t_k
    # is the value held over the step that ended at t_k.
    x = X_DAMPER_START + np.concatenate(([0.0], np.cumsum(r["v_damper"][1:] * np.diff(r["time"]))))
    assert np.max(np.abs(r["x_damper"] - x)) < X_INTEGRAL_TOL


def test_fmpy_command_line_gives_the_same_result(fmu, work_dir):
    out = work_dir / "result.csv"
    cmd = [str(FMPY_CLI), "simulate", str(fmu), "--interface-type", "CoSimulation", "--stop-time", "1.5",
           "--output-interval", str(OUTPUT_INTERVAL), "--input-file", str(INPUT_CSV),
           "--start-values", "x_damper_start", str(X_DAMPER_START),
           "--output-variables", "F_damper", "x_damper", "--output-file", str(out)]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    cli = read_csv(out)
    api = simulate_input_file(fmu)
    assert np.allclose(cli["time"], api["time"])
    assert np.allclose(cli["F_damper"], api["F_damper"], rtol=1e-6, atol=1e-6)


def test_fmpy_relative_tolerance_is_the_step_size_controls(fmu):
    """fmpy's relative_tolerance reaches the FMU through fmi2SetupExperiment and sets its rtol, as a
    start value for rtol would; a start value for rtol, where both are given, wins."""
    signals = read_csv(INPUT_CSV)

    def force(relative_tolerance=None, rtol=None):
        start = {"x_damper_start": X_DAMPER_START} | ({} if rtol is None else {"rtol": rtol})
        return simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.5, output_interval=OUTPUT_INTERVAL,
                            input=signals, start_values=start, relative_tolerance=relative_tolerance,
                            output=["F_damper"])["F_damper"]

    default, tight = force(), force(rtol=1e-5)
    assert not np.array_equal(default, tight)
    assert np.array_equal(force(relative_tolerance=1e-5), tight)
    assert np.array_equal(force(relative_tolerance=1e-5, rtol=3e-4), default)


def test_a_master_that_interpolates_inputs_moves_them_along_ramps(damper_unit):
    """canInterpolateInputs: a master sends each input's slope with fmi2SetRealInputDerivatives.
    The velocity's equals setting a_damper; a demand's ramp changes the force. (fmpy's
    simulate_fmu(set_input_derivatives=True) cannot be used: fmpy 0.3.32 sizes its derivative
    buffer for nine inputs.)"""
    h, slope, demand_rate = 1e-3, 4.0, 2e5   # s, m/s2, N/s
    by_derivative, by_a_damper, demand_ramped = (Slave(damper_unit, name) for name in ("deriv", "a", "ramp"))
    for s in (by_derivative, by_a_damper, demand_ramped):
        s.initialize(x_damper_start=X_DAMPER_START)
    v_vr, f_vr = damper_unit.vr("v_damper"), damper_unit.vr("F_demand")
    forces = []
    for k in range(50):
        v = 0.05 + slope * k * h
        by_derivative.fmu.setRealInputDerivatives([v_vr], [1], [slope])
        by_derivative.step(h, k * h, v_damper=v, F_demand=6e3)
        by_a_damper.step(h, k * h, v_damper=v, a_damper=slope, F_demand=6e3)
        demand_ramped.fmu.setRealInputDerivatives([v_vr, f_vr], [1, 1], [slope, demand_rate])
        demand_ramped.step(h, k * h, v_damper=v, F_demand=6e3 + demand_rate * k * h)
        forces.append([s.get(["F_damper"])[0] for s in (by_derivative, by_a_damper, demand_ramped)])
    forces = np.array(forces)
    assert np.array_equal(forces[:, 0], forces[:, 1])
    assert np.max(np.abs(forces[:, 2] - forces[:, 0])) > 100.0
    # a second derivative is refused, not dropped
    assert by_derivative.errors() == [] and demand_ramped.errors() == []
    with pytest.raises(FMICallException):
        by_derivative.fmu.setRealInputDerivatives([v_vr], [2], [1.0])
    assert "v_damper: derivative of order 2 refused" in by_derivative.errors()[-1][2]
    assert demand_ramped.errors() == [], "each instance keeps its own messages"
    for s in (by_derivative, by_a_damper, demand_ramped):
        s.free()


def test_non_dissipative_demand_is_clipped(fmu):
    r = simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.2, output_interval=OUTPUT_INTERVAL,
                     start_values={"v_damper": 0.15, "F_demand": -5e3},
                     output=["F_damper", "F_demand_clipped"])
    assert np.all(r["F_demand_clipped"][1:] == 0.0)
    settled = r["F_damper"][r["time"] >= 0.1]
    assert np.all((settled > CLIPPED_FORCE_RANGE[0]) & (settled < CLIPPED_FORCE_RANGE[1])), settled


def test_variable_communication_steps_end_close_to_fixed_steps(damper_unit):
    """Steps alternating 0.5 ms and 1.5 ms against 1 ms steps. Inputs change only at t = 0.1 s,
    a point of both grids; outputs are compared where both grids have points (every 2 ms)."""
    def inputs_at(t):
        return {"v_damper": 0.15, "F_demand": 6e3} if t < 0.1 - 1e-9 else {"v_damper": -0.15, "F_demand": -6e3}

    fixed = Slave(damper_unit, "fixed")
    variable = Slave(damper_unit, "variable")
    try:
        for s in (fixed, variable):
            s.initialize(x_damper_start=-0.01)
        t_fix, y_fix = drive(fixed, [1e-3] * 200, inputs_at, names=["F_damper"])
        t_var, y_var = drive(variable, [0.5e-3, 1.5e-3] * 100, inputs_at, names=["F_damper"])
    finally:
        fixed.free()
        variable.free()
    assert abs(t_fix[-1] - 0.2) < 1e-12 and abs(t_var[-1] - 0.2) < 1e-12
    f_fix = y_fix[1::2, 0]          # t = 2, 4, ... ms
    f_var = y_var[1::2, 0]          # t = 2, 4, ... ms
    assert np.allclose(t_fix[1::2], t_var[1::2], atol=1e-12)
    assert np.max(np.abs(f_fix - f_var)) < VARIABLE_STEP_TOL_N


# Abrupt starts from rest are the hardest case for the internal step-size control: a velocity
# step at t = 0, near a stroke end (small chamber), or at 0.5 m/s in compression.
VELOCITY_STEPS = {
    "fig4_start_near_stroke_end": ({"control_mode": 1, "x_damper_start": -0.09}, {"v_damper": 0.15}),
    "compression_0.5_m_s": ({"control_mode": 0}, {"v_damper": -0.5, "F_demand": -10e3}),
    "extension_0.5_m_s": ({"control_mode": 0, "x_damper_start": -0.05}, {"v_damper": 0.5, "F_demand": 10e3}),
}


@pytest.mark.parametrize("case", sorted(VELOCITY_STEPS))
def test_velocity_step_from_rest_is_converged(fmu, case):
    """The default internal integration agrees with a much finer one."""
    params, inputs = VELOCITY_STEPS[case]
    runs = []
    for solver in ({}, FINE_SOLVER):
        r = simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.1, output_interval=OUTPUT_INTERVAL,
                         start_values={**params, **inputs, **solver}, output=["F_damper"])
        runs.append(r["F_damper"])
    default, fine = runs
    rms = np.sqrt(np.mean((default - fine) ** 2))
    assert rms < CONVERGED_RMS_REL_TOL * np.sqrt(np.mean(fine ** 2)), rms
