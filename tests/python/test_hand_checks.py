"""The hand-computed figures of docs/physics.md, recomputed from the parameters' defaults.

physics.md tags the values it derives from other values with [C]: areas, volumes and the 3:1 volume
ratio, the gas force, bulk moduli, the oil column's time constants, the spool's dynamics, the steady
operating points of the valve, the passive valve's hand check, gains and road figures; the reasoning
column of the parameter tables (§5.1, §5.2, §5.4) quotes more (diameters, forces, inertias). Each test
here takes the start values of modelDescription.xml (the damper), crates/quarter_truck/modelDescription.xml
(the truck) and crates/full_truck/modelDescription.xml (the full truck), evaluates the equations
physics.md states with plain Python (math and scipy, independently of the Rust model and of the FMUs),
reads the figure out of the document's text and checks that it is the computed value rounded to the
digits the document quotes: a changed default or equation then cannot leave a figure stale. Where a
sentence also quotes its inputs (the oil's air content, the passive valve's bleeds), those are held to
the XML's defaults too.

The valve law's hand check of §3.3 and the natural frequencies of §6.4 and of §6.6's linear model are
checked as the exact strings the document prints (the last test). Not here: the reference
implementation's numbers (not computed by hand) and the figures that come from a simulation (the lost
stroke of §3.2, the tuned loops' step responses, the benchmark's errors).
"""

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from types import SimpleNamespace
from typing import NamedTuple

from scipy.optimize import brentq, minimize_scalar

from damper_tools import full_truck
from damper_tools.crosscheck import Plant

REPO = Path(__file__).resolve().parents[2]
PHYSICS = REPO / "docs" / "physics.md"
DAMPER_XML = REPO / "modelDescription.xml"
TRUCK_XML = REPO / "crates" / "quarter_truck" / "modelDescription.xml"
FULL_TRUCK_XML = REPO / "crates" / "full_truck" / "modelDescription.xml"

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


def switches(path: Path) -> dict[str, bool]:
    """name -> start value of every Boolean variable (the effect switches)."""
    return {v.get("name", ""): next(iter(v)).get("start") == "true"
            for v in ET.parse(path).getroot().iter("ScalarVariable") if next(iter(v)).tag == "Boolean"}


DAMPER = starts(DAMPER_XML)
# The §3 equations the hand checks share with the plain-Python cross-check of the plant
# (damper_tools.crosscheck, itself held to the FMU): areas, volumes, the orifice and port laws, the gas.
PLANT = Plant(SimpleNamespace(**DAMPER, **switches(DAMPER_XML)))
TRUCK = starts(TRUCK_XML)
FULL_TRUCK = starts(FULL_TRUCK_XML)


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
    return PLANT.A_p, PLANT.A_r, PLANT.A_a


def volumes_at_mid_stroke() -> tuple[float, float]:
    """§3.1 at x_p = 0: V_A = A_a (L_half_stroke + L_dead) + V_hose, V_B = A_p (L_half_stroke + L_dead) (m³)."""
    return PLANT.V_A0, PLANT.V_B0


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
    return PLANT.port_area(DAMPER["x_lap"] + h)


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


def orifice_slope(cd: float, area: float, dp: float, area_slope: float = 0.0) -> float:
    """∂Q/∂Δp (m³/(s·Pa)) of §3.3's regularised law Q = C_d A sqrt(2/ρ) Δp/(Δp² + p_transition²)^(1/4), with
    an area A(Δp) of slope `area_slope` (m²/Pa) where the orifice opens with the drop (a check valve)."""
    root = dp * dp + DAMPER["p_transition"] ** 2
    shape, shape_slope = dp * math.pow(root, -0.25), math.pow(root, -0.25) - 0.5 * dp * dp * math.pow(root, -1.25)
    return cd * math.sqrt(2 / DAMPER["rho"]) * (area * shape_slope + area_slope * shape)


def check_valve(dp: float) -> tuple[float, float]:
    """§3.3, cracking on: A_cv = A_cv_leak + A_cv_max s(u), u = (Δp − p_cv_crack)/(p_cv_full − p_cv_crack),
    s = 3u² − 2u³ on [0, 1]. Returns the area (m²) and its slope dA_cv/dΔp (m²/Pa)."""
    span = DAMPER["p_cv_full"] - DAMPER["p_cv_crack"]
    u = min(max((dp - DAMPER["p_cv_crack"]) / span, 0.0), 1.0)
    a_max = DAMPER["A_cv_max"]
    return DAMPER["A_cv_leak"] + a_max * (3 * u * u - 2 * u ** 3), a_max * 6 * u * (1 - u) / span


def reservoir_pressure(x: float) -> float:
    """§3.5 at rest at stroke x: V_g = V_gas0 + A_r x, p_r = (p_reservoir0 + p_atm)(V_gas0/V_g)^n − p_atm (Pa)."""
    return PLANT.reservoir(DAMPER["V_gas0"] + areas()[1] * x)


def annulus_at_extension_end() -> float:
    """§3.1's V_A at x_p = L_half_stroke, the extension stroke's end: A_a L_dead + V_hose (m³)."""
    return areas()[2] * DAMPER["L_dead"] + DAMPER["V_hose"]


def valve_pole(v_a: float, p_a: float, dp: float) -> float:
    """§7's pole −(β_e(p_A)/V_A)·∂Q_v/∂p_A of chamber A through the valve with the spool at its stop,
    Q_v = Q(C_d,valve, A(x_spool_max − x_lap) + A_valve_leak, Δp = p_A − p_r), the mount left out (s⁻¹)."""
    area = port_area(DAMPER["x_spool_max"] - DAMPER["x_lap"]) + DAMPER["A_valve_leak"]
    return -bulk_modulus(p_a) / v_a * orifice_slope(DAMPER["Cd_valve"], area, dp)


def rk4_real_limit() -> float:
    """Where classical RK4's stability function 1 + z + z²/2 + z³/6 + z⁴/24 returns to 1 on the negative
    real axis: the largest stable h|λ| of a real pole."""
    return -brentq(lambda z: z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24, -3.0, -2.5, xtol=1e-15)


def diameter(area: float) -> float:
    """The diameter (m) of a round hole of the area (m²): the "equivalent diameter" of §5.1's orifices."""
    return math.sqrt(4 * area / math.pi)


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
    # §5.1, D_rod: the rod takes half the bore
    assert_quotes(rf"A_r/A_p = {NUMBER} gives the paper's ~3:1 compressed-volume ratio \({NUMBER}, §2\)",
                  a_r / a_p, (v_a + v_b) / v_a)


def test_the_stroke_is_twice_the_half_stroke() -> None:
    # §5.1, L_half_stroke: x_damper runs ±L_half_stroke about mid-stroke
    assert_quotes(rf"\| {NUMBER} mm stroke, x_damper = 0 at mid-stroke \|", 2 * DAMPER["L_half_stroke"] * 1e3)


def test_the_gas_volume_is_large_against_what_the_rod_displaces() -> None:
    # §5.1, V_gas0: the rod moves A_r L_half_stroke of oil in or out of the reservoir either side of mid-stroke
    displaced = areas()[1] * DAMPER["L_half_stroke"]
    assert_quotes(rf"Gas volume large against the rod volume \(±{NUMBER} L over the stroke\)", displaced * 1e3)
    assert DAMPER["V_gas0"] > 4 * displaced


def test_the_gas_force_at_rest_is_the_precharge_on_the_rod_area() -> None:
    assert_quotes(rf"F_0 = −p_r0·A_r = {NUMBER} N with the defaults \[C\]", gas_force())
    assert_quotes(rf"\| gas force at rest −p_reservoir0 A_r \| {NUMBER} N \|", gas_force())
    assert_quotes(rf"plus the {NUMBER} kN gas offset", gas_force() / 1e3)
    # §5.1, p_reservoir0
    assert_quotes(rf"so chamber B does not cavitate; gas force {NUMBER} kN \|", -gas_force() / 1e3)


def test_the_foot_valve_refills_the_full_bore_above_the_cavitation_pressure() -> None:
    # §5.1, A_cv_max: in extension at 1 m/s CV2 passes A_p v into chamber B, wide open (its drop is beyond
    # p_cv_full), so its drop is the turbulent ρ/2 (Q/(Cd_cv A))² (the regularisation is a few ppm there)
    a_p = areas()[0]
    area = DAMPER["A_cv_max"] + DAMPER["A_cv_leak"]
    drop = DAMPER["rho"] / 2 * (a_p * 1.0 / (DAMPER["Cd_cv"] * area)) ** 2
    assert DAMPER["p_cv_full"] < drop < DAMPER["p_reservoir0"]
    assert_quotes(rf"About {NUMBER} mm diameter: CV2 drops {NUMBER} bar refilling chamber B at 1 m/s, below the "
                  rf"{NUMBER} bar pre-charge",
                  diameter(DAMPER["A_cv_max"]) * 1e3, drop / 1e5, DAMPER["p_reservoir0"] / 1e5)


def test_the_relief_valve_caps_the_force_near_37_kN() -> None:
    _, a_r, a_a = areas()
    cap = DAMPER["p_relief"] * a_a - DAMPER["p_reservoir0"] * a_r
    assert_quotes(rf"It caps the force near p_relief·A_a − p_r0·A_r = {NUMBER} kN \[C\]", cap / 1e3)
    assert_quotes(rf"\| relief force cap p_relief A_a − p_reservoir0 A_r \| {NUMBER} kN \|", cap / 1e3)
    assert_quotes(rf"{NUMBER} bar safety valve \(not in the paper\): caps the force near {NUMBER} kN",
                  DAMPER["p_relief"] / 1e5, cap / 1e3)


def test_the_ports_open_at_most_n_pi_r_squared() -> None:
    largest = DAMPER["n_ports"] * math.pi * DAMPER["r_port"] ** 2
    assert_quotes(rf"\| largest valve area n π r² \| {NUMBER} mm² \|", largest * 1e6)
    # §5.1, n_ports and r_port
    assert_quotes(rf"Two circular ports, maximum area {NUMBER} mm² with r_port", largest * 1e6)
    assert_quotes(rf"{NUMBER} mm ports: maximum area {NUMBER}π\({NUMBER} mm\)² = {NUMBER} mm²",
                  2 * DAMPER["r_port"] * 1e3, DAMPER["n_ports"], DAMPER["r_port"] * 1e3, largest * 1e6)


def test_the_spools_stop_leaves_the_ports_partly_covered() -> None:
    # §5.1, x_spool_max: the ports uncover x_s − x_lap; fully at 2 r_port past the lap
    x_max, x_lap = DAMPER["x_spool_max"], DAMPER["x_lap"]
    x_demand = x_max - DEMAND_MARGIN
    full = x_lap + 2 * DAMPER["r_port"]
    assert x_max < full
    assert_quotes(rf"Upper stop at {NUMBER} mm: {NUMBER} mm² open; the force loop demands at most {NUMBER} mm "
                  rf"\({NUMBER} mm²\), full opening \({NUMBER} mm\) is never reached",
                  x_max * 1e3, port_area(x_max - x_lap) * 1e6, x_demand * 1e3, port_area(x_demand - x_lap) * 1e6,
                  full * 1e3)


def test_the_amplifier_delays_the_command_by_whole_controller_samples() -> None:
    # §4.4: a FIFO of round(tau_amp/T_sample) samples
    samples = round(DAMPER["tau_amp"] / DAMPER["T_sample"])
    assert_quotes(rf"\| amplifier delay \| {NUMBER} controller samples \|", samples)
    assert_quotes(rf"\({NUMBER} samples with the defaults; at most 200\)", samples)


def test_both_loops_sample_at_2_kHz() -> None:
    # §5.1, T_sample: the rate is its inverse
    assert_quotes(rf"\| {NUMBER} kHz for both loops", 1 / DAMPER["T_sample"] / 1e3)


def test_the_coil_holds_the_spool_against_its_spring_at_rest() -> None:
    rest = DAMPER["k_spool"] * DAMPER["x_spool_start"] / DAMPER["K_sol"]
    assert_quotes(rf"\| rest coil current k_spool x_spool_start/K_sol \| {NUMBER} A \|", rest)
    assert_quotes(rf"i₀ = k_spool x_spool_start/K_sol = {NUMBER} A, which holds the spool at "
                  rf"x_spool_start = {NUMBER} mm", rest, DAMPER["x_spool_start"] * 1e3)


def test_the_solenoid_pushes_at_most_its_gain_times_the_current_limit() -> None:
    assert_quotes(rf"\| largest solenoid force K_sol I_max \| {NUMBER} N \|", DAMPER["K_sol"] * DAMPER["I_max"])
    assert_quotes(rf"\| {NUMBER} N at {NUMBER} A \[A\]; a proportional solenoid",
                  DAMPER["K_sol"] * DAMPER["I_max"], DAMPER["I_max"])


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
    # §5.1, k1_mount: the mount is stiffer than that column, so the oil sets the lag
    assert DAMPER["k1_mount"] > k_oil
    assert_quotes(rf"Stiffer than the oil column \({NUMBER} MN/m at {NUMBER} bar in extension, §3.4\)",
                  k_oil / 1e6, p_a / 1e5)


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


def test_the_mount_stiffens_only_at_large_forces() -> None:
    # §5.1, k3_mount: g'(δ) = k1 + 3 k3 δ² doubles at δ = sqrt(k1/(3 k3)), where g = k1 δ + k3 δ³
    k1, k3 = DAMPER["k1_mount"], DAMPER["k3_mount"]
    doubled = math.sqrt(k1 / (3 * k3))
    assert_quotes(rf"the tangent stiffness doubles at δ = {NUMBER} mm \({NUMBER} kN\)",
                  doubled * 1e3, (k1 * doubled + k3 * doubled ** 3) / 1e3)
    # §3.4: the fitted table covers ε = k3 u²/k1 ≤ 0.25, u = F/k1, so |F| ≤ sqrt(0.25 k1³/k3)
    epsilon = quoted(rf"from a fitted table up to ε = {NUMBER} \(")[0].value
    assert_quotes(rf"up to ε = [^ ]+ \({NUMBER} kN with the defaults\)", math.sqrt(epsilon * k1 ** 3 / k3) / 1e3)


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
    # §5.1, k_spool: the span of those three
    span = [stiffness(10e3, 0.15), stiffness(20e3, 0.5), stiffness(20e3, 1.0)]
    assert_quotes(rf"Must exceed most of the flow-force negative stiffness \({NUMBER}–{NUMBER} kN/m, §3.6\)",
                  min(span) / 1e3, max(span) / 1e3)


def test_the_spool_is_a_well_damped_159_Hz_oscillator_stiffened_by_its_stops() -> None:
    k, m = DAMPER["k_spool"], DAMPER["m_spool"]
    omega = math.sqrt(k / m)
    assert_quotes(rf"ω_n = sqrt\(k_spool/m_spool\) = {NUMBER} rad/s \({NUMBER} Hz\), damping ratio "
                  rf"c_spool/\(2 sqrt\(k_spool m_spool\)\) = {NUMBER};",
                  omega, omega / (2 * math.pi), DAMPER["c_spool"] / (2 * math.sqrt(k * m)))
    # "6300": sqrt(k_stop/m_spool) = 6325 rad/s to two significant digits
    assert_quotes(rf"the end stops stiffen it to sqrt\(k_stop/m_spool\) = {NUMBER} rad/s",
                  math.sqrt(DAMPER["k_stop"] / m), significant=2)
    # §5.1, c_spool, and §7's stiff sources
    assert_quotes(rf"Damping ratio {NUMBER} with m_spool and k_spool", DAMPER["c_spool"] / (2 * math.sqrt(k * m)))
    assert_quotes(rf"the spool \({NUMBER} rad/s\) and its end stops", omega)
    assert_quotes(rf"and its end stops \({NUMBER} rad/s\)\. The mount adds no pole", math.sqrt(DAMPER["k_stop"] / m),
                  significant=2)


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
    # §5.1, G_bleed_reb
    assert_quotes(rf"\(§3.8 hand check: {NUMBER} kN\)", (dp * a_a - DAMPER["p_reservoir0"] * a_r) / 1e3)


def test_the_passive_orifices_have_their_quoted_diameters() -> None:
    # §5.1: the diameter of a round hole of each area
    assert_quotes(rf"The other half: a {NUMBER} mm bleed orifice", diameter(DAMPER["A_bleed_reb"]) * 1e3)
    assert_quotes(rf"Fully open blow-off: {NUMBER} mm equivalent diameter", diameter(DAMPER["A_open_reb"]) * 1e3)
    assert_quotes(rf"A {NUMBER} mm compression bleed orifice", diameter(DAMPER["A_bleed_comp"]) * 1e3)
    assert_quotes(rf"Fully open base blow-off: {NUMBER} mm equivalent diameter",
                  diameter(DAMPER["A_open_comp"]) * 1e3)


def test_the_blow_offs_open_near_4_kN_either_way() -> None:
    # §3.8 in steady motion: in extension F ≈ Δp A_a − p_r A_r, in compression F ≈ −(p_r + Δp) A_r; the
    # straight part of the blow-off's law passes through Δp = p_open
    _, a_r, a_a = areas()
    p_r = DAMPER["p_reservoir0"]
    assert_quotes(rf"Blow-off at about {NUMBER} kN in extension \({NUMBER} bar on the annulus\)",
                  (DAMPER["p_open_reb"] * a_a - p_r * a_r) / 1e3, DAMPER["p_open_reb"] / 1e5)
    assert_quotes(rf"Blow-off at about {NUMBER} kN in compression \({NUMBER} bar on the rod area, with the gas\)",
                  (p_r + DAMPER["p_open_comp"]) * a_r / 1e3, DAMPER["p_open_comp"] / 1e5)


def test_the_rebound_valve_gives_about_20_kN_at_one_metre_per_second() -> None:
    # §3.8: Q = G Δp + Q_or(Cd, A_bleed, Δp) + Q_or(Cd, A_open s(u), Δp), u = k_open (Δp − p_open)/A_open,
    # at T_ref (μ_r = 1), passing A_a v; F ≈ Δp A_a − p_r A_r (CV2's 3 bar drop would add 0.6 kN)
    _, a_r, a_a = areas()
    a_open, cd = DAMPER["A_open_reb"], DAMPER["Cd_passive"]

    def ramp(u: float) -> float:
        return 0.0 if u <= -0.05 else (u + 0.05) ** 2 / 0.2 if u < 0.05 else u

    def flow(dp: float) -> float:
        u = DAMPER["k_open_reb"] * (dp - DAMPER["p_open_reb"]) / a_open
        area = DAMPER["A_bleed_reb"] + a_open * (ramp(u) - ramp(u - 1))
        return DAMPER["G_bleed_reb"] * dp + PLANT.orifice(cd, area, dp)

    dp = brentq(lambda d: flow(d) - a_a * 1.0, 0.0, 1e9, xtol=1e-3)
    assert_quotes(rf"About {NUMBER} kN at 1 m/s in extension with the bleeds",
                  (dp * a_a - DAMPER["p_reservoir0"] * a_r) / 1e3, significant=1)


# --------------------------------------------------------------------------- §3.9: oil temperature

def test_the_viscosity_halves_every_20_K() -> None:
    # μ_r = exp(−visc_temp_coeff ΔT) halves over ln 2/visc_temp_coeff; the default is ln 2/20 K rounded
    coefficient = math.log(2) / 20
    assert_quotes(rf"visc_temp_coeff = ln 2/20 K = {NUMBER} /K", coefficient)
    assert_quotes(rf"\| `visc_temp_coeff` \| 1/K \| {NUMBER} \| \[S\] \| [^|]*: ln 2/20 K \(§3.9\) \|", coefficient)


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


def test_the_laminar_regularisation_leaves_the_operating_points_alone() -> None:
    # §3.3: at a drop Δp the regularised law passes (1 + (p_transition/Δp)²)^(−1/4) of the turbulent flow,
    # so the area an operating point needs moves by the rest
    def shift(dp: float) -> float:
        return 1 - math.pow(1 + (DAMPER["p_transition"] / dp) ** 2, -0.25)

    assert_quotes(rf"The regularised law at that Δp differs from the turbulent one by {NUMBER} \(relative\)",
                  shift(extension_point(10e3, 0.15)[0]))
    # §5.1, p_transition: a bound on all of §5.3's points, the smallest drop (2 kN) the largest shift
    bound = quoted(rf"changes the operating points by less than {NUMBER} % \(§3.3\)")[0].value / 100
    drops = [extension_point(force, v)[0] for force, v in ((2e3, 0.15), (10e3, 0.15), (20e3, 0.15), (10e3, 1.0))]
    assert max(shift(dp) for dp in drops) < bound


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


# --------------------------------------------------------------------------- §5.2 and §5.4: the trucks

def quarter_truck_hop() -> float:
    """§6.4: the wheel-hop frequency (Hz), the larger root of M_s M_u ω⁴ − (M_s (k_s + k_t) + M_u k_s) ω² + k_s k_t."""
    ms, mu, ks, kt = TRUCK["m_body"], TRUCK["m_axle"], TRUCK["k_susp"], TRUCK["k_tyre"]
    b = ms * (ks + kt) + mu * ks
    return math.sqrt((b + math.sqrt(b * b - 4 * ms * mu * ks * kt)) / (2 * ms * mu)) / (2 * math.pi)


def test_the_passive_damper_is_the_skyhook_laws_relative_velocity_term() -> None:
    # §5.2 and §5.4, c_passive: α·C_m, so that the passive runs compare with the law's own damping
    for truck in (TRUCK, FULL_TRUCK):
        assert math.isclose(truck["c_passive"], truck["alpha"] * truck["Cm"], rel_tol=1e-12)


def test_the_quarter_trucks_step_resolves_the_wheel_hop() -> None:
    # §5.2, h_max: a fraction of the period of the truck's fastest mode, the wheel hop of §6.4
    assert_quotes(rf"RK4 step: {NUMBER} % of the {NUMBER} ms wheel-hop period",
                  TRUCK["h_max"] * quarter_truck_hop() * 100, 1e3 / quarter_truck_hop())


def test_the_road_profile_spans_its_quoted_wavelengths_and_duration() -> None:
    # §5.2: the profile lasts its length over the speed; a spatial frequency n is a wave 1/n long
    assert_quotes(rf"Profile length \(about {NUMBER} s at 14 m/s\)", TRUCK["road_length"] / TRUCK["road_speed"],
                  significant=1)
    assert_quotes(rf"Lowest spatial frequency of the profile \({NUMBER} m waves\)", 1 / TRUCK["road_n_min"])
    assert_quotes(rf"Highest spatial frequency \({NUMBER} m, shorter", 1 / TRUCK["road_n_max"])


def test_the_full_truck_is_six_quarter_trucks() -> None:
    # §5.4: the body carries six corners' sprung mass and each axle two wheel stations' unsprung mass
    assert_quotes(rf"\| `m_body` \| kg \| {NUMBER} \| \[A\] \| Six times Table 1's quarter-truck sprung mass "
                  rf"\({NUMBER} kg a corner\)", 6 * TRUCK["m_body"], TRUCK["m_body"])
    for axle in ("front", "drive1", "drive2"):
        assert_quotes(rf"\| `{axle}.m_axle` \| kg \| {NUMBER} \| \[A\] \| Twice Table 1's unsprung mass "
                      rf"\({NUMBER} kg a side\) \|", 2 * TRUCK["m_axle"], TRUCK["m_axle"])


def test_the_bodys_inertias_are_an_evenly_laden_block() -> None:
    # §5.4, I_pitch and I_roll: a uniform block's moments of inertia from the dimensions their rows give
    mass = FULL_TRUCK["m_body"]
    length = quoted(rf"spread evenly over an {NUMBER} m long body")[0].value
    width, height = (q.value for q in quoted(rf"as a {NUMBER} m wide, {NUMBER} m high block"))
    # the defaults are rounded to the digits they keep: 160 756 to two, 27 812 to three
    assert_quotes(rf"\| `I_pitch` \| kg.m2 \| {NUMBER} \| \[A\] \| [^|]*, M L²/12 \|", mass * length ** 2 / 12,
                  significant=2)
    assert_quotes(rf"\| `I_roll` \| kg.m2 \| {NUMBER} \| \[A\] \| [^|]*, M \(w² \+ h²\)/12 \|",
                  mass * (width ** 2 + height ** 2) / 12, significant=3)


def test_the_centre_of_mass_is_the_axles_centroid() -> None:
    # the front axle at x = 0; on equal springs the centroid loads each corner with a sixth of the body
    x_cg = (0 + FULL_TRUCK["drive1.x_axle"] + FULL_TRUCK["drive2.x_axle"]) / 3
    assert_quotes(rf"\| `x_cg` \| m \| {NUMBER} \| \[A\] \| The centroid of the three axles, so each corner carries "
                  rf"Table 1's {NUMBER} kg", x_cg, FULL_TRUCK["m_body"] / 6)
    assert_quotes(rf"The tandem {NUMBER} m behind the first drive axle",
                  FULL_TRUCK["drive2.x_axle"] - FULL_TRUCK["drive1.x_axle"])


def test_the_axles_roll_inertia_is_their_mass_at_the_wheels() -> None:
    # §5.4, J_axle: the axle's mass m at the row's radius r, J = m r²; the air springs at ±s/2
    radius = quoted(rf"with its wheels about {NUMBER} m from its centre")[0].value
    assert_quotes(rf"from its centre: {NUMBER} m² × {NUMBER} kg \|", radius ** 2, FULL_TRUCK["front.m_axle"])
    # "600": m r² = 607 kg·m² to the one digit the default keeps
    assert_quotes(rf"\| `front.J_axle` \| kg.m2 \| {NUMBER} \|", FULL_TRUCK["front.m_axle"] * radius ** 2,
                  significant=1)
    assert_quotes(rf"about {NUMBER} m either side of its centre", FULL_TRUCK["suspension_track"] / 2)


def body_roll(k_roll: bool = True, gravity: bool = True) -> float:
    """The body's roll frequency (Hz) of §3.10, quasi-statically (the axles' modes are ten times faster): per
    axle, the roll stiffness (if `k_roll`) and the air springs at ±s/2 in series with the tyres at ±t/2,
    summed over the axles, less gravity's M g h_roll (if `gravity`), over I_roll."""
    half_s, half_t = FULL_TRUCK["suspension_track"] / 2, FULL_TRUCK["tyre_track"] / 2
    stiffness = sum(1 / (1 / (FULL_TRUCK[f"{a}.k_roll"] * k_roll + 2 * FULL_TRUCK[f"{a}.k_susp"] * half_s ** 2)
                         + 1 / (2 * FULL_TRUCK[f"{a}.k_tyre"] * half_t ** 2)) for a in ("front", "drive1", "drive2"))
    stiffness -= FULL_TRUCK["m_body"] * FULL_TRUCK["gravity"] * FULL_TRUCK["h_roll"] * gravity
    return math.sqrt(stiffness / FULL_TRUCK["I_roll"]) / (2 * math.pi)


def test_the_roll_stiffness_puts_the_body_roll_near_1_Hz() -> None:
    assert_quotes(rf"{NUMBER} MN·m/rad puts the body's roll mode near {NUMBER} Hz",
                  FULL_TRUCK["front.k_roll"] / 1e6, body_roll(), significant=1)


def test_the_body_rolls_at_0_63_Hz_without_the_roll_stiffness() -> None:
    # §3.10 and §6.6: k_roll = 0 on every axle, gravity's roll moment kept (§6.6's linear model: 0.6300 Hz)
    assert_quotes(rf"without it the body rolls at {NUMBER} Hz\)", body_roll(k_roll=False))
    assert_quotes(rf"Without the roll stiffness k_roll the body rolls at {NUMBER} Hz,", body_roll(k_roll=False))


def test_the_body_rolls_at_1_14_Hz_without_gravitys_roll_moment() -> None:
    # §6.6: M g h_roll left out, k_roll kept (§6.6's linear model: 1.1353 Hz)
    assert_quotes(rf"without gravity's roll moment at {NUMBER} Hz\.", body_roll(gravity=False))


def test_the_full_trucks_step_resolves_the_axles_modes() -> None:
    # each axle on its springs and tyres with the body held: bounce on 2(k_s + k_t), roll on
    # k_roll + 2 k_s (s/2)² + 2 k_t (t/2)² (§6.6's coupled modes are within 0.02 Hz of these)
    half_s, half_t = FULL_TRUCK["suspension_track"] / 2, FULL_TRUCK["tyre_track"] / 2
    modes = []
    for a in ("front", "drive1", "drive2"):
        k_s, k_t = FULL_TRUCK[f"{a}.k_susp"], FULL_TRUCK[f"{a}.k_tyre"]
        modes.append(math.sqrt(2 * (k_s + k_t) / FULL_TRUCK[f"{a}.m_axle"]) / (2 * math.pi))
        roll = FULL_TRUCK[f"{a}.k_roll"] + 2 * k_s * half_s ** 2 + 2 * k_t * half_t ** 2
        modes.append(math.sqrt(roll / FULL_TRUCK[f"{a}.J_axle"]) / (2 * math.pi))
    assert_quotes(rf"RK4 step as the quarter truck: {NUMBER} % of the wheel-hop period \(the axles' modes are "
                  rf"{NUMBER}–{NUMBER} Hz\)", FULL_TRUCK["h_max"] * max(modes) * 100, min(modes), max(modes))


# --------------------------------------------------------------------------- §7: numerics

# The mount's elimination (§3.4) multiplies chamber A's diagonal entry by (g' + b A_p²)/(g' + a A_a² + b A_p²)
# at a steady state (chamber B's by (g' + a A_a²)/(g' + a A_a² + b A_p²)): it lowers §7's poles by 3 % (the
# valve's laminar zone at mid-stroke), 6 % (CV2), a fifth (that zone at the stroke end) and, for the turbulent
# valve at the stroke end between 10 and 200 bar, to 0.2–0.4 of them (−2e3 … −6e3 s⁻¹).


def refilling_pole() -> tuple[float, float]:
    """§7's stiffest pole of chamber B through CV2 in its opening ramp (s⁻¹) and p_B there (Pa).
    ṗ_B = β_e(p_B)/V_B (… + Q_cv2), Q_cv2 = Q(Cd_cv, A_cv(Δp₂), Δp₂), Δp₂ = p_r − p_B: the pole is
    −β_e(p_B)/V_B ∂Q_cv2/∂Δp₂, chamber B at mid-stroke, the reservoir at its pre-charge."""
    _, v_b = volumes_at_mid_stroke()
    p_r = DAMPER["p_reservoir0"]

    def pole(dp: float) -> float:
        area, slope = check_valve(dp)
        return -bulk_modulus(p_r - dp) / v_b * orifice_slope(DAMPER["Cd_cv"], area, dp, slope)

    stiffest = minimize_scalar(pole, bounds=(DAMPER["p_cv_crack"], DAMPER["p_cv_full"]), method="bounded",
                               options={"xatol": 1.0})
    return float(stiffest.fun), p_r - float(stiffest.x)


def laminar_pole_at_mid_stroke() -> float:
    """§7's pole of chamber A at mid-stroke in the valve's laminar zone, Δp = 0, at the reservoir's pressure
    there (the pre-charge), the spool at its stop (s⁻¹)."""
    return valve_pole(volumes_at_mid_stroke()[0], reservoir_pressure(0.0), 0.0)


def laminar_pole_at_stroke_end() -> float:
    """The same at the extension stroke end (V_A = A_a L_dead + V_hose), at the reservoir's pressure the gas
    law gives at that stroke (s⁻¹)."""
    return valve_pole(annulus_at_extension_end(), reservoir_pressure(DAMPER["L_half_stroke"]), 0.0)


def turbulent_poles() -> tuple[float, float, float]:
    """§7's pole of chamber A at the extension stroke end, the spool at its stop, p_A from the reservoir's
    pressure there up to the relief valve's opening: the largest (s⁻¹), the p_A where it is (Pa), and the
    pole at Δp = p_relief (s⁻¹). −β_e(p_A)/V_A ∂Q_v/∂p_A ∝ β_e(p_A)/sqrt(Δp) beyond the laminar zone peaks
    where β_e's relative rise equals 1/(2Δp) and falls beyond."""
    v_a, p_r = annulus_at_extension_end(), reservoir_pressure(DAMPER["L_half_stroke"])
    peak = minimize_scalar(lambda p_a: valve_pole(v_a, p_a, p_a - p_r), bounds=(p_r + 1e5, p_r + DAMPER["p_relief"]),
                           method="bounded", options={"xatol": 1.0})
    return float(peak.fun), float(peak.x), valve_pole(v_a, p_r + DAMPER["p_relief"], DAMPER["p_relief"])


def test_the_refilling_check_valve_gives_the_full_bore_a_pole_near_minus_1e4_per_second() -> None:
    # CV2 in its opening ramp, where the pole is largest (Δp₂ ≈ 0.7 bar, p_B ≈ 4.3 bar: its area's slope adds to
    # the orifice's); wide open at 4 bar it is −2e3 s⁻¹
    pole, p_b = refilling_pole()
    assert_quotes(rf"about {NUMBER} s⁻¹ with CV2 opening at {NUMBER} bar \(chamber B at mid-stroke\)", pole, p_b / 1e5,
                  significant=1)


def test_the_valves_laminar_zone_gives_chamber_A_a_pole_near_minus_1e4_per_second_at_mid_stroke() -> None:
    # Δp = 0, the spool at its stop (at rest, x_spool_start, it is −4.5e3 s⁻¹), the reservoir's 5 bar
    assert_quotes(rf"; - {NUMBER} s⁻¹ in the valve's laminar zone \(Δp → 0\) with the spool at its stop, chamber A "
                  rf"at mid-stroke and the reservoir at {NUMBER} bar;",
                  laminar_pole_at_mid_stroke(), reservoir_pressure(0.0) / 1e5, significant=1)


def test_the_valves_laminar_zone_gives_a_pole_near_minus_7e4_per_second_at_the_extension_stroke_end() -> None:
    # Δp = 0, the spool at its stop, V_A at x_p = L_half_stroke and the reservoir at 3.7 bar (at 5 bar it would be
    # −1.1e5 s⁻¹; the spool at rest gives −3.2e4 s⁻¹)
    assert_quotes(rf"; - {NUMBER} s⁻¹ in that zone with the spool at its stop at the extension stroke end,",
                  laminar_pole_at_stroke_end(), significant=1)
    assert_quotes(rf"at the extension stroke end, where V_A is {NUMBER} cm³ and the reservoir's gas law gives "
                  rf"{NUMBER} bar;",
                  annulus_at_extension_end() * 1e6, reservoir_pressure(DAMPER["L_half_stroke"]) / 1e5)


def test_the_turbulent_valves_pole_peaks_near_minus_2e4_per_second_at_40_bar() -> None:
    # the stroke end and the spool at its stop as above; the peak at p_A = 38 bar, −1.1e4 s⁻¹ at Δp = 200 bar
    peak, p_peak, at_relief = turbulent_poles()
    assert_quotes(rf"falls faster than β_e rises above about {NUMBER} bar, where the pole peaks at {NUMBER} s⁻¹, "
                  rf"and it is {NUMBER} s⁻¹ at the relief valve's opening,",
                  p_peak / 1e5, peak, at_relief, significant=1)
    assert_quotes(rf"at the relief valve's opening, Δp = {NUMBER} bar", DAMPER["p_relief"] / 1e5)


def test_an_explicit_method_needs_steps_of_about_40_us() -> None:
    # classical RK4 is stable for a real pole λ while h|λ| ≤ 2.785: the step is that over the largest chamber
    # pole the sentence quotes (the laminar zone at the stroke end). The spool's stops allow far longer steps:
    # RK4's imaginary-axis limit 2√2 over their 6300 rad/s is about 450 µs.
    largest = max(abs(refilling_pole()[0]), abs(laminar_pole_at_mid_stroke()), abs(laminar_pole_at_stroke_end()),
                  *(abs(pole) for pole in turbulent_poles()[::2]))
    assert 2 * math.sqrt(2) / math.sqrt(DAMPER["k_stop"] / DAMPER["m_spool"]) > 10 * rk4_real_limit() / largest
    assert_quotes(rf"steps of about {NUMBER} µs or less \(classical RK4's real-axis limit, [^ ]+, over {NUMBER} s⁻¹;",
                  rk4_real_limit() / largest * 1e6, largest, significant=1)
    assert_quotes(rf"classical RK4's real-axis limit, {NUMBER}, over", rk4_real_limit())


# --------------------------------------------------------------------------- §8: effects

def test_the_bump_stops_default_is_its_quoted_force_at_6_mm() -> None:
    # the stop's force at the sentence's travel, from the default stiffness of F = k (|x| − x_end_stop)²
    travel = quoted(rf"kN at {NUMBER} mm gives k_end_stop")[0].value
    assert_quotes(rf"{NUMBER} kN at 6 mm gives k_end_stop", DAMPER["k_end_stop"] * (travel * 1e-3) ** 2 / 1e3)
    assert_quotes(rf"at 6 mm gives k_end_stop = {NUMBER} N/m²", DAMPER["k_end_stop"])
    # §5.1, k_end_stop and x_end_stop
    assert_quotes(rf"A polyurethane bump stop: {NUMBER} kN at {NUMBER} mm \(§8\)",
                  DAMPER["k_end_stop"] * (travel * 1e-3) ** 2 / 1e3, travel)
    share = DAMPER["x_end_stop"] / DAMPER["L_half_stroke"] * 100
    assert_quotes(rf"\| {NUMBER} % of the default half stroke \(§8\) \|", share)
    assert_quotes(rf"default x_end_stop = {NUMBER} mm is {NUMBER} % of the default half stroke",
                  DAMPER["x_end_stop"] * 1e3, share)


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
    # §5.1, G_leak
    assert_quotes(rf"πDc³/\(12μL\) for a {NUMBER} µm gap, {NUMBER} mm long, μ = {NUMBER} Pa·s gives "
                  rf"{NUMBER}e-13 \(§8\)", gap * 1e6, length * 1e3, viscosity, conductance(gap) * 1e13)
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


# --------------------------------------------------------------------------- §3.3, §6.4, §6.6: quoted exactly

def test_the_valve_law_and_the_natural_frequencies_are_quoted_as_computed() -> None:
    # §6.4's two-mass roots, §6.6's linear full truck and §3.3's valve hand check, each as the formatted
    # string the document prints
    ms, mu, ks, kt = TRUCK["m_body"], TRUCK["m_axle"], TRUCK["k_susp"], TRUCK["k_tyre"]
    b = ms * (ks + kt) + mu * ks
    root = math.sqrt(b * b - 4 * ms * mu * ks * kt)
    body, hop = (math.sqrt((b + s * root) / (2 * ms * mu)) / (2 * math.pi) for s in (-1, 1))
    markdown = PHYSICS.read_text(encoding="utf-8")
    assert f"body **{body:.3f} Hz**, wheel hop **{hop:.3f} Hz**" in markdown
    roll, pitch, heave = full_truck.natural_frequencies(dict(FULL_TRUCK))[:3]
    assert f"roll **{roll:.3f} Hz**, pitch **{pitch:.3f} Hz**, heave **{heave:.3f} Hz**" in markdown
    _, a_rod, a_annulus = areas()
    dp = (10e3 + DAMPER["p_reservoir0"] * a_rod) / a_annulus
    area = a_annulus * 0.15 / (DAMPER["Cd_valve"] * math.sqrt(2 * dp / DAMPER["rho"]))
    assert f"{dp / 1e6:.3f} MPa ({dp / 1e5:.1f} bar)" in markdown
    assert f"= {area * 1e6:.2f} mm²" in markdown
