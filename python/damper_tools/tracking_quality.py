"""How well a damper tracks its force demand, as the idealised tracking damper of QuarterTruck.fmu
(damper_mode 3) would: a pure delay and a first-order lag per direction, fitted to a record.

    force_model = dissipative(lag_bw(demand(t - delay)), v)      (extension: v > 0, compression: v < 0)

The delay is searched in whole samples, the bandwidth on a log grid (and infinity); each direction
takes the pair that leaves the least RMS error over its samples (|v| > EXT_V). A damper that
overshoots (the FMU's force loop in extension) has no exact match in this family: the fit's RMS error
is reported beside the raw error, so that a reader sees how much of the tracking the family explains.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from damper_tools import FloatArray
from damper_tools.hil_scenarios import EXT_V  # m/s: the directions' classes, as the HiL metrics

MAX_DELAY = 0.04  # s, longest delay searched
BANDWIDTHS = tuple(np.geomspace(2.0, 500.0, 33)) + (math.inf,)  # Hz, 19 % apart


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
    first-order lag of corner `bandwidth` (Hz), discretised exactly for a piecewise-constant input."""
    d = np.concatenate([np.full(delay_samples, demand[0]), demand[: demand.size - delay_samples]])
    if math.isinf(bandwidth):
        return d
    pole = math.exp(-2 * math.pi * bandwidth * step)
    filtered: FloatArray = lfilter([1 - pole], [1, -pole], d, zi=[pole * d[0]])[0]
    return filtered


def dissipative(force: FloatArray, v: FloatArray) -> FloatArray:
    """`force` kept to what a semi-active damper moving at `v` gives (floor 0)."""
    return np.where(v > 0, np.maximum(force, 0.0), np.where(v < 0, np.minimum(force, 0.0), 0.0))


def fit(demand: FloatArray, force: FloatArray, v: FloatArray, step: float) -> dict[str, Tracking]:
    """The delay and bandwidth of each direction ("extension", "compression") that make the clipped
    `demand` (N) into the `force` (N) acting at velocity `v` (m/s), sampled every `step` (s)."""
    demand, force, v = (np.asarray(x, dtype=float) for x in (demand, force, v))
    samples = {"extension": np.flatnonzero(v > EXT_V), "compression": np.flatnonzero(v < -EXT_V)}
    best: dict[str, tuple[float, int, float]] = {k: (math.inf, 0, math.inf) for k in samples}
    for bw in BANDWIDTHS:
        # a delay commutes with the lag: lag once, then delay by indexing (the start's value held)
        lag = lagged(demand, step, 0, bw)
        for n in range(int(round(MAX_DELAY / step)) + 1):
            for name, idx in samples.items():
                model = dissipative(lag[np.maximum(idx - n, 0)], v[idx])
                err = float(np.sqrt(np.mean((model - force[idx]) ** 2)))
                if err < best[name][0]:
                    best[name] = (err, n, bw)
    return {name: Tracking(delay=n * step, bandwidth=bw, fit_error_rms=err,
                           error_rms=float(np.sqrt(np.mean((force[idx] - demand[idx]) ** 2))))
            for (name, idx), (err, n, bw) in zip(samples.items(), best.values(), strict=True)}
