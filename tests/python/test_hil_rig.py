"""The HiL rig as a model (damper_tools.hil_rig, damper-hil-rig): an ideal rig changes nothing,
and its parts do what their parameters say."""

import math

import numpy as np
import pytest

from damper_tools import hil_rig

DURATION = 3.0  # s after the settling time: enough to compare runs


def test_ideal_rig_reproduces_the_direct_coupling(fmus):
    direct = hil_rig.run(None, duration=DURATION, **fmus)
    ideal = hil_rig.run(hil_rig.RigParameters(), duration=DURATION, **fmus)
    for name in ("v_damper", "F_demand", "a_body", "F_tyre", "damper.F_damper", "F_logged"):
        assert np.array_equal(direct[name], ideal[name]), name


def test_rig_latency_raises_the_force_peak(fmus):
    """A rig delays the damper's force on the truck: the force spectrum's wheel-hop peak moves up
    (a lagging damper force acts partly as a spring)."""
    base = hil_rig.metrics(hil_rig.run(None, duration=8.0, **fmus))
    rig = hil_rig.RigParameters(f_load_cell=500.0, load_cell_delay=3e-3)
    delayed = hil_rig.metrics(hil_rig.run(rig, duration=8.0, **fmus))
    assert delayed["peak_Hz"] > base["peak_Hz"] + 2.0


def test_rig_parts():
    step = 1e-3
    # pure delay of 2.5 steps: linear interpolation between samples
    d = hil_rig._Delay(2.5e-3, step)
    out = [d(float(k)) for k in range(8)]
    assert out[5:] == pytest.approx([2.5, 3.5, 4.5])
    # the actuator: unit static gain, and its -3 dB frequency where the parameters put it
    f_act = 40.0
    act = hil_rig._SecondOrder(f_act, 1 / math.sqrt(2), step, "zoh")
    act(0.0)
    ys = [act(1.0) for _ in range(400)]
    assert ys[-1] == pytest.approx(1.0, abs=1e-9)
    t = step * np.arange(4000)
    for f, gain in ((f_act, 1 / math.sqrt(2)), (f_act / 10, 1.0)):
        act = hil_rig._SecondOrder(f_act, 1 / math.sqrt(2), step, "zoh")
        y = np.array([act(v) for v in np.sin(2 * np.pi * f * t)])
        assert np.abs(y[2000:]).max() == pytest.approx(gain, rel=0.03)
    # an infinite bandwidth and a zero delay pass through
    assert hil_rig._SecondOrder(math.inf, 0.7, step, "zoh")(3.0) == 3.0
    assert hil_rig._Delay(0.0, step)(3.0) == 3.0
    with pytest.raises(ValueError):
        hil_rig.Rig(hil_rig.RigParameters(rt_period=1.5e-3), step)
