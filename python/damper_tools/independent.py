"""Measurement-like records made independently of the diagnosis's numerics, with a truth file.

    .venv/bin/python -m damper_tools.independent --kind rig --seed 3 --effect seal_friction \\
        --out out/ind/rig_sf.csv --truth out/ind/rig_sf.truth.json

`damper generate` (crates/damper_engine/src/generate.rs) makes its truth with the model the diagnosis
runs: the same in-process integrator, stepped over the record's own sample grid in substeps of the
controller's period with the velocity on a cubic through the samples, and a load-cell filter fed the
force of every substep. A diagnosis
tested on such data is tested on truths it made itself. The records here differ in every one of
those steps:

- the truth is the PACKAGED FMU (target/fmu/SemiActiveDamper.fmu) run through fmpy at FMU tolerance
  `rtol` = 1e-7 (the diagnosis: 1e-4) and a communication step of 0.1 ms (the diagnosis: the sample
  interval, 0.5-2 ms, in substeps of at most 0.5 ms);
- the velocity the truth moves with is the true, continuous motion evaluated every 0.1 ms, plus the
  velocity sensor's noise of the current sample (the rig's controller works with the measured
  velocity); the record holds only the measured samples;
- the load cell is a CONTINUOUS first-order low-pass (default 400 Hz) integrated exactly on the
  0.1 ms force (`lowpass_fine`), then sampled at the record's rate (500, 1000 or 2000 Hz);
- white sensor noise (load cell 20 N, velocity 0.1 mm/s) and quantisation (1 N, 0.01 mm/s);
- other inputs: triangle and trapezoid velocity waves, a chirp, band-limited random velocity with
  demand steps (rig), and the quarter truck on a random road through damper_tools.cosim with its
  Modified Skyhook demand (HiL), drawn with numpy's generator (not the Rust one);
- other formats: time in ms, velocity in mm/s, forces in kN (units in the header, `time [ms]`) or SI.

Foreign dampers (`damper_tools.foreign`) use the same inputs and the same sensor model.

Hidden effects come from the effect catalog as the `damper` program exports it
(`damper effects --json`, read by `catalog`): its key, size parameter, the `hidden_range` a
generator hides it in and the settings that go with hiding it. An effect that is off by default is
switched on
(`effect_<key>`), one that is on has its parameter moved, in both cases to a value drawn from the
hidden range. Same case and seed: the same record, bit for bit.
"""

import argparse
import json
import math
import subprocess
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.signal import butter, filtfilt, lfilter, lfilter_zi

from damper_tools import DAMPER, DAMPER_FMU, TRUCK_FMU, FloatArray, cosim, foreign, roads
from damper_tools.fmu import FmuUnit, Slave, Value
from damper_tools.sensors import FINE_STEP, SENSORS, quantise, steps_per_sample

RTOL = 1e-7  # the FMU's step-size control tolerance for the truth
LOWPASS_HZ = 400.0  # load-cell corner
RATES = (500.0, 1000.0, 2000.0)  # Hz
SPLIT = 0.7  # the diagnosis validates on the last 30 %
DEMAND_QUANTUM = 0.1  # N: the demand is digital
KINDS = ("rig", "hil", "foreign_mr", "foreign_passive")
MOTIONS = ("continuous", "sample_hold")
# The measurement chain of a rig record: `transducer`, a velocity transducer (white noise); `lvdt`,
# the velocity a logger differentiates from an LVDT's displacement and filters zero-phase (both
# columns written), and a quieter load cell (LVDT_SENSORS).
CHAINS = ("transducer", "lvdt")
# LVDT chain: displacement noise and quantum (m), the logger's zero-phase Butterworth (order, Hz),
# and the load cell (noise, quantum) in N.
LVDT_NOISE, LVDT_QUANTUM = 5e-6, 1e-6
LOGGER_FILTER = (4, 100.0)
LVDT_LOAD_CELL = (6.0, 0.5)
# How the columns are written: SI, or ms / mm/s / kN.
FORMATS = {
    "si": {"time": ("time", 1.0, 6), "x": ("x_damper", 1.0, 7), "v": ("v_damper", 1.0, 5),
           "fd": ("F_demand", 1.0, 1), "f": ("F_damper", 1.0, 1)},
    "ms": {"time": ("time [ms]", 1e-3, 3), "x": ("x_damper [mm]", 1e-3, 4), "v": ("v_damper [mm/s]", 1e-3, 2),
           "fd": ("F_demand [kN]", 1e3, 4), "f": ("F_damper [kN]", 1e3, 4)},
}


# --------------------------------------------------------------------------- the catalog

@dataclass(frozen=True)
class CatalogEffect:
    key: str
    parameter: str  # the first fitted parameter: the effect's size
    hidden_range: tuple[float, float]
    default_on: bool
    # other parameters a generator sets with it (an end stop within the stroke)
    hide_with: dict[str, float] = field(default_factory=dict)
    # when a diagnosis tries it: always, when_on, with_temperature or controlled
    candidacy: str = "always"

    @property
    def hideable(self) -> bool:
        """Whether these records (semi-active, controlled, without a temperature column) can hide it
        so that a diagnosis may name it: a passive valve the model lacks is never switched on by a
        diagnosis, and the oil temperature needs a temperature column."""
        return self.candidacy in ("always", "controlled") or (self.candidacy == "when_on" and self.default_on)


def catalog(damper: str | Path = DAMPER) -> dict[str, CatalogEffect]:
    """The effect catalog as `damper effects --json` exports it."""
    listed = json.loads(subprocess.run([str(damper), "effects", "--json"], capture_output=True, text=True,
                                       check=True).stdout)
    return {e["key"]: CatalogEffect(e["key"], e["size_parameter"], tuple(e["hidden_range"]), e["default_on"],
                                    dict(e["hide_with"]["set"]), e["candidacy"]) for e in listed}


# --------------------------------------------------------------------------- a case

@dataclass
class Case:
    """One record to make. kind: rig, hil, foreign_mr or foreign_passive; effects: catalog keys
    hidden in the truth (the FMU kinds only); rate in Hz; fmt: si or ms (ms, mm/s, kN)."""
    kind: str
    seed: int
    effects: tuple[str, ...] = ()
    rate: float = 1000.0
    duration: float | None = None  # s; default 4 (rig) or 6 (HiL)
    fmt: str = "ms"
    lowpass_hz: float = LOWPASS_HZ
    # continuous: the truth moves with the true motion at every fine step (a real rig); sample_hold:
    # with the true velocity of the record's sample held over the sample interval, as the diagnosis's
    # model is driven (isolates the other differences: tolerance, fine step, filter, inputs, format).
    motion: str = "continuous"
    chain: str = "transducer"
    name: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind {self.kind!r}: one of {', '.join(KINDS)}")
        if self.fmt not in FORMATS:
            raise ValueError(f"fmt {self.fmt!r}: one of {', '.join(FORMATS)}")
        if self.effects and self.kind.startswith("foreign"):
            raise ValueError("catalog effects are hidden in the FMU's records only")
        if self.motion not in MOTIONS:
            raise ValueError(f"motion {self.motion!r}: one of {', '.join(MOTIONS)}")
        if self.chain not in CHAINS or (self.chain == "lvdt" and self.kind != "rig"):
            raise ValueError(f"chain {self.chain!r}: one of {', '.join(CHAINS)}; lvdt on rig records only")
        self.effects = tuple(self.effects)
        if self.duration is None:
            self.duration = 6.0 if self.kind == "hil" else 4.0
        if not self.name:
            what = "+".join(self.effects) if self.effects else ("clean" if not self.kind.startswith("foreign")
                                                                 else "foreign")
            held = "_held" if self.motion == "sample_hold" else ""
            lvdt = "_lvdt" if self.chain == "lvdt" else ""
            self.name = f"{self.kind}_{what}_s{self.seed}_{int(self.rate)}hz{held}{lvdt}"

    @property
    def duration_s(self) -> float:
        """The record's length (s), `duration` or its default."""
        assert self.duration is not None  # set in __post_init__
        return self.duration

    @property
    def tared(self) -> bool:
        """HiL records have the load cell tared (the damper in a vehicle loop, cosim's default)."""
        return self.kind == "hil"


def streams(case: Case) -> dict[str, np.random.Generator]:
    """Independent random streams of a case (numpy's PCG64), fixed by its kind and seed: the inputs,
    the hidden values and each sensor's noise. Records of one kind and seed share inputs and noise."""
    kind = KINDS.index(case.kind)
    names = ("inputs", "effects", "noise_f", "noise_v", "road", "foreign")
    seqs = np.random.SeedSequence([case.seed, kind, 20260]).spawn(len(names))
    return {n: np.random.default_rng(s) for n, s in zip(names, seqs, strict=True)}


def hidden_values(case: Case, cat: dict[str, CatalogEffect], rng: np.random.Generator) -> dict[str, dict[str, Any]]:
    """Each hidden effect's parameter drawn uniformly from its hidden range (log-uniform when the range
    spans more than a factor 3)."""
    out = {}
    for key in case.effects:
        if key not in cat:
            raise ValueError(f"unknown effect {key!r}: {', '.join(cat)}")
        e = cat[key]
        lo, hi = e.hidden_range
        value = float(math.exp(rng.uniform(math.log(lo), math.log(hi))) if hi / lo > 3 else rng.uniform(lo, hi))
        out[key] = {"switch": f"effect_{key}", "switched_on": not e.default_on, "parameter": e.parameter,
                    "value": value, "hidden_range": list(e.hidden_range), "set": dict(e.hide_with)}
    return out


# --------------------------------------------------------------------------- the measurement chain

def lowpass_fine(u: FloatArray, h: float, corner_hz: float) -> FloatArray:
    """First-order low-pass y' = w (u - y), integrated exactly for u linear between its samples
    (spacing h), starting at rest at u[0]."""
    w = 2 * math.pi * corner_hz
    a = math.exp(-w * h)
    b = (1 - a) / (w * h)
    # y[i] = a y[i-1] + (1 - b) u[i] + (b - a) u[i-1]
    num, den = [1 - b, b - a], [1.0, -a]
    u = np.asarray(u, dtype=float)
    y: FloatArray
    y, _ = lfilter(num, den, u, zi=lfilter_zi(num, den) * u[0])
    return y


def measure(x: FloatArray, sensor: str | tuple[float, float], rng: np.random.Generator) -> FloatArray:
    sigma, q = SENSORS[sensor] if isinstance(sensor, str) else sensor
    return quantise(x + sigma * rng.standard_normal(x.size), q)


def lvdt_velocity(x_true: FloatArray, rate: float, rng: np.random.Generator) -> tuple[FloatArray, FloatArray]:
    """The displacement an LVDT records (noise, quantum) and the velocity a logger makes of it:
    central differences, then a zero-phase Butterworth (LOGGER_FILTER) run forwards and backwards."""
    x = quantise(x_true + LVDT_NOISE * rng.standard_normal(x_true.size), LVDT_QUANTUM)
    order, corner = LOGGER_FILTER
    b, a = butter(order, corner / (rate / 2.0))
    return x, filtfilt(b, a, np.gradient(x, 1.0 / rate))


# --------------------------------------------------------------------------- rig inputs

def _taper(tau: FloatArray, length: float, w: float = 0.015) -> FloatArray:
    """1 inside a segment, raised-cosine ramps of w at both ends."""
    up = np.clip(tau / w, 0, 1)
    down = np.clip((length - tau) / w, 0, 1)
    taper: FloatArray = np.sin(0.5 * math.pi * up) ** 2 * np.sin(0.5 * math.pi * down) ** 2
    return taper


@dataclass
class RigInputs:
    """A rig run in four equal parts: a triangle velocity wave, a trapezoid wave, a linear chirp and a
    band-limited random velocity (a sum of sines, 0.5-8 Hz). `velocity(t)` is the true motion at any
    time; the force demand is made per record sample from the MEASURED velocity (as a rig controller
    does), by `demand(v_measured)`."""
    duration: float
    parts: list[dict[str, Any]] = field(default_factory=list)
    levels: list[tuple[float, float, float]] = field(default_factory=list)  # (start, level N, gain N s/m)

    @classmethod
    def draw(cls, duration: float, rng: np.random.Generator) -> "RigInputs":
        q = duration / 4
        parts = [
            {"shape": "triangle", "t0": 0.0, "len": q, "amp": rng.uniform(0.08, 0.25), "freq": rng.uniform(1.0, 2.5)},
            {"shape": "trapezoid", "t0": q, "len": q, "amp": rng.uniform(0.05, 0.2), "period": rng.uniform(0.25, 0.4),
             "ramp": rng.uniform(0.02, 0.05)},
            {"shape": "chirp", "t0": 2 * q, "len": q, "amp": rng.uniform(0.06, 0.12), "f0": rng.uniform(1.5, 3.0),
             "f1": rng.uniform(10.0, 16.0)},
            {"shape": "random", "t0": 3 * q, "len": q, "rms": rng.uniform(0.05, 0.1),
             "freqs": np.geomspace(0.5, 8.0, 40).tolist(), "phases": rng.uniform(0, 2 * math.pi, 40).tolist()},
        ]
        levels, t = [], 0.0
        while t < duration:
            # Demand steps every 80-250 ms: a level (1-15 kN) with the sign of the velocity, plus a
            # viscous part C v (0-40 kN s/m).
            levels.append((t, rng.uniform(1e3, 15e3), rng.uniform(0.0, 40e3)))
            t += rng.uniform(0.08, 0.25)
        return cls(duration, parts, levels)

    def velocity(self, t: FloatArray) -> FloatArray:
        t = np.asarray(t, dtype=float)
        v = np.zeros_like(t)
        for p in self.parts:
            inside = (t >= p["t0"]) & (t < p["t0"] + p["len"])
            tau = t[inside] - p["t0"]
            if p["shape"] == "triangle":
                # starts at 0 rising: 4 amp |frac - 1/2| shape, phase so that v(0) = 0
                ph = (tau * p["freq"] + 0.25) % 1.0
                shape = p["amp"] * (1 - 4 * np.abs(ph - 0.5))
            elif p["shape"] == "trapezoid":
                ph = (tau / p["period"]) % 1.0
                r = p["ramp"] / p["period"]
                # odd trapezoid: up-ramp, plateau, down through zero, plateau, up-ramp
                shape = p["amp"] * np.clip(np.where(ph < 0.5, np.minimum(ph, 0.5 - ph), -np.minimum(ph - 0.5, 1 - ph))
                                           / r, -1, 1)
            elif p["shape"] == "chirp":
                k = (p["f1"] - p["f0"]) / p["len"]
                shape = p["amp"] * np.sin(2 * math.pi * (p["f0"] * tau + 0.5 * k * tau ** 2))
            else:
                f, phi = np.array(p["freqs"]), np.array(p["phases"])
                # 1/f amplitudes (a displacement-like spectrum), scaled to the RMS
                a = 1.0 / f
                a *= p["rms"] * math.sqrt(2) / math.sqrt(np.sum(a ** 2))
                shape = np.sin(2 * math.pi * np.outer(tau, f) + phi) @ a
            v[inside] = shape * _taper(tau, p["len"])
        return v

    def demand(self, t: FloatArray, v_measured: FloatArray) -> FloatArray:
        """The demand level takes the sign of the programmed motion (the rig knows where it moves, so
        the demand does not flip with the velocity noise near rest), its viscous part follows the
        measured velocity."""
        starts = np.array([s for s, _, _ in self.levels])
        idx = np.searchsorted(starts, t, side="right") - 1
        level = np.array([lv for _, lv, _ in self.levels])[idx]
        gain = np.array([g for _, _, g in self.levels])[idx]
        return quantise(np.sign(self.velocity(t)) * level + gain * v_measured, DEMAND_QUANTUM)

    def describe(self) -> str:
        return ("four equal parts: triangle velocity wave (0.08-0.25 m/s, 1-2.5 Hz), odd trapezoid wave "
                "(0.05-0.2 m/s, period 0.25-0.4 s, ramps 20-50 ms), linear chirp (0.06-0.12 m/s, 1.5-3 -> 10-16 Hz), "
                "band-limited random velocity (40 sines 0.5-8 Hz, 1/f amplitudes, 0.05-0.1 m/s RMS); "
                "demand = sign(v_programmed)*level + C*v_measured, level 1-15 kN and C 0-40 kNs/m stepping every "
                "80-250 ms, computed per record sample from the measured velocity and held")


# --------------------------------------------------------------------------- truths through the FMU

def _damper_parameters(effects: dict[str, dict[str, Any]], tared: bool) -> dict[str, Value]:
    params: dict[str, Value] = {"rtol": RTOL, "tare_load_cell": tared}
    for e in effects.values():
        if e["switched_on"]:
            params[e["switch"]] = True
        params.update(e.get("set", {}))
        params[e["parameter"]] = e["value"]
    return params


# An end stop hidden on the rig: at this share of the rig's largest stroke (the catalog's hide_with
# places it for `damper generate`'s strokes, which are shorter: at the rig's 45 mm its stiffness
# would give forces of meganewtons).
END_STOP_SHARE = 0.85


def place_within_stroke(effects: dict[str, dict[str, Any]], params: dict[str, Value], rig: "RigInputs",
                        duration: float) -> None:
    """Moves a hidden end stop to END_STOP_SHARE of the rig motion's largest stroke in the part the
    diagnosis fits on (the first SPLIT of the record), so that the stop acts there."""
    if "end_stops" not in effects:
        return
    t = np.arange(0.0, SPLIT * duration, FINE_STEP)
    x_stop = END_STOP_SHARE * float(np.max(np.abs(np.cumsum(rig.velocity(t)) * FINE_STEP)))
    effects["end_stops"]["set"]["x_end_stop"] = x_stop
    params["x_end_stop"] = x_stop


def rig_truth_fmu(case: Case, rig: RigInputs, noise_v: FloatArray, params: dict[str, Value],
                  damper_fmu: str | Path) -> dict[str, Any]:
    """The damper FMU driven at the fine step by the true velocity plus the current sample's velocity
    noise, and the demand of the current sample. Returns the fine-step force and the sampled inputs."""
    m = steps_per_sample(case.rate)
    n_samples = int(round(case.duration_s * case.rate)) + 1
    n_fine = (n_samples - 1) * m
    t_fine = FINE_STEP * np.arange(n_fine + 1, dtype=float)
    v_true = rig.velocity(t_fine)
    t_rec = t_fine[::m]
    v_meas = quantise(v_true[::m] + noise_v[:n_samples], SENSORS["v_damper"][1])
    demand = rig.demand(t_rec, v_meas)
    # What the FMU's velocity input sees in each fine step: the true motion at the step's start plus the
    # sensor noise of the sample it belongs to (unquantised: the controller's converter is finer).
    motion = v_true[:-1] if case.motion == "continuous" else np.repeat(v_true[:-1:m], m)
    # the LVDT chain's controller senses the motion itself (its converter is not the logger's)
    v_drive = motion + (0.0 if case.chain == "lvdt" else np.repeat(noise_v[:n_samples - 1], m))
    # continuous: the velocity moves along the true motion's chord over each fine step (the FMU's
    # a_damper input), not held (a hold would lag the motion by half a fine step, 0.05 ms)
    a_drive = np.diff(v_true) / FINE_STEP if case.motion == "continuous" else np.zeros(n_fine)
    f_drive = np.repeat(demand[:-1], m)
    slave = Slave(FmuUnit.load(damper_fmu), f"truth_{case.name}")
    force = np.empty(n_fine + 1)
    try:
        slave.initialize(0.0, t_fine[-1], **params)
        force[0] = slave.get(["F_damper"])[0]
        for j in range(n_fine):
            slave.step(FINE_STEP, t_fine[j], v_damper=float(v_drive[j]), a_damper=float(a_drive[j]),
                       F_demand=float(f_drive[j]))
            # the force at t_{j+1} with the velocity of t_{j+1}: F_damper depends on v_damper
            # directly, and the velocity of the step just taken is 0.1 ms old
            if j + 1 < n_fine:
                slave.set(v_damper=float(v_drive[j + 1]), F_demand=float(f_drive[j + 1]))
            force[j + 1] = slave.get(["F_damper"])[0]
    finally:
        slave.free()
    x = np.concatenate([[0.0], np.cumsum(v_drive) * FINE_STEP])
    return {"t_fine": t_fine, "force_fine": force, "t": t_rec, "v_measured": v_meas, "demand": demand,
            "v_true": v_true[::m], "x_true": x[::m], "max_abs_stroke": float(np.max(np.abs(x)))}


def hil_truth_fmu(case: Case, noise_v: FloatArray, road_seed: int, params: dict[str, Value],
                  damper_fmu: str | Path, truck_fmu: str | Path) -> dict[str, Any]:
    """The quarter truck on a minor road at 14 m/s with its clipped MSD demand and the damper FMU,
    coupled by damper_tools.cosim at the fine step. The damper sees the truck's relative velocity
    plus the current sample's velocity noise, and the demand of the current sample held (the
    logger's and the damper controller's view); the truck gets the damper's force."""
    m = steps_per_sample(case.rate)
    n_samples = int(round(case.duration_s * case.rate)) + 1
    n_fine = (n_samples - 1) * m
    road = roads.road_case("minor", 14.0, n_fine * FINE_STEP, road_seed, step=FINE_STEP)
    held = {"f": 0.0, "v": 0.0}
    hold_motion = case.motion == "sample_hold"

    def damper_inputs(k: int, v: float, f_demand: float) -> tuple[float, float, float]:
        i = k // m
        if k % m == 0:
            held["f"] = round(f_demand / DEMAND_QUANTUM) * DEMAND_QUANTUM
            held["v"] = v
        # continuous: the velocity's ramp over the fine step, extrapolated from the last one (the
        # loop's next velocity is not known yet); a hold would lag the motion by 0.05 ms
        ramp = 0.0 if hold_motion or k == 0 else (v - held["v_prev"]) / FINE_STEP
        held["v_prev"] = v
        return (held["v"] if hold_motion else v) + noise_v[i], held["f"], ramp

    car = cosim.Car("hil", road.z_road, road.v_road, {"damper_mode": cosim.MODE_EXTERNAL}, params, damper_inputs)
    res = cosim.simulate([car], FINE_STEP, n_fine, truck_fmu=truck_fmu, damper_fmu=damper_fmu)[0]
    v_true = res["v_damper"][::m]
    demand = quantise(res["F_demand"][::m], DEMAND_QUANTUM)
    return {"t_fine": res["time"], "force_fine": res["damper.F_damper"], "t": res["time"][::m],
            "v_measured": quantise(v_true + noise_v[:n_samples], SENSORS["v_damper"][1]), "demand": demand,
            "v_true": v_true, "max_abs_stroke": float(np.max(np.abs(res["x_damper"]))),
            "road": road.header()}


# --------------------------------------------------------------------------- a record

def _fixed(x: float, digits: int) -> str:
    """x with `digits` decimals, without a negative zero."""
    text = f"{x:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def write_csv(path: Path, case: Case, columns: dict[str, FloatArray], comment: str) -> None:
    fmt = FORMATS[case.fmt]
    keys = ("time", "x", "v", "fd", "f") if "x" in columns else ("time", "v", "fd", "f")
    scaled = [np.asarray(columns[k]) / fmt[k][1] for k in keys]
    lines = [f"# {comment}", ",".join(fmt[k][0] for k in keys)]
    digits = [fmt[k][2] for k in keys]
    for row in zip(*scaled, strict=True):
        lines.append(",".join(_fixed(x, d) for x, d in zip(row, digits, strict=True)))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def make(case: Case, out: str | Path, truth_path: str | Path, damper_fmu: str | Path = DAMPER_FMU,
         truck_fmu: str | Path = TRUCK_FMU, keep: dict[str, Any] | None = None) -> dict[str, Any]:
    """Writes the record `out` and its truth `truth_path` (JSON); returns the truth. `keep`, a dict,
    receives the fine-step force and the sampled signals (for tests)."""
    out, truth_path = Path(out), Path(truth_path)
    rng = streams(case)
    n_samples = int(round(case.duration_s * case.rate)) + 1
    noise_v = SENSORS["v_damper"][0] * rng["noise_v"].standard_normal(n_samples)
    truth: dict[str, Any] = {"generator": "damper_tools.independent", "case": asdict(case), "kind": case.kind,
                   "seed": case.seed, "rate_hz": case.rate, "duration_s": case.duration, "format": case.fmt,
                   "columns": [FORMATS[case.fmt][k][0] for k in ("time", "v", "fd", "f")],
                   "tare_load_cell": case.tared, "fine_step_s": FINE_STEP,
                   "load_cell_lowpass_hz": case.lowpass_hz, "load_cell_filter": "continuous first-order, "
                   "integrated exactly on the fine-step force (linear between fine steps), then sampled",
                   "sensors": {k: {"noise": s, "quantum": q} for k, (s, q) in SENSORS.items()},
                   "demand_quantum_N": DEMAND_QUANTUM, "motion": case.motion}
    if case.kind in ("rig", "hil"):
        effects = hidden_values(case, catalog(), rng["effects"])
        params = _damper_parameters(effects, case.tared)
        truth.update(model="SemiActiveDamper.fmu through fmpy", fmu_rtol=RTOL, hidden_effects=effects,
                     fmu_parameters=params)
        if case.kind == "rig":
            rig = RigInputs.draw(case.duration_s, rng["inputs"])
            place_within_stroke(effects, params, rig, case.duration_s)
            sim = rig_truth_fmu(case, rig, noise_v, params, damper_fmu)
            truth["inputs"] = rig.describe()
        else:
            road_seed = int(rng["road"].integers(1, 2**31))
            sim = hil_truth_fmu(case, noise_v, road_seed, params, damper_fmu, truck_fmu)
            truth["inputs"] = (f"quarter truck (QuarterTruck.fmu, clipped Modified Skyhook) through damper_tools.cosim "
                               f"at {FINE_STEP:g} s; road: {sim.pop('road')}; demand held per record sample")
    else:
        rig = RigInputs.draw(case.duration_s, rng["inputs"])
        sim, desc = foreign.simulate(case, rig, noise_v, rng["foreign"])
        truth.update(model=desc, hidden_effects={}, inputs=rig.describe())
    m = steps_per_sample(case.rate)
    filtered = lowpass_fine(sim["force_fine"], FINE_STEP, case.lowpass_hz)[::m]
    load_cell = LVDT_LOAD_CELL if case.chain == "lvdt" else SENSORS["F_damper"]
    force = measure(filtered, load_cell, rng["noise_f"])
    t = sim["t"]
    valid = force[int(SPLIT * force.size):]
    sigma, q = load_cell
    columns = {"time": t, "v": sim["v_measured"], "fd": sim["demand"], "f": force}
    if case.chain == "lvdt":
        x_measured, v_logged = lvdt_velocity(sim["x_true"], case.rate, rng["noise_v"])
        columns.update(x=x_measured, v=v_logged)
        truth["chain"] = {"lvdt_noise_m": LVDT_NOISE, "lvdt_quantum_m": LVDT_QUANTUM,
                          "logger_filter": f"Butterworth order {LOGGER_FILTER[0]} at {LOGGER_FILTER[1]} Hz, "
                                           "zero-phase (filtfilt) on the central differences of x",
                          "load_cell": {"noise": LVDT_LOAD_CELL[0], "quantum": LVDT_LOAD_CELL[1]}}
    truth.update(samples=int(t.size), max_abs_stroke_m=sim["max_abs_stroke"],
                 noise_floor_nrmse=math.sqrt(sigma ** 2 + q ** 2 / 12) / float(np.std(valid)))
    write_csv(out, case, columns, f"independent record {case.name} (damper_tools.independent); truth kept elsewhere")
    truth_path.parent.mkdir(parents=True, exist_ok=True)
    truth_path.write_text(json.dumps(truth, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    if keep is not None:
        keep.update(sim, filtered=filtered, measured_force=force)
    return truth


def foh_filter_difference(force_fine: FloatArray, rate: float, corner_hz: float = LOWPASS_HZ) -> FloatArray:
    """The continuous load-cell filter (on the fine-step force, then sampled) minus a first-order hold
    on the force sampled at the record's rate (what the diagnosis's filter was before it was fed every
    0.5 ms substep)."""
    m = steps_per_sample(rate)
    continuous = lowpass_fine(force_fine, FINE_STEP, corner_hz)[::m]
    sampled_foh = lowpass_fine(force_fine[::m], 1.0 / rate, corner_hz)
    return continuous - sampled_foh


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kind", choices=KINDS, default="rig")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--effect", action="append", default=[], help="catalog key to hide; repeatable")
    parser.add_argument("--rate", type=float, default=1000.0, choices=RATES)
    parser.add_argument("--duration", type=float, default=None, help="s (default 4 rig, 6 HiL)")
    parser.add_argument("--format", dest="fmt", choices=tuple(FORMATS), default="ms")
    parser.add_argument("--motion", choices=MOTIONS, default="continuous")
    parser.add_argument("--chain", choices=CHAINS, default="transducer",
                        help="lvdt: velocity differentiated from the displacement by the logger (rig only)")
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--truth", type=Path, required=True)
    args = parser.parse_args(argv)
    case = Case(args.kind, args.seed, tuple(args.effect), args.rate, args.duration, args.fmt, motion=args.motion,
                chain=args.chain)
    truth = make(case, args.out, args.truth, args.damper_fmu, args.truck_fmu)
    print(f"wrote {args.out} ({truth['samples']} samples) and {args.truth}; noise floor NRMSE "
          f"{truth['noise_floor_nrmse']:.4f}")


if __name__ == "__main__":
    main()
