"""The quarter-truck FMU on its own: a valid FMU, the natural frequencies of Table 1 from a free
response, and the three damper modes."""

import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from damper_tools import cosim, hil_scenarios

FMUTOOL = Path(sys.executable).parent / "fmutool"

STEP = 1e-3  # s
FREE_RESPONSE = 2 ** 15 * STEP  # 32.8 s
ZERO_PAD = 16
# Body 1.50 Hz and wheel hop 12.18 Hz: the eigenvalues of the undamped two-mass model with Table 1
# (docs/physics.md §6.4). The measured peak of a Hann-windowed, 16x zero-padded FFT of a 32.8 s free
# response (bin 0.03 Hz, interpolated grid 0.002 Hz) lies within ~0.002 Hz of the true frequency;
# RK4 with 0.25 ms steps adds a phase error below 1e-8. 0.3 % (0.005 Hz at the body mode) leaves room
# for the grid and the leakage of the other mode, and fails for any error in a mass or stiffness
# (1 % in k_tyre moves the wheel hop by 0.4 %).
FREQ_REL_TOL = 0.003
PAPER_BODY_HZ, PAPER_WHEEL_HOP_HZ = 1.50, 12.2  # docs/physics.md §6.4, from Table 1


def test_truck_fmu_is_valid(truck_fmu):
    assert validate_fmu(str(truck_fmu)) == []
    md = read_model_description(str(truck_fmu), validate=True)
    assert md.coSimulation.modelIdentifier == "QuarterTruck"
    causality = {v.name: v.causality for v in md.modelVariables}
    assert [n for n, c in causality.items() if c == "input"] == ["z_road", "v_road", "F_damper"]
    with zipfile.ZipFile(truck_fmu) as z:
        names = set(z.namelist())
        assert {"modelDescription.xml", "binaries/linux64/QuarterTruck.so", "documentation/index.html"} <= names
        assert "<code>damper_mode</code>" in z.read("documentation/index.html").decode()
    proc = subprocess.run([str(FMUTOOL), "-input", str(truck_fmu), "-check"], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0 and "This FMU seems to be compliant with FMI-2.0" in proc.stdout + proc.stderr, \
        proc.stdout + proc.stderr


def spectral_peak(x, step, f_lo, f_hi):
    x = (x - np.mean(x)) * np.hanning(x.size)
    spec = np.abs(np.fft.rfft(x, ZERO_PAD * x.size))
    f = np.fft.rfftfreq(ZERO_PAD * x.size, step)
    m = (f >= f_lo) & (f <= f_hi)
    return f[m][np.argmax(spec[m])]


def free_response(fmus, **start):
    n = int(round(FREE_RESPONSE / STEP))
    zero = np.zeros(n + 1)
    return cosim.simulate_one(zero, zero, STEP, n, cosim.MODE_PASSIVE, {"c_passive": 0.0, **start}, **fmus)


def test_natural_frequencies_from_a_free_response(fmus):
    consts = hil_scenarios.truck_constants(fmus["truck_fmu"])
    assert (consts["m_body"], consts["m_axle"], consts["k_susp"], consts["k_tyre"]) == (4450.0, 420.0, 0.5e6, 1.95e6)
    body_hz, hop_hz = hil_scenarios.natural_frequencies(consts)
    assert body_hz == pytest.approx(PAPER_BODY_HZ, abs=0.01) and hop_hz == pytest.approx(PAPER_WHEEL_HOP_HZ, abs=0.05)

    # the body lifted by 10 mm: the body mode dominates z_body; the axle lifted: wheel hop dominates z_axle
    res = free_response(fmus, z_body_start=0.01)
    assert spectral_peak(res["z_body"], STEP, 0.5, 5.0) == pytest.approx(body_hz, rel=FREQ_REL_TOL)
    res = free_response(fmus, z_axle_start=0.01)
    assert spectral_peak(res["z_axle"], STEP, 5.0, 30.0) == pytest.approx(hop_hz, rel=FREQ_REL_TOL)
    # undamped: the amplitude does not decay (energy kept to 0.1 % over 33 s)
    first, last = np.abs(res["z_axle"][:2000]).max(), np.abs(res["z_axle"][-2000:]).max()
    assert last == pytest.approx(first, rel=1e-3)


def test_damper_modes(fmus):
    """Mode 1 applies the clipped MSD demand itself, mode 2 the passive force, mode 0 the input."""
    n = 2000
    t = STEP * np.arange(n + 1)
    z = 0.01 * np.sin(2 * np.pi * 2.0 * t) * np.clip(t / 0.2, 0, 1)
    v = np.append(np.diff(z) / STEP, 0.0)
    ideal = cosim.simulate_one(z, v, STEP, n, cosim.MODE_IDEAL, **fmus)
    assert np.array_equal(ideal["F_suspension"], ideal["F_demand"])
    assert np.all(ideal["F_demand"] * ideal["v_damper"] >= 0)  # dissipative only (clipped)
    # ... and clipped to 0 part of the time while the damper moves (skyhook part against V_rel)
    assert ((ideal["F_demand"] == 0) & (ideal["v_damper"] != 0)).sum() > 20
    passive = cosim.simulate_one(z, v, STEP, n, cosim.MODE_PASSIVE, {"c_passive": 12e3}, **fmus)
    assert np.allclose(passive["F_suspension"], 12e3 * passive["v_damper"], rtol=1e-12, atol=1e-9)
    # mode 0 (Jacobi coupling): the force reported at t_k+1 is the damper's force of t_k, held over the step
    fmu = cosim.simulate_one(z, v, STEP, n, cosim.MODE_EXTERNAL, **fmus)
    assert np.array_equal(fmu["F_suspension"][1:], fmu["damper.F_damper"][:-1])
