"""The valve's transfer functions and flow map (damper_tools.valve_response, damper-valve-response):
the estimator recovers a known system, the FMU's valve lies where its parameters put it, and the flow
map lies on the sharp-edged orifice law."""

import math

import numpy as np
import pytest

from damper_tools import valve_response as vr

H = vr.STEP
TAU_LAG, DELAY = 4e-3, 3e-3   # s: a first-order lag (-3 dB at 39.8 Hz) behind a pure delay


def lag_with_delay(u: np.ndarray) -> np.ndarray:
    """y' = (u(t - DELAY) - y)/TAU_LAG with u held over each step, solved exactly (not with the FMU)."""
    d = int(round(DELAY / H))
    a = math.exp(-H / TAU_LAG)
    y = np.zeros(u.size)
    for k in range(u.size - 1):
        y[k + 1] = a * y[k] + (1 - a) * (u[k - d] if k >= d else u[0])
    return y


def test_estimator_recovers_a_known_lag_and_delay():
    bins = vr.multisine_lines()
    shape = vr.multisine(H, vr.PERIOD, bins)
    u = 1.0 + 0.1 * np.tile(shape, 3)
    frf = vr.estimate_frf(u, lag_with_delay(u), H, vr.PERIOD, bins)
    m = vr.bode_metrics(frf, 1.0)
    # exact response of the sampled system (held input, one sample of output lag): e^{-jw(DELAY + H)} times
    # the ZOH-sampled lag (1 - a) e^{-jwH} / (1 - a e^{-jwH}) ... compared directly:
    z = np.exp(1j * 2 * np.pi * frf.f * H)
    a = math.exp(-H / TAU_LAG)
    exact = (1 - a) / (z - a) * z ** -round(DELAY / H)
    assert np.allclose(frf.H, exact, rtol=1e-9, atol=1e-9)
    assert frf.coherence.min() > 0.999999
    # -3 dB of the lag: 1/(2 pi TAU_LAG) = 39.8 Hz, read between lines 4 Hz apart
    assert m["f_3dB"] == pytest.approx(1 / (2 * math.pi * TAU_LAG), rel=0.05)
    # low-frequency phase slope: lag + delay + the half step of the hold (+ the sampled lag's own half step)
    assert m["delay"] == pytest.approx(TAU_LAG + DELAY + H / 2, rel=0.08)


def test_pooled_coherence_sees_a_nonlinearity():
    """Over multisine realizations with different phases, a linear system keeps coherence 1 and its
    exact response, while a static nonlinearity (a saturation, computed here, not by the FMU) lowers
    the coherence at the excited lines; one realization's repeated periods could not tell them apart."""
    bins = vr.multisine_lines()
    shapes = [np.tile(vr.multisine(H, vr.PERIOD, bins, vr.SEED + r), 3) for r in range(3)]
    linear = vr.pooled_frf([(u, lag_with_delay(u)) for u in shapes], H, vr.PERIOD, bins)
    assert linear.coherence.min() > 0.999999
    saturated = vr.pooled_frf([(u, lag_with_delay(np.tanh(2.0 * u))) for u in shapes], H, vr.PERIOD, bins)
    assert saturated.coherence.min() < 0.99
    one = vr.estimate_frf(shapes[0], lag_with_delay(np.tanh(2.0 * shapes[0])), H, vr.PERIOD, bins)
    assert one.coherence.min() > 0.999999  # the periods of one realization repeat exactly


@pytest.fixture(scope="module")
def valve_mid(damper_unit):
    return vr.valve_run(damper_unit, 2.5e-3, vr.SPOOL_SMALL)


def test_valve_current_to_spool_is_the_spool_mass_spring_damper(valve_mid, model_description):
    """At mid-opening the flow force is small: i_sol -> x_spool is K_sol / (m s^2 + c s + k). Its static
    gain K_sol/k, its -90 deg at the natural frequency sqrt(k/m)/(2 pi) and its -3 dB frequency
    (zeta 0.8: 0.87 f_n) follow from the start values."""
    p = {v.name: float(v.start) for v in model_description.modelVariables if v.name in
         ("K_sol", "k_spool", "m_spool", "c_spool")}
    m = valve_mid.metrics["valve"]
    f_n = math.sqrt(p["k_spool"] / p["m_spool"]) / (2 * math.pi)
    zeta = p["c_spool"] / (2 * math.sqrt(p["k_spool"] * p["m_spool"]))
    f_3db = f_n * math.sqrt(1 - 2 * zeta ** 2 + math.sqrt(4 * zeta ** 4 - 4 * zeta ** 2 + 2))
    assert m["gain_low"] == pytest.approx(p["K_sol"] / p["k_spool"], rel=0.05)
    # sampled at 2 kHz with the output read at the step's end: a quarter-millisecond-scale extra lag
    assert m["f_90deg"] == pytest.approx(f_n, rel=0.1)
    assert m["f_3dB"] == pytest.approx(f_3db, rel=0.1)


def test_closed_spool_loop_bandwidth_is_set_by_the_amplifier_delay(valve_mid):
    """The inner loop carries the 3 ms amplifier delay: its -3 dB bandwidth is well below the spool's own
    (159 Hz) and of the order of 1/(2 pi x its delay); its equivalent delay exceeds the amplifier's."""
    cl = valve_mid.metrics["closed_loop"]
    assert 20 <= cl["f_3dB"] <= 80
    assert 3e-3 < cl["delay"] < 15e-3
    assert cl["f_3dB"] < valve_mid.metrics["valve"]["f_3dB"]


def test_flow_map_points_lie_on_the_orifice_law(damper_unit):
    p = damper_unit.parameters()
    points = vr.flow_map(damper_unit, spools=(1.2e-3, 2.8e-3), velocities=(0.05, 0.1, 0.25, 0.6))
    dev = vr.orifice_law_deviation(points, p)
    assert dev.size >= 8
    # turbulent: Q = C_d A sqrt(2 dp / rho) within 0.5 % (the laminar transition adds (p_tr/dp)^2 / 4)
    assert np.abs(dev).max() < 5e-3
    # and the law at the demand, not just at the measured spool: the spool holds its position
    for q in points:
        assert q["x_spool"] == pytest.approx(q["x_spool_demand"], abs=20e-6)
    # the force resists the motion once the drop outweighs the gas force (about 1 kN pushing out)
    assert all(q["F_damper"] * q["velocity"] > 0 for q in points if q["dp"] > 2e6)


def test_force_loop_is_slower_in_compression(damper_unit):
    """The paper: compression (3x the compressed oil) responds slower. The force loop's -3 dB bandwidth
    at 0.15 m/s is lower in compression than in extension."""
    ext = vr.force_run(damper_unit, 0.15)
    com = vr.force_run(damper_unit, -0.15)
    assert com.metrics["f_3dB"] < ext.metrics["f_3dB"]
    assert com.metrics["f_90deg"] < ext.metrics["f_90deg"]
