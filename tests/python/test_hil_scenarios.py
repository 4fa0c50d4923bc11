"""HiL scenarios (damper-hil-scenarios) on the paper's case, a minor road at 14 m/s: the ideal
semi-active damper beats the best passive one on ride at equal road damage, and the damper FMU in the
loop shows the paper's force-tracking asymmetry (above the demand extending, below compressing)."""

import numpy as np
import pytest

from damper_tools import hil_scenarios

DURATION = 10.0  # s recorded after the settling time (the script uses 15 s)
C_VALUES = np.arange(10e3, 50e3 + 1, 2.5e3)  # N s/m: the part of the 5-60 kNs/m sweep around the DLC minimum
# Measured (seed 3, 15 s): ideal 0.90 m/s^2 against 0.97 m/s^2 for the best passive (30 kNs/m), 7 %
# better. 3 % keeps a margin for the shorter record and still demands a real improvement.
RIDE_MARGIN = 0.03
# Measured: extension +0.35 kN, 60 % of the time above the demand; compression -0.30 kN, 59 % below.
# The reference (docs/physics.md §6.5) found +0.71 kN / 73 % and -0.63 kN / 69 %, with a feedforward biased
# by the gas force (see the README). The test asks only for the paper's signs: a positive mean error
# and a majority above when extending, the reverse compressing.


@pytest.fixture(scope="module")
def minor_14(fmus):
    summary, _ = hil_scenarios.run_scenario("minor", 14.0, duration=DURATION, c_values=C_VALUES, **fmus)
    return summary


def test_ideal_semi_active_beats_best_passive_on_ride_at_equal_dlc(minor_14):
    s = minor_14
    ideal, best, sweep = s["ideal"], s["best_passive"], s["passive_sweep"]
    # best passive as defined by the script: lowest RMS a_body with DLC <= the ideal's, else lowest DLC
    eligible = [p for p in sweep if p["DLC"] <= ideal["DLC"]]
    if eligible:
        assert best["a_body_rms"] == min(p["a_body_rms"] for p in eligible)
    else:
        assert best["DLC"] == min(p["DLC"] for p in sweep)
    assert ideal["a_body_rms"] < (1 - RIDE_MARGIN) * best["a_body_rms"]
    # at the ideal's DLC the passive trade-off curve (its Pareto front, interpolated) rides worse; if
    # the ideal's DLC is below every passive setting's, no passive damper reaches it at all
    at = hil_scenarios.passive_ride_at_dlc(sweep, ideal["DLC"])
    if at is not None:
        assert ideal["a_body_rms"] < (1 - RIDE_MARGIN) * at
    # and no passive setting is as good on both counts
    assert not any(p["a_body_rms"] <= ideal["a_body_rms"] and p["DLC"] <= ideal["DLC"] for p in sweep)


def test_damper_fmu_tracking_asymmetry_has_the_papers_sign(minor_14):
    tr = minor_14["tracking"]
    ext, com = tr["extension"], tr["compression"]
    assert ext["fraction_of_time"] > 0.2 and com["fraction_of_time"] > 0.2
    assert ext["mean_error"] > 0 and ext["fraction_above"] > 0.5, ext
    assert com["mean_error"] < 0 and com["fraction_below"] > 0.5, com
    # the force follows the demand: error well below the demand itself
    assert tr["error_rms"] < 0.8 * tr["F_demand_rms"]
    # below the velocities where the valve's limit cycles were measured (docs/limits.md: 0.6 m/s and up)
    assert tr["v_max"] < 0.6


def test_metric_definitions():
    res = {"time": np.arange(5) * 1e-3,
           "a_body": np.array([0.0, 1.0, -1.0, 1.0, -1.0]), "F_tyre": np.array([9.0, 100.0, -100.0, 100.0, -100.0]),
           "x_damper": np.array([0.0, 0.01, -0.02, 0.01, 0.0]), "F_suspension": np.zeros(5),
           "v_damper": np.array([0.0, 0.1, -0.3, 0.2, 0.0])}
    m = hil_scenarios.vehicle_metrics(res, slice(1, None), static_load=1000.0)
    assert m["a_body_rms"] == 1.0 and m["DLC"] == pytest.approx(0.1)
    # ±100 N on 1000 N: (1.1⁴ + 0.9⁴)/2
    assert m["road_stress"] == pytest.approx((1.1**4 + 0.9**4) / 2)
    assert m["x_damper_peak"] == 0.02 and m["v_damper_max"] == 0.3
    tr = hil_scenarios.tracking_metrics(force=[2000.0, 600.0, -1000.0, -3000.0],
                                        demand=[1000.0, 1000.0, -2000.0, -2000.0], v=[0.1, 0.1, -0.1, -0.1])
    assert tr["extension"]["mean_error"] == pytest.approx(300.0) and tr["extension"]["fraction_above"] == 0.5
    assert tr["compression"]["mean_error"] == 0.0 and tr["compression"]["fraction_below"] == 0.5
