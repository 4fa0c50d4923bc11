"""The three-axle full truck (FullTruck.fmu) as a user meets it: a valid FMU whose free response rings
at the natural frequencies of a linear model written independently of its equations, that is the
quarter truck at every corner when all six tyres see the same road, that rolls on the Belgian block's
left and right tracks, and that runs with six damper FMU instances."""

import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

from damper_tools import cosim, full_truck
from damper_tools.fmu import FmuUnit, Slave

FMUTOOL = Path(sys.executable).parent / "fmutool"
STEP = 1e-3


def test_the_full_truck_fmu_is_valid(full_truck_fmu):
    assert validate_fmu(str(full_truck_fmu)) == []
    md = read_model_description(str(full_truck_fmu), validate=True)
    assert md.coSimulation.modelIdentifier == "FullTruck"
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    assert inputs == [f"{c}.{q}" for c in full_truck.CORNERS for q in ("z_road", "v_road", "F_damper")]
    with zipfile.ZipFile(full_truck_fmu) as z:
        assert {"binaries/linux64/FullTruck.so", "documentation/index.html"} <= set(z.namelist())
        assert "I_φ φ̈" in z.read("documentation/index.html").decode()
    proc = subprocess.run([str(FMUTOOL), "-input", str(full_truck_fmu), "-check"], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0 and "This FMU seems to be compliant with FMI-2.0" in proc.stdout + proc.stderr


def level_road(n):
    zero = np.zeros(n + 1)
    return {c: (zero, zero) for c in full_truck.CORNERS}


def crossing_frequency(t, x):
    """Frequency (Hz) from the zero crossings of x, interpolated linearly between samples."""
    i = np.where(np.sign(x[:-1]) * np.sign(x[1:]) < 0)[0]
    times = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return (len(times) - 1) / (2 * (times[-1] - times[0]))


def test_the_free_response_rings_at_the_linear_models_frequencies(full_truck_fmu):
    """Heave, pitch and roll displaced from rest, undamped: each rings at its mode of the 9-DOF
    linear model (damper_tools.full_truck.linear_model, written from the potential energy, not from
    the FMU's force sums). Zero crossings over 12 s resolve a period to ~1e-5 s; the axles' 12 Hz
    modes ride on the body's angle at 1e-3 of it; 0.2 % fails a 0.5 % error of a stiffness."""
    p = full_truck.parameters(FmuUnit.load(full_truck_fmu))
    freqs = full_truck.natural_frequencies(p)
    roll_hz, pitch_hz, heave_hz = freqs[:3]
    assert (roll_hz, pitch_hz, heave_hz) == pytest.approx((1.025, 1.338, 1.502), abs=1e-3)
    assert np.all(freqs[3:] > 12.0)  # the axles' bounce and roll
    n = 12_000
    for start, output, expected in (("z_body_start", "z_body", heave_hz), ("pitch_start", "pitch", pitch_hz),
                                    ("roll_start", "roll", roll_hz)):
        res = full_truck.simulate(level_road(n), STEP, n, {"damper_mode": cosim.MODE_PASSIVE, "c_passive": 0.0,
                                                           start: 0.01}, full_truck_fmu=full_truck_fmu)
        assert crossing_frequency(res["time"], res[output]) == pytest.approx(expected, rel=2e-3), output
        others = {"z_body", "pitch", "roll"} - {output}
        assert all(np.max(np.abs(res[o])) < 1e-9 for o in others), "heave, pitch and roll are decoupled"


def test_static_loads_are_the_quarter_trucks_and_follow_the_centre_of_mass():
    xml = Path(__file__).resolve().parents[2] / "crates" / "full_truck" / "modelDescription.xml"
    md = read_model_description(str(xml))
    start = {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter"}
    loads = full_truck.static_tyre_loads(start)
    # the centre of mass at the axles' centroid: every tyre carries a sixth of the body and half its axle
    assert all(w == pytest.approx((26700 / 6 + 840 / 2) * 9.81, rel=1e-12) for w in loads.values())
    # moved 0.5 m forward, the front tyres carry more: by the moment balance of a rigid body on three
    # equally stiff axles, the load on axle i is W/3 + W e x_i / sum(x_i^2) (x from the centroid)
    moved = {**start, "x_cg": start["x_cg"] - 0.5}
    x = np.array([0.0, 3.8, 5.15])
    x = x.mean() - x
    body = 26700 * 9.81
    expected = body / 3 + body * 0.5 * x / np.sum(x ** 2)
    got = full_truck.static_tyre_loads(moved)
    for i, axle in enumerate(full_truck.AXLES):
        assert 2 * got[f"{axle}_left"] == pytest.approx(expected[i] + 840 * 9.81, rel=1e-9)


def test_the_same_road_under_every_tyre_is_the_quarter_truck_at_every_corner(fmus, full_truck_fmu):
    """All six tyres on one road at once, six damper FMU instances: the body only heaves, and every
    corner is QuarterTruck.fmu with its damper (Table 1 at each corner, the centre of mass at the
    axles' centroid), to rounding."""
    n = 2000
    t = STEP * np.arange(n + 1)
    z = 0.01 * np.sin(2 * np.pi * 1.7 * t) * np.clip(t / 0.3, 0, 1) + 0.004 * np.sin(2 * np.pi * 11 * t)
    v = np.append(np.diff(z) / STEP, 0.0)
    quarter = cosim.simulate_one(z, v, STEP, n, cosim.MODE_EXTERNAL, **fmus)
    full = full_truck.simulate({c: (z, v) for c in full_truck.CORNERS}, STEP, n, full_truck_fmu=full_truck_fmu,
                               damper_fmu=fmus["damper_fmu"])
    for name in ("F_tyre", "a_body", "x_damper", "F_demand", "v_damper"):
        scale = np.std(quarter[name])
        assert scale > 0
        for c in full_truck.CORNERS:
            assert np.max(np.abs(full[f"{c}.{name}"] - quarter[name])) < 1e-9 * scale, (c, name)
    assert np.max(np.abs(full["front_left.damper.F_damper"] - quarter["damper.F_damper"])) < 1e-6
    assert np.max(np.abs(full["pitch"])) < 1e-12 and np.max(np.abs(full["roll"])) < 1e-12


def test_the_belgian_block_rolls_and_pitches_the_truck(full_truck_fmu):
    """The measured surface under the left and right tyres (0.925 m either side of the centre line):
    two different tracks, each met by the drive axles later; the body rolls and pitches on them."""
    p = full_truck.parameters(FmuUnit.load(full_truck_fmu))
    speed = 3.0
    wheels, n, window = full_truck.crg_wheel_roads(speed, STEP, full_truck.axle_positions(p), p["tyre_track"])
    t = STEP * np.arange(n + 1)
    left, right = wheels["front_left"][0], wheels["front_right"][0]
    assert np.std(left[window]) > 5e-3 and np.corrcoef(left[window], right[window])[0, 1] < 0.9
    delay = p["drive2.x_axle"] / speed
    later = t >= delay
    rear = wheels["drive2_left"][0]
    assert np.max(np.abs(rear[later] - np.interp(t[later] - delay, t, left))) < 0.02 * np.std(left[window])
    assert np.all(rear[:int(delay / STEP) - 1] == 0.0), "the rear tyres stand on level road until they get there"
    res = full_truck.simulate(wheels, STEP, n, {"damper_mode": cosim.MODE_IDEAL}, full_truck_fmu=full_truck_fmu)
    m = full_truck.metrics(res, window, full_truck.static_tyre_loads(p))
    assert m["a_roll_rms"] > 0.1 and m["a_pitch_rms"] > 0.1 and 0.05 < m["DLC"] < m["DLC_max"] < 0.5


def test_a_bad_parameter_is_refused_by_name(full_truck_fmu):
    unit = FmuUnit.load(full_truck_fmu)
    truck = Slave(unit, "light_axle", echo=False)
    try:
        with pytest.raises(FMICallException):
            truck.initialize(0.0, 1.0, **{"drive1.J_axle": 0.01})
        assert any("J_axle" in text for _, _, text in truck.errors()), truck.messages
    finally:
        truck.fmu.freeInstance()


def test_the_benefit_study_compares_with_the_best_riding_passive_damper(fmus, full_truck_fmu):
    """A short run of the study's machinery: its reference is the passive damper of least seat Wk RMS
    (benefit 0 there), and each row's DLC change is against that damper's DLC."""
    paths = {"full_truck": full_truck_fmu, "damper": fmus["damper_fmu"]}
    rows = full_truck.run_case(full_truck.Case("minor", 14.0), paths, duration=1.0, c_passive=(10e3, 40e3),
                               laws=((48e3, 0.2, 0.0),))
    rows = full_truck.with_benefits(rows)
    assert len(rows) == 2 + len(full_truck.SETTINGS) + 2
    passive = [r for r in rows if r["passive"]]
    best = min(passive, key=lambda r: r["a_seat_wk_rms"])
    assert all(r["reference"] == best["setting"] for r in rows)
    assert best["benefit"] == 0.0 and best["dlc_change"] == 0.0
    for r in rows:
        assert r["benefit"] == pytest.approx(1 - r["a_seat_wk_rms"] / best["a_seat_wk_rms"])
        assert r["dlc_change"] == pytest.approx(r["DLC"] / best["DLC"] - 1)
    text = full_truck.table(rows)
    assert "(best passive)" in text and "FMU, paper's law" in text
