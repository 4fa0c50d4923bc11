"""How well a damper tracks its force demand, as the idealised tracking damper of QuarterTruck.fmu
(damper_mode 3) would: a pure delay and a first-order lag per direction, fitted to a record.

    force_model = dissipative(lag_bw(demand(t - delay)), v)      (extension: v > 0, compression: v < 0)

The delay is searched in whole samples, the bandwidth on a log grid (and infinity); each direction
takes the pair that leaves the least RMS error over its samples (|v| > EXT_V). A damper that
overshoots (the FMU's force loop in extension) has no exact match in this family: the fit's RMS error
is reported beside the raw error, so that a reader sees how much of the tracking the family explains.

The grid is scored in compiled code (crates/cosim_runner's tracking_fit.rs through damper_tools.runner,
whose library `cargo build --release -p cosim_runner` builds); `sse_reference` and `lagged` are the
numpy reference it is tested against.
"""

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy.signal import lfilter

from damper_tools import FloatArray, runner
from damper_tools.hil_scenarios import EXT_V  # m/s: the directions' classes, as the HiL metrics

MAX_DELAY = 0.04  # s, longest delay searched
BANDWIDTHS = tuple(np.geomspace(2.0, 500.0, 33)) + (math.inf,)  # Hz, 19 % apart
# grid points evaluated again sample by sample: the correlations' rounding (1e-13 of the force's
# square) cannot reorder pairs further apart than that, and the nearest differ by more
CANDIDATES = 8


@dataclass(frozen=True)
class Tracking:
    """A direction's fitted delay (s) and bandwidth (Hz, inf: no lag), the RMS error (N) the fit leaves
    and the raw RMS error force − demand (N) over the same samples."""
    delay: float
    bandwidth: float
    fit_error_rms: float
    error_rms: float


def lagged(demand: FloatArray, step: float, delay_samples: int, bandwidth: float) -> FloatArray:
    """`demand` delayed by whole samples (the first value held before the start) and through a
    first-order lag of corner `bandwidth` (Hz), discretised exactly for a piecewise-constant input.
    The reference of the compiled lags fit() uses (runner.first_order_lags, the same bits)."""
    d = np.concatenate([np.full(delay_samples, demand[0]), demand[: demand.size - delay_samples]])
    if math.isinf(bandwidth):
        return d
    p = pole(bandwidth, step)
    filtered: FloatArray = lfilter([1 - p], [1, -p], d, zi=[p * d[0]])[0]
    return filtered


def pole(bandwidth: float, step: float) -> float:
    """The discrete pole of a first-order lag of corner `bandwidth` (Hz) sampled every `step` (s): 0
    for no lag (bandwidth inf)."""
    return 0.0 if math.isinf(bandwidth) else math.exp(-2 * math.pi * bandwidth * step)


def dissipative(force: FloatArray, v: FloatArray) -> FloatArray:
    """`force` kept to what a semi-active damper moving at `v` gives (floor 0)."""
    return np.where(v > 0, np.maximum(force, 0.0), np.where(v < 0, np.minimum(force, 0.0), 0.0))


def sse_reference(lags: FloatArray, force: FloatArray, idx: npt.NDArray[np.intp], n_delays: int,
                  sign: float) -> FloatArray:
    """Sums of squared errors of the dissipative model against `force` over the samples `idx` of one
    direction (sign +1: extension, the model max(lag, 0); -1: compression, min(lag, 0)), for every
    bandwidth (the rows of `lags`) and delay 0 .. n_delays - 1 (the columns) at once, in numpy: the
    reference of the compiled grid fit() uses (runner.tracking_sse), slower by ten. With m the
    model before the delay (its first value held before the start) and w the direction's mask,
    Σ_i w_i (m_{i-n} − F_i)² = Σ_i w_i m²_{i-n} − 2 Σ_i w_i F_i m_{i-n} + Σ_i w_i F_i²: the first two
    for all delays are two matrix products with the mask shifted once per delay."""
    m = np.maximum(lags, 0.0) if sign > 0 else np.minimum(lags, 0.0)
    held = np.concatenate([np.repeat(m[:, :1], n_delays - 1, axis=1), m], axis=1)
    size = lags.shape[1]
    w = np.zeros(size)
    w[idx] = 1.0
    wf = w * force
    mask, weighted = np.zeros((held.shape[1], n_delays)), np.zeros((held.shape[1], n_delays))
    for n in range(n_delays):  # delay n reads held[i + n_delays - 1 - n] for sample i
        start = n_delays - 1 - n
        mask[start:start + size, n] = w
        weighted[start:start + size, n] = wf
    sse: FloatArray = (held ** 2) @ mask - 2.0 * (held @ weighted) + float(np.sum(wf * force))
    return sse


def _rms_errors(lags: FloatArray, force: FloatArray, v: FloatArray, idx: npt.NDArray[np.intp],
                bandwidths: npt.NDArray[np.intp], delays: npt.NDArray[np.intp]) -> FloatArray:
    """The RMS errors of the models of the given (bandwidth row, delay in samples) pairs, evaluated
    directly, a row per pair (the reported figures; numpy sums each row as it sums a single array)."""
    models = dissipative(lags[bandwidths[:, None], np.maximum(idx[None, :] - delays[:, None], 0)], v[idx][None, :])
    errors: FloatArray = np.sqrt(np.mean((models - force[idx][None, :]) ** 2, axis=1))
    return errors


def fit(demand: FloatArray, force: FloatArray, v: FloatArray, step: float) -> dict[str, Tracking]:
    """The delay and bandwidth of each direction ("extension", "compression") that make the clipped
    `demand` (N) into the `force` (N) acting at velocity `v` (m/s), sampled every `step` (s).

    Every pair of the grid is scored by its sum of squared errors, compiled (runner.tracking_sse; numpy's
    sse_reference gives the same sums to rounding); the best few of each direction are evaluated
    again sample by sample, and the least of those is the fit, so that the reported error is the
    direct RMS of the chosen model and the choice does not rest on the sums' rounding order."""
    demand, force, v = (np.asarray(x, dtype=float) for x in (demand, force, v))
    samples = {"extension": (np.flatnonzero(v > EXT_V), 1.0), "compression": (np.flatnonzero(v < -EXT_V), -1.0)}
    n_delays = int(round(MAX_DELAY / step)) + 1
    # a delay commutes with the lag: lag once per bandwidth, delay by index (the start's value held)
    lags = runner.first_order_lags(demand, [pole(bw, step) for bw in BANDWIDTHS])
    out = {}
    for name, (idx, sign) in samples.items():
        sse = runner.tracking_sse(lags, force, idx, n_delays, extension=sign > 0)
        bws, delays = np.divmod(np.argsort(sse, axis=None, kind="stable")[:CANDIDATES], n_delays)
        errors = _rms_errors(lags, force, v, idx, bws, delays)
        # the grid's order breaks ties, as the sample-by-sample search over (bandwidth, delay) did
        err, b, n = min(zip(errors.tolist(), bws.tolist(), delays.tolist(), strict=True))
        out[name] = Tracking(delay=n * step, bandwidth=BANDWIDTHS[b], fit_error_rms=err,
                             error_rms=float(np.sqrt(np.mean((force[idx] - demand[idx]) ** 2))))
    return out
