"""Dyno records of passive dampers from an independent model (damper_tools.dyno), checked as a user
would check a rig's files: the same seed gives the same bytes; a constant-velocity stretch gives the
force the valve law gives by hand; the gas force at rest is -p_r A_r and grows as T/T_ref; only the
end-stop record goes past the bump rubbers; the datasheet TOML has the template's sections; the CSV
has the documented comment lines, header and units.

The records here are the short (`quick`) programs; the whole suite takes about 15 s on 2 cores.
"""

import json
import math
import tomllib
import xml.etree.ElementTree as ET
from datetime import datetime

import numpy as np
import pytest
from scipy.optimize import brentq

from damper_tools import REPO, dyno

P_ATM = 101325.0
# The parameters the brief lists, named as in modelDescription.xml.
FMU_NAMES = ("D_piston D_rod L_half_stroke L_dead V_hose p_reservoir0 V_gas0 n_polytropic rho beta_oil air_fraction "
             "p_transition A_cv_max Cd_cv p_cv_crack p_cv_full A_cv_leak G_bleed_reb A_bleed_reb p_open_reb k_open_reb "
             "A_open_reb G_bleed_comp A_bleed_comp p_open_comp k_open_comp A_open_comp Cd_passive F_coulomb v_friction "
             "k1_mount k3_mount x_end_stop k_end_stop T_ref visc_temp_coeff").split()
KNOWN_UNITS = {"s", "ms", "us", "m", "cm", "mm", "um", "in", "m/s", "cm/s", "mm/s", "in/s", "N", "daN", "kN", "lbf",
               "Pa", "kPa", "MPa", "mbar", "bar", "psi", "A", "mA", "K", "degC", "degF"}


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    """Short records of a few dampers and scenarios, written once for the module."""
    out = tmp_path_factory.mktemp("dyno")
    made = {}
    for size, seed, scenario in (("small", 5, "unchanged"), ("truck", 2, "calibration"), ("car", 4, "end_stop"),
                                 ("car", 4, "heated")):
        made[(size, seed, scenario)] = dyno.make_records(size, seed, scenario, out / f"{size}_{seed}", quick=True)
    return made


def truth_of(csv_path):
    return json.loads(csv_path.with_suffix(".json").read_text())


def read_csv(path):
    """The comment lines, the header cells and the data columns (text) of a record."""
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    header = body[0].split(",")
    rows = [line.split(",") for line in body[1:]]
    return comments, header, {h: [r[i] for r in rows] for i, h in enumerate(header)}


# --------------------------------------------------------------------------- the valve law by hand

def orifice(p, cd, area, dp):
    """physics.md §3.3: Q = Cd A sqrt(2/rho) dp / (dp^2 + p_transition^2)^(1/4)."""
    return cd * area * math.sqrt(2 / p["rho"]) * dp / (dp * dp + p["p_transition"] ** 2) ** 0.25


def check_valve(p, dp):
    u = min(max((dp - p["p_cv_crack"]) / (p["p_cv_full"] - p["p_cv_crack"]), 0.0), 1.0)
    return orifice(p, p["Cd_cv"], p["A_cv_leak"] + p["A_cv_max"] * (3 * u * u - 2 * u ** 3), dp)


def passive_valve(p, which, dp, mu_r):
    """physics.md §3.8: laminar bleed, orifice bleed and the blow-off on its rounded ramp s(u)."""
    def ramp(w):
        return 0.0 if w <= -0.05 else ((w + 0.05) ** 2 / 0.2 if w < 0.05 else w)
    u = p[f"k_open_{which}"] * (dp - p[f"p_open_{which}"]) / p[f"A_open_{which}"]
    opening = p[f"A_open_{which}"] * (ramp(u) - ramp(u - 1)) if dp > 0 else 0.0
    area = p[f"A_bleed_{which}"] + opening
    return p[f"G_bleed_{which}"] * dp / mu_r + orifice(p, p["Cd_passive"], area, dp)


def drop(flow, q):
    """The pressure drop that passes the flow q."""
    return brentq(lambda d: flow(d) - q, 0.0, 1e9, xtol=1e-6, rtol=1e-13)


def steady_force_by_hand(p, v, x, temperature):
    """Extension: the rebound valve passes A_a v (CV1 leaks back), CV2 refills A_r v from the
    reservoir, F = dp A_a - p_B A_r + friction with p_B = p_r - dp_CV2. Compression: the compression
    valve passes A_r |v|, CV1 passes A_a |v| into the annulus, F = -(p_r + dp) A_r - dp_CV1 A_a +
    friction. The gas pressure at V_gas0 + A_r x and T/T_ref; the bleeds' viscosity exp(-b (T - T_ref))."""
    a_p, a_r = math.pi * p["D_piston"] ** 2 / 4, math.pi * p["D_rod"] ** 2 / 4
    a_a = a_p - a_r
    mu_r = math.exp(-p["visc_temp_coeff"] * (temperature - p["T_ref"]))
    p_r = ((p["p_reservoir0"] + P_ATM) * (p["V_gas0"] / (p["V_gas0"] + a_r * x)) ** p["n_polytropic"]
           * temperature / p["T_ref"] - P_ATM)
    friction = p["F_coulomb"] * math.tanh(v / p["v_friction"])
    if v > 0:
        dp = drop(lambda d: passive_valve(p, "reb", d, mu_r) - check_valve(p, -d), a_a * v)
        dp_cv2 = drop(lambda d: check_valve(p, d) - passive_valve(p, "comp", -d, mu_r), a_r * v)
        return dp * a_a - (p_r - dp_cv2) * a_r + friction
    dp_cv1 = drop(lambda d: check_valve(p, d) - passive_valve(p, "reb", -d, mu_r), -a_a * v)
    dp = drop(lambda d: passive_valve(p, "comp", d, mu_r) - check_valve(p, -d), -a_r * v)
    return -(p_r + dp) * a_r - dp_cv1 * a_a + friction


def stretches(p, v):
    """From the bottom of the free stroke, a constant-velocity stretch +v across it, then -v back."""
    length = p["x_end_stop"] - 0.006
    seg = dyno.Segment
    motion = dyno.Motion([seg("hold", 0.1), seg("move", 0.5, dx=-length), seg("hold", 0.1),
                          seg("cruise", 2 * length / v + 0.05, v=v, t_ramp=0.05), seg("hold", 0.1),
                          seg("cruise", 2 * length / v + 0.05, v=-v, t_ramp=0.05), seg("hold", 0.1)])
    # the last fine sample of each constant-velocity part
    ends = [motion.starts[k] + motion.segments[k].duration - 0.05 - dyno.FINE_STEP for k in (3, 5)]
    return motion, [int(round(t / dyno.FINE_STEP)) for t in ends]


# --------------------------------------------------------------------------- tests

def test_the_same_seed_gives_the_same_bytes(records, tmp_path):
    first = records[("small", 5, "unchanged")][0]
    again = dyno.make_records("small", 5, "unchanged", tmp_path / "again", quick=True)[0]
    other = dyno.make_records("small", 6, "unchanged", tmp_path / "other", quick=True)[0]
    assert again.read_bytes() == first.read_bytes()
    assert again.with_suffix(".json").read_bytes() == first.with_suffix(".json").read_bytes()
    assert (tmp_path / "again" / "small_5_datasheet.toml").read_bytes() == (
        first.parent / "small_5_datasheet.toml").read_bytes()
    assert other.read_bytes() != first.read_bytes()
    assert truth_of(other)["truth_parameters"] != truth_of(first)["truth_parameters"]


@pytest.mark.parametrize("size", dyno.SIZES)
@pytest.mark.parametrize("celsius", [20.0, 60.0])
def test_a_constant_velocity_stretch_gives_the_valve_law_by_hand(size, celsius):
    """With a gas volume 1000x the datasheet's (the gas pressure constant along the stroke) the
    dynamic model settles on the hand-solved valve law to a few ppm, warm oil included."""
    p = dyno.truth_parameters(size, 2)
    p["V_gas0"] *= 1e3
    temperature = celsius + dyno.T_ZERO
    for v in (0.1, 0.3):
        motion, ends = stretches(p, v)
        sim = dyno.simulate(p, motion, dyno.constant_temperature(temperature))
        for i in ends:
            hand = steady_force_by_hand(p, sim["v"][i], sim["x"][i], temperature)
            print(f"{size} {celsius:.0f} degC v {sim['v'][i]:+.2f} m/s: model {sim['F'][i]:10.3f} N, "
                  f"by hand {hand:10.3f} N")
            assert sim["F"][i] == pytest.approx(hand, rel=2e-5, abs=1e-3)


@pytest.mark.parametrize("size", dyno.SIZES)
def test_with_the_real_gas_spring_the_force_lags_the_hand_value_only_slightly(size):
    """With the datasheet's gas volume the gas pressure changes along the stroke and the force
    follows it with the oil column's lag: within 0.5 % of the hand value at the instant."""
    p = dyno.truth_parameters(size, 2)
    motion, ends = stretches(p, 0.3)
    sim = dyno.simulate(p, motion)
    for i in ends:
        hand = steady_force_by_hand(p, sim["v"][i], sim["x"][i], p["T_ref"])
        assert sim["F"][i] == pytest.approx(hand, rel=5e-3)
        assert abs(sim["F"][i] - hand) > 1e-6 * abs(hand)  # the gas spring is there


@pytest.mark.parametrize("size", dyno.SIZES)
def test_the_gas_force_at_rest_is_minus_p_r_times_the_rod_area_and_grows_as_t_over_t_ref(size):
    p = dyno.truth_parameters(size, 3)
    a_r = math.pi * p["D_rod"] ** 2 / 4
    rest = dyno.Motion([dyno.Segment("hold", 0.2)])
    forces = {}
    for celsius in (20.0, 70.0):
        temperature = celsius + dyno.T_ZERO
        sim = dyno.simulate(p, rest, dyno.constant_temperature(temperature))
        p_r = (p["p_reservoir0"] + P_ATM) * temperature / p["T_ref"] - P_ATM
        assert sim["F"] == pytest.approx(-p_r * a_r, rel=1e-9)
        forces[celsius] = sim["F"][-1]
    # the absolute pressure's force scales with the absolute temperature
    ratio = (forces[70.0] - P_ATM * a_r) / (forces[20.0] - P_ATM * a_r)
    assert ratio == pytest.approx((70.0 + dyno.T_ZERO) / p["T_ref"], rel=1e-9)


def test_released_gas_softens_the_oil_as_docs_physics_says():
    """physics.md §3.2 by hand, the numbers the Rust unit tests hold: oil with 2.5 % air saturated at
    5 bar (L = 0.09) is 3.491 MPa at 4.5 bar, where its air alone gives 97.57 MPa; above the band
    nothing is released."""
    p = {**dyno.truth_parameters("truck", 1), "air_fraction": 0.025, "n_polytropic": 1.4, "beta_oil": 1.5e9}
    air_only = dyno.Circuit(p)
    releasing = dyno.Circuit({**p, "gas_solubility": 0.09, "p_saturation": 5e5})
    assert releasing.bulk_modulus(4.5e5) / 1e6 == pytest.approx(3.491, abs=1e-3)
    assert air_only.bulk_modulus(4.5e5) / 1e6 == pytest.approx(97.57, abs=1e-2)
    for pressure in (5.1e5, 6e5, 50e5):
        assert releasing.bulk_modulus(pressure) == pytest.approx(air_only.bulk_modulus(pressure), rel=1e-15)


def test_the_fmu_releases_gas_as_the_independent_model_does(fmu):
    """The gas_release scenario's truth (the car damper of seed 1, quick program) through the FMU with
    the truth's parameters (fmu_settings), at 0.1 ms steps on the same continuous motion: the two
    implementations agree to 0.1 % of what the released gas changes (0.0007 N RMS of 25.9 N)."""
    from damper_tools.fmu import FmuUnit, Slave

    plan = dyno.plans("car", 1, "gas_release", quick=True)[0]
    motion = plan.motion
    truth = dyno.simulate(plan.params, motion)
    without = dyno.simulate(dyno.without_gas_release(plan.params), motion)
    slave = Slave(FmuUnit.load(fmu), "dyno")
    try:
        slave.initialize(0.0, motion.duration, **{k: v for k, v in plan.params.items()},
                         **dyno.fmu_settings(plan.params), rtol=1e-7, x_damper_start=motion.segments[0].x0)
        force = [slave.get(["F_damper"])[0]]
        x, v = truth["x"], truth["v"]
        for k in range(len(x) - 1):
            h = dyno.FINE_STEP
            slave.step(h, t=k * h, v_damper=v[k], a_damper=(v[k + 1] - v[k]) / h)
            force.append(slave.get(["F_damper"])[0])
    finally:
        slave.free()
    difference = np.sqrt(np.mean((np.array(force) - truth["F"]) ** 2))
    effect = np.sqrt(np.mean((without["F"] - truth["F"]) ** 2))
    print(f"released gas moves the force by {effect:.1f} N RMS; the FMU and the dyno model differ by "
          f"{difference:.4f} N")
    assert effect > 10.0
    assert difference < 1e-3 * effect


def test_the_measured_rest_force_is_the_gas_force(records):
    """The true force at rest is -p_r A_r at the record's starting temperature; the logger's force
    over the first rest (0.4 s) averages to it within its noise."""
    for paths in records.values():
        for path in paths:
            truth = truth_of(path)
            p = truth["truth_parameters"]
            a_r = math.pi * p["D_rod"] ** 2 / 4
            p_r = (p["p_reservoir0"] + P_ATM) * truth["temperature"]["start_K"] / p["T_ref"] - P_ATM
            assert truth["true_force"]["rest_N"] == pytest.approx(-p_r * a_r, rel=1e-9)
            _, header, cols = read_csv(path)
            unit = 1e3 if "F_damper [kN]" in header else 1.0
            force = np.array(cols[[h for h in header if h.startswith("F_damper")][0]], dtype=float) * unit
            n = int(0.4 * truth["sample_rate_hz"])
            sigma = truth["chain"]["force_sigma"] + truth["chain"]["force_quantum"]
            assert abs(force[:n].mean() - truth["true_force"]["rest_N"]) < 5 * sigma / math.sqrt(n) + 0.5


def test_only_the_end_stop_record_goes_beyond_the_bump_rubbers(records):
    for (_, _, scenario), paths in records.items():
        for path in paths:
            truth = truth_of(path)
            x_stop = truth["truth_parameters"]["x_end_stop"]
            _, _, cols = read_csv(path)
            x_measured = np.abs(np.array(cols["x_damper [mm]"], dtype=float)) * 1e-3
            x_true = max(truth["motion"]["max_x_m"], -truth["motion"]["min_x_m"])
            if scenario == "end_stop":
                beyond = max(truth["change"]["beyond_m"].values())
                assert 0.003 <= beyond <= 0.01
                assert x_true == pytest.approx(x_stop + beyond, abs=1e-6)
                assert x_measured.max() > x_stop + 0.0025
                # the bump rubber's force is in the true force: k (x - x0)^2 on top of the damping
                assert max(truth["true_force"]["max_N"], -truth["true_force"]["min_N"]) > (
                    0.9 * truth["truth_parameters"]["k_end_stop"] * beyond ** 2)
            else:
                assert x_true < x_stop - 0.9 * dyno.MARGIN
                assert x_measured.max() < x_stop


def test_the_scenarios_change_what_they_say_and_nothing_else():
    base = dyno.truth_parameters("car", 7)
    for scenario in dyno.SCENARIOS:
        for plan in dyno.plans("car", 7, scenario, quick=True):
            changed = {k for k in base if plan.params[k] != base[k]}
            if scenario == "gas":
                assert changed == {"p_reservoir0"}
                assert 0.15 <= abs(plan.change["factor"] - 1) <= 0.30
            elif scenario == "valve":
                assert changed == {plan.change["parameter"]} <= {"A_bleed_reb", "A_bleed_comp"}
                assert 0.5 <= plan.change["factor"] <= 0.8 or 1.3 <= plan.change["factor"] <= 2.0
            elif scenario == "gas_release":
                # the oil saturated at the truth's own pre-charge, a solubility in the drawn range
                assert not changed
                assert plan.params["p_saturation"] == base["p_reservoir0"]
                assert dyno.SOLUBILITY[0] <= plan.params["gas_solubility"] <= dyno.SOLUBILITY[1]
            elif scenario == "settings":
                # each record is one setting of one bleed adjuster: that parameter and nothing else
                name, setting = plan.change["parameter"], plan.change["setting"]
                assert changed <= {name} <= {"A_bleed_reb", "A_bleed_comp"}
                assert plan.params[name] == pytest.approx(base[name] * plan.change["factors"][setting], rel=1e-12)
                assert (setting == "middle") == (not changed)
            else:
                assert not changed
            t_start, t_end = plan.temperature(0.0), plan.temperature(plan.motion.duration)
            if scenario == "heated":
                assert 30.0 <= plan.change["rise_K"] <= 50.0
                assert max(t_start, t_end) - base["T_ref"] > 29.0
            else:
                assert t_start == t_end == base["T_ref"]
    # the truth differs from the datasheet only where a datasheet cannot know the value
    for size in dyno.SIZES:
        truth = dyno.truth_parameters(size, 7)
        assert {k for k in truth if truth[k] != dyno.NOMINAL[size][k]} == set(dyno.SPREADS)
        assert 0.002 <= truth["air_fraction"] <= 0.02


def test_the_truth_names_every_parameter_as_the_fmu_does(records):
    xml = ET.parse(REPO / "modelDescription.xml").getroot()
    fmu = {v.get("name") for v in xml.iter("ScalarVariable")}
    assert set(FMU_NAMES) <= fmu
    truth = truth_of(records[("truck", 2, "calibration")][0])
    assert set(truth["truth_parameters"]) == set(truth["nominal_parameters"]) == set(FMU_NAMES)
    assert set(truth["fmu_settings"]) <= fmu
    # truck: the model's default geometry
    for name in ("D_piston", "D_rod", "L_half_stroke", "L_dead", "V_hose", "V_gas0"):
        start = next(v for v in xml.iter("ScalarVariable") if v.get("name") == name).find("Real").get("start")
        assert truth["truth_parameters"][name] == float(start)


# The datasheet's keys and the FMU parameters they set (the template's comments), and its units.
SHEET_KEYS = {
    "cylinder": {"piston_diameter": "D_piston", "rod_diameter": "D_rod", "stroke": "L_half_stroke",
                 "dead_length": "L_dead", "extra_volume": "V_hose"},
    "gas": {"precharge": "p_reservoir0", "volume": "V_gas0", "polytropic_index": "n_polytropic"},
    "oil": {"density": "rho", "air_fraction": "air_fraction", "viscosity_temperature_coefficient": "visc_temp_coeff",
            "reference_temperature": "T_ref"},
    "check_valves": {"area": "A_cv_max", "cracking_pressure": "p_cv_crack", "full_open_pressure": "p_cv_full"},
    "mount": {"stiffness": "k1_mount", "cubic_stiffness": "k3_mount"},
    "seals": {"friction": "F_coulomb", "friction_velocity": "v_friction"},
}
# the datasheet leaves the bump rubbers out, as datasheets do
NOT_ON_THE_SHEET = {"end_stops"}
NOT_ON_THE_SHEET_PARAMETERS = {"x_end_stop", "k_end_stop"}
for _section, _w in (("rebound_valve", "reb"), ("compression_valve", "comp")):
    SHEET_KEYS[_section] = {"laminar_bleed": f"G_bleed_{_w}", "bleed_area": f"A_bleed_{_w}",
                            "blow_off_pressure": f"p_open_{_w}", "blow_off_area_per_pressure": f"k_open_{_w}",
                            "blow_off_area": f"A_open_{_w}"}
SHEET_KEYS["rebound_valve"]["discharge_coefficient"] = "Cd_passive"
SHEET_UNITS = {"mm": 1e-3, "cm3": 1e-6, "bar": 1e5, "mm2": 1e-6, "m3/(s.Pa)": 1.0, "m2/Pa": 1.0, "kg/m3": 1.0,
               "1/K": 1.0, "N/m": 1.0, "N/m3": 1.0, "N": 1.0, "mm/s": 1e-3, "N/m2": 1.0}


def si(value):
    """A datasheet value in SI: a number, or a string "number unit"."""
    if not isinstance(value, str):
        return value
    number, unit = value.split(" ", 1)
    return float(number) + dyno.T_ZERO if unit == "degC" else float(number) * SHEET_UNITS[unit]


def test_the_datasheet_toml_has_the_template_s_sections_and_the_nominal_values(records):
    template = tomllib.loads((REPO / "crates" / "damper_engine" / "src" / "damper_template.toml").read_text())
    sheet = tomllib.loads((records[("car", 4, "end_stop")][0].parent / "car_4_datasheet.toml").read_text())
    assert sheet["kind"] == "passive" and sheet["name"]
    sections = {k for k, v in template.items() if isinstance(v, dict)}
    assert {k for k, v in sheet.items() if isinstance(v, dict)} == sections - NOT_ON_THE_SHEET
    for section in sections - {"parameters"} - NOT_ON_THE_SHEET:
        assert set(sheet[section]) <= set(template[section]), section
    assert sheet["oil"]["reference_temperature"] == "20 degC"
    # read back, the datasheet is the nominal damper, every parameter of it
    read = {param: si(sheet[section][key]) for section, keys in SHEET_KEYS.items() for key, param in keys.items()}
    read["L_half_stroke"] /= 2
    read.update(sheet["parameters"])
    assert set(read) == set(FMU_NAMES) - NOT_ON_THE_SHEET_PARAMETERS
    for name, value in dyno.NOMINAL["car"].items():
        if name in NOT_ON_THE_SHEET_PARAMETERS:
            continue
        assert read[name] == pytest.approx(value, rel=1e-12), name


def test_the_csv_has_the_documented_comments_header_and_units(records):
    for paths in records.values():
        for path in paths:
            truth = truth_of(path)
            comments, header, cols = read_csv(path)
            rate = truth["sample_rate_hz"]
            assert rate in (500, 1000, 2000)
            assert f"# Sample rate: {rate} Hz" in comments
            assert header == truth["columns"]
            assert header[1:] == ["x_damper [mm]", "v_damper [mm/s]", f"F_damper [{truth['chain']['force_unit']}]",
                                  "T_oil [degC]"]
            for cell in header:
                if "[" in cell:
                    assert cell.split("[")[1].rstrip("]") in KNOWN_UNITS
            assert len(cols["T_oil [degC]"]) == truth["samples"]
            if header[0] == "time [s]":
                t = np.array(cols["time [s]"], dtype=float)
            else:
                assert header[0] == "time" and truth["chain"]["time_format"] == "iso"
                stamps = [datetime.fromisoformat(s) for s in cols["time"]]
                t = np.array([(s - stamps[0]).total_seconds() for s in stamps])
            assert np.allclose(np.diff(t), 1.0 / rate, rtol=0, atol=1e-9)
            temp = np.array(cols["T_oil [degC]"], dtype=float)
            assert np.allclose(temp * 10, np.round(temp * 10))  # 0.1 K quantum
            if truth["scenario"] != "heated":
                assert abs(temp.mean() - 20.0) < 0.05 and 0.1 < temp.std() < 0.35
            assert any(c.startswith("# v_damper: ") for c in comments)


def test_the_velocity_column_follows_the_true_motion(records):
    """Derived by the logger or from its sensor, the velocity column is the motion's within noise."""
    for paths in records.values():
        for path in paths:
            truth = truth_of(path)
            _, _, cols = read_csv(path)
            v = np.array(cols["v_damper [mm/s]"], dtype=float) * 1e-3
            scale = truth["motion"]["max_abs_v_m_s"]
            assert np.max(np.abs(v)) == pytest.approx(scale, rel=0.08, abs=0.004)
