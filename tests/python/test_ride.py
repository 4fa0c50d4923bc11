"""The ride and road-damage measures against the standard's table and hand results."""

import numpy as np
import pytest

from damper_tools import ride

# ISO 2631-1:1997 Table 3, weighting Wk (factors x 1000) at one-third-octave band centres
WK_TABLE = {0.5: 418, 1.0: 482, 2.0: 531, 4.0: 967, 5.0: 1039, 8.0: 1036, 16.0: 768, 31.5: 405, 63.0: 186}


@pytest.mark.parametrize("f_hz,factor", WK_TABLE.items())
def test_wk_of_a_sine_is_the_standard_s_factor(f_hz: float, factor: int) -> None:
    step = 1e-3
    t = np.arange(0.0, 40.0, step)
    weighted = ride.wk_rms(np.sin(2 * np.pi * f_hz * t), step)
    assert weighted * np.sqrt(2) == pytest.approx(factor / 1000, abs=0.0015)


def test_wk_adds_two_tones_by_power() -> None:
    step = 1e-3
    t = np.arange(0.0, 40.0, step)
    a = np.sin(2 * np.pi * 1.0 * t) + 2 * np.sin(2 * np.pi * 8.0 * t)
    expected = np.sqrt((ride.wk_gain([1.0])[0] ** 2 + 4 * ride.wk_gain([8.0])[0] ** 2) / 2)
    assert ride.wk_rms(a, step) == pytest.approx(expected, rel=1e-6)


def test_road_stress_of_a_gaussian_load() -> None:
    rng = np.random.default_rng(7)
    dlc, load = 0.15, 42e3
    f = rng.normal(0.0, dlc * load, 2_000_000)
    assert ride.road_stress_factor(f, load) == pytest.approx(1 + 6 * dlc**2 + 3 * dlc**4, rel=2e-3)


def test_a_lifted_tyre_does_no_damage() -> None:
    assert ride.road_stress_factor([-2000.0, 1000.0], 1000.0) == pytest.approx(2**4 / 2)
