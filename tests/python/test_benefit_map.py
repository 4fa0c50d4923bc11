"""The semi-active benefit map (damper_tools.benefit_map, docs/benefit-map.md): the packaged truck's
idealised tracking damper against its hand results at both ends, the fit of a damper's tracking on a
record it did not make, the comparison rule, and the command on a small grid."""

import math

import numpy as np
import pandas as pd
import pytest

from damper_tools import benefit_map, cosim, roads, sweep, tracking_quality


@pytest.fixture(scope="module")
def paths(fmus):
    return {"truck": fmus["truck_fmu"], "damper": fmus["damper_fmu"]}


def hil(paths, **point):
    return sweep.run_hil({"duration": 3.0, "settle": 1.0, **point}, 11, paths["truck"], paths["damper"])


def test_a_speed_only_scales_a_homogeneous_truck(paths):
    """The hand result behind the map's nine cases: an ISO 8608 road of waviness 2 is a white velocity
    input at any speed, and the truck with the clipped MSD law or a linear damper is positively
    homogeneous, so the ratio of two dampers' rides hardly moves with the speed (the profile's band
    limits move in frequency)."""
    ratios = []
    for speed in (14.0, 25.0):
        ideal = hil(paths, mode="ideal", speed=speed, duration=8.0)
        passive = hil(paths, mode="passive", c_passive=25e3, speed=speed, duration=8.0)
        ratios.append(ideal["a_body_rms"] / passive["a_body_rms"])
    assert ratios[0] == pytest.approx(ratios[1], rel=3e-3)
    assert ratios[0] < 0.97, "the ideal damper rides better"


def test_no_delay_and_no_lag_is_the_ideal_damper(paths):
    ideal = hil(paths, mode="ideal")
    tracking = hil(paths, mode="tracking", tracking_delay=0.0, tracking_bandwidth=math.inf)
    assert ideal["a_body_rms"] > 0.3
    for m in ("a_body_rms", "a_body_wk_rms", "DLC", "road_stress", "x_damper_peak"):
        assert tracking[m] == ideal[m], m


def test_a_lag_that_never_moves_is_the_passive_floor(paths):
    floor = hil(paths, mode="passive", c_passive=6e3)
    slow = hil(paths, mode="tracking", c_min=6e3, tracking_delay=0.01, tracking_bandwidth=1e-9)
    for m in ("a_body_rms", "DLC", "road_stress", "x_damper_peak"):
        assert slow[m] == pytest.approx(floor[m], rel=1e-6), m
    # and the demand law's own floor: the ideal damper with c_min never dissipates less
    assert hil(paths, mode="ideal", c_min=6e3)["DLC"] != hil(paths, mode="ideal")["DLC"]


def test_a_delay_costs_ride(paths):
    ideal = hil(paths, mode="tracking")
    late = hil(paths, mode="tracking", tracking_delay=0.02, tracking_bandwidth=20.0)
    assert late["a_body_rms"] > 1.05 * ideal["a_body_rms"]


def test_the_non_linear_passive_damper_is_its_characteristic(fmus):
    """The truck's passive damper with a softer compression and a degressive knee: its force on the
    masses is the characteristic at its velocity, at every communication point."""
    case = roads.road_case("minor", 14.0, 4.0, 3, step=1e-3, fade_in=1.0)
    p = {"c_passive": 20e3, "passive_compression_ratio": 0.4, "passive_v_knee": 0.05, "passive_high_speed_ratio": 0.3}
    r = cosim.simulate_one(case.z_road, case.v_road, 1e-3, case.t.size - 1, cosim.MODE_PASSIVE, p,
                           truck_fmu=fmus["truck_fmu"])
    v = r["v_damper"]
    low = np.clip(v, -0.05, 0.05)
    expected = 20e3 * np.where(v < 0, 0.4, 1.0) * (low + 0.3 * (v - low))
    assert np.abs(v).max() > 0.1, "the road takes the damper past its knee"
    np.testing.assert_allclose(r["F_suspension"], expected, rtol=1e-12, atol=1e-9)


def test_the_fit_finds_the_tracking_of_a_record_it_did_not_make(fmus):
    """The truck's tracking damper (RK4, the delay interpolated at 0.25 ms, a continuous lag) with 7 ms
    and 30 Hz in extension, 12 ms and 15 Hz in compression; the fit knows whole 1 ms samples and a
    discrete lag."""
    case = roads.road_case("minor", 14.0, 10.0, 3, step=1e-3, fade_in=1.0)
    truth = {"tracking_delay_extension": 0.007, "tracking_delay_compression": 0.012,
             "tracking_time_constant_extension": 1 / (2 * math.pi * 30), "tracking_time_constant_compression":
             1 / (2 * math.pi * 15)}
    r = cosim.simulate_one(case.z_road, case.v_road, 1e-3, case.t.size - 1, cosim.MODE_TRACKING, truth,
                           truck_fmu=fmus["truck_fmu"])
    w = slice(2000, None)
    fit = tracking_quality.fit(r["F_demand"][w], r["F_suspension"][w], r["v_damper"][w], 1e-3)
    for side, delay, bandwidth in (("extension", 0.007, 30.0), ("compression", 0.012, 15.0)):
        assert fit[side].delay == pytest.approx(delay, abs=1.01e-3), side
        assert fit[side].bandwidth == pytest.approx(bandwidth, rel=0.25), side
        assert fit[side].fit_error_rms < 0.1 * fit[side].error_rms, side


def test_the_benefit_is_over_the_best_riding_passive_damper():
    passive = pd.DataFrame({"road": "minor", "speed": 14.0, "c_passive": [10e3, 20e3, 30e3],
                            "a_body_rms": [1.00, 0.90, 0.95], "a_body_wk_rms": [0.70, 0.66, 0.65],
                            "DLC": [0.12, 0.11, 0.10]})
    rows = pd.DataFrame({"road": "minor", "speed": 14.0, "a_body_rms": [0.81, 0.99], "a_body_wk_rms": [0.65, 0.52],
                         "DLC": [0.099, 0.121]})
    passive["road_stress"] = [1.10, 1.08, 1.06]
    rows["road_stress"] = [1.05, 1.12]
    b = benefit_map.benefits(rows, passive)
    assert b["stress_change"].tolist() == pytest.approx([1.05 / 1.08 - 1, 1.12 / 1.08 - 1])
    # plain: against 20 kNs/m (0.90 m/s², DLC 0.11); Wk: against 30 kNs/m (0.65, DLC 0.10)
    assert b["benefit"].tolist() == pytest.approx([0.10, -0.10])
    assert b["dlc_change"].tolist() == pytest.approx([0.099 / 0.11 - 1, 0.121 / 0.11 - 1])
    assert b["benefit_wk"].tolist() == pytest.approx([0.0, 0.2])
    assert b["dlc_change_wk"].tolist() == pytest.approx([-0.01, 0.21])


def test_tracking_settings_are_checked():
    with pytest.raises(sweep.SweepError, match="tracking_direction"):
        sweep.tracking_parameters({"tracking_direction": "rebound", "tracking_delay": 0.0,
                                   "tracking_bandwidth": math.inf})
    p = sweep.tracking_parameters({"tracking_direction": "compression", "tracking_delay": 0.01,
                                   "tracking_bandwidth": 50.0})
    assert p["tracking_delay_extension"] == 0.0 and p["tracking_delay_compression"] == 0.01
    assert p["tracking_time_constant_compression"] == pytest.approx(1 / (2 * math.pi * 50))


def test_the_command_writes_its_tables_and_maps(paths, tmp_path):
    grid = benefit_map.Grid(roads=("minor",), speeds=(14.0,), delays=(0.0, 0.01), bandwidths=(20.0, math.inf),
                            c_passive=(15e3, 25e3, 35e3), duration=3.0, law_alphas=(0.4, 0.8), law_cms=(24e3,),
                            nonlinear={"c_passive": (20e3,), "passive_compression_ratio": (0.5, 1.0),
                                       "passive_v_knee": (0.1,), "passive_high_speed_ratio": (0.5,)},
                            controller={"Cm": (48e3,), "alpha": (0.2,), "Kp_F": (0.3,), "Ki_F": (0.0,)},
                            hybrid={"Cm": (24e3,), "alpha": (0.8,), "C_ground": (20e3,)})
    results = benefit_map.run(grid, tmp_path, paths)
    for name in ("map.parquet", "passive.parquet", "nonlinear.parquet", "laws.parquet", "controller.parquet",
                 "hybrid.parquet", "fmu.parquet", "table.md",
                 "results.json",
                 "benefit_map_headline.png", "benefit_wk_map_headline.png", "benefit_map_cases.png", "demand_laws.png",
                 "pareto_fronts.png"):
        assert (tmp_path / name).is_file(), name
    m = pd.DataFrame(results["map"])
    assert sorted(m["road"].unique()) == ["belgian_block", "minor"]
    m = m[m["road"] == "minor"]
    assert len(m) == 3 * 2 * 2
    ideal = m[(m["tracking_delay"] == 0) & np.isinf(m["tracking_bandwidth"].astype(float))]
    assert ideal["a_body_rms"].nunique() == 1, "the ideal point is the same run in every direction"
    table = (tmp_path / "table.md").read_text()
    assert "minor, 14 m/s" in table and "belgian_block, 3 m/s" in table
