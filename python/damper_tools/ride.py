"""Ride comfort and road damage of a vehicle record: the ISO 2631-1 frequency weighting Wk of a vertical
acceleration, and the fourth-power road stress of a tyre force.

    >>> import numpy as np
    >>> t = np.arange(0, 20, 1e-3)
    >>> round(wk_rms(np.sin(2 * np.pi * 8.0 * t), 1e-3) / (1 / np.sqrt(2)), 3)   # Wk(8 Hz) = 1.036
    1.036

The weighting is applied in the frequency domain (the record's FFT times |Wk(jw)|), which for an RMS is
exact at every frequency of the record; a digital filter (bilinear transform) would warp the 100 Hz
band limit at the 1 kHz rates used here. scipy has no ISO 2631 weighting, and the packages that do are
not maintained, so it is written here from the standard's transfer functions (ISO 2631-1:1997,
Annex A: band limiting, acceleration-velocity transition and upward step).
"""

import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from damper_tools import FloatArray

# ISO 2631-1:1997 Table A.1, weighting Wk (vertical, seated): Hz and quality factors
WK_F1, WK_F2 = 0.4, 100.0  # band limits (2nd-order Butterworth high- and low-pass)
WK_F3, WK_F4, WK_Q4 = 12.5, 12.5, 0.63  # acceleration-velocity transition
WK_F5, WK_Q5, WK_F6, WK_Q6 = 2.37, 0.91, 3.35, 0.91  # upward step


def wk_gain(f: npt.ArrayLike) -> FloatArray:
    """|Wk| at the frequencies `f` (Hz): ISO 2631-1's band limiting x transition x upward step."""
    s = 2j * np.pi * np.asarray(f, dtype=float)
    w = [2 * np.pi * x for x in (WK_F1, WK_F2, WK_F3, WK_F4, WK_F5, WK_F6)]
    q12 = 1 / math.sqrt(2)
    high = s**2 / (s**2 + w[0] / q12 * s + w[0] ** 2)
    low = w[1] ** 2 / (s**2 + w[1] / q12 * s + w[1] ** 2)
    transition = (1 + s / w[2]) / (1 + s / (WK_Q4 * w[3]) + (s / w[3]) ** 2)
    step = (1 + s / (WK_Q5 * w[4]) + (s / w[4]) ** 2) / (1 + s / (WK_Q6 * w[5]) + (s / w[5]) ** 2) * (w[4] / w[5]) ** 2
    return np.abs(high * low * transition * step)


def wk_rms(a: FloatArray | Sequence[float], step: float) -> float:
    """The Wk-weighted RMS (m/s²) of a vertical acceleration `a` (m/s²) sampled every `step` (s)."""
    a = np.asarray(a, dtype=float)
    spectrum = np.fft.rfft(a - a.mean())
    weighted = np.fft.irfft(spectrum * wk_gain(np.fft.rfftfreq(a.size, step)), n=a.size)
    return float(np.sqrt(np.mean(weighted**2)))


def road_stress_factor(f_tyre: FloatArray | Sequence[float], static_load: float) -> float:
    """The fourth-power road stress of a dynamic tyre force `f_tyre` (N, compression positive) on a
    wheel of `static_load` (N): mean((W + F)⁴)/W⁴, the damage it does relative to the static load
    (Cebon's fourth-power law; a tyre that lifts off gives no force). A Gaussian load of dynamic
    load coefficient DLC gives 1 + 6 DLC² + 3 DLC⁴."""
    total = np.maximum(static_load + np.asarray(f_tyre, dtype=float), 0.0)
    return float(np.mean((total / static_load) ** 4))
