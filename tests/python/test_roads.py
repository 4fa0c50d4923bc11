"""Road inputs (damper-roads): ISO 8608 profiles have their class's spectrum, road CSV files read
back exactly and fail loudly, and the OpenCRG reader returns the documented Belgian-block geometry."""

import shutil

import numpy as np
import pytest

from damper_tools import roads

CRG = roads.Path(__file__).resolve().parents[2] / "data" / "roads" / "belgian_block.crg"

PROFILE_LENGTH = 2000.0  # m: long enough for ~19 Welch segments of 204.8 m
SEEDS = (1, 2, 3)
# The generator draws random phases with deterministic amplitudes, so a profile's spectrum is exact
# and only the Welch estimate scatters (measured: within 0.6 % over 6 seeds and 2 km). ±10 % still
# catches every normalisation slip (one- vs two-sided PSD: factor 2; amplitude vs variance: factor 2
# and more; a wrong class: factor 4).
GD0_REL_TOL = 0.10
W_TOL = 0.1  # exponent of a free log-log fit, nominal 2
SPEED = 14.0  # m/s
STEP = 1e-3  # s


def test_named_roads_and_classes():
    assert roads.gd0_of("motorway") == 16e-6 == roads.gd0_of("A")
    assert roads.gd0_of("major") == 64e-6 == roads.gd0_of("B")
    assert roads.gd0_of("minor") == 128e-6  # B/C boundary, an assumption (no value in the paper)
    assert roads.gd0_of("C") == 256e-6 and roads.gd0_of("D") == 1024e-6
    assert roads.gd0_of("h") == pytest.approx(16e-6 * 4 ** 7)
    assert roads.gd0_of(3e-5) == 3e-5 and roads.gd0_of("3e-5") == 3e-5
    with pytest.raises(ValueError, match="unknown road"):
        roads.gd0_of("cobbles")
    assert roads.iso_class_of(128e-6) == "B/C" and roads.iso_class_of(100e-6) == "B"
    assert roads.iso_class_of(16e-6) == "A" and roads.iso_class_of(300e-6) == "C"


@pytest.mark.parametrize("road", ["motorway", "major", "minor", "C"])
def test_generated_profile_has_its_class_spectrum(road):
    gd0 = roads.gd0_of(road)
    for seed in SEEDS:
        x, z = roads.generate_profile(PROFILE_LENGTH, gd0, seed)
        assert x[1] - x[0] == pytest.approx(roads.DX) and x[-1] >= PROFILE_LENGTH
        n, g = roads.profile_psd(z, roads.DX)
        fitted, w = roads.fit_gd0(n, g)
        assert fitted == pytest.approx(gd0, rel=GD0_REL_TOL), (road, seed, fitted / gd0)
        assert w == pytest.approx(roads.WAVINESS, abs=W_TOL)
    # the variance is the integral of G_d over the generation band
    n = np.linspace(roads.N_MIN, roads.N_MAX, 200001)
    expected_std = np.sqrt(np.trapezoid(roads.displacement_psd(n, gd0), n))
    assert np.std(z) == pytest.approx(expected_std, rel=0.1)


def test_seed_makes_the_profile_repeatable():
    a = roads.generate_profile(100.0, 64e-6, seed=7)[1]
    assert np.array_equal(a, roads.generate_profile(100.0, 64e-6, seed=7)[1])
    assert not np.array_equal(a, roads.generate_profile(100.0, 64e-6, seed=8)[1])


def test_time_series_at_a_speed_keeps_the_spatial_spectrum():
    case = roads.road_case("minor", SPEED, duration=120.0, seed=4, step=STEP, fade_in=1.0)
    assert case.t.size == 120001 and case.t[1] == STEP
    # starts level, and v_road takes z_road exactly to the next sample
    assert case.z_road[0] == case.z_road[1] == case.v_road[0] == 0.0
    assert np.allclose(case.z_road[:-1] + case.v_road[:-1] * STEP, case.z_road[1:], rtol=0, atol=1e-15)
    n, g = roads.profile_psd(case.z_road[2000:], SPEED * STEP, segment_length=100.0)
    fitted, _ = roads.fit_gd0(n, g, band=(0.1, 2.0))
    assert fitted == pytest.approx(128e-6, rel=GD0_REL_TOL)
    with pytest.raises(ValueError, match="covers"):
        roads.time_series(*roads.generate_profile(10.0, 1e-5, 1), SPEED, STEP, 1000)


def test_csv_round_trip_is_exact(work_dir):
    case = roads.road_case("major", 20.0, duration=2.0, seed=9, step=STEP)
    path = roads.write_time_csv(work_dir / "major.csv", case)
    lines = path.read_text().splitlines()
    assert lines[0].startswith("# road: major road") and "seed=9" in lines[0] and "speed=20 m/s" in lines[0]
    assert "G_d(n0)=6.4e-05" in lines[0]
    assert lines[1] == "time,z_road,v_road"
    data, comments = roads.read_road_csv(path)
    assert data.dtype.names == ("time", "z_road", "v_road")
    for name, ref in (("time", case.t), ("z_road", case.z_road), ("v_road", case.v_road)):
        assert np.array_equal(data[name], ref)
    meta = roads.parse_header_comment(comments[0])
    assert float(meta["speed"]) == 20.0 and int(meta["seed"]) == 9


def test_csv_errors_name_file_line_and_column(work_dir):
    good = "# road: test\ntime,z_road,v_road\n0.0,0.0,0.0\n0.001,1e-5,0.01\n"
    cases = {
        "not a number": (good + "0.002,abc,0.0\n", ":5:2 (z_road): not a number: 'abc'"),
        "nan": (good + "0.002,0.0,nan\n", ":5:3 (v_road): not a finite number"),
        "too few": (good + "0.002,0.0\n", ":5: expected 3 values (time, z_road, v_road), found 2"),
        "too many": (good + "0.002,0.0,0.0,1\n", ":5: expected 3 values"),
        "empty line": (good + "\n0.003,0,0\n", ":5: expected 3 values"),
        "time back": (good + "0.0005,0.0,0.0\n", ":5:1 (time): 0.0005 does not increase"),
        "no rows": ("# road: test\ntime,z_road,v_road\n", "no data rows"),
        "no header": ("# only a comment\n", "no header line"),
    }
    for name, (text, expected) in cases.items():
        path = work_dir / f"{name.replace(' ', '_')}.csv"
        path.write_text(text)
        with pytest.raises(roads.RoadFileError) as err:
            roads.read_road_csv(path)
        assert str(path) in str(err.value) and expected in str(err.value), (name, str(err.value))


def test_opencrg_belgian_block_geometry():
    surface = roads.read_crg(CRG)
    assert surface.z.shape == (1001, 341)
    assert surface.u[0] == pytest.approx(730.0) and surface.u[-1] == pytest.approx(740.0)
    assert surface.u[1] - surface.u[0] == pytest.approx(0.01)
    assert surface.v[0] == pytest.approx(-1.70) and surface.v[-1] == pytest.approx(1.70)
    assert np.isnan(surface.phi[0]) and surface.phi[1] == pytest.approx(2.6528, abs=1e-4)
    assert surface.phi[-1] == pytest.approx(2.3053, abs=1e-4)
    nan = np.isnan(surface.z)
    assert 0.06 < nan.mean() < 0.07  # 6.5 % of the grid, outside the measured area
    assert not nan[:, surface.v > -1.37 + 1e-9].any()
    assert "Heidestrecke" in surface.comment
    # absolute elevation about 2.1 m above a local datum
    assert 1.9 < np.nanmean(surface.z) < 2.3


def test_opencrg_track_is_detrended_and_filtered():
    surface = roads.read_crg(CRG)
    track = roads.crg_track(surface, v=0.5)
    assert track.v == pytest.approx(0.5) and track.x[0] == 0.0 and track.x[-1] == pytest.approx(10.0)
    assert abs(np.mean(track.z)) < 1e-9 and abs(np.polyfit(track.x, track.z, 1)[0]) < 1e-9
    assert 0.010 < np.std(track.z) < 0.030 and 0.05 < np.ptp(track.z) < 0.12  # ±50 mm undulations
    smooth = roads.crg_track(surface, v=0.5, envelope=0.2)
    assert np.std(np.diff(smooth.z)) < 0.5 * np.std(np.diff(track.z))  # texture removed
    # a section in the unmeasured area is refused, one outside the surface too
    with pytest.raises(roads.CrgError, match=r"v = -1.6 m: 99\d of 1001 samples are NaN"):
        roads.crg_track(surface, v=-1.6)
    with pytest.raises(roads.CrgError, match="outside the surface"):
        roads.crg_track(surface, v=2.0)


def test_opencrg_truncated_or_foreign_file_fails_clearly(work_dir):
    data = CRG.read_bytes()
    truncated = work_dir / "truncated.crg"
    truncated.write_bytes(data[: len(data) // 2])
    with pytest.raises(roads.CrgError) as err:
        roads.read_crg(truncated)
    message = str(err.value)
    assert str(truncated) in message and "truncated" in message and "1001 records" in message
    assert "u stops at" in message

    header_only = work_dir / "header_only.crg"
    header_only.write_bytes(data[: data.index(b"$$$$") + 73])
    with pytest.raises(roads.CrgError, match="found 0 bytes"):
        roads.read_crg(header_only)

    foreign = work_dir / "foreign.crg"
    shutil.copy(__file__, foreign)
    with pytest.raises(roads.CrgError, match="not an OpenCRG file"):
        roads.read_crg(foreign)
