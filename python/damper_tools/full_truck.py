"""The three-axle full truck (FullTruck.fmu: the body heaves, pitches and rolls, each axle bounces and
rolls) with six damper FMU instances in one master, and the semi-active benefit on it.

    .venv/bin/python -m damper_tools.full_truck [--quick] [--docs] [--out out/full_truck]

Coupling (Jacobi, a fixed communication step, as damper_tools.cosim couples one quarter truck): at
each communication point every damper instance gets its corner's v_damper and F_demand from the truck,
the truck every corner's F_damper, and all seven step. With damper_mode 1-3 the truck runs alone.

Roads: each tyre has its own road. On a random road (ISO 8608, damper_tools.roads) the left and right
tracks are partially correlated,

    z_right = rho z_left + sqrt(1 - rho^2) z_2        (z_left, z_2 independent, same PSD)

with rho = 0.6 at all wavelengths (an assumption; real roads lose coherence at short wavelengths).
On the measured Belgian block (data/roads/belgian_block.crg) the tracks are the surface's own
sections under the left and right tyres (tyre_track apart). Each axle runs over the front axle's
tracks, delayed by its distance behind the front axle over the speed; the axle positions and the
tyre track come from the FMU's parameters.

The benefit study (`main`) compares on the paper's three road/speed cases and the Belgian block the
best linear passive damper (a grid of c_passive), the ideal semi-active damper and the damper FMU
with the paper's law and with the law and gains docs/benefit-map.md found for the quarter truck:
ride at the driver's seat (ISO 2631 Wk), body heave, pitch and roll, the six tyres' DLC and road
stress. Writes out/full_truck/ (results.json, table.md, full_truck.png); --docs copies the table to
docs/full-truck-table.md and the figure to docs/figures/, and writes the headline figures the
documents quote to docs/full_truck.json (damper_tools.doc_figures).
"""

import argparse
import json
import math
import shutil
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from fmpy.fmi1 import FMICallException

from damper_tools import (
    DAMPER_FMU,
    FULL_TRUCK_FMU,
    REPO,
    FloatArray,
    cosim,
    doc_figures,
    hil_scenarios,
    pyplot,
    ride,
    roads,
)
from damper_tools.fmu import FmuUnit, Slave, Value

OUT = REPO / "out" / "full_truck"
AXLES = ("front", "drive1", "drive2")
SIDES = ("left", "right")
CORNERS = tuple(f"{axle}_{side}" for axle in AXLES for side in SIDES)
CORNER_OUTPUTS = ("v_damper", "F_demand", "x_damper", "v_body", "a_body", "F_tyre", "F_suspension")
BODY_OUTPUTS = ("z_body", "v_body", "a_body", "pitch", "pitch_rate", "a_pitch", "roll", "roll_rate", "a_roll",
                "a_seat")
TRACK_CORRELATION = 0.6  # [A]
FADE_IN_DISTANCE = 10.0  # m of road over which a random road rises from level


Wheels = dict[str, tuple[FloatArray, FloatArray]]  # corner: (z_road, v_road) at t_k, k = 0..n


def parameters(unit: FmuUnit, overrides: dict[str, Value] | None = None) -> dict[str, Value]:
    """The truck's parameters: the FMU's start values with `overrides`."""
    p = unit.parameters()
    for name in overrides or {}:
        unit.variable(name)  # a name the FMU does not have is an error here, not at the first step
    return {**p, **(overrides or {})}


def axle_positions(p: dict[str, Value]) -> dict[str, float]:
    """Each axle's distance behind the front axle (m)."""
    return {"front": 0.0, "drive1": float(p["drive1.x_axle"]), "drive2": float(p["drive2.x_axle"])}


def random_wheel_roads(road: str | float, speed: float, duration: float, seed: int, step: float,
                       axle_x: dict[str, float], correlation: float = TRACK_CORRELATION) -> tuple[Wheels, int]:
    """Correlated left and right ISO 8608 tracks (module docstring), each axle on the front axle's
    tracks later; level where the wheels stand at t = 0, then a rise over FADE_IN_DISTANCE."""
    gd0 = roads.gd0_of(road)
    n_steps = int(round(duration / step))
    lag = max(axle_x.values())
    length = lag + speed * n_steps * step + 1.0
    x, z_left = roads.generate_profile(length, gd0, seed)
    _, z_2 = roads.generate_profile(length, gd0, seed + 1000)
    z_right = correlation * z_left + math.sqrt(1.0 - correlation ** 2) * z_2
    ramp = np.clip((x - lag) / FADE_IN_DISTANCE, 0.0, 1.0)
    window = 0.5 * (1.0 - np.cos(np.pi * ramp))
    tracks = {"left": z_left * window, "right": z_right * window}
    return _delayed(x, tracks, speed, step, n_steps, axle_x, lag), n_steps


def _delayed(x: FloatArray, tracks: dict[str, FloatArray], speed: float, step: float, n_steps: int,
             axle_x: dict[str, float], lag: float) -> Wheels:
    """Each corner's road: its side's track at the position of its axle, the front axle `lag` m
    into the profile at t = 0."""
    out = {}
    for axle in AXLES:
        for side in SIDES:
            _, zr, vr = roads.time_series(x, tracks[side], speed, step, n_steps, offset=lag - axle_x[axle])
            out[f"{axle}_{side}"] = (zr, vr)
    return out


def crg_wheel_roads(speed: float, step: float, axle_x: dict[str, float], tyre_track: float,
                    path: str | Path = hil_scenarios.CRG) -> tuple[Wheels, int, slice]:
    """The Belgian block's sections under the left and right tyres (detrended, the tyre envelope of
    damper_tools.hil_scenarios), between level road: CRG_LEAD s before the front axle reaches it,
    CRG_RUNOUT s after the last axle leaves it. Returns the wheels' roads, the number of steps and
    the window of samples while any wheel is on the track."""
    surface = roads.read_crg(path)
    sections = {side: roads.crg_track(surface, v=sign * 0.5 * tyre_track, envelope=hil_scenarios.CRG_ENVELOPE)
                for side, sign in (("left", 1.0), ("right", -1.0))}
    lag = max(axle_x.values())
    lead = speed * hil_scenarios.CRG_LEAD + lag
    length = sections["left"].x[-1]
    x = np.concatenate(([0.0], lead + sections["left"].x, [lead + length + lag + speed * hil_scenarios.CRG_RUNOUT]))
    tracks = {}
    for side, section in sections.items():
        blend = np.clip(section.x / hil_scenarios.CRG_BLEND, 0.0, 1.0)
        z = section.z * 0.5 * (1 - np.cos(np.pi * blend))
        tracks[side] = np.concatenate(([0.0], z, [z[-1]]))
    duration = hil_scenarios.CRG_LEAD + (length + lag) / speed + hil_scenarios.CRG_RUNOUT
    n_steps = int(round(duration / step)) - 1
    first = int(round(hil_scenarios.CRG_LEAD / step))
    last = int(round((hil_scenarios.CRG_LEAD + (length + lag) / speed) / step))
    return _delayed(x, tracks, speed, step, n_steps, axle_x, lag), n_steps, slice(first, last + 1)


def simulate(wheels: Wheels, step: float, n_steps: int, truck_parameters: dict[str, Value] | None = None,
             damper_parameters: dict[str, Value] | None = None, full_truck_fmu: str | Path = FULL_TRUCK_FMU,
             damper_fmu: str | Path = DAMPER_FMU, start_time: float = 0.0,
             echo: bool = True) -> dict[str, FloatArray]:
    """Runs the full truck (with six damper FMU instances for damper_mode 0) for n_steps Jacobi steps
    of `step` seconds. Returns 'time', each corner's road and outputs as 'CORNER.NAME'
    (CORNER_OUTPUTS; 'CORNER.damper.F_damper' with dampers) and the body's outputs (BODY_OUTPUTS), at
    the communication points, the first row after initialisation. A refused call raises
    cosim.Refused."""
    tp = dict(truck_parameters or {})
    dp = dict(cosim.HIL_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters)
    if not step > 0 or n_steps < 1:
        raise ValueError(f"need step > 0 and n_steps >= 1 (got {step}, {n_steps})")
    if set(wheels) != set(CORNERS) or any(min(len(z), len(v)) < n_steps + 1 for z, v in wheels.values()):
        raise ValueError(f"need the road of each of {CORNERS} with {n_steps + 1} samples")
    truck_unit = FmuUnit.load(full_truck_fmu)
    with_dampers = int(tp.get("damper_mode", cosim.MODE_EXTERNAL)) == cosim.MODE_EXTERNAL
    truck_out = [f"{c}.{n}" for c in CORNERS for n in CORNER_OUTPUTS] + list(BODY_OUTPUTS)
    i_v = [truck_out.index(f"{c}.v_damper") for c in CORNERS]
    i_fd = [truck_out.index(f"{c}.F_demand") for c in CORNERS]
    road_names = [(f"{c}.z_road", f"{c}.v_road", f"{c}.F_damper") for c in CORNERS]
    times = start_time + step * np.arange(n_steps + 1, dtype=float)
    rec = np.empty((n_steps + 1, len(truck_out)))
    rec_f = np.zeros((n_steps + 1, len(CORNERS)))
    instances: list[Slave] = []
    t = start_time
    try:
        truck = Slave(truck_unit, "full_truck", echo=echo)
        instances.append(truck)
        truck.initialize(start_time, times[-1], **tp)
        dampers = []
        if with_dampers:
            damper_unit = FmuUnit.load(damper_fmu)
            for c in CORNERS:
                damper = Slave(damper_unit, f"{c}.damper", echo=echo)
                instances.append(damper)
                damper.initialize(start_time, times[-1], **dp)
                dampers.append(damper)
        rec[0] = truck.get(truck_out)
        for j, damper in enumerate(dampers):
            rec_f[0, j] = damper.get(["F_damper"])[0]
        for k in range(n_steps):
            t = times[k]
            inputs = {}
            for j, (c, (zn, vn, fn)) in enumerate(zip(CORNERS, road_names, strict=True)):
                inputs.update({zn: wheels[c][0][k], vn: wheels[c][1][k], fn: rec_f[k, j]})
            truck.set(**inputs)
            for j, damper in enumerate(dampers):
                damper.set(v_damper=rec[k, i_v[j]], F_demand=rec[k, i_fd[j]], a_damper=0.0)
            for inst in instances:
                inst.step(step, t)
            rec[k + 1] = truck.get(truck_out)
            for j, damper in enumerate(dampers):
                rec_f[k + 1, j] = damper.get(["F_damper"])[0]
    except FMICallException as e:
        culprit = next((s for s in instances if s.errors()), None)
        if culprit is None:
            raise
        raise cosim.Refused(culprit.name, float(t), culprit.errors()[-1][2]) from e
    finally:
        for inst in instances:
            inst.free()
    res = {"time": times}
    for c in CORNERS:
        res[f"{c}.z_road"] = np.asarray(wheels[c][0][:n_steps + 1], float)
    res.update({name: rec[:, i] for i, name in enumerate(truck_out)})
    if with_dampers:
        res.update({f"{c}.damper.F_damper": rec_f[:, j] for j, c in enumerate(CORNERS)})
    return res


# --------------------------------------------------------------------------- the linear model

def _coordinate_rows(p: dict[str, Value]) -> list[tuple[float, FloatArray, str]]:
    """Every spring of the truck as (stiffness, row, kind): its stretch is row · q, q = [z, θ, φ,
    z_1, φ_1, z_2, φ_2, z_3, φ_3] (the FMU's coordinates), written here from the geometry alone."""
    x_cg = float(p["x_cg"])
    s, t = 0.5 * float(p["suspension_track"]), 0.5 * float(p["tyre_track"])
    springs = []
    for i, (axle, behind) in enumerate(axle_positions(p).items()):
        x = x_cg - behind
        for sign in (1.0, -1.0):
            susp = np.zeros(9)
            susp[[0, 1, 2, 3 + 2 * i, 4 + 2 * i]] = [1.0, x, sign * s, -1.0, -sign * s]
            tyre = np.zeros(9)
            tyre[[3 + 2 * i, 4 + 2 * i]] = [1.0, sign * t]
            springs += [(float(p[f"{axle}.k_susp"]), susp, "suspension"), (float(p[f"{axle}.k_tyre"]), tyre, "tyre")]
        roll = np.zeros(9)
        roll[[2, 4 + 2 * i]] = [1.0, -1.0]
        springs.append((float(p[f"{axle}.k_roll"]), roll, "roll"))
    return springs


def linear_model(p: dict[str, Value]) -> tuple[FloatArray, FloatArray]:
    """The undamped truck's mass and stiffness matrices (SI), from its potential energy
    ½ Σ k (row · q)² − ½ M g h φ² (gravity's roll moment), independently of the FMU's equations."""
    mass = np.diag([float(p["m_body"]), float(p["I_pitch"]), float(p["I_roll"])]
                   + [float(p[f"{a}.{n}"]) for a in AXLES for n in ("m_axle", "J_axle")])
    stiffness = np.zeros((9, 9))
    for k, r, _ in _coordinate_rows(p):
        stiffness = stiffness + k * np.outer(r, r)
    stiffness[2, 2] -= float(p["m_body"]) * float(p["gravity"]) * float(p["h_roll"])
    return mass, stiffness


def natural_frequencies(p: dict[str, Value]) -> FloatArray:
    """The undamped natural frequencies (Hz), ascending, with each mode's largest coordinate."""
    mass, stiffness = linear_model(p)
    w2, _ = np.linalg.eig(np.linalg.solve(mass, stiffness))
    return np.sort(np.sqrt(np.real(w2))) / (2 * np.pi)


def static_tyre_loads(p: dict[str, Value]) -> dict[str, float]:
    """Each tyre's static load (N): the linear truck's deflection under its weight (the body's at
    its centre of mass, each axle's at its centre), then each tyre's spring force."""
    mass, stiffness = linear_model(p)
    g = float(p["gravity"])
    weight = np.zeros(9)
    weight[[0, 3, 5, 7]] = [-mass[j, j] * g for j in (0, 3, 5, 7)]
    q = np.linalg.solve(stiffness, weight)
    tyres = [(k, r) for k, r, kind in _coordinate_rows(p) if kind == "tyre"]
    return {c: float(-k * (r @ q)) for c, (k, r) in zip(CORNERS, tyres, strict=True)}


# --------------------------------------------------------------------------- metrics

def metrics(res: dict[str, FloatArray], window: slice, static_loads: dict[str, float]) -> dict[str, float]:
    """Ride, road holding and working space over the samples in `window`: the driver's seat (RMS and
    ISO 2631 Wk RMS), the body's heave, pitch and roll accelerations (RMS), the six tyres' DLC (mean
    and largest) and fourth-power road stress (mean), the dampers' deflection (RMS mean, peak)."""
    step = float(res["time"][1] - res["time"][0])
    dlc = [np.std(res[f"{c}.F_tyre"][window]) / static_loads[c] for c in CORNERS]
    stress = [ride.road_stress_factor(res[f"{c}.F_tyre"][window], static_loads[c]) for c in CORNERS]
    x = [res[f"{c}.x_damper"][window] for c in CORNERS]
    return {
        "a_seat_wk_rms": ride.wk_rms(res["a_seat"][window], step),
        "a_seat_rms": float(np.std(res["a_seat"][window])),
        "a_body_rms": float(np.std(res["a_body"][window])),
        "a_pitch_rms": float(np.std(res["a_pitch"][window])),
        "a_roll_rms": float(np.std(res["a_roll"][window])),
        "DLC": float(np.mean(dlc)), "DLC_max": float(np.max(dlc)),
        "road_stress": float(np.mean(stress)),
        "x_damper_rms": float(np.mean([np.std(v) for v in x])),
        "x_damper_peak": float(np.max([np.max(np.abs(v)) for v in x])),
    }


# --------------------------------------------------------------------------- the benefit study

@dataclass(frozen=True)
class Case:
    """A road and speed: an ISO 8608 road (`road`) or the Belgian block (`road == CRG_ROAD`)."""
    road: str
    speed: float

    @property
    def label(self) -> str:
        return "Belgian block" if self.road == CRG_ROAD else f"{self.road} road"


CRG_ROAD = hil_scenarios.CRG_ROAD
CASES = (Case("minor", 14.0), Case("major", 20.0), Case("motorway", 25.0), Case(CRG_ROAD, hil_scenarios.CRG_SPEED))
C_PASSIVE = tuple(float(c) for c in np.arange(5e3, 60e3 + 1, 5e3))  # N s/m per damper
# The laws and gains: the paper's (the FMU's defaults), and docs/benefit-map.md's best for the FMU in
# the quarter truck (Cm 48 kN s/m, alpha 0.2, force loop Kp_F 1, Ki_F 0).
PAPER_LAW: dict[str, Value] = {}
BEST_LAW: dict[str, Value] = {"Cm": 48e3, "alpha": 0.2}
BEST_GAINS: dict[str, Value] = {"Kp_F": 1.0, "Ki_F": 0.0}
SETTINGS: dict[str, tuple[int, dict[str, Value], dict[str, Value]]] = {
    # name: (damper_mode, truck parameters, damper parameters)
    "ideal, paper's law": (cosim.MODE_IDEAL, PAPER_LAW, {}),
    "ideal, Cm 48 alpha 0.2": (cosim.MODE_IDEAL, BEST_LAW, {}),
    "FMU, paper's law": (cosim.MODE_EXTERNAL, PAPER_LAW, {}),
    "FMU, Cm 48 alpha 0.2, Ki_F 0": (cosim.MODE_EXTERNAL, BEST_LAW, BEST_GAINS),
}
# The laws searched for the best at a DLC no worse than the best-riding passive damper's: ideal, and
# the FMU with BEST_GAINS (Cm in N s/m, alpha, C_ground in N s/m); groundhook never gave the least
# DLC in the quarter truck's map, one hybrid law keeps it in view.
LAW_GRID = tuple((cm, alpha, 0.0) for cm in (36e3, 48e3, 60e3, 72e3) for alpha in (0.2, 0.3, 0.4))
LAW_GRID += ((48e3, 0.3, 12e3),)
# The families of the law search (a row's setting starts with one of them).
LAW_SEARCH = ("ideal law search", "FMU law search (Kp_F 1, Ki_F 0)")
SEED = 3
STEP = 1e-3
DURATION, SETTLE = 15.0, 3.0  # s: the quarter truck's HiL record (docs/hil.md)
QUICK_DURATION = 4.0


def case_roads(case: Case, p: dict[str, Value], duration: float = DURATION, settle: float = SETTLE,
               step: float = STEP, seed: int = SEED,
               correlation: float = TRACK_CORRELATION) -> tuple[Wheels, int, slice]:
    """The wheels' roads of a case (with the truck's parameters `p`), the steps, and the window the
    metrics use: after `settle` on a random road, while a wheel is on the Belgian block."""
    axle_x = axle_positions(p)
    if case.road == CRG_ROAD:
        return crg_wheel_roads(case.speed, step, axle_x, float(p["tyre_track"]))
    wheels, n = random_wheel_roads(case.road, case.speed, settle + duration, seed, step, axle_x, correlation)
    return wheels, n, slice(int(round(settle / step)), None)


def run_case(case: Case, fmus: dict[str, Path], duration: float = DURATION, c_passive: Sequence[float] = C_PASSIVE,
             laws: Sequence[tuple[float, float, float]] = LAW_GRID) -> list[dict[str, Any]]:
    """Every passive damper of the grid, every setting and every law of `laws` (ideal, and the FMU
    with BEST_GAINS) on one case: rows of metrics."""
    unit = FmuUnit.load(fmus["full_truck"])
    p = parameters(unit)
    loads = static_tyre_loads(p)
    wheels, n, window = case_roads(case, p, duration)
    runs: list[tuple[str, int, dict[str, Value], dict[str, Value]]] = [
        (f"passive {c / 1e3:g} kN s/m", cosim.MODE_PASSIVE, {"c_passive": c}, {}) for c in c_passive]
    runs += [(name, mode, tp, dp) for name, (mode, tp, dp) in SETTINGS.items()]
    for cm, alpha, cg in laws:
        law = {"Cm": cm, "alpha": alpha, "C_ground": cg}
        label = f"Cm {cm / 1e3:g} alpha {alpha:g} C_ground {cg / 1e3:g}"
        runs += [(f"{LAW_SEARCH[0]}: {label}", cosim.MODE_IDEAL, law, {}),
                 (f"{LAW_SEARCH[1]}: {label}", cosim.MODE_EXTERNAL, law, BEST_GAINS)]
    rows = []
    for name, mode, tp, dp in runs:
        res = simulate(wheels, STEP, n, {"damper_mode": mode, **tp}, {**cosim.HIL_DAMPER_PARAMETERS, **dp},
                       full_truck_fmu=fmus["full_truck"], damper_fmu=fmus["damper"])
        rows.append({"road": case.road, "speed": case.speed, "setting": name, "passive": mode == cosim.MODE_PASSIVE,
                     "c_passive": tp.get("c_passive", math.nan), **metrics(res, window, loads)})
    return rows


def with_benefits(rows: list[dict[str, Any]], ride_metric: str = "a_seat_wk_rms") -> list[dict[str, Any]]:
    """Each row's ride benefit over the best-riding passive damper of its case (least `ride_metric`)
    and its DLC against that damper's (at most 0: no worse), as docs/benefit-map.md compares; and its
    ride benefit over the passive front at its own DLC (`benefit_equal_dlc`: the passive dampers that
    no other rides and holds the road better than, their ride interpolated linearly in DLC by
    damper_tools.hil_scenarios; NaN outside their DLC range, `dlc_off_front` saying on which side)."""
    out = []
    for r in rows:
        passive = [q for q in rows if q["passive"] and (q["road"], q["speed"]) == (r["road"], r["speed"])]
        ref = min(passive, key=lambda q: q[ride_metric])
        at_dlc = hil_scenarios.passive_ride_at_dlc(passive, r["DLC"], ride_metric)
        front = hil_scenarios.pareto_front(passive, ride_metric)
        side = "below" if r["DLC"] < front[0]["DLC"] else "above" if r["DLC"] > front[-1]["DLC"] else ""
        out.append({**r, "benefit": 1 - r[ride_metric] / ref[ride_metric], "dlc_change": r["DLC"] / ref["DLC"] - 1,
                    "reference": ref["setting"],
                    "benefit_equal_dlc": math.nan if at_dlc is None else 1 - r[ride_metric] / at_dlc,
                    "dlc_off_front": side})
    return out


def table(rows: list[dict[str, Any]]) -> str:
    """The Markdown table of the study (one row per case and setting, the best passive first)."""
    lines = ["| case | damper | seat Wk RMS (m/s²) | ride benefit | heave RMS (m/s²) | pitch RMS (rad/s²) "
             "| roll RMS (rad/s²) | DLC (mean, max) | DLC change | ride benefit at equal DLC | road stress |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for case in dict.fromkeys((r["road"], r["speed"]) for r in rows):
        of_case = [r for r in rows if (r["road"], r["speed"]) == case]
        best = next(r for r in of_case if r["setting"] == of_case[0]["reference"])
        label = Case(*case).label + f", {case[1]:g} m/s"
        searched = [best_at_dlc(of_case, family) for family in LAW_SEARCH]
        fixed = [r for r in of_case if r["setting"] in SETTINGS]
        for r in [best] + fixed + [r for r in searched if r is not None]:
            lines.append(f"| {label} | {r['setting']}{' (best passive)' if r is best else ''} "
                         f"| {r['a_seat_wk_rms']:.3f} | {100 * r['benefit']:+.1f} % | {r['a_body_rms']:.3f} "
                         f"| {r['a_pitch_rms']:.3f} | {r['a_roll_rms']:.3f} | {r['DLC']:.3f}, {r['DLC_max']:.3f} "
                         f"| {100 * r['dlc_change']:+.1f} % | {_equal_dlc(r)} "
                         f"| {r['road_stress']:.3f} |")
    return "\n".join(lines) + "\n"


def best_at_dlc(rows: list[dict[str, Any]], family: str) -> dict[str, Any] | None:
    """The row of a law-search family with the largest ride benefit at a DLC no worse than the
    best-riding passive damper's (None if no law of it holds the road as well)."""
    fair = [r for r in rows if r["setting"].startswith(family) and r["dlc_change"] <= 0]
    return max(fair, key=lambda r: r["benefit"]) if fair else None


def _equal_dlc(r: dict[str, Any]) -> str:
    """The benefit at equal DLC, or where the row's DLC lies off the passive front."""
    if r["dlc_off_front"]:
        return f"DLC {r['dlc_off_front']} every passive's on the front"
    return f"{100 * r['benefit_equal_dlc']:+.1f} %"


def plot(path: Path, rows: list[dict[str, Any]]) -> None:
    """Seat ride against DLC per case: the passive family and each setting."""
    plt = pyplot()

    cases = list(dict.fromkeys((r["road"], r["speed"]) for r in rows))
    fig, axes = plt.subplots(1, len(cases), figsize=(4.2 * len(cases), 4.2))
    markers = dict(zip(SETTINGS, ("o", "s", "^", "D"), strict=True))
    for ax, case in zip(np.atleast_1d(axes), cases, strict=True):
        of_case = [r for r in rows if (r["road"], r["speed"]) == case]
        passive = [r for r in of_case if r["passive"]]
        ax.plot([r["DLC"] for r in passive], [r["a_seat_wk_rms"] for r in passive], "-", color="0.5", marker=".",
                label="passive, c 5-60 kN s/m")
        for family, colour in zip(LAW_SEARCH, ("tab:green", "tab:red"), strict=True):
            found = [r for r in of_case if r["setting"].startswith(family)]
            ax.plot([r["DLC"] for r in found], [r["a_seat_wk_rms"] for r in found], "x", color=colour, ms=5,
                    label=f"{family}, {len(found)} laws")
        for r in of_case:
            if r["setting"] in SETTINGS:
                ax.plot(r["DLC"], r["a_seat_wk_rms"], markers[r["setting"]], ms=7, label=r["setting"])
        ax.set_title(f"{Case(*case).label}, {case[1]:g} m/s", fontsize=10)
        ax.set_xlabel("DLC, mean of six tyres")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("driver's seat, Wk-weighted RMS (m/s²)")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.suptitle("Three-axle truck with pitch and roll (FullTruck.fmu): ride against road holding", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


DOCS_TABLE = REPO / "docs" / "full-truck-table.md"
DOCS_HEADER = "<!-- generated by `python -m damper_tools.full_truck --docs`; do not edit -->\n"


def headline(text: str) -> dict[str, float]:
    """The figures the documents quote, read from the table (table(), docs/full-truck-table.md, so
    the test can read them again from the committed table): the seat's ride benefit of each setting
    over the cases (%), on the random roads and on the Belgian block, and the DLC change of the
    quarter truck's best setting on the random roads."""
    rows = doc_figures.table_rows(text)[0]
    crg = Case(CRG_ROAD, hil_scenarios.CRG_SPEED).label

    def of(setting: str, where: str = "all") -> list[list[float]]:
        return [[doc_figures.numbers(r[3])[0], doc_figures.numbers(r[8])[0]] for r in rows if r[1].startswith(setting)
                and (where == "all" or r[0].startswith(crg) == (where == "crg"))]

    out: dict[str, float] = {}
    for name, setting in (("ideal_paper", "ideal, paper's law"), ("fmu_paper", "FMU, paper's law"),
                          ("ideal_search", LAW_SEARCH[0]), ("fmu_best_qt", "FMU, Cm 48 alpha 0.2, Ki_F 0")):
        doc_figures.span(out, f"{name}_benefit_pct", [b for b, _ in of(setting)])
    doc_figures.span(out, "fmu_search_random_benefit_pct", [b for b, _ in of(LAW_SEARCH[1], "random")])
    out["fmu_search_crg_benefit_pct"] = of(LAW_SEARCH[1], "crg")[0][0]
    doc_figures.span(out, "fmu_best_qt_random_dlc_change_pct", [d for _, d in of("FMU, Cm 48 alpha 0.2", "random")])
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--full-truck-fmu", type=Path, default=FULL_TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK_DURATION:g} s records, three passive dampers, three laws")
    parser.add_argument("--docs", action="store_true", help="copy the table and figure into docs/, the headline "
                        "figures into docs/full_truck.json")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    fmus = {"full_truck": args.full_truck_fmu, "damper": args.damper_fmu}
    duration = QUICK_DURATION if args.quick else DURATION
    c_passive = C_PASSIVE[1::4] if args.quick else C_PASSIVE
    laws = LAW_GRID[::5] if args.quick else LAW_GRID
    p = parameters(FmuUnit.load(fmus["full_truck"]))
    print("full_truck: natural frequencies (Hz) " + ", ".join(f"{f:.2f}" for f in natural_frequencies(p)))
    rows = []
    for case in CASES:
        rows += run_case(case, fmus, duration, c_passive, laws)
        print(f"full_truck: {case.label}, {case.speed:g} m/s done")
    rows = with_benefits(rows)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "results.json").write_text(json.dumps(rows, indent=1), encoding="utf-8")
    text = table(rows)
    (args.out / "table.md").write_text(text, encoding="utf-8")
    plot(args.out / "full_truck.png", rows)
    print(text)
    if args.docs:
        if args.quick:
            raise SystemExit("full_truck: --docs needs the whole study (the documents quote it)")
        DOCS_TABLE.write_text(DOCS_HEADER + text, encoding="utf-8")
        shutil.copy(args.out / "full_truck.png", REPO / "docs" / "figures" / "full_truck.png")
        doc_figures.write("full_truck", headline(text), ".venv/bin/python -m damper_tools.full_truck --docs")
    print(f"full_truck: wrote {args.out}")


if __name__ == "__main__":
    main()
