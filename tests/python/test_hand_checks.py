"""The hand-computed figures of docs/physics.md, recomputed from the parameters' defaults.

physics.md tags the values it derives from other values with [C]: areas, volumes and the 3:1 volume
ratio, the gas force, bulk moduli, the oil column's time constants, the spool's dynamics, the steady
operating points of the valve, the passive valve's hand check, gains and road figures. Each test here
takes the start values of modelDescription.xml (the damper) and crates/quarter_truck/modelDescription.xml
(the truck), evaluates the equations physics.md states with plain Python (math and scipy, independently
of the Rust model and of the FMUs), reads the figure out of the document's text and checks that it is
the computed value rounded to the digits the document quotes: a changed default or equation then
cannot leave a figure stale. Where a sentence also quotes its inputs (the oil's air content, the
passive valve's bleeds), those are held to the XML's defaults too.

Not here: the valve law's hand check of §3.3 and the natural frequencies of §6.4 and §6.6 (test_docs.py
holds them), the reference implementation's numbers (not computed by hand) and the figures that come
from a simulation (the lost stroke of §3.2, the stiff poles of §7).
"""

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import NamedTuple

from scipy.optimize import brentq

REPO = Path(__file__).resolve().parents[2]
PHYSICS = REPO / "docs" / "physics.md"
DAMPER_XML = REPO / "modelDescription.xml"
TRUCK_XML = REPO / "crates" / "quarter_truck" / "modelDescription.xml"

# The document with every run of whitespace made one space, so that a pattern reads across the
# document's line breaks.
TEXT = " ".join(PHYSICS.read_text(encoding="utf-8").split())
# A quoted number: plain or in e-notation, with an ASCII or a typographic minus.
NUMBER = r"([−-]?\d+(?:\.\d+)?(?:e[−+-]?\d+)?)"
P_ATM = 101_325.0  # Pa, physics.md's atmosphere (fluid.rs P_ATM)
FROZEN_BELOW = 0.02 * P_ATM  # Pa absolute: the air law's floor (§3.2)
RELEASE_BAND = 0.1e5  # Pa, δ of the gas release's blend h (§3.2)
# §4.3: the force loop demands at most A(x_spool_max − 0.5 mm).
DEMAND_MARGIN = 0.5e-3  # m


def starts(path: Path) -> dict[str, float]:
    """name -> start value (SI, as the XML gives it) of every Real and Integer variable that has one."""
    result = {}
    for variable in ET.parse(path).getroot().iter("ScalarVariable"):
        value = next(iter(variable))
        if value.tag in ("Real", "Integer") and value.get("start") is not None:
            result[variable.get("name", "")] = float(value.get("start", ""))
    return result


DAMPER = starts(DAMPER_XML)
TRUCK = starts(TRUCK_XML)


def half_unit(number: str, significant: int | None = None) -> float:
    """Half a unit in the last digit of `number` as written ("2.94" 0.005, "982" 0.5, "5.7e-11" 0.05e-11),
    or in its `significant`-th significant digit where the document rounds an integer to fewer
    digits than it writes ("6300", two significant digits: 50)."""
    mantissa, _, exponent = number.replace("−", "-").partition("e")
    if significant is not None:
        return 0.5 * 10.0 ** (math.floor(math.log10(abs(float(number.replace("−", "-"))))) - significant + 1)
    decimals = len(mantissa.partition(".")[2])
    return 0.5 * 10.0 ** (int(exponent or 0) - decimals)


class Quote(NamedTuple):
    """A number physics.md quotes: its value, half a unit of its last digit, and the sentence it is in."""
    value: float
    half: float
    text: str
    sentence: str


def quoted(pattern: str, significant: int | None = None) -> list[Quote]:
    """The numbers that `pattern`'s groups capture in physics.md. The pattern must match once, so that a
    figure cannot be read from the wrong sentence (LookupError otherwise: a reworded sentence is not a
    wrong figure)."""
    matches = list(re.finditer(pattern, TEXT))
    if len(matches) != 1:
        raise LookupError(f"physics.md: {len(matches)} matches of {pattern!r}, expected one")
    return [Quote(float(g.replace("−", "-")), half_unit(g, significant), g, matches[0][0])
            for g in matches[0].groups()]


def assert_quotes(pattern: str, *computed: float, significant: int | None = None) -> None:
    """Every number `pattern` captures is the corresponding computed value rounded as quoted."""
    quotes = quoted(pattern, significant)
    assert len(quotes) == len(computed), f"{pattern!r} captures {len(quotes)} numbers, {len(computed)} computed"
    for k, (quote, mine) in enumerate(zip(quotes, computed, strict=True), 1):
        # the half unit itself is a rounded binary number: allow its own rounding error
        assert abs(mine - quote.value) <= quote.half * (1 + 1e-9), (
            f"physics.md quotes {quote.text} (figure {k} of \"{quote.sentence}\"); the defaults give {mine:.6g}, "
            f"which does not round to it (±{quote.half:g})")


# --------------------------------------------------------------------------- the equations, by hand

def areas() -> tuple[float, float, float]:
    """§3.1: A_p = π D_piston²/4, A_r = π D_rod²/4, A_a = A_p − A_r (m²)."""
    a_p = math.pi * DAMPER["D_piston"] ** 2 / 4
    a_r = math.pi * DAMPER["D_rod"] ** 2 / 4
    return a_p, a_r, a_p - a_r


def volumes_at_mid_stroke() -> tuple[float, float]:
    """§3.1 at x_p = 0: V_A = A_a (L_half_stroke + L_dead) + V_hose, V_B = A_p (L_half_stroke + L_dead) (m³)."""
    a_p, _, a_a = areas()
    length = DAMPER["L_half_stroke"] + DAMPER["L_dead"]
    return a_a * length + DAMPER["V_hose"], a_p * length


def gas_force() -> float:
    """§2: the force at rest, −p_reservoir0 A_r (N)."""
    return -DAMPER["p_reservoir0"] * areas()[1]


def bulk_modulus(p: float, solubility: float = 0.0, p_saturation: float = 0.0) -> float:
    """§3.2: β_e at gauge pressure p (Pa) of oil with entrained air and, with a solubility L, the gas
    released below the saturation pressure: α = α₀ + L h(p_sat,abs − p_abs)/p_atm,
    β_e = (1 + α r)/(1/β_L + α r/(n p_abs) + L h'(p_sat,abs − p_abs) r/p_atm), r = (p_atm/p_abs)^(1/n),
    with p_abs frozen at 0.02 p_atm below it."""
    n, beta_oil = DAMPER["n_polytropic"], DAMPER["beta_oil"]
    p_abs = max(p + P_ATM, FROZEN_BELOW)
    r = math.pow(P_ATM / p_abs, 1 / n)
    t = min(max((p_saturation + P_ATM - p_abs + RELEASE_BAND) / (2 * RELEASE_BAND), 0.0), 1.0)
    released = 2 * RELEASE_BAND * (t ** 3 - t ** 4 / 2) if t < 1 else p_saturation + P_ATM - p_abs
    alpha = DAMPER["air_fraction"] + solubility * released / P_ATM
    rate = solubility * (3 * t * t - 2 * t ** 3) / P_ATM  # L h'/p_atm, h' = smoothstep(t)
    return (1 + alpha * r) / (1 / beta_oil + alpha * r / (n * p_abs) + rate * r)


def port_area(h: float) -> float:
    """§3.3: n ports of radius r uncovered by h, n [r² acos((r − h)/r) − (r − h) sqrt(2rh − h²)] (m²)."""
    n, r = DAMPER["n_ports"], DAMPER["r_port"]
    if h <= 0:
        return 0.0
    if h >= 2 * r:
        return n * math.pi * r * r
    return n * (r * r * math.acos((r - h) / r) - (r - h) * math.sqrt(2 * r * h - h * h))


def opening_for_area(area: float) -> float:
    """§3.3's inverse: φ − sin φ = 2A/(n r²) (Kepler's equation), h = 2r sin²(φ/4) (m)."""
    n, r = DAMPER["n_ports"], DAMPER["r_port"]
    phi = brentq(lambda f: f - math.sin(f) - 2 * area / (n * r * r), 0.0, 2 * math.pi, xtol=1e-15)
    return 2 * r * math.sin(phi / 4) ** 2


def flow_force_gain() -> float:
    """§3.6: F_flow = 2 C_d C_v cos θ_jet · A · Δp."""
    return 2 * DAMPER["Cd_valve"] * DAMPER["Cv_valve"] * math.cos(DAMPER["theta_jet"])


def extension_point(force: float, v: float) -> tuple[float, float, float, float]:
    """§3.3's calculation in steady extension with p_B = p_r: Δp = (F + p_reservoir0 A_r)/A_a,
    A = A_a v/(C_d sqrt(2Δp/ρ)), x_s = x_lap + h(A), F_flow = gain·A·Δp. Returns (Δp (Pa), A (m²), x_s (m),
    F_flow (N)). As §3.3, the turbulent law (the regularised one differs by a few ppm above 15 bar) and A
    the whole open area (counting A_valve_leak's 0.01 mm² apart would move x_s by about 1 µm)."""
    _, a_r, a_a = areas()
    dp = (force + DAMPER["p_reservoir0"] * a_r) / a_a
    area = a_a * v / (DAMPER["Cd_valve"] * math.sqrt(2 * dp / DAMPER["rho"]))
    return dp, area, DAMPER["x_lap"] + opening_for_area(area), flow_force_gain() * area * dp


def valve_drop(area: float, v: float) -> float:
    """The turbulent drop (Pa) of the proportional valve of area `area` passing A_a v."""
    return DAMPER["rho"] / 2 * (areas()[2] * v / (DAMPER["Cd_valve"] * area)) ** 2


def in_series(k_oil: float) -> float:
    """§3.4: the oil column in series with the mount's tangent stiffness k1_mount at small force (N/m)."""
    return 1 / (1 / k_oil + 1 / DAMPER["k1_mount"])


# --------------------------------------------------------------------------- §2 and §5.3: geometry

def test_the_compressed_volumes_give_the_papers_three_to_one_ratio() -> None:
    a_p, a_r, a_a = areas()
    v_a, v_b = volumes_at_mid_stroke()
    assert_quotes(rf"\| A_p, A_r, A_a \| {NUMBER}e-3, {NUMBER}e-3, {NUMBER}e-3 m² \|",
                  a_p * 1e3, a_r * 1e3, a_a * 1e3)
    assert_quotes(rf"\| V_A \(with hose\), V_B, V_A \+ V_B at mid-stroke \| {NUMBER}, {NUMBER}, {NUMBER} cm³; "
                  rf"ratio \(V_A \+ V_B\)/V_A = {NUMBER} \(paper",
                  v_a * 1e6, v_b * 1e6, (v_a + v_b) * 1e6, (v_a + v_b) / v_a)
    assert_quotes(rf"With the defaults it is {NUMBER} \[C\]", (v_a + v_b) / v_a)


def test_the_gas_force_at_rest_is_the_precharge_on_the_rod_area() -> None:
    assert_quotes(rf"F_0 = −p_r0·A_r = {NUMBER} N with the defaults \[C\]", gas_force())
    assert_quotes(rf"\| gas force at rest −p_reservoir0 A_r \| {NUMBER} N \|", gas_force())
    assert_quotes(rf"plus the {NUMBER} kN gas offset", gas_force() / 1e3)


def test_the_relief_valve_caps_the_force_near_37_kN() -> None:
    _, a_r, a_a = areas()
    cap = DAMPER["p_relief"] * a_a - DAMPER["p_reservoir0"] * a_r
    assert_quotes(rf"It caps the force near p_relief·A_a − p_r0·A_r = {NUMBER} kN \[C\]", cap / 1e3)
    assert_quotes(rf"\| relief force cap p_relief A_a − p_reservoir0 A_r \| {NUMBER} kN \|", cap / 1e3)


def test_the_ports_open_at_most_n_pi_r_squared() -> None:
    largest = DAMPER["n_ports"] * math.pi * DAMPER["r_port"] ** 2
    assert_quotes(rf"\| largest valve area n π r² \| {NUMBER} mm² \|", largest * 1e6)


def test_the_amplifier_delays_the_command_by_whole_controller_samples() -> None:
    # §4.4: a FIFO of round(tau_amp/T_sample) samples
    samples = round(DAMPER["tau_amp"] / DAMPER["T_sample"])
    assert_quotes(rf"\| amplifier delay \| {NUMBER} controller samples \|", samples)
    assert_quotes(rf"\({NUMBER} samples with the defaults; at most 200\)", samples)


def test_the_coil_holds_the_spool_against_its_spring_at_rest() -> None:
    rest = DAMPER["k_spool"] * DAMPER["x_spool_start"] / DAMPER["K_sol"]
    assert_quotes(rf"\| rest coil current k_spool x_spool_start/K_sol \| {NUMBER} A \|", rest)
    assert_quotes(rf"i₀ = k_spool x_spool_start/K_sol = {NUMBER} A, which holds the spool at "
                  rf"x_spool_start = {NUMBER} mm", rest, DAMPER["x_spool_start"] * 1e3)


def test_the_solenoid_pushes_at_most_its_gain_times_the_current_limit() -> None:
    assert_quotes(rf"\| largest solenoid force K_sol I_max \| {NUMBER} N \|", DAMPER["K_sol"] * DAMPER["I_max"])


# --------------------------------------------------------------------------- §3.2: compressibility

# The pressures (bar) of §3.2's table of bulk moduli, and the unit each is quoted in.
BULK_MODULUS_TABLE = ((0, "MPa"), (5, "MPa"), (10, "MPa"), (20, "MPa"), (50, "GPa"), (100, "GPa"), (150, "GPa"))


def test_air_softens_the_oil_as_the_table_of_bulk_moduli_says() -> None:
    assert_quotes(rf"Values with α₀ = {NUMBER}, n = {NUMBER}, β_L = {NUMBER} GPa \[C\]",
                  DAMPER["air_fraction"], DAMPER["n_polytropic"], DAMPER["beta_oil"] / 1e9)
    table = ", ".join(rf"{NUMBER} {unit} at {bar} bar" for bar, unit in BULK_MODULUS_TABLE)
    scale = {"MPa": 1e6, "GPa": 1e9}
    assert_quotes(rf"holds them\): {table}\.",
                  *(bulk_modulus(bar * 1e5) / scale[unit] for bar, unit in BULK_MODULUS_TABLE))


def test_released_gas_makes_the_oil_28_times_softer_below_saturation() -> None:
    solubility, p_saturation = DAMPER["gas_solubility"], DAMPER["p_saturation"]
    below = 0.5e5  # Pa under the saturation pressure, beyond the release band
    released = bulk_modulus(p_saturation - below, solubility, p_saturation)
    air_alone = bulk_modulus(p_saturation - below)
    assert_quotes(rf"At {NUMBER} bar below a {NUMBER}-bar saturation, L = {NUMBER} makes the oil {NUMBER} times "
                  rf"softer than its {NUMBER} % air alone \({NUMBER} MPa against {NUMBER} MPa \[C\]",
                  below / 1e5, p_saturation / 1e5, solubility, air_alone / released, DAMPER["air_fraction"] * 100,
                  released / 1e6, air_alone / 1e6)


def test_the_bulk_modulus_varies_13_times_between_5_and_150_bar() -> None:
    # §7, the stiffness of the chamber pressures' poles
    assert_quotes(rf"β_e itself varies {NUMBER}× between 5 and 150 bar", bulk_modulus(150e5) / bulk_modulus(5e5))


# --------------------------------------------------------------------------- §3.4: time constants

# §3.4's operating point: 12 kN at 0.15 m/s, either way.
STEP_FORCE = 12e3  # N
STEP_VELOCITY = 0.15  # m/s


def test_the_oil_column_in_extension_has_an_11_ms_time_constant() -> None:
    # the valve passes A_a v at Δp = (F + p_r0 A_r)/A_a; V_A is compressed; c_t = 2ΔpA/v
    _, a_r, a_a = areas()
    v_a, _ = volumes_at_mid_stroke()
    dp = (STEP_FORCE + DAMPER["p_reservoir0"] * a_r) / a_a
    p_a = dp + DAMPER["p_reservoir0"]
    k_oil = bulk_modulus(p_a) * a_a ** 2 / v_a
    c_t = 2 * dp * a_a / STEP_VELOCITY
    assert_quotes(rf"At 12 kN and 0.15 m/s in extension: Δp = {NUMBER} bar, p_A = {NUMBER} bar, "
                  rf"β_e = {NUMBER} GPa, oil stiffness β_e A_a²/V_A = {NUMBER} MN/m, with the mount {NUMBER} MN/m; "
                  rf"c_t = {NUMBER} kN·s/m; τ = c_t/k = {NUMBER} ms\.",
                  dp / 1e5, p_a / 1e5, bulk_modulus(p_a) / 1e9, k_oil / 1e6, in_series(k_oil) / 1e6, c_t / 1e3,
                  c_t / in_series(k_oil) * 1e3)


def test_the_oil_column_in_compression_is_twice_as_slow() -> None:
    # F ≈ −p A_r; the valve passes A_r |v| at p − p_r0; V_A + V_B is compressed (CV1 open)
    _, a_r, _ = areas()
    v_a, v_b = volumes_at_mid_stroke()
    p = STEP_FORCE / a_r
    k_oil = bulk_modulus(p) * a_r ** 2 / (v_a + v_b)
    c_t = 2 * (p - DAMPER["p_reservoir0"]) * a_r / STEP_VELOCITY
    assert_quotes(rf"In compression at −12 kN: p = {NUMBER} bar, β_e = {NUMBER} GPa, oil stiffness "
                  rf"β_e A_r²/\(V_A \+ V_B\) = {NUMBER} MN/m, with the mount {NUMBER} MN/m; c_t = {NUMBER} kN·s/m; "
                  rf"τ = {NUMBER} ms, about twice as slow",
                  p / 1e5, bulk_modulus(p) / 1e9, k_oil / 1e6, in_series(k_oil) / 1e6, c_t / 1e3,
                  c_t / in_series(k_oil) * 1e3)


# --------------------------------------------------------------------------- §3.6 and §4.2: the spool

def test_the_flow_force_coefficient_is_close_to_merritts() -> None:
    assert_quotes(rf"θ = {NUMBER}° \(von Mises jet angle\), 2C_dC_v cos 69° = {NUMBER} with C_d {NUMBER}, "
                  rf"C_v {NUMBER},",
                  math.degrees(DAMPER["theta_jet"]), flow_force_gain(), DAMPER["Cd_valve"], DAMPER["Cv_valve"])


def test_the_flow_force_stiffness_is_comparable_to_the_centring_spring() -> None:
    # at imposed flow the flow force falls with the opening: −gain·Δp·dA/dh, dA/dh = 2n sqrt(h (2r − h))
    # (the ports' chord), at the steady operating points of §5.3
    n, r = DAMPER["n_ports"], DAMPER["r_port"]

    def stiffness(force: float, v: float) -> float:
        dp, _, x_s, _ = extension_point(force, v)
        h = x_s - DAMPER["x_lap"]
        return flow_force_gain() * dp * 2 * n * math.sqrt(h * (2 * r - h))

    assert_quotes(rf"a centring stiffness \+{NUMBER} Δp dA/dh\)", flow_force_gain())
    assert_quotes(rf"a negative stiffness of {NUMBER} kN/m at 10 kN and 0.15 m/s and {NUMBER}–{NUMBER} kN/m at 20 kN "
                  rf"and 0.5–1 m/s \({NUMBER} Δp times the ports' chord\)",
                  stiffness(10e3, 0.15) / 1e3, stiffness(20e3, 0.5) / 1e3, stiffness(20e3, 1.0) / 1e3,
                  flow_force_gain())


def test_the_spool_is_a_well_damped_159_Hz_oscillator_stiffened_by_its_stops() -> None:
    k, m = DAMPER["k_spool"], DAMPER["m_spool"]
    omega = math.sqrt(k / m)
    assert_quotes(rf"ω_n = sqrt\(k_spool/m_spool\) = {NUMBER} rad/s \({NUMBER} Hz\), damping ratio "
                  rf"c_spool/\(2 sqrt\(k_spool m_spool\)\) = {NUMBER};",
                  omega, omega / (2 * math.pi), DAMPER["c_spool"] / (2 * math.sqrt(k * m)))
    # "6300": sqrt(k_stop/m_spool) = 6325 rad/s to two significant digits
    assert_quotes(rf"the end stops stiffen it to sqrt\(k_stop/m_spool\) = {NUMBER} rad/s",
                  math.sqrt(DAMPER["k_stop"] / m), significant=2)


def test_the_spring_holds_80_N_against_the_flow_forces_at_the_compensation_runs_demand() -> None:
    # §6.2: the reference's flow forces against the centring spring's k_spool x at x_dem = 1.6 mm
    x_demand = quoted(rf"of spring force at {NUMBER} mm\)")[0].value
    assert_quotes(rf"against {NUMBER} N of spring force", DAMPER["k_spool"] * x_demand * 1e-3)


def test_the_fixed_flow_force_compensation_gain_at_50_bar() -> None:
    # §4.2, flow_force_compensation 1: i_fc = Cv_compensation cos θ sqrt(2 ρ dp_fc_nominal) Q̂ / K_sol
    gain = (DAMPER["Cv_compensation"] * math.cos(DAMPER["theta_jet"])
            * math.sqrt(2 * DAMPER["rho"] * DAMPER["dp_fc_nominal"]) / DAMPER["K_sol"])
    assert_quotes(rf"K_fc = {NUMBER} A/\(m³/s\) at {NUMBER} bar \[C\]", gain, DAMPER["dp_fc_nominal"] / 1e5)


# --------------------------------------------------------------------------- §3.8: passive valves

def test_the_passive_bleeds_give_2_kN_at_a_tenth_of_a_metre_per_second() -> None:
    # below the preload only the two bleeds pass the flow: G Δp + Cd A_bleed sqrt(2Δp/ρ) = A_a v
    _, a_r, a_a = areas()
    v = 0.1  # m/s
    g, a_bleed, cd = DAMPER["G_bleed_reb"], DAMPER["A_bleed_reb"], DAMPER["Cd_passive"]
    rho = DAMPER["rho"]
    dp = brentq(lambda d: g * d + cd * a_bleed * math.sqrt(2 * d / rho) - a_a * v, 0.0, 1e8, xtol=1e-6)
    # the blow-off's rounded ramp starts 0.05 A_open/k_open below the preload: it is still shut at Δp
    assert dp < DAMPER["p_open_reb"] - 0.05 * DAMPER["A_open_reb"] / DAMPER["k_open_reb"]
    assert_quotes(rf"\(A_a = {NUMBER}e-3 m², ρ = {NUMBER} kg/m³, Cd = {NUMBER}\): at 0.1 m/s in extension "
                  rf"Q = {NUMBER}e-4 m³/s; below the preload of {NUMBER} bar the bleeds pass it at Δp with "
                  rf"{NUMBER} Δp \+ {NUMBER}·{NUMBER}·sqrt\(2Δp/{NUMBER}\) = {NUMBER}e-4, Δp = {NUMBER} bar: "
                  rf"F = {NUMBER}e5·{NUMBER}e-3 − {NUMBER} = {NUMBER} kN\.",
                  a_a * 1e3, rho, cd, a_a * v * 1e4, DAMPER["p_open_reb"] / 1e5,
                  g, cd, a_bleed, rho, a_a * v * 1e4, dp / 1e5,
                  dp / 1e5, a_a * 1e3, -gas_force(), (dp * a_a - DAMPER["p_reservoir0"] * a_r) / 1e3)


# --------------------------------------------------------------------------- §4.5: the demand

def test_the_skyhook_demand_spans_2_to_10_kN_at_usual_velocities() -> None:
    c = TRUCK["alpha"] * TRUCK["Cm"]
    # the velocities as the sentence gives them, then the forces they make
    slow, fast = (q.value for q in quoted(rf"× {NUMBER}–{NUMBER} m/s ≈ [^ ]+ kN\."))
    assert_quotes(rf"α C_m V_rel = {NUMBER} kN·s/m × [^ ]+ m/s ≈ {NUMBER}–{NUMBER} kN\.",
                  c / 1e3, c * slow / 1e3, c * fast / 1e3)


# --------------------------------------------------------------------------- §5.3: operating points

def test_the_steady_operating_points_follow_the_valve_law() -> None:
    points = [extension_point(force, v) for force, v in ((2e3, 0.15), (10e3, 0.15), (20e3, 0.15), (10e3, 1.0))]
    figures = [(dp / 1e5, x_s * 1e3, f_flow) for dp, _, x_s, f_flow in points]
    assert_quotes(rf"Steady operating points at 0.15 m/s extension \(§3.3's calculation, with p_B = p_r\) \[C\]: "
                  rf"2 kN ↔ Δp {NUMBER} bar, x_s {NUMBER} mm, F_flow {NUMBER} N; "
                  rf"10 kN ↔ {NUMBER} bar, {NUMBER} mm, {NUMBER} N; 20 kN ↔ {NUMBER} bar, {NUMBER} mm, {NUMBER} N\. "
                  rf"At 1 m/s: 10 kN ↔ x_s {NUMBER} mm, F_flow {NUMBER} N\.",
                  *figures[0], *figures[1], *figures[2], *figures[3][1:])


def test_the_open_valve_floors_the_force_in_extension() -> None:
    # the force loop opens the spool at most to x_spool_max − 0.5 mm (§4.3); the floor is the valve's
    # drop there times A_a, the gas force (p_B = p_r) apart
    x_demand = DAMPER["x_spool_max"] - DEMAND_MARGIN
    area = port_area(x_demand - DAMPER["x_lap"])
    at_stop = port_area(DAMPER["x_spool_max"] - DAMPER["x_lap"])
    a_a = areas()[2]
    assert_quotes(rf"as far as the force loop demands \(x_s {NUMBER} mm, {NUMBER} mm²\): in extension about "
                  rf"{NUMBER} kN at 0.15 m/s",
                  x_demand * 1e3, area * 1e6, valve_drop(area, 0.15) * a_a / 1e3)
    assert_quotes(rf"\({NUMBER} kN with the spool at its {NUMBER} mm stop\)",
                  valve_drop(at_stop, 1.0) * a_a / 1e3, DAMPER["x_spool_max"] * 1e3)


def test_the_open_valve_floors_the_force_at_one_metre_per_second() -> None:
    area = port_area(DAMPER["x_spool_max"] - DEMAND_MARGIN - DAMPER["x_lap"])
    assert_quotes(rf"and {NUMBER} kN at 1 m/s \(", valve_drop(area, 1.0) * areas()[2] / 1e3)


# --------------------------------------------------------------------------- §8: effects

def test_the_bump_stops_default_is_its_quoted_force_at_6_mm() -> None:
    # the stop's force at the sentence's travel, from the default stiffness of F = k (|x| − x_end_stop)²
    travel = quoted(rf"kN at {NUMBER} mm gives k_end_stop")[0].value
    assert_quotes(rf"{NUMBER} kN at 6 mm gives k_end_stop", DAMPER["k_end_stop"] * (travel * 1e-3) ** 2 / 1e3)
    assert_quotes(rf"at 6 mm gives k_end_stop = {NUMBER} N/m²", DAMPER["k_end_stop"])


def test_the_piston_gap_gives_the_default_leakage_conductance() -> None:
    # G = π D c³/(12 μ L) of a concentric gap (ε = 0) around the piston
    diameter = DAMPER["D_piston"]
    gap, length, viscosity = 15e-6, 15e-3, 0.02  # m, m, Pa·s: physics.md §8's gap

    def conductance(c: float) -> float:
        return math.pi * diameter * c ** 3 / (12 * viscosity * length)

    assert_quotes(rf"with D = {NUMBER} mm, c = {NUMBER} µm, L = {NUMBER} mm, μ = {NUMBER} Pa·s and ε = 0, "
                  rf"G = {NUMBER}e-13 m³/\(s·Pa\) \[C\], the default of `G_leak`; 10–20 µm gaps give "
                  rf"{NUMBER}e-13 to {NUMBER}e-13\.",
                  diameter * 1e3, gap * 1e6, length * 1e3, viscosity, conductance(gap) * 1e13,
                  conductance(10e-6) * 1e13, conductance(20e-6) * 1e13)
    # the XML's default is the computed conductance rounded to the digit it writes ("2e-13")
    start = ET.parse(DAMPER_XML).getroot().find(".//ScalarVariable[@name='G_leak']/Real")
    assert start is not None
    default = start.get("start", "")
    assert abs(conductance(gap) - float(default)) <= half_unit(default), \
        f"G_leak's default {default} is not π D c³/(12 μ L) = {conductance(gap):.3g} rounded"


# --------------------------------------------------------------------------- §9: roads

def test_the_minor_road_has_a_white_velocity_spectrum_of_7e_4() -> None:
    # with waviness 2, G_v = (2π n0)² G_d(n0) U, flat in frequency
    n0, g_d0, speed = TRUCK["road_n0"], TRUCK["road_gd0"], TRUCK["road_speed"]
    assert TRUCK["road_waviness"] == 2
    assert_quotes(rf"\*\*minor road = {NUMBER}e-6 m³", g_d0 * 1e6)
    assert_quotes(rf"\(2π n0\)² G_d\(n0\) U = {NUMBER}e-4 \(m/s\)²/Hz for the minor road at {NUMBER} m/s \[C\]",
                  (2 * math.pi * n0) ** 2 * g_d0 * speed * 1e4, speed)
