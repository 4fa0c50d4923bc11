"""tare_load_cell = true, as used in the HiL loop: the tared damper must follow a demand without a
steady bias. A symmetric viscous demand (19.2 kNs/m = alpha*Cm, the MSD's passive part) on a 3 Hz
sinusoidal velocity must give a mean force error near zero, as the raw load cell does when the master
does the taring itself (demand + F0 in, F_damper - F0 out)."""

import numpy as np

from damper_tools.fmu import FmuUnit, Slave

STEP = 1e-3  # s
DURATION = 3.0  # s; the first second is not counted
C_VISCOUS = 19.2e3  # N s/m
FREQ = 3.0  # Hz
AMPLITUDE = 0.2  # m/s
# The raw-frame run (the master tares) gives mean(F - F_dem) = -1 N at 0.2 m/s (-82 .. +45 N over
# 0.1 .. 0.4 m/s). 150 N (6 % of the demand's RMS of 2.7 kN) allows that spread; a bias of the order of
# the gas force (0.98 kN) fails.
MEAN_ERROR_TOL = 150.0  # N


def run(damper_fmu, tare):
    d = Slave(FmuUnit.load(damper_fmu), f"tare_{tare}")
    n = int(round(DURATION / STEP))
    try:
        d.initialize(0.0, n * STEP, tare_load_cell=tare)
        f0 = 0.0 if tare else d.get(["F_damper"])[0]
        rows = []
        for k in range(n):
            v = AMPLITUDE * np.sin(2 * np.pi * FREQ * k * STEP)
            d.step(STEP, k * STEP, v_damper=v, F_demand=C_VISCOUS * v + f0)
            rows.append((v, C_VISCOUS * v, d.get(["F_damper"])[0] - f0))
    finally:
        d.free()
    v, demand, force = np.array(rows)[int(round(1.0 / STEP)):].T
    return f0, float(np.mean(force - demand))


def test_tared_damper_follows_a_symmetric_demand_without_bias(fmu):
    f0, raw_bias = run(fmu, tare=False)
    assert -1200 < f0 < -800  # the gas force at rest, removed by the master here
    assert abs(raw_bias) < MEAN_ERROR_TOL, raw_bias
    _, tared_bias = run(fmu, tare=True)
    assert abs(tared_bias) < MEAN_ERROR_TOL, (
        f"tared damper: mean(F_damper - F_demand) = {tared_bias:+.0f} N under a symmetric viscous demand, "
        f"against {raw_bias:+.0f} N when the master tares the raw load cell")
