"""The tracking fit's compiled grid (runner.first_order_lags, runner.tracking_sse: crates/cosim_runner's
tracking_fit.rs) against the numpy reference it replaced in tracking_quality.fit: the lags equal bit
for bit, the sums of squared errors equal to rounding and ranked alike, and the fit itself equal to
the one the reference grid gives, on a HiL record of the damper FMU."""

import numpy as np
import pytest

from damper_tools import runner, tracking_quality
from damper_tools.hil_scenarios import EXT_V

STEP = 1e-3


@pytest.fixture(scope="module")
def record(runner_library, fmus):
    """8 s of the quarter truck with the damper FMU on its own minor road; the first second dropped."""
    res = runner.run_quarter_truck({**runner.own_road("minor", 14.0, 8.0, 11, step=STEP), "damper_mode": 0},
                                   STEP, 8000, **fmus)
    w = slice(1000, None)
    return res["F_demand"][w], res["F_suspension"][w], res["v_damper"][w]


def test_the_compiled_lags_are_scipys_bit_for_bit(record):
    demand = record[0]
    compiled = runner.first_order_lags(demand, [tracking_quality.pole(bw, STEP) for bw in tracking_quality.BANDWIDTHS])
    reference = np.array([tracking_quality.lagged(demand, STEP, 0, bw) for bw in tracking_quality.BANDWIDTHS])
    assert np.array_equal(compiled, reference)


@pytest.mark.parametrize("sign", [1.0, -1.0], ids=["extension", "compression"])
def test_the_compiled_sums_are_the_references_to_rounding(record, sign):
    demand, force, v = record
    lags = runner.first_order_lags(demand, [tracking_quality.pole(bw, STEP) for bw in tracking_quality.BANDWIDTHS])
    idx = np.flatnonzero(sign * v > EXT_V)
    compiled = runner.tracking_sse(lags, force, idx, 41, extension=sign > 0)
    reference = tracking_quality.sse_reference(lags, force, idx, 41, sign)
    # the reference expands the square and loses about 1e-13 of Σ F² to cancellation; the compiled
    # sums do not expand it
    assert np.max(np.abs(compiled - reference)) < 1e-11 * np.sum(force[idx] ** 2)
    best = np.argsort(compiled, axis=None)[: tracking_quality.CANDIDATES]
    assert np.argmin(reference) in best


def test_the_fit_is_the_reference_grids_fit(record, monkeypatch):
    demand, force, v = record
    fitted = tracking_quality.fit(demand, force, v, STEP)
    monkeypatch.setattr(runner, "tracking_sse", lambda lags, f, idx, n, extension:
                        tracking_quality.sse_reference(lags, f, idx, n, 1.0 if extension else -1.0))
    assert tracking_quality.fit(demand, force, v, STEP) == fitted


def test_wrong_shapes_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="sample index 9 beyond the 5 samples"):
        runner.tracking_sse(np.zeros((2, 5)), np.zeros(5), np.array([0, 9]), 3, extension=True)
    with pytest.raises(ValueError, match="tracking fit"):
        runner.first_order_lags(np.zeros(0), [0.5])
