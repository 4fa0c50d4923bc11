"""The sensors and the fine time step of the generated records (damper_tools.independent and
damper_tools.foreign share them): each sensor's noise and quantum, and the fine step the truth is
computed on, a whole number of which makes a record's sample."""

import numpy as np

from damper_tools import FloatArray

FINE_STEP = 1e-4  # s: communication step of the truth
# Sensor (noise standard deviation, quantum), SI.
SENSORS = {"F_damper": (20.0, 1.0), "v_damper": (1e-4, 1e-5)}


def quantise(x: FloatArray, quantum: float) -> FloatArray:
    return np.round(x / quantum) * quantum


def steps_per_sample(rate: float) -> int:
    """Fine steps per record sample at `rate` (Hz); an error where the rate does not divide them."""
    m = round(1.0 / (rate * FINE_STEP))
    if abs(m * FINE_STEP * rate - 1) > 1e-9:
        raise ValueError(f"rate {rate} Hz is not a whole number of {FINE_STEP:g} s steps")
    return m
