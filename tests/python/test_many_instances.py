"""Six damper FMU instances at once (damper_tools.instances): six quarter trucks in one master.
Each pair's result equals, bit for bit, the same pair run alone."""

import numpy as np

from damper_tools import instances

DURATION = 1.0  # s
STEP = 1e-3
SPEED = 15.2  # m/s: the first drive axle (3.8 m behind the front) is then exactly 250 steps behind


def test_six_dampers_in_one_master_are_independent(fmus):
    wheels, n = instances.wheel_roads("minor", SPEED, DURATION, seed=5, step=STEP)
    cars = instances.quarter_truck_cars(wheels)
    assert len(cars) == 6 and all(c.has_damper and c.damper_parameters == {"tare_load_cell": True} for c in cars)
    together, same = instances.independence(cars, STEP, n, **fmus)
    assert all(same.values()), same
    # six different loads (so the equality above is not trivial), all of kN
    rms = [np.std(r["damper.F_damper"]) for r in together]
    assert len(set(rms)) == 6 and min(rms) > 500.0
    # left and right are correlated but not equal; the rear axle follows the front one's track
    by = {c.name: r for c, r in zip(cars, together, strict=True)}
    left, right = by["front_left"]["z_road"], by["front_right"]["z_road"]
    rho = np.corrcoef(left, right)[0, 1]
    assert 0.3 < rho < 0.9, rho
    lag = int(round(instances.AXLE_X["drive1"] / SPEED / STEP))
    assert lag == 250
    rear = by["drive1_left"]["z_road"]
    assert np.max(np.abs(rear[lag:] - left[:-lag])) < 1e-12 and np.std(rear[lag:]) > 1e-3


def test_cost_is_measured_per_pair(fmus):
    """The scaling run returns a time per pair (no assertion on timings, only that it ran)."""
    wheels, n = instances.wheel_roads("motorway", 25.0, 0.2, seed=1, step=STEP)
    cars = instances.quarter_truck_cars(wheels)
    rows, slope, _ = instances.scaling(cars, STEP, n, pairs=(1, 2), repeat=1, **fmus)
    assert [r["pairs"] for r in rows] == [1, 2] and all(r["wall_s"] > 0 for r in rows)
    assert np.isfinite(slope)
