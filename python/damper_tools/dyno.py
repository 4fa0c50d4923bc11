"""Dyno records of PASSIVE twin-tube dampers, made by an independent model, with their truth.

    .venv/bin/python -m damper_tools.dyno --size car --seed 3 --scenario calibration --out out/dyno/car_3
    .venv/bin/python -m damper_tools.dyno --fv out/dyno/fv_presets.png     # the presets' F-v curves
    .venv/bin/python -m damper_tools.dyno --gas-release docs/figures/gas_release.png

The diagnosis (`damper`, Rust) models a passive damper with the circuit of docs/physics.md §2 and the
passive valves of §3.8. The records here are made by a second implementation of that physics, written
from the documented equations only (numpy/scipy, not a port of the Rust code):

- states p_A, p_B (Pa, gauge) and the gas volume V_g (m3); the stroke x(t) is the dyno's CONTINUOUS
  prescribed displacement, given in closed form with its velocity and acceleration;
- chambers A (annulus) and B (full bore) of §3.1, oil with entrained air (§3.2, the absolute pressure
  frozen at 0.02 atm below it) and, in the gas_release scenario, the gas that the oil, saturated at the
  reservoir's pre-charge, lets out below it (§3.2, Henry's law at equilibrium), the gas reservoir
  polytropic and scaled with T_oil/T_ref (§3.5, §3.9);
- check valves CV1 (B -> A) and CV2 (reservoir -> B) with the smoothstep cracking law and the
  regularised orifice law of §3.3; no proportional valve and no relief valve;
- the rebound valve (A -> B) and the compression valve (B -> reservoir) of §3.8: laminar bleed
  G dp/mu_r, orifice bleed and blow-off A_open s(u) with the rounded ramp (e = 0.1);
- seal friction F_coulomb tanh(v/v_friction) and end stops sign(x) k max(|x| - x0, 0)^2 in the load
  path (§8), evaluated at the stroke x and its velocity v as documented;
- the mount: a massless cubic spring k1 d + k3 d^3 = F in series (§3.4). Its deflection d is solved
  from the load-cell force F (the real root of the cubic, Cardano's hyperbolic form) and its rate
  from the derivative of that constraint, including the rate of the friction and end-stop forces;
  the piston moves at v - d'(t);
- the load-cell force F = p_A A_a - p_B A_p + friction + end stops (tension +, extension velocity +).

Integration: scipy's LSODA (stiff/non-stiff switching, rtol 1e-9, steps <= 1 ms) segment by segment
of the motion (each segment is smooth: the solver never steps over a kink), the true force kept every
0.1 ms; Radau (`method=`) gives the same forces within 1e-4 N. The measurement chain is drawn per
record: sample rate 500/1000/2000 Hz, a first-order anti-alias filter on every analog channel
(integrated exactly on the 0.1 ms signals), load-cell noise partly before and partly after it, LVDT
noise, quantisation, velocity either differentiated from the displacement and zero-phase filtered by
the logger (filtfilt Butterworth) or from a velocity transducer, a thermocouple column (T_oil, degC),
timestamps in ISO 8601 or seconds, forces in N or kN.

The files of `--out DIR`: `<size>_<seed>_<scenario>[_k].csv` (the records), a `.json` truth beside
each (every parameter by FMU name, truth and nominal, what the scenario changed, the motion, the
oil temperature, the sensors and seeds), and `<size>_<seed>_datasheet.toml`.

Three dampers (`small`, `car`, `truck`): NOMINAL datasheet values (written as the damper TOML of
crates/damper_engine/src/damper_template.toml) and, per seed, the TRUTH: the nominal values perturbed
by manufacturing spreads for what a datasheet cannot know (SPREADS). Scenarios: calibration (three
records at 20 degC), unchanged, gas (pre-charge changed), valve (a bleed adjuster changed), heated
(the oil 30-50 K warmer), end_stop (the stroke beyond the bump rubbers), gas_release (the oil has
absorbed the reservoir's gas: saturated at the pre-charge, it lets gas out below it), settings (a calibration
campaign over three settings of one bleed adjuster: a gas record and a peak-velocity record at the
middle setting, a peak-velocity record closed, a random record open; each record's truth JSON
names its setting and the adjuster's value). Every parameter is named as in the FMU's
modelDescription.xml. The same arguments give the same bytes.
"""

import argparse
import json
import math
import time as wallclock
from bisect import bisect_right
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any, Literal

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from scipy.signal import butter, filtfilt

from damper_tools import FloatArray, pyplot
from damper_tools.fmu import Value
from damper_tools.independent import lowpass_fine
from damper_tools.sensors import quantise

P_ATM = 101325.0  # Pa
T_ZERO = 273.15  # K at 0 degC
FINE_STEP = 1e-4  # s: the truth's output step
# scipy solve_ivp's methods.
Method = Literal["RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA"]
METHOD: Method = "LSODA"  # scipy solve_ivp method (stiff switching); "Radau" gives the same forces within 1e-4 N
RTOL = 1e-9  # relative tolerance
MAX_STEP = 1e-3  # s: the largest step
ATOL = (1e-3, 1e-3, 1e-15)  # Pa, Pa, m3
P_ABS_FLOOR = 0.02 * P_ATM  # Pa: the bulk modulus's absolute pressure is frozen below it (§3.2)
ROUNDING = 0.1  # the blow-off's rounded ramp (§3.8)
RELEASE_BAND = 1e4  # Pa: gas starts to come out of solution over +/- this around saturation (§3.2)
SOLUBILITY = (0.02, 0.09)  # the gas_release scenario's Bunsen coefficient, drawn log-uniformly
RELEASE_PARAMETERS = ("gas_solubility", "p_saturation")  # what the gas_release scenario adds
SIZES = ("small", "car", "truck")
# (new scenarios go last: a scenario's random streams are keyed by its place here)
SCENARIOS = ("calibration", "unchanged", "gas", "valve", "heated", "end_stop", "settings", "gas_release")
RATES = (500, 1000, 2000)  # Hz
MARGIN = 0.005  # m: the programs stay this far inside x_end_stop (except end_stop)

# --------------------------------------------------------------------------- the three dampers

# Nominal datasheet values, SI, named as the FMU's parameters. small: a 25 mm cab or seat damper,
# about 0.3 kN at 0.5 m/s; car: a 40 mm twin-tube car damper, about 3 kN; truck: the model's
# default geometry (70/50 mm), about 25-30 kN.
_COMMON = {"n_polytropic": 1.4, "rho": 870.0, "beta_oil": 1.5e9, "air_fraction": 0.005, "p_transition": 5000.0,
           "Cd_cv": 0.7, "Cd_passive": 0.7, "T_ref": 293.15, "visc_temp_coeff": 0.035}
NOMINAL: dict[str, dict[str, float]] = {
    "small": {**_COMMON,
              "D_piston": 0.025, "D_rod": 0.010, "L_half_stroke": 0.05, "L_dead": 0.004, "V_hose": 1e-6,
              "p_reservoir0": 3e5, "V_gas0": 5e-5,
              "A_cv_max": 2.5e-5, "p_cv_crack": 2e4, "p_cv_full": 6e4, "A_cv_leak": 2e-10,
              "G_bleed_reb": 4.5e-11, "A_bleed_reb": 6.5e-7, "p_open_reb": 3e5, "k_open_reb": 1.5e-11,
              "A_open_reb": 1e-5,
              "G_bleed_comp": 1.2e-11, "A_bleed_comp": 3e-7, "p_open_comp": 8e5, "k_open_comp": 6e-12,
              "A_open_comp": 5e-6,
              "F_coulomb": 8.0, "v_friction": 0.005, "k1_mount": 1e7, "k3_mount": 2e12,
              "x_end_stop": 0.04, "k_end_stop": 1e7},
    "car": {**_COMMON,
            "D_piston": 0.040, "D_rod": 0.020, "L_half_stroke": 0.06, "L_dead": 0.005, "V_hose": 3e-6,
            "p_reservoir0": 6e5, "V_gas0": 1.5e-4,
            "A_cv_max": 8e-5, "p_cv_crack": 3e4, "p_cv_full": 1e5, "A_cv_leak": 5e-10,
            "G_bleed_reb": 1.5e-11, "A_bleed_reb": 1.4e-6, "p_open_reb": 1.1e6, "k_open_reb": 3e-12,
            "A_open_reb": 1.2e-5,
            "G_bleed_comp": 1.1e-11, "A_bleed_comp": 6e-7, "p_open_comp": 1.1e6, "k_open_comp": 9.5e-13,
            "A_open_comp": 6e-6,
            "F_coulomb": 40.0, "v_friction": 0.005, "k1_mount": 2e7, "k3_mount": 1e13,
            "x_end_stop": 0.05, "k_end_stop": 1e8},
    "truck": {**_COMMON,
              "D_piston": 0.070, "D_rod": 0.050, "L_half_stroke": 0.10, "L_dead": 0.005, "V_hose": 1e-5,
              "p_reservoir0": 5e5, "V_gas0": 1e-3,
              "A_cv_max": 2e-4, "p_cv_crack": 3e4, "p_cv_full": 1e5, "A_cv_leak": 1e-9,
              "G_bleed_reb": 1.5e-11, "A_bleed_reb": 9e-7, "p_open_reb": 2e6, "k_open_reb": 1e-12,
              "A_open_reb": 2e-5,
              "G_bleed_comp": 4e-11, "A_bleed_comp": 3.5e-6, "p_open_comp": 7e5, "k_open_comp": 5e-12,
              "A_open_comp": 2.5e-5,
              "F_coulomb": 200.0, "v_friction": 0.01, "k1_mount": 5e7, "k3_mount": 2e13,
              "x_end_stop": 0.09, "k_end_stop": 5e8},
}
PARAMETERS = tuple(NOMINAL["truck"])

# Manufacturing spreads a datasheet cannot know: a relative half-width (uniform factor 1 +/- s), or
# ("log", lo, hi) for a value drawn log-uniformly. Geometry, gas volume, oil, check valves, blow-off
# areas, end stops and friction velocity are known exactly.
SPREADS: dict[str, float | tuple[str, float, float]] = {
    "A_bleed_reb": 0.25, "A_bleed_comp": 0.25, "p_open_reb": 0.15, "p_open_comp": 0.15,
    "k_open_reb": 0.25, "k_open_comp": 0.25, "G_bleed_reb": 0.40, "G_bleed_comp": 0.40,
    "p_reservoir0": 0.10, "air_fraction": ("log", 0.002, 0.02), "k1_mount": 0.40, "k3_mount": 0.40,
    "F_coulomb": 0.30,
}
# Load-cell noise (total sigma, N) and ADC quanta (N) by size.
LOAD_CELL = {"small": ((1.5, 4.0), (0.1, 0.2)), "car": ((6.0, 15.0), (0.5, 1.0)),
             "truck": ((20.0, 45.0), (1.0, 2.0, 5.0))}


def _stream(*key: int) -> np.random.Generator:
    """numpy's PCG64 generator for a key of integers (20262 tags this module)."""
    return np.random.default_rng(np.random.SeedSequence([20262, *key]))


def truth_parameters(size: str, seed: int) -> dict[str, float]:
    """The TRUTH of damper (size, seed): the nominal values with the SPREADS drawn (same for every
    scenario of the seed)."""
    rng = _stream(SIZES.index(size), seed, 1)
    p = dict(NOMINAL[size])
    for name in sorted(SPREADS):
        s = SPREADS[name]
        if isinstance(s, tuple):
            p[name] = float(math.exp(rng.uniform(math.log(s[1]), math.log(s[2]))))
        else:
            p[name] = float(p[name] * (1.0 + rng.uniform(-s, s)))
    return p


# --------------------------------------------------------------------------- the physics (docs/physics.md)

def areas(p: dict[str, float]) -> tuple[float, float, float]:
    """Full bore A_p, rod A_r and annulus A_a = A_p - A_r (m2)."""
    a_p, a_r = math.pi * p["D_piston"] ** 2 / 4, math.pi * p["D_rod"] ** 2 / 4
    return a_p, a_r, a_p - a_r


def smoothstep(u: float) -> float:
    """3u^2 - 2u^3 of u clamped to [0, 1] (the check valves' opening, §3.3)."""
    u = min(max(u, 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


def rounded_ramp(u: float) -> float:
    """s(u) = ramp(u) - ramp(u - 1), ramp rounded over a tenth centred on 0 (§3.8): the blow-off's
    opening fraction, 0 below its preload, 1 on its stop, = u between, continuously differentiable."""
    half = ROUNDING / 2

    def ramp(w: float) -> float:
        if w <= -half:
            return 0.0
        return (w + half) ** 2 / (2 * ROUNDING) if w < half else w
    return ramp(u) - ramp(u - 1.0)


class Circuit:
    """The passive damper's hydraulic circuit with parameters `p` (SI, FMU names): flows (m3/s) of
    the orifices and valves, the oil's bulk modulus, the gas pressure and the mount."""

    def __init__(self, p: dict[str, float]):
        self.p = dict(p)
        self.a_p, self.a_r, self.a_a = areas(p)
        self.k_orifice = math.sqrt(2.0 / p["rho"])
        self.pt2 = p["p_transition"] ** 2

    def orifice(self, cd_area: float, dp: float) -> float:
        """Q = Cd A sqrt(2/rho) dp / (dp^2 + p_transition^2)^(1/4): turbulent, laminar near dp = 0 (§3.3)."""
        q: float = cd_area * self.k_orifice * dp / (dp * dp + self.pt2) ** 0.25
        return q

    def check_valve(self, dp: float) -> float:
        """CV1 or CV2 passing forwards at dp > 0: leakage area plus the smoothstep opening between
        p_cv_crack and p_cv_full (§3.3)."""
        p = self.p
        area = p["A_cv_leak"] + p["A_cv_max"] * smoothstep((dp - p["p_cv_crack"]) / (p["p_cv_full"] - p["p_cv_crack"]))
        return self.orifice(p["Cd_cv"] * area, dp)

    def passive_valve(self, which: str, dp: float, mu_r: float) -> float:
        """Rebound (which = 'reb', A -> B) or compression valve ('comp', B -> reservoir) at dp (§3.8):
        laminar bleed G dp/mu_r, orifice bleed, blow-off of area A_open s(k_open (dp - p_open)/A_open)."""
        p = self.p
        a_open = p[f"A_open_{which}"]
        # the blow-off opens forwards only
        opening = a_open * rounded_ramp(p[f"k_open_{which}"] * (dp - p[f"p_open_{which}"]) / a_open) if dp > 0 else 0.0
        return (p[f"G_bleed_{which}"] * dp / mu_r
                + self.orifice(p["Cd_passive"] * (p[f"A_bleed_{which}"] + opening), dp))

    def bulk_modulus(self, pressure: float) -> float:
        """beta_e of oil with entrained air (§3.2), the absolute pressure frozen at 0.02 atm below it;
        with gas_solubility in the parameters, the gas released below p_saturation added to the air."""
        p = self.p
        p_abs = max(pressure + P_ATM, P_ABS_FLOOR)
        r = (P_ATM / p_abs) ** (1.0 / p["n_polytropic"])
        free, released_per_pa = self.released_gas(p_abs)
        alpha = p["air_fraction"] + free
        beta: float = (1.0 + alpha * r) / (1.0 / p["beta_oil"] + alpha * r / (p["n_polytropic"] * p_abs)
                                           + released_per_pa * r)
        return beta

    def released_gas(self, p_abs: float) -> tuple[float, float]:
        """Gas out of solution at the absolute pressure p_abs (§3.2): its volume at p_atm per oil volume,
        L h(u)/p_atm, and how much more comes out per pascal of pressure drop, L h'(u)/p_atm, where
        u = p_sat,abs - p_abs and h is max(u, 0) rounded over +/-RELEASE_BAND (a quartic in the band,
        its slope the smoothstep). Nothing without gas_solubility."""
        solubility = self.p.get("gas_solubility", 0.0)
        if solubility == 0.0:
            return 0.0, 0.0
        u = self.p["p_saturation"] + P_ATM - p_abs
        if u <= -RELEASE_BAND:
            return 0.0, 0.0
        if u >= RELEASE_BAND:
            return solubility * u / P_ATM, solubility / P_ATM
        t = (u + RELEASE_BAND) / (2.0 * RELEASE_BAND)
        return solubility * RELEASE_BAND * t ** 3 * (2.0 - t) / P_ATM, solubility * smoothstep(t) / P_ATM

    def gas_pressure(self, v_gas: float, temperature: float) -> float:
        """Reservoir pressure (gauge): polytropic from the pre-charge at V_gas0, its absolute value
        scaled with T/T_ref (§3.5, §3.9)."""
        p = self.p
        pressure: float = ((p["p_reservoir0"] + P_ATM) * (p["V_gas0"] / v_gas) ** p["n_polytropic"]
                           * temperature / p["T_ref"] - P_ATM)
        return pressure

    def viscosity_ratio(self, temperature: float) -> float:
        """mu(T)/mu(T_ref) = exp(-b (T - T_ref)) (§3.9)."""
        return math.exp(-self.p["visc_temp_coeff"] * (temperature - self.p["T_ref"]))

    def load_path(self, x: float, v: float, a: float) -> tuple[float, float]:
        """Seal friction plus end stops at stroke x, velocity v (§8), and its rate for acceleration a."""
        p = self.p
        th = math.tanh(v / p["v_friction"])
        beyond = max(abs(x) - p["x_end_stop"], 0.0)
        force = p["F_coulomb"] * th + math.copysign(p["k_end_stop"] * beyond * beyond, x)
        rate = p["F_coulomb"] * (1.0 - th * th) * a / p["v_friction"] + 2.0 * p["k_end_stop"] * beyond * v
        return force, rate

    def mount_deflection(self, force: float) -> float:
        """The real root d of k1 d + k3 d^3 = F (Cardano, hyperbolic form for a cubic with one real root)."""
        k1, k3 = self.p["k1_mount"], self.p["k3_mount"]
        if k3 <= 0.0:
            return force / k1
        q = k1 / k3
        return 2.0 * math.sqrt(q / 3.0) * math.sinh(math.asinh(1.5 * force / k1 * math.sqrt(3.0 / q)) / 3.0)

    def volumes(self, x_piston: float) -> tuple[float, float]:
        """V_A (annulus, with the hose) and V_B (full bore) at piston stroke x_p (§3.1), floored at 1e-7 m3."""
        p = self.p
        v_a = self.a_a * (p["L_half_stroke"] + p["L_dead"] - x_piston) + p["V_hose"]
        v_b = self.a_p * (p["L_half_stroke"] + p["L_dead"] + x_piston)
        return max(v_a, 1e-7), max(v_b, 1e-7)

    def rhs(self, y: FloatArray, x: float, v: float, a: float, temperature: float) -> list[float]:
        """d/dt [p_A, p_B, V_g] (§3.4, §3.5, §3.8) for the stroke x, its velocity v and acceleration a."""
        p_a, p_b, v_gas = float(y[0]), float(y[1]), float(y[2])
        mu_r = self.viscosity_ratio(temperature)
        p_r = self.gas_pressure(v_gas, temperature)
        f_e, f_e_rate = self.load_path(x, v, a)
        force = p_a * self.a_a - p_b * self.a_p + f_e
        delta = self.mount_deflection(force)
        v_a, v_b = self.volumes(x - delta)
        q_cv1 = self.check_valve(p_b - p_a)  # B -> A
        q_cv2 = self.check_valve(p_r - p_b)  # reservoir -> B
        q_reb = self.passive_valve("reb", p_a - p_b, mu_r)  # A -> B
        q_comp = self.passive_valve("comp", p_b - p_r, mu_r)  # B -> reservoir
        r_a = q_cv1 - q_reb
        r_b = -q_cv1 + q_cv2 + q_reb - q_comp
        ka, kb = self.bulk_modulus(p_a) / v_a, self.bulk_modulus(p_b) / v_b
        k_h = ka * self.a_a ** 2 + kb * self.a_p ** 2
        s = ka * self.a_a * r_a - kb * self.a_p * r_b
        k_mount = self.p["k1_mount"] + 3.0 * self.p["k3_mount"] * delta * delta
        v_piston = v - (k_h * v + s + f_e_rate) / (k_mount + k_h)
        return [ka * (self.a_a * v_piston + r_a), kb * (-self.a_p * v_piston + r_b), q_cv2 - q_comp]

    def rest_state(self, x0: float, temperature: float) -> list[float]:
        """At rest at stroke x0: V_g = V_gas0 + A_r x0 (the pre-charge holds at mid-stroke), both
        chambers at the gas pressure (§3.5)."""
        v_gas = self.p["V_gas0"] + self.a_r * x0
        p_r = self.gas_pressure(v_gas, temperature)
        return [p_r, p_r, v_gas]


# --------------------------------------------------------------------------- steady force (F-v curves)

def _solve_flow(flow: Callable[[float], float], target: float) -> float:
    """The pressure drop dp >= 0 at which flow(dp) = target (> 0)."""
    hi = 1e4
    while flow(hi) < target:
        hi *= 2.0
        if hi > 1e10:
            raise ValueError("no pressure drop passes this flow")
    return brentq(lambda dp: flow(dp) - target, 0.0, hi, xtol=1e-9, rtol=1e-14)


def steady_force(p: dict[str, float], v: float, temperature: float | None = None, x: float = 0.0) -> float:
    """The load-cell force (N) in steady motion at velocity v (m/s) and stroke x: incompressible flow
    balance, gas pressure at V_gas0 + A_r x (§3.8 'In steady motion', with the check valves' drops).
    Extension: the rebound valve (and CV1's leak backwards) pass A_a v, CV2 (and the compression
    valve's bleeds backwards) A_r v; compression: CV1 (and the rebound bleeds backwards) pass
    A_a |v|, the compression valve (and CV2's leak backwards) A_r |v|."""
    c = Circuit(p)
    t = p["T_ref"] if temperature is None else temperature
    mu_r = c.viscosity_ratio(t)
    p_r = c.gas_pressure(p["V_gas0"] + c.a_r * x, t)
    f_e, _ = c.load_path(x, v, 0.0)
    if v == 0.0:
        return -p_r * c.a_r + f_e
    if v > 0:
        dp_reb = _solve_flow(lambda d: c.passive_valve("reb", d, mu_r) - c.check_valve(-d), c.a_a * v)
        dp_cv2 = _solve_flow(lambda d: c.check_valve(d) - c.passive_valve("comp", -d, mu_r), c.a_r * v)
        p_b = p_r - dp_cv2
        return dp_reb * c.a_a - p_b * c.a_r + f_e
    dp_cv1 = _solve_flow(lambda d: c.check_valve(d) - c.passive_valve("reb", -d, mu_r), -c.a_a * v)
    dp_comp = _solve_flow(lambda d: c.passive_valve("comp", d, mu_r) - c.check_valve(-d), -c.a_r * v)
    p_b = p_r + dp_comp
    return -p_b * c.a_r - dp_cv1 * c.a_a + f_e


# --------------------------------------------------------------------------- dyno motion programs

@dataclass
class Segment:
    """A smooth piece of the prescribed displacement: x0 + shape(tau), tau from 0 to `duration`.
    kind: hold; move (cycloidal, dx, peak velocity 2 dx/T); cruise (constant velocity `v` between
    raised-cosine ramps of `t_ramp`); cosine (x0 + A (cos w tau - 1), whole cycles from a top dead
    point); random (a sum of sines faded in and out)."""
    kind: str
    duration: float
    x0: float = 0.0
    dx: float = 0.0
    v: float = 0.0
    t_ramp: float = 0.0
    amplitude: float = 0.0
    omega: float = 0.0
    t_fade: float = 0.0
    freqs: list[float] = field(default_factory=list)  # rad/s
    amps: list[float] = field(default_factory=list)  # m
    phases: list[float] = field(default_factory=list)  # rad

    def __post_init__(self) -> None:
        w, a = np.asarray(self.freqs, dtype=float), np.asarray(self.amps, dtype=float)
        self._w, self._phi = w, np.asarray(self.phases, dtype=float)
        self._moments = np.array([a, a * w, a * w * w])  # the sum of sines and its two derivatives

    @property
    def end(self) -> float:
        """The displacement at the segment's end."""
        return self.x0 + {"move": self.dx, "cruise": self.v * (self.duration - self.t_ramp)}.get(self.kind, 0.0)

    def state(self, tau: float) -> tuple[float, float, float]:
        """(x, v, a) at tau (scalar)."""
        if self.kind == "hold":
            return self.x0, 0.0, 0.0
        if self.kind == "move":
            s, w = tau / self.duration, 2 * math.pi / self.duration
            return (self.x0 + self.dx * (s - math.sin(w * tau) / (2 * math.pi)),
                    self.dx / self.duration * (1 - math.cos(w * tau)), self.dx / self.duration * w * math.sin(w * tau))
        if self.kind == "cruise":
            tr, tc, v = self.t_ramp, self.duration - 2 * self.t_ramp, self.v
            w = math.pi / tr
            if tau < tr:
                return (self.x0 + v * (tau / 2 - math.sin(w * tau) / (2 * w)), v * (1 - math.cos(w * tau)) / 2,
                        v * w * math.sin(w * tau) / 2)
            if tau <= tr + tc:
                return self.x0 + v * (tr / 2 + tau - tr), v, 0.0
            u = tau - tr - tc
            return (self.x0 + v * (tr / 2 + tc + u / 2 + math.sin(w * u) / (2 * w)), v * (1 + math.cos(w * u)) / 2,
                    -v * w * math.sin(w * u) / 2)
        if self.kind == "cosine":
            c, s = math.cos(self.omega * tau), math.sin(self.omega * tau)
            return (self.x0 + self.amplitude * (c - 1), -self.amplitude * self.omega * s,
                    -self.amplitude * self.omega ** 2 * c)
        # random: x0 + w(tau) s(tau) with a sin^2 fade-in and fade-out
        m = self._moments @ np.exp(1j * (self._w * tau + self._phi))
        s0, s1, s2 = m[0].imag, m[1].real, -m[2].imag
        w0, w1, w2 = self._fade(tau)
        return self.x0 + w0 * s0, w1 * s0 + w0 * s1, w2 * s0 + 2 * w1 * s1 + w0 * s2

    def _fade(self, tau: float) -> tuple[float, float, float]:
        """The random segment's window over t_fade at both ends, the quintic 10u^3 - 15u^4 + 6u^5
        (its first two derivatives vanish at both ends of the fade), and its two derivatives."""
        tf = self.t_fade
        if tf < tau < self.duration - tf:
            return 1.0, 0.0, 0.0
        u, sign = (tau / tf, 1.0) if tau <= tf else ((self.duration - tau) / tf, -1.0)
        u = min(max(u, 0.0), 1.0)
        return (u ** 3 * (10 - 15 * u + 6 * u * u), sign * 30 * u * u * (1 - u) ** 2 / tf,
                60 * u * (1 - u) * (1 - 2 * u) / tf ** 2)

    def arrays(self, tau: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(x, v) at many tau (vectorised `state`)."""
        tau = np.asarray(tau, dtype=float)
        if self.kind == "hold":
            return np.full(tau.shape, self.x0), np.zeros(tau.shape)
        if self.kind == "move":
            w = 2 * np.pi / self.duration
            return (self.x0 + self.dx * (tau / self.duration - np.sin(w * tau) / (2 * np.pi)),
                    self.dx / self.duration * (1 - np.cos(w * tau)))
        if self.kind == "cosine":
            return (self.x0 + self.amplitude * (np.cos(self.omega * tau) - 1),
                    -self.amplitude * self.omega * np.sin(self.omega * tau))
        if self.kind == "cruise":
            tr, tc, v = self.t_ramp, self.duration - 2 * self.t_ramp, self.v
            w = np.pi / tr
            u = np.clip(tau - tr - tc, 0.0, None)
            r = np.minimum(tau, tr)
            x = (self.x0 + v * (r / 2 - np.sin(w * r) / (2 * w)) + v * np.clip(tau - tr, 0.0, tc)
                 + v * (u / 2 + np.sin(w * u) / (2 * w)))
            vel = np.where(tau < tr, v * (1 - np.cos(w * r)) / 2,
                           np.where(tau <= tr + tc, v, v * (1 + np.cos(w * u)) / 2))
            return x, vel
        arg = np.outer(tau, self._w) + self._phi
        s0, s1 = np.sin(arg) @ self._moments[0], np.cos(arg) @ self._moments[1]
        tf = self.t_fade
        u = np.clip(np.minimum(tau, self.duration - tau) / tf, 0.0, 1.0)
        sign = np.where(tau <= tf, 1.0, np.where(tau >= self.duration - tf, -1.0, 0.0))
        w0, w1 = u ** 3 * (10 - 15 * u + 6 * u * u), sign * 30 * u * u * (1 - u) ** 2 / tf
        return self.x0 + w0 * s0, w1 * s0 + w0 * s1


@dataclass
class Motion:
    """The dyno's program: segments run one after another (each starts where the last ended), all
    durations whole multiples of the fine step; `name` and `description` for the truth."""
    segments: list[Segment]
    name: str = ""
    description: str = ""

    def __post_init__(self) -> None:
        self.starts = [0.0]
        x = self.segments[0].x0
        for seg in self.segments:
            cycles = round(seg.omega * seg.duration / (2 * math.pi))
            seg.duration = round(seg.duration / FINE_STEP) * FINE_STEP
            if seg.kind == "cosine":  # whole cycles in the rounded duration: the blocks join at rest
                seg.omega = 2 * math.pi * cycles / seg.duration
            seg.x0 = x
            x = seg.end
            self.starts.append(self.starts[-1] + seg.duration)

    @property
    def duration(self) -> float:
        return self.starts[-1]

    def state(self, t: float) -> tuple[float, float, float]:
        i = min(bisect_right(self.starts, t) - 1, len(self.segments) - 1)
        return self.segments[i].state(t - self.starts[i])

    def arrays(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        """(x, v) at many times t (increasing)."""
        t = np.asarray(t, dtype=float)
        i = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.segments) - 1)
        x, v = np.empty(t.shape), np.empty(t.shape)
        for k, seg in enumerate(self.segments):
            at = i == k
            if at.any():
                x[at], v[at] = seg.arrays(t[at] - self.starts[k])
        return x, v


def _cruise(v: float, distance: float, t_ramp: float) -> Segment:
    """A constant-velocity stretch covering `distance` (signed, with v's sign) with its ramps."""
    return Segment("cruise", abs(distance / v) + t_ramp, v=v, t_ramp=t_ramp)


def gas_program(rng: np.random.Generator, size: str, quick: bool = False) -> Motion:
    """(a) The gas force against stroke: 0 -> +A -> -A -> 0 at a constant 3-5 mm/s (a rounded
    triangle), after 1 s at rest."""
    v = rng.uniform(0.003, 0.005)
    amp = (0.003 if quick else {"small": 0.012, "car": 0.015, "truck": 0.02}[size]) * rng.uniform(0.9, 1.1)
    tr = 0.25
    segs = [Segment("hold", 0.5 if quick else 1.0), _cruise(v, amp, tr), Segment("hold", 0.2),
            _cruise(-v, -2 * amp, tr), Segment("hold", 0.2), _cruise(v, amp, tr), Segment("hold", 0.5)]
    return Motion(segs, "gas", f"gas-force program: rounded triangle at {v * 1e3:.2f} mm/s between "
                               f"+/-{amp * 1e3:.1f} mm (ramps {tr} s), rests at the ends")


def peak_velocity_program(rng: np.random.Generator, size: str, p: dict[str, float], quick: bool = False,
                          velocities: tuple[float, ...] = (0.025, 0.05, 0.1, 0.2, 0.3, 0.5)) -> Motion:
    """(b) The peak-velocity (CVP) program: sines at a constant stroke amplitude whose frequency sets
    each peak velocity, two or three cycles each, from a top dead point (the blocks join at rest)."""
    amp = {"small": 0.012, "car": 0.02, "truck": 0.025}[size] * rng.uniform(0.8, 1.0)
    amp = min(amp, p["x_end_stop"] - MARGIN)
    if quick:
        velocities = (0.05, 0.3)
    segs = [Segment("hold", 0.5), Segment("move", 0.25 + 2 * amp / 0.05, dx=amp)]
    for vp in velocities:
        cycles = 1 if quick else (2 if vp <= 0.05 else 3)
        w = vp / amp
        segs.append(Segment("cosine", cycles * 2 * math.pi / w, amplitude=amp, omega=w))
    segs += [Segment("move", 0.25 + 2 * amp / 0.05, dx=-amp), Segment("hold", 0.3)]
    cycles_text = "1 cycle each" if quick else "2 cycles up to 0.05 m/s, 3 above"
    return Motion(segs, "peak_velocity", f"peak-velocity sine sequence at {amp * 1e3:.1f} mm amplitude, peak "
                                         f"velocities {', '.join(f'{v:g}' for v in velocities)} m/s, "
                                         f"{cycles_text}, from the top point")


def random_program(rng: np.random.Generator, size: str, p: dict[str, float], quick: bool = False) -> Motion:
    """(c) Band-limited random displacement: 60 sines 0.5-12 Hz, amplitudes 1/f (a flat velocity
    spectrum) scaled to a drawn velocity RMS, faded in and out over 0.5 s (a quintic window), scaled
    down if needed to stay MARGIN inside the end stops."""
    duration = 2.0 if quick else rng.uniform(8.0, 10.0)
    v_range = {"small": (0.12, 0.2), "car": (0.12, 0.25), "truck": (0.1, 0.2)}[size]
    v_rms = rng.uniform(*v_range)
    f = np.geomspace(0.5, 12.0, 60)
    phases = rng.uniform(0, 2 * math.pi, f.size)
    amps = 1.0 / (2 * math.pi * f)
    amps *= v_rms * math.sqrt(2) / math.sqrt(np.sum((amps * 2 * math.pi * f) ** 2))
    seg = Segment("random", duration, t_fade=0.5, freqs=(2 * math.pi * f).tolist(), amps=amps.tolist(),
                  phases=phases.tolist())
    tau = np.arange(0.0, duration, 1e-3)
    peak = float(np.max(np.abs(seg.arrays(tau)[0])))
    limit = p["x_end_stop"] - MARGIN
    scale = min(1.0, 0.95 * limit / peak)
    seg = Segment("random", duration, t_fade=0.5, freqs=seg.freqs, amps=(amps * scale).tolist(), phases=seg.phases)
    return Motion([Segment("hold", 0.5), seg, Segment("hold", 0.3)], "random",
                  f"band-limited random displacement: 60 sines 0.5-12 Hz, 1/f amplitudes, velocity RMS "
                  f"{v_rms * scale:.3f} m/s, {duration:.2f} s, 0.5 s quintic fades")


def end_stop_program(rng: np.random.Generator, p: dict[str, float],
                     quick: bool = False) -> tuple[Motion, dict[str, Any]]:
    """Strokes 3-10 mm beyond x_end_stop in one or both directions: cycloidal moves top -> bottom ->
    top at rising peak velocities, with short rests at the ends."""
    side = str(rng.choice(["both", "extension", "compression"]))
    over = {"extension": rng.uniform(0.003, 0.01), "compression": rng.uniform(0.003, 0.01)}
    x0 = p["x_end_stop"]
    top = x0 + over["extension"] if side in ("both", "extension") else 0.6 * x0
    bottom = -(x0 + over["compression"]) if side in ("both", "compression") else -0.6 * x0
    segs = [Segment("hold", 0.5), Segment("move", 2 * top / 0.05, dx=top), Segment("hold", 0.2)]
    at = top
    speeds = (0.1,) if quick else (0.05, 0.1, 0.2)
    for vp in speeds:
        for target in (bottom, top):
            segs += [Segment("move", 2 * abs(target - at) / vp, dx=target - at), Segment("hold", 0.2)]
            at = target
    segs += [Segment("move", 2 * top / 0.05, dx=-top), Segment("hold", 0.3)]
    beyond = {k: (float(over[k]) if side in ("both", k) else 0.0) for k in over}
    text = (f"end-stop program ({side}): cycloidal moves between {top * 1e3:.1f} and {bottom * 1e3:.1f} mm at peak "
            f"velocities {', '.join(f'{v:g}' for v in speeds)} m/s, rests of 0.2 s")
    return Motion(segs, "end_stop", text), {"side": side, "beyond_m": beyond, "top_m": top, "bottom_m": bottom}


# --------------------------------------------------------------------------- the truth simulation

def constant_temperature(value: float) -> Callable[[float], float]:
    return lambda t: value


def simulate(p: dict[str, float], motion: Motion, temperature: Callable[[float], float] | None = None,
             rtol: float = RTOL, max_step: float = MAX_STEP, method: Method = METHOD) -> dict[str, FloatArray]:
    """The damper `p` on the dyno driven by `motion` with the oil at `temperature(t)` (K, default
    T_ref): scipy's `method` on each smooth segment, the states kept every FINE_STEP. Returns time (s),
    x (m), v (m/s), T (K), F (N, the load-cell force), p_A, p_B, p_r (Pa gauge), V_g (m3), delta (m,
    the mount) and nfev, the solver's function evaluations."""
    temperature = temperature or constant_temperature(p["T_ref"])
    c = Circuit(p)
    n = int(round(motion.duration / FINE_STEP))
    t_fine = FINE_STEP * np.arange(n + 1, dtype=float)
    y = np.empty((3, n + 1))
    x0 = motion.segments[0].x0
    y[:, 0] = c.rest_state(x0, temperature(0.0))
    nfev = 0
    for seg, t0, t1 in zip(motion.segments, motion.starts[:-1], motion.starts[1:], strict=True):
        k0, k1 = int(round(t0 / FINE_STEP)), int(round(t1 / FINE_STEP))
        if k1 == k0:
            continue

        def fun(t: float, yy: FloatArray, seg: Segment = seg, t0: float = t0) -> list[float]:
            x, v, a = seg.state(t - t0)
            return c.rhs(yy, x, v, a, temperature(t))

        sol = solve_ivp(fun, (t_fine[k0], t_fine[k1]), y[:, k0], method=method, t_eval=t_fine[k0:k1 + 1],
                        rtol=rtol, atol=ATOL, max_step=max_step)
        if not sol.success:
            raise RuntimeError(f"Radau failed in the {seg.kind} segment at t = {t0:.4f} s: {sol.message}")
        y[:, k0 + 1:k1 + 1] = sol.y[:, 1:]
        nfev += sol.nfev
    x, v = motion.arrays(t_fine)
    temp = np.array([temperature(float(t)) for t in t_fine])
    f_e = p["F_coulomb"] * np.tanh(v / p["v_friction"]) + np.sign(x) * p["k_end_stop"] * np.maximum(
        np.abs(x) - p["x_end_stop"], 0.0) ** 2
    force = y[0] * c.a_a - y[1] * c.a_p + f_e
    p_r = (p["p_reservoir0"] + P_ATM) * (p["V_gas0"] / y[2]) ** p["n_polytropic"] * temp / p["T_ref"] - P_ATM
    km1, km3 = p["k1_mount"], p["k3_mount"]
    delta = (2.0 * np.sqrt(km1 / km3 / 3.0) * np.sinh(np.arcsinh(1.5 * force / km1 * np.sqrt(3.0 * km3 / km1)) / 3.0)
             if km3 > 0 else force / km1)
    return {"time": t_fine, "x": x, "v": v, "T": temp, "F": force, "p_A": y[0], "p_B": y[1], "V_g": y[2],
            "p_r": p_r, "delta": delta, "nfev": nfev}


# --------------------------------------------------------------------------- the measurement chain

@dataclass
class Chain:
    """A logger's setup for one record (drawn by `Chain.draw`)."""
    rate: int
    antialias_hz: float
    force_sigma: float  # N, total at the output
    force_pre_share: float  # share of the force noise's variance added before the anti-alias filter
    force_quantum: float  # N
    force_unit: str  # N or kN
    x_sigma: float  # m
    x_quantum: float  # m
    velocity: str  # "derived" or "sensor"
    v_cutoff_hz: float  # derived: the logger's zero-phase Butterworth corner
    v_order: int
    v_sigma: float  # sensor: m/s
    v_quantum: float  # m/s
    t_sigma: float = 0.2  # K
    t_quantum: float = 0.1  # K
    time_format: str = "seconds"  # or "iso"
    start: str = ""  # ISO start time of an "iso" record

    @classmethod
    def draw(cls, rng: np.random.Generator, size: str) -> "Chain":
        rate = int(rng.choice(RATES))
        sigmas, quanta = LOAD_CELL[size]
        unit = "N" if size == "small" else str(rng.choice(["N", "kN"]))
        iso = bool(rng.uniform() < 0.5)
        start = datetime(2026, 3, 2, 8, 0, 0) + timedelta(days=int(rng.integers(0, 200)),
                                                          seconds=int(rng.integers(0, 9 * 3600)))
        return cls(rate=rate, antialias_hz=float(rate * rng.uniform(0.2, 0.4)),
                   force_sigma=float(rng.uniform(*sigmas)), force_pre_share=float(rng.uniform(0.3, 0.8)),
                   force_quantum=float(rng.choice(quanta)), force_unit=unit,
                   x_sigma=float(rng.uniform(2e-6, 10e-6)), x_quantum=float(rng.choice([1e-6, 2e-6, 5e-6])),
                   velocity=str(rng.choice(["derived", "sensor"])), v_cutoff_hz=float(rng.uniform(30.0, 80.0)),
                   v_order=int(rng.choice([2, 4])), v_sigma=float(rng.uniform(5e-4, 2e-3)), v_quantum=5e-5,
                   time_format="iso" if iso else "seconds", start=start.isoformat() if iso else "")


def measure(sim: dict[str, FloatArray], chain: Chain, rng: np.random.Generator) -> dict[str, FloatArray]:
    """The logger's columns (SI, degC for T) from the 0.1 ms truth: analog channels through the
    anti-alias filter, sampled, noise and quantisation; velocity derived or from its sensor."""
    m = round(1.0 / (chain.rate * FINE_STEP))
    n_fine = sim["time"].size
    # load cell: white noise at the fine step before the filter, scaled to its share at the output
    unit_noise = rng.standard_normal(n_fine)
    gain = float(np.std(lowpass_fine(unit_noise, FINE_STEP, chain.antialias_hz)[1000:]))
    pre = math.sqrt(chain.force_pre_share) * chain.force_sigma / gain * unit_noise
    force = lowpass_fine(sim["F"] + pre, FINE_STEP, chain.antialias_hz)[::m]
    n = force.size
    post = math.sqrt(1.0 - chain.force_pre_share) * chain.force_sigma * rng.standard_normal(n)
    force = quantise(force + post, chain.force_quantum)
    x = lowpass_fine(sim["x"], FINE_STEP, chain.antialias_hz)[::m]
    x = quantise(x + chain.x_sigma * rng.standard_normal(n), chain.x_quantum)
    if chain.velocity == "derived":
        b, a = butter(chain.v_order, chain.v_cutoff_hz / (chain.rate / 2))
        v = filtfilt(b, a, np.gradient(x, 1.0 / chain.rate), padtype="even")  # records start and end at rest
    else:
        v = lowpass_fine(sim["v"], FINE_STEP, chain.antialias_hz)[::m] + chain.v_sigma * rng.standard_normal(n)
    v = quantise(v, chain.v_quantum)
    temp = quantise(sim["T"][::m] - T_ZERO + chain.t_sigma * rng.standard_normal(n), chain.t_quantum)
    return {"time": sim["time"][::m], "x": x, "v": v, "F": force, "T": temp}


def _column(values: FloatArray, digits: int) -> list[str]:
    """Numbers with `digits` decimals, no negative zero."""
    return [f"{x:.{digits}f}" for x in np.round(values, digits) + 0.0]


def _digits(quantum: float) -> int:
    return max(0, math.ceil(-math.log10(quantum) - 1e-9))


def write_csv(path: Path, columns: dict[str, FloatArray], chain: Chain, comments: list[str]) -> list[str]:
    """Writes the record: `#` comment lines, the header `NAME [UNIT]`, one sample a line. Returns the header."""
    f_scale = 1e3 if chain.force_unit == "kN" else 1.0
    if chain.time_format == "iso":
        start = datetime.fromisoformat(chain.start)
        times = [(start + timedelta(microseconds=int(round(t * 1e6)))).isoformat(timespec="microseconds")
                 for t in columns["time"]]
        time_header = "time"
    else:
        times = _column(columns["time"], 4)
        time_header = "time [s]"
    header = [time_header, "x_damper [mm]", "v_damper [mm/s]", f"F_damper [{chain.force_unit}]", "T_oil [degC]"]
    cols = [times, _column(columns["x"] * 1e3, 3), _column(columns["v"] * 1e3, 2),
            _column(columns["F"] / f_scale, _digits(chain.force_quantum / f_scale)), _column(columns["T"], 1)]
    lines = [f"# {c}" for c in comments] + [",".join(header)]
    lines += [",".join(row) for row in zip(*cols, strict=True)]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return header


# --------------------------------------------------------------------------- scenarios and records

@dataclass
class Plan:
    """What one record is: the damper's truth, its motion, the oil temperature and what changed."""
    name: str
    params: dict[str, float]
    motion: Motion
    temperature: Callable[[float], float]
    temperature_text: str
    change: dict[str, Any]
    chain: Chain
    noise_key: tuple[int, ...]


def _record_rng(size: str, seed: int, scenario: str, k: int, what: int) -> np.random.Generator:
    return _stream(SIZES.index(size), seed, 2, SCENARIOS.index(scenario), k, what)


def scenario_change(size: str, seed: int, scenario: str,
                    base: dict[str, float]) -> tuple[dict[str, float], dict[str, Any]]:
    """The truth of the scenario's record and a description of what changed."""
    rng = _stream(SIZES.index(size), seed, 3, SCENARIOS.index(scenario))
    p = dict(base)
    if scenario == "gas":
        factor = 1.0 + float(rng.choice([-1.0, 1.0])) * rng.uniform(0.15, 0.30)
        p["p_reservoir0"] = base["p_reservoir0"] * factor
        return p, {"parameter": "p_reservoir0", "factor": factor, "before": base["p_reservoir0"],
                   "after": p["p_reservoir0"], "what": "gas pre-charge changed"}
    if scenario == "valve":
        name = str(rng.choice(["A_bleed_reb", "A_bleed_comp"]))
        factor = rng.uniform(0.5, 0.8) if rng.uniform() < 0.5 else rng.uniform(1.3, 2.0)
        p[name] = base[name] * factor
        return p, {"parameter": name, "factor": float(factor), "before": base[name], "after": p[name],
                   "what": f"{'rebound' if name.endswith('reb') else 'compression'} bleed (adjuster) changed"}
    if scenario == "heated":
        rise = rng.uniform(30.0, 50.0)
        mode = str(rng.choice(["during", "before"]))
        return p, {"parameter": "T_oil", "what": f"oil heated by {rise:.1f} K {mode} the record",
                   "rise_K": float(rise), "mode": mode, "drift_K": float(rng.uniform(0.5, 3.0))}
    if scenario == "end_stop":
        return p, {"what": "stroke beyond x_end_stop"}
    if scenario == "gas_release":
        lo, hi = SOLUBILITY
        p["gas_solubility"] = float(math.exp(rng.uniform(math.log(lo), math.log(hi))))
        p["p_saturation"] = base["p_reservoir0"]
        return p, {"parameter": "gas_solubility", "before": 0.0, "after": p["gas_solubility"],
                   "p_saturation": p["p_saturation"],
                   "what": "oil saturated with the reservoir's gas at its pre-charge: gas out of solution below it"}
    if scenario == "settings":
        name = str(rng.choice(["A_bleed_reb", "A_bleed_comp"]))
        factors = {"middle": 1.0, "closed": float(rng.uniform(0.4, 0.7)), "open": float(rng.uniform(1.4, 2.2))}
        return p, {"parameter": name, "factors": factors, "values": {k: base[name] * f for k, f in factors.items()},
                   "what": f"{'rebound' if name.endswith('reb') else 'compression'} bleed adjuster at three settings"}
    return p, {"what": "nothing changed"}


# the settings scenario's records: (setting, program)
SETTINGS_RECORDS = (("middle", "gas"), ("middle", "peak"), ("closed", "peak"), ("open", "random"))


def _heating(change: dict[str, Any], t_ref: float, duration: float) -> tuple[Callable[[float], float], str]:
    """T_oil(t) of the heated scenario: rising by rise_K over the record (1 - exp(-3 t/T), normalised),
    or already warm before it and cooling slowly by drift_K."""
    rise, drift = change["rise_K"], change["drift_K"]
    if change["mode"] == "during":
        norm = 1.0 - math.exp(-3.0)
        return (lambda t: t_ref + rise * (1.0 - math.exp(-3.0 * t / duration)) / norm,
                f"rising from {t_ref - T_ZERO:.2f} to {t_ref - T_ZERO + rise:.2f} degC, (1 - exp(-3 t/T)) normalised")
    return (lambda t: t_ref + rise - drift * t / duration,
            f"warm before the record: {t_ref - T_ZERO + rise:.2f} degC, cooling linearly by {drift:.2f} K")


def _mixed_program(rng: np.random.Generator, size: str, p: dict[str, float], quick: bool) -> Motion:
    """The single record of a scenario: a short peak-velocity sequence, then random motion."""
    pv = peak_velocity_program(rng, size, p, quick, velocities=(0.05, 0.1, 0.2, 0.4))
    rnd = random_program(rng, size, p, quick)
    return Motion(pv.segments + rnd.segments[1:], "mixed", pv.description + "; then " + rnd.description)


def plans(size: str, seed: int, scenario: str, quick: bool = False) -> list[Plan]:
    """The records of a scenario of damper (size, seed)."""
    if size not in SIZES or scenario not in SCENARIOS:
        raise ValueError(f"size one of {SIZES}, scenario one of {SCENARIOS}")
    base = truth_parameters(size, seed)
    params, change = scenario_change(size, seed, scenario, base)
    out = []
    count = {"calibration": 3, "settings": len(SETTINGS_RECORDS)}.get(scenario, 1)
    for k in range(count):
        rng = _record_rng(size, seed, scenario, k, 0)
        if scenario == "settings":
            setting, program = SETTINGS_RECORDS[k]
            params = {**base, change["parameter"]: change["values"][setting]}
            if program == "gas":
                motion = gas_program(rng, size, quick)
            elif program == "peak":
                motion = peak_velocity_program(rng, size, params, quick)
            else:
                motion = random_program(rng, size, params, quick)
            change = {**change, "setting": setting}
        elif scenario == "calibration":  # (a) gas force, (b) peak velocities, (c) random
            if k == 0:
                motion = gas_program(rng, size, quick)
            elif k == 1:
                motion = peak_velocity_program(rng, size, params, quick)
            else:
                motion = random_program(rng, size, params, quick)
        elif scenario == "end_stop":
            motion, stops = end_stop_program(rng, params, quick)
            change = {**change, **stops}
        else:
            motion = _mixed_program(rng, size, params, quick)
        t_ref = params["T_ref"]
        if scenario == "heated":
            temperature, text = _heating(change, t_ref, motion.duration)
        else:
            temperature, text = constant_temperature(t_ref), f"constant {t_ref - T_ZERO:.2f} degC (T_ref)"
        chain = Chain.draw(_record_rng(size, seed, scenario, k, 1), size)
        name = f"{size}_{seed}_{scenario}" + (f"_{k + 1}" if count > 1 else "")
        out.append(Plan(name, params, motion, temperature, text, change, chain, (SIZES.index(size), seed, 2,
                                                                                SCENARIOS.index(scenario), k, 2)))
    return out


def without_gas_release(params: dict[str, float]) -> dict[str, float]:
    """The damper `params` with its oil holding its gas (the gas_release scenario's parameters out)."""
    return {k: v for k, v in params.items() if k not in RELEASE_PARAMETERS}


def fmu_settings(params: dict[str, float]) -> dict[str, Value]:
    """How to reproduce the truth `params` with SemiActiveDamper.fmu (physics.md §4.6, §8): the valve
    held shut without leakage, no relief valve (area 0), the passive valves and the load-path effects
    on, gas release where the truth has it."""
    return {"control_mode": 2, "effect_gas_release": "gas_solubility" in params,
            "x_spool_start": 0.0, "A_valve_leak": 0.0, "A_relief": 0.0,
            "effect_flow_forces": False, "effect_amplifier_delay": False, "effect_rebound_valve": True,
            "effect_compression_valve": True, "effect_seal_friction": True,
            "effect_end_stops": True, "effect_oil_temperature": True, "effect_compressibility": True,
            "effect_mount_compliance": True, "effect_check_valve_cracking": True, "effect_piston_leakage": False,
            "effect_viscous_friction": False, "tare_load_cell": False}


def make_record(plan: Plan, size: str, seed: int, scenario: str, out_dir: Path, quick: bool = False,
                keep: dict[str, Any] | None = None) -> Path:
    """Simulates and writes one record and its truth JSON; returns the CSV's path. `keep` receives
    the 0.1 ms truth and the measured columns (for tests)."""
    sim = simulate(plan.params, plan.motion, plan.temperature)
    meas = measure(sim, plan.chain, _stream(*plan.noise_key))
    ch = plan.chain
    velocity = (f"derived by the logger: central differences of x_damper, zero-phase Butterworth order {ch.v_order} "
                f"at {ch.v_cutoff_hz:.1f} Hz (filtfilt)" if ch.velocity == "derived" else
                "velocity transducer (anti-alias filtered like the other channels)")
    comments = [f"Damper dyno record {plan.name}: {size} passive damper, {plan.motion.description}",
                "Rig: servo-hydraulic damper dyno, displacement controlled; x_damper from mid-stroke, extension +; "
                "F_damper tension +",
                f"Sample rate: {ch.rate} Hz", f"Anti-alias filter: 1st order low-pass {ch.antialias_hz:.0f} Hz on "
                                              "the analog channels",
                f"v_damper: {velocity}", "T_oil: thermocouple on the damper body"]
    if ch.time_format == "iso":
        comments.append(f"Start: {ch.start}")
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / f"{plan.name}.csv"
    header = write_csv(csv_path, meas, ch, comments)
    truth = {
        "generator": "damper_tools.dyno (independent Python model of docs/physics.md §2, §3.1-3.5, §3.8, §3.9, §8)",
        "record": csv_path.name, "size": size, "seed": seed, "scenario": scenario, "quick": quick,
        "truth_parameters": plan.params, "nominal_parameters": NOMINAL[size],
        "spreads": {k: (list(v) if isinstance(v, tuple) else v) for k, v in SPREADS.items()},
        "change": plan.change, "fmu_settings": fmu_settings(plan.params),
        "motion": {"name": plan.motion.name, "description": plan.motion.description,
                   "duration_s": plan.motion.duration, "start_x_m": plan.motion.segments[0].x0,
                   "max_x_m": float(np.max(sim["x"])), "min_x_m": float(np.min(sim["x"])),
                   "max_abs_v_m_s": float(np.max(np.abs(sim["v"])))},
        "temperature": {"description": plan.temperature_text, "start_K": float(sim["T"][0]),
                        "min_K": float(np.min(sim["T"])),
                        "max_K": float(np.max(sim["T"]))},
        "true_force": {"min_N": float(np.min(sim["F"])), "max_N": float(np.max(sim["F"])),
                       "rest_N": float(sim["F"][0])},
        "min_absolute_pressure_Pa": float(min(np.min(sim["p_A"]), np.min(sim["p_B"]), np.min(sim["p_r"]))) + P_ATM,
        "solver": {"method": f"scipy solve_ivp {METHOD} per smooth segment", "rtol": RTOL, "atol": list(ATOL),
                   "max_step_s": MAX_STEP, "fine_step_s": FINE_STEP},
        "sample_rate_hz": ch.rate, "samples": int(meas["time"].size), "columns": header,
        "chain": {**asdict(ch), "velocity_method": velocity},
        "seeds": {"damper": [SIZES.index(size), seed, 1], "scenario": [SIZES.index(size), seed, 3,
                                                                      SCENARIOS.index(scenario)],
                  "noise": list(plan.noise_key), "namespace": 20262},
    }
    csv_path.with_suffix(".json").write_text(json.dumps(truth, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    if keep is not None:
        keep.update(sim=sim, measured=meas, plan=plan)
    return csv_path


# --------------------------------------------------------------------------- the datasheet TOML

def _g(x: float) -> str:
    """x in at most 6 significant digits, the exponent without '+' and leading zeros (5e7, 1.5e-11)."""
    mantissa, _, exponent = f"{x:.6g}".partition("e")
    return mantissa + (f"e{int(exponent)}" if exponent else "")


def _float(x: float) -> str:
    """x as a TOML float (with a point or an exponent)."""
    text = _g(x)
    return text if any(c in text for c in ".e") else text + ".0"


def datasheet_toml(size: str, seed: int) -> str:
    """The damper's NOMINAL values in the format of crates/damper_engine/src/damper_template.toml.
    The end stops (bump and rebound rubbers) are left out, as datasheets leave them out: a record
    that reaches them shows what the description lacks."""
    p = NOMINAL[size]

    def q(value: float, unit: str) -> str:
        return f'"{_g(value)} {unit}"'

    def valve(w: str) -> list[tuple[str, str]]:
        return [("laminar_bleed", q(p[f"G_bleed_{w}"], "m3/(s.Pa)")), ("bleed_area", q(p[f"A_bleed_{w}"] * 1e6, "mm2")),
                ("blow_off_pressure", q(p[f"p_open_{w}"] / 1e5, "bar")),
                ("blow_off_area_per_pressure", q(p[f"k_open_{w}"], "m2/Pa")),
                ("blow_off_area", q(p[f"A_open_{w}"] * 1e6, "mm2"))]

    sections = {
        "cylinder": [("piston_diameter", q(p["D_piston"] * 1e3, "mm")), ("rod_diameter", q(p["D_rod"] * 1e3, "mm")),
                     ("stroke", q(2 * p["L_half_stroke"] * 1e3, "mm")), ("dead_length", q(p["L_dead"] * 1e3, "mm")),
                     ("extra_volume", q(p["V_hose"] * 1e6, "cm3"))],
        "gas": [("precharge", q(p["p_reservoir0"] / 1e5, "bar")), ("volume", q(p["V_gas0"] * 1e6, "cm3")),
                ("polytropic_index", _float(p["n_polytropic"]))],
        "oil": [("density", q(p["rho"], "kg/m3")), ("air_fraction", _float(p["air_fraction"])),
                ("viscosity_temperature_coefficient", q(p["visc_temp_coeff"], "1/K")),
                ("reference_temperature", q(p["T_ref"] - T_ZERO, "degC"))],
        "rebound_valve": valve("reb") + [("discharge_coefficient", _float(p["Cd_passive"]))],
        "compression_valve": valve("comp"),
        "check_valves": [("area", q(p["A_cv_max"] * 1e6, "mm2")),
                         ("cracking_pressure", q(p["p_cv_crack"] / 1e5, "bar")),
                         ("full_open_pressure", q(p["p_cv_full"] / 1e5, "bar"))],
        "mount": [("stiffness", q(p["k1_mount"], "N/m")), ("cubic_stiffness", q(p["k3_mount"], "N/m3"))],
        "seals": [("friction", q(p["F_coulomb"], "N")), ("friction_velocity", q(p["v_friction"] * 1e3, "mm/s"))],
        "parameters": [(name, _float(p[name])) for name in ("beta_oil", "p_transition", "Cd_cv", "A_cv_leak")],
    }
    lines = [f"# {size} passive twin-tube damper, datasheet values (damper_tools.dyno, seed {seed}).",
             "# Nominal values: the damper on the dyno differs by manufacturing spreads (the truth JSON).",
             'kind = "passive"', f'name = "{size} passive damper {seed}"']
    for section, keys in sections.items():
        lines += ["", f"[{section}]"] + [f"{key} = {value}" for key, value in keys]
    return "\n".join(lines) + "\n"


def make_records(size: str, seed: int, scenario: str, out_dir: str | Path, quick: bool = False) -> list[Path]:
    """Writes the scenario's record CSV(s), one truth JSON per record and the datasheet TOML into
    `out_dir`; returns the CSV paths. quick: short programs (for tests)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = [make_record(plan, size, seed, scenario, out_dir, quick) for plan in plans(size, seed, scenario, quick)]
    (out_dir / f"{size}_{seed}_datasheet.toml").write_text(datasheet_toml(size, seed), encoding="utf-8")
    return paths


# --------------------------------------------------------------------------- F-v curves of the presets

FV_VELOCITIES = (0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0)


def fv_table(seed: int = 1) -> dict[str, dict[str, list[float]]]:
    """Steady forces (N) of each preset's nominal and seed-`seed` truth at FV_VELOCITIES, both ways."""
    out = {}
    for size in SIZES:
        rows = {}
        for label, p in (("nominal", NOMINAL[size]), (f"truth {seed}", truth_parameters(size, seed))):
            rows[label + " rebound"] = [steady_force(p, v) for v in FV_VELOCITIES]
            rows[label + " compression"] = [steady_force(p, -v) for v in FV_VELOCITIES]
        out[size] = rows
    return out


def plot_fv(path: str | Path, seed: int = 1) -> Path:
    """The three presets' steady F-v curves (nominal, truth of `seed`, and the nominal at +40 K), with
    the dyno's peak-velocity loops of the truth (a quick simulated program) over them."""
    plt = pyplot()

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    v = np.linspace(-1.0, 1.0, 201)
    for ax, size in zip(axes, SIZES, strict=True):
        truth = truth_parameters(size, seed)
        for label, p, t, style in (("nominal", NOMINAL[size], None, "k-"), (f"truth seed {seed}", truth, None, "C0-"),
                                   ("nominal at +40 K", NOMINAL[size], NOMINAL[size]["T_ref"] + 40, "C3--")):
            ax.plot(v, [steady_force(p, vv, t) / 1e3 for vv in v], style, label=label, lw=1.2)
        motion = peak_velocity_program(_stream(99), size, truth, velocities=(0.05, 0.1, 0.2, 0.3, 0.5))
        sim = simulate(truth, motion, rtol=1e-7)
        ax.plot(sim["v"], sim["F"] / 1e3, "C1-", lw=0.5, alpha=0.7, label="dyno loops (truth)")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.axvline(0, color="0.7", lw=0.5)
        ax.set_title(f"{size}: D {NOMINAL[size]['D_piston'] * 1e3:g}/{NOMINAL[size]['D_rod'] * 1e3:g} mm")
        ax.set_xlabel("v (m/s, extension +)")
        ax.set_ylabel("F (kN, tension +)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_gas_release(path: str | Path, size: str = "car", seed: int = 1) -> Path:
    """The gas_release scenario's truth (quick program) against the same damper without gas release,
    over 1.5 s of its random part: the force in time and against the stroke, and the full bore's
    pressure with the saturation pressure. The lost motion sits at the turns into compression."""
    plt = pyplot()

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    plan = plans(size, seed, "gas_release", quick=True)[0]
    with_gas = simulate(plan.params, plan.motion)
    without = simulate(without_gas_release(plan.params), plan.motion)
    t = with_gas["time"]
    sel = (t > 5.0) & (t < 6.5)
    runs = (("no gas release", without), (f"gas release, solubility {plan.params['gas_solubility']:.3f}", with_gas))
    fig, (ax_t, ax_x, ax_p) = plt.subplots(1, 3, figsize=(15, 4.5))
    for label, run in runs:
        ax_t.plot(t[sel], run["F"][sel], label=label)
        ax_x.plot(run["x"][sel] * 1e3, run["F"][sel], label=label)
        ax_p.plot(t[sel], run["p_B"][sel] / 1e5, label=label)
    ax_p.axhline(plan.params["p_saturation"] / 1e5, color="k", ls=":", label="p_saturation (the pre-charge)")
    for ax, x_label, y_label in ((ax_t, "time (s)", "F (N, tension +)"), (ax_x, "stroke (mm)", "F (N, tension +)"),
                                 (ax_p, "time (s)", "full-bore pressure p_B (bar, gauge)")):
        ax.set_xlabel(x_label)
        ax.set_ylabel(y_label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{size} damper, seed {seed}: oil saturated at the pre-charge (damper_tools.dyno's own model)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", choices=SIZES)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--scenario", choices=SCENARIOS, default="calibration")
    parser.add_argument("--out", type=Path, help="directory for the records, truth JSONs and datasheet TOML")
    parser.add_argument("--quick", action="store_true", help="short programs (a few seconds a record)")
    parser.add_argument("--fv", type=Path, help="print the presets' steady F-v table and plot it to this PNG")
    parser.add_argument("--gas-release", type=Path, help="plot the gas_release scenario's truth against the "
                        "damper without it to this PNG (docs/figures/gas_release.png)")
    args = parser.parse_args(argv)
    if args.gas_release:
        print(f"wrote {plot_gas_release(args.gas_release, args.size or 'car', args.seed)}")
        if not (args.size and args.out):
            return
    if args.fv:
        table = fv_table(args.seed)
        print("v (m/s): " + "  ".join(f"{v:>7g}" for v in FV_VELOCITIES))
        for size, rows in table.items():
            for label, forces in rows.items():
                print(f"{size:5s} {label:24s} " + "  ".join(f"{f:7.0f}" for f in forces))
        print(f"wrote {plot_fv(args.fv, args.seed)}")
        if not args.size:
            return
    if not (args.size and args.out):
        parser.error("--size and --out are required (or --fv alone)")
    t0 = wallclock.perf_counter()
    paths = make_records(args.size, args.seed, args.scenario, args.out, args.quick)
    print(f"wrote {', '.join(p.name for p in paths)} (a truth JSON each) and {args.size}_{args.seed}_datasheet.toml "
          f"into {args.out} in {wallclock.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
