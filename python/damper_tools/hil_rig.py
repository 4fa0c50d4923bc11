"""The HiL rig as a model: what the paper's rig put between its quarter-truck model and the damper.

In the paper's hardware-in-the-loop test (Besinger et al.'s rig, Fig. 7) a real-time computer ran the
quarter truck; a servo-hydraulic actuator moved the damper's rod to the truck's damper displacement,
a load cell measured the damper force and fed it back to the truck model, and the computer sent the
Modified Skyhook demand to the damper's controller. The co-simulation of damper_tools.hil_scenarios
couples the two FMUs directly (one communication step of Jacobi lag). `Rig` puts the rig's parts
in between, through the hooks of damper_tools.cosim.Car:

    truck v_damper --[RT computer: sample T_rt]--[actuator: pure delay tau_act, 2nd-order f_act]--> damper v_damper
    truck F_demand --[RT computer: sample T_rt]-------------------------------------------------> damper F_demand
    damper F_damper --[load cell: 2nd-order Butterworth f_lc]--[pure delay tau_lc]--[RT sample T_rt]--> truck F_damper

The actuator follows the truck's damper displacement; as it is linear with unit static gain it is
applied to the velocity (the FMU's input), whose integral is the displacement. The demand leaves the
computer with the displacement command and reaches the damper's controller without the actuator's
delay. Tracking is judged as the rig's computer logs it: the demand it computed against the
load-cell force it received at the same sample, split by the truck model's damper velocity.

Every parameter is an assumption (the paper gives none of them); the reasoning is in
docs/hil.md ("The HiL rig as a model"). The default rig is NO rig: `Rig(RigParameters())` with
infinite bandwidths, zero delays and T_rt = the communication step passes every signal through
unchanged (tested: bit-identical to the direct coupling).

Computing functions print nothing; `main` (damper-hil-rig) runs the sweep and the robustness
table, plots and writes out/rig/ (with --docs also the headline figures, docs/hil_rig.json).
"""

import argparse
import json
import math
import shutil
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, TypedDict

import numpy as np
import numpy.typing as npt

from damper_tools import DAMPER_FMU, REPO, TRUCK_FMU, cosim, jsonable, pyplot, roads
from damper_tools.hil_scenarios import FADE_IN, SETTLE, STEP, force_spectrum, spectral_peaks, tracking_metrics

OUT = REPO / "out" / "rig"

# The paper's case: minor road at 14 m/s (Fig. 7).
ROAD, SPEED = "minor", 14.0
DURATION = 15.0           # s recorded after SETTLE (as hil_scenarios)
SEED = 3                  # road seed of hil_scenarios
PAPER_DOMINANT_HZ = 15.0  # [P] "The dominant frequency is 15 Hz"
PAPER_BAND_HZ = 2.0       # the acceptance: 15 +- 2 Hz
PEAK_BAND = (5.0, 30.0)   # Hz, band of the dominant-frequency search (wheel hop; as hil_scenarios)
PROMINENCE_BAND = (3.0, 30.0)   # Hz: prominence = peak PSD / median PSD over this band

# Sweep of rig latency x actuator bandwidth (the other rig parts at RIG_FIXED).
SWEEP_LATENCIES = (0.0, 1e-3, 2e-3, 3e-3, 4e-3, 6e-3, 8e-3)        # s, actuator pure delay tau_act [A]
SWEEP_BANDWIDTHS = (10.0, 20.0, 40.0, 70.0, 100.0, 150.0, math.inf)  # Hz, actuator -3 dB bandwidth [A]
# The force path alone (ideal actuator, a delay on the measured force into the truck model), as the
# slow reference of docs/physics.md §6.4 modelled the rig.
SWEEP_LOAD_CELL_DELAYS = (1e-3, 2e-3, 3e-3, 4e-3, 6e-3, 8e-3)     # s [A]
ROBUST_SEEDS = (1, 2, 3, 4, 5)                           # road seeds [A]
ROBUST_DURATION = 15.0    # s recorded per robustness run (30 runs) [A]


@dataclass
class RigParameters:
    """The rig between truck and damper (all [A], reasoning in docs/hil.md).

    actuator_delay   s   pure delay from the computer's displacement command to the actuator's
                         motion (D/A, servo-valve spool, transport), the 'rig latency' swept
    f_actuator       Hz  -3 dB bandwidth of the position-controlled servo-hydraulic actuator,
                         second order with damping zeta_actuator (inf: follows exactly)
    zeta_actuator    -   its damping ratio; 1/sqrt(2) makes f_actuator the -3 dB frequency
    f_load_cell      Hz  corner of the load cell's conditioning / anti-alias filter, 2nd-order
                         Butterworth (inf: none)
    load_cell_delay  s   pure delay of the measured force into the truck model (A/D, computation)
    rt_period        s   sample period of the real-time computer; None = the communication step.
                         Must be a multiple of it (inputs and outputs held over the period)
    """
    actuator_delay: float = 0.0
    f_actuator: float = math.inf
    zeta_actuator: float = 1 / math.sqrt(2)
    f_load_cell: float = math.inf
    load_cell_delay: float = 0.0
    rt_period: float | None = None


# The rig parts held fixed in the sweep: a 1 kHz real-time computer (the communication step) and a
# load cell behind a 500 Hz second-order filter (docs/hil.md).
class _RigFixed(TypedDict):
    f_load_cell: float
    load_cell_delay: float
    rt_period: float | None


RIG_FIXED: _RigFixed = {"f_load_cell": 500.0, "load_cell_delay": 0.0, "rt_period": None}


class _Delay:
    """Pure delay of `delay` seconds on a signal sampled every `step` (linear interpolation between
    samples; before the first sample the first value)."""

    def __init__(self, delay: float, step: float) -> None:
        if delay < 0:
            raise ValueError("delay must be >= 0")
        self.d = delay / step
        self.history: list[float] = []

    def __call__(self, x: float) -> float:
        self.history.append(x)
        if self.d == 0:
            return x
        pos = len(self.history) - 1 - self.d
        if pos <= 0:
            return self.history[0]
        i = int(math.floor(pos))
        frac = pos - i
        return self.history[i] if frac == 0 else (1 - frac) * self.history[i] + frac * self.history[i + 1]


class _SecondOrder:
    """w^2 / (s^2 + 2 zeta w s + w^2) sampled every `step`, starting in steady state at its first
    input; f = inf passes the input through.

    method 'zoh': an actuator driven by a command held over the step; the output is the exact mean
    of the continuous output over the step (the velocity that moves the actuator by its displacement
    over the step; it tends to the command as f grows). 'bilinear': Tustin, for a conditioning filter
    of a sampled signal."""

    def __init__(self, f: float, zeta: float, step: float, method: Literal["zoh", "bilinear"]) -> None:
        self.passthrough = math.isinf(f)
        if self.passthrough:
            return
        from scipy.signal import cont2discrete

        w = 2 * math.pi * f
        a = np.array([[0.0, 1.0], [-w * w, -2 * zeta * w]])
        b = np.array([[0.0], [w * w]])
        c = np.array([[1.0, 0.0]])
        if method == "zoh":
            # augmented with the integral z of the output: the mean over the step is (z_{k+1} - z_k)/h
            a_aug = np.zeros((3, 3))
            a_aug[:2, :2], a_aug[2, :2] = a, c
            b_aug = np.vstack([b, [[0.0]]])
            ad_aug, bd_aug, *_ = cont2discrete((a_aug, b_aug, np.eye(3), np.zeros((3, 1))), step, method="zoh")
            self.ad, self.bd = ad_aug[:2, :2], bd_aug[:2, 0]
            self.cd, self.dd = ad_aug[2, :2] / step, float(bd_aug[2, 0]) / step
        else:
            ad, bd, cd, dd, _ = cont2discrete((a, b, c, np.zeros((1, 1))), step, method=method)
            self.ad, self.bd, self.cd, self.dd = ad, bd[:, 0], cd[0], float(dd[0, 0])
        self.x: npt.NDArray[np.floating[Any]] | None = None

    def __call__(self, u: float) -> float:
        if self.passthrough:
            return u
        x = self.x
        if x is None:  # steady state at the first input: x = (I - A)^-1 B u
            x = np.linalg.solve(np.eye(2) - self.ad, self.bd * u)
        y = float(self.cd @ x + self.dd * u)
        self.x = self.ad @ x + self.bd * u
        return y


class Rig:
    """One rig for one run (it keeps the signals' history): `damper_inputs` and `truck_force` are
    the hooks of damper_tools.cosim.Car; `logged_force` the force the computer received at each step."""

    def __init__(self, params: RigParameters, step: float) -> None:
        self.p = params
        period = step if params.rt_period is None else params.rt_period
        m = period / step
        if abs(m - round(m)) > 1e-9 or round(m) < 1:
            raise ValueError(f"rt_period {period} is not a multiple of the communication step {step}")
        self.m = int(round(m))
        self.act_delay = _Delay(params.actuator_delay, step)
        # the actuator is fed a held command and moves continuously: its exact ZOH discretisation
        self.actuator = _SecondOrder(params.f_actuator, params.zeta_actuator, step, "zoh")
        self.load_cell = _SecondOrder(params.f_load_cell, 1 / math.sqrt(2), step, "bilinear")
        self.lc_delay = _Delay(params.load_cell_delay, step)
        self._held_cmd = (0.0, 0.0)
        self._held_force = 0.0
        self.logged_force: list[float] = []

    def damper_inputs(self, k: int, v_truck: float, f_demand: float) -> tuple[float, float]:
        if k % self.m == 0:
            self._held_cmd = (v_truck, f_demand)
        v_cmd, f_cmd = self._held_cmd
        return self.actuator(self.act_delay(v_cmd)), f_cmd

    def truck_force(self, k: int, f_load_cell: float) -> float:
        f = self.lc_delay(self.load_cell(f_load_cell))
        if k % self.m == 0:
            self._held_force = f
        self.logged_force.append(self._held_force)
        return self._held_force


# ----------------------------------------------------------------------------- runs and metrics

def run(params: RigParameters | None, seed: int = SEED, duration: float = DURATION, settle: float = SETTLE,
        step: float = STEP, tare_load_cell: bool = True, force_controller: int = 0, road: str = ROAD,
        speed: float = SPEED, truck_fmu: str | Path = TRUCK_FMU,
        damper_fmu: str | Path = DAMPER_FMU, echo: bool = True) -> dict[str, Any]:
    """The quarter truck + damper FMU on a random road, with a rig (params) or without (None).
    Returns the result dict of cosim.simulate plus 'F_logged' (the force the truck received: the
    damper's F_damper without a rig) and 'first' (the first sample after settle). A run that goes
    unstable raises cosim.Refused (echo: print the FMU's refusal too)."""
    case = roads.road_case(road, speed, settle + duration, seed, step=step, fade_in=FADE_IN)
    car = cosim.Car("qt", case.z_road, case.v_road, {"damper_mode": cosim.MODE_EXTERNAL},
                    {"tare_load_cell": tare_load_cell, "force_controller": force_controller})
    rig = None
    if params is not None:
        rig = Rig(params, step)
        car.damper_inputs, car.truck_force = rig.damper_inputs, rig.truck_force
    n = case.t.size - 1
    res: dict[str, Any] = cosim.simulate([car], step, n, truck_fmu=truck_fmu, damper_fmu=damper_fmu,
                         damper_outputs=("F_damper", "F_demand_clipped", "x_spool", "x_damper"), echo=echo)[0]
    if rig is None:
        res["F_logged"] = res["damper.F_damper"]
    else:  # the force the truck got over step k, k = 0..n-1; the last point: what it would get next
        rig.truck_force(n, res["damper.F_damper"][-1])
        res["F_logged"] = np.array(rig.logged_force)
    res["first"] = int(round(settle / step))
    return res


def metrics(res: dict[str, Any], step: float = STEP) -> dict[str, Any]:
    """Tracking (hil_scenarios.tracking_metrics on the logged force, the truck's demand and the truck's
    damper velocity), the force spectrum's peaks and the peak's prominence, over the recorded part."""
    w = slice(res["first"], None)
    tr = tracking_metrics(res["F_logged"][w], res["F_demand"][w], res["v_damper"][w])
    f, p = force_spectrum(res["F_logged"][w], step)
    pk = spectral_peaks(f, p)
    band = (f >= PEAK_BAND[0]) & (f <= PEAK_BAND[1])
    prom = (f >= PROMINENCE_BAND[0]) & (f <= PROMINENCE_BAND[1])
    ext, com = tr["extension"], tr["compression"]
    return {
        "peak_Hz": pk["peak_wheel_hop_band"], "peak_above_3Hz": pk["peak_above_3Hz"],
        "prominence": float(p[band].max() / np.median(p[prom])),
        "ext_mean_error": ext["mean_error"], "ext_above": ext["fraction_above"],
        "comp_mean_error": com["mean_error"], "comp_below": com["fraction_below"],
        "pattern": bool(ext["mean_error"] > 0 and ext["fraction_above"] > 0.5
                        and com["mean_error"] < 0 and com["fraction_below"] > 0.5),
        "error_rms": tr["error_rms"], "F_rms": tr["F_rms"], "F_demand_rms": tr["F_demand_rms"],
        "v_max": tr["v_max"], "F_max": tr["F_max"], "psd": (f, p),
    }


def paper_like(m: dict[str, Any]) -> bool:
    """The paper's Fig. 7: dominant force frequency 15 +- 2 Hz and the sign pattern."""
    return bool(abs(m["peak_Hz"] - PAPER_DOMINANT_HZ) <= PAPER_BAND_HZ and m["pattern"])


@dataclass
class SweepPoint:
    actuator_delay: float
    f_actuator: float
    metrics: dict[str, Any] = field(repr=False)


def sweep(latencies: Sequence[float] = SWEEP_LATENCIES, bandwidths: Sequence[float] = SWEEP_BANDWIDTHS,
          duration: float = DURATION, seed: int = SEED, **kwargs: Any) -> tuple[dict[str, Any], list[SweepPoint]]:
    """The no-rig run and the grid latency x bandwidth (RIG_FIXED for the rest); returns
    (no-rig metrics, points)."""
    base = metrics(run(None, seed, duration, **kwargs))
    points = []
    for lat in latencies:
        for fa in bandwidths:
            p = RigParameters(actuator_delay=lat, f_actuator=fa, **RIG_FIXED)
            points.append(SweepPoint(lat, fa, _metrics_or_unstable(p, seed, duration, **kwargs)))
    return base, points


def force_path_sweep(delays: Sequence[float] = SWEEP_LOAD_CELL_DELAYS, duration: float = DURATION, seed: int = SEED,
                     **kwargs: Any) -> list[tuple[float, dict[str, Any]]]:
    """Ideal actuator, the 500 Hz load cell and a pure delay on the measured force: [(delay, metrics)]."""
    out = []
    for d in delays:
        p = RigParameters(f_load_cell=RIG_FIXED["f_load_cell"], load_cell_delay=d)
        out.append((d, _metrics_or_unstable(p, seed, duration, **kwargs)))
    return out


def _metrics_or_unstable(params: RigParameters, seed: int, duration: float, **kwargs: Any) -> dict[str, Any]:
    """The run's metrics, or {'unstable': what was refused} when the loop went unstable and the damper
    refused a velocity or a force demand outside its range (expected at some sweep points: not echoed)."""
    try:
        return metrics(run(params, seed, duration, echo=False, **kwargs))
    except cosim.Refused as e:
        return {"unstable": _refusal(e)}


# The rigs whose seed-3 run is paper-like (force_path_sweep): their robustness over the seeds, in the
# frame and with the controller where the pattern holds without a rig.
ROBUST_RIG_DELAYS = (2e-3, 3e-3)  # s, load-cell (force-path) delay [A]


def robustness_cases() -> list[tuple[str, RigParameters | None, bool, int]]:
    """(rig label, rig, tare_load_cell, force_controller) of the robustness table: no rig in both
    load-cell frames with both force controllers (0: feedforward + PI, 1: the paper's PID), then the
    paper-like rigs, tared with the default controller."""
    cases: list[tuple[str, RigParameters | None, bool, int]] = [
        ("none", None, tare, fc) for tare in (True, False) for fc in (0, 1)]
    cases += [(f"load-cell delay {1e3 * d:g} ms",
               RigParameters(f_load_cell=RIG_FIXED["f_load_cell"], load_cell_delay=d), True, 0)
              for d in ROBUST_RIG_DELAYS]
    return cases


def robustness(seeds: Sequence[float] = ROBUST_SEEDS, duration: float = ROBUST_DURATION,
               cases: Sequence[tuple[str, RigParameters | None, bool, int]] | None = None,
               **kwargs: Any) -> list[dict[str, Any]]:
    """The Fig. 7 statements over road seeds for each case of `cases` (default robustness_cases()). One
    row per case: the per-seed metrics and their mean, standard deviation, min and max."""
    rows = []
    for label, rig, tare, fc in robustness_cases() if cases is None else cases:
        per_seed = []
        for seed in seeds:
            m = metrics(run(rig, int(seed), duration, tare_load_cell=tare, force_controller=fc, **kwargs))
            m.pop("psd")
            per_seed.append(m)
        stats = {}
        for key in ("peak_Hz", "prominence", "ext_mean_error", "ext_above", "comp_mean_error", "comp_below",
                    "error_rms"):
            vals = np.array([m[key] for m in per_seed], float)
            stats[key] = (float(vals.mean()), float(vals.std(ddof=1)) if vals.size > 1 else 0.0,
                          float(vals.min()), float(vals.max()))
        rows.append({"rig": label, "tare_load_cell": tare, "force_controller": fc, "seeds": list(seeds),
                     "pattern_count": sum(m["pattern"] for m in per_seed),
                     "paper_like_count": sum(paper_like(m) for m in per_seed), "stats": stats,
                     "per_seed": per_seed})
    return rows


# ----------------------------------------------------------------------------- tables and plots

def _fhz(f: float) -> str:
    return "∞" if math.isinf(f) else f"{f:g}"


def _kn(x: float) -> str:
    return f"{x / 1e3:+.2f}"


def _refusal(e: cosim.Refused) -> str:
    """'F_demand 101.7 kN refused at 4.21 s' from the damper's refusal 'fmi2SetReal: F_demand = 101663.9
    refused: ...' (the whole message where it does not read so)."""
    name, _, rest = e.message.partition(": ")[2].partition(" = ")
    try:
        value = float(rest.split()[0])
    except (ValueError, IndexError):
        return f"{e.message} at {e.time:.2f} s"
    shown = {"F_demand": f"{value / 1e3:.1f} kN", "v_damper": f"{value:.2f} m/s"}.get(name, f"{value:g}")
    return f"{name} {shown} refused at {e.time:.2f} s"


def sweep_table(base: dict[str, Any], points: Sequence[SweepPoint],
                force_path: Sequence[tuple[float, dict[str, Any]]]) -> str:
    rows = ["| actuator delay (ms) | actuator bandwidth (Hz) | load-cell delay (ms) | force peak 5–30 Hz (Hz) | "
            "prominence | extension: mean error (kN), time above | compression: mean error (kN), time below | "
            "RMS error (kN) | max abs v (m/s) | sign pattern | paper-like (15 ± 2 Hz and pattern) |",
            "|---|---|---|---|---|---|---|---|---|---|---|"]

    def row(lat: str, fa: str, lcd: str, m: dict[str, Any]) -> str:
        if m.get("unstable"):
            return f"| {lat} | {fa} | {lcd} | unstable: {m['unstable']} | | | | | | no | no |"
        return (f"| {lat} | {fa} | {lcd} | {m['peak_Hz']:.1f} | {m['prominence']:.1f} | "
                f"{_kn(m['ext_mean_error'])}, {100 * m['ext_above']:.0f} % | "
                f"{_kn(m['comp_mean_error'])}, {100 * m['comp_below']:.0f} % | {m['error_rms'] / 1e3:.2f} | "
                f"{m['v_max']:.2f} | {'yes' if m['pattern'] else 'no'} | {'**yes**' if paper_like(m) else 'no'} |")

    rows.append(row("no rig", "—", "—", base))
    for p in points:
        rows.append(row(f"{1e3 * p.actuator_delay:g}", _fhz(p.f_actuator), "0", p.metrics))
    for d, m in force_path:
        rows.append(row("0", "∞", f"{1e3 * d:g}", m))
    return "\n".join(rows)


def robustness_table(rows: Sequence[dict[str, Any]]) -> str:
    def ms(stat: tuple[float, ...], scale: float = 1.0, fmt: str = "{:+.2f}") -> str:
        mean, sd, lo, hi = (x * scale for x in stat)
        return f"{fmt.format(mean)} ± {abs(sd):.2f} [{fmt.format(lo)}, {fmt.format(hi)}]"

    out = ["| rig | load cell | force controller | extension: mean(abs F − abs F_dem) (kN) | "
           "extension: time above (%) | compression: mean(abs F − abs F_dem) (kN) | compression: time below (%) | "
           "force peak 5–30 Hz (Hz) | peak / median PSD | RMS error (kN) | seeds with the sign pattern | "
           "seeds paper-like (15 ± 2 Hz and pattern) |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        st = r["stats"]
        out.append(f"| {r['rig']} | {'tared' if r['tare_load_cell'] else 'raw'} | "
                   f"{'feedforward + PI (0)' if r['force_controller'] == 0 else 'paper PID (1)'} | "
                   f"{ms(st['ext_mean_error'], 1e-3)} | {ms(st['ext_above'], 100, '{:.0f}')} | "
                   f"{ms(st['comp_mean_error'], 1e-3)} | {ms(st['comp_below'], 100, '{:.0f}')} | "
                   f"{ms(st['peak_Hz'], 1, '{:.1f}')} | {ms(st['prominence'], 1, '{:.1f}')} | "
                   f"{ms(st['error_rms'], 1e-3, '{:.2f}')} | {r['pattern_count']} of {len(r['seeds'])} | "
                   f"{r['paper_like_count']} of {len(r['seeds'])} |")
    return "\n".join(out)


def plot_sweep(path: Path, base: dict[str, Any], points: Sequence[SweepPoint]) -> None:
    """Heat map of the force peak over latency x bandwidth, cells marked with the sign pattern."""
    plt = pyplot()
    lats = sorted({p.actuator_delay for p in points})
    bws = sorted({p.f_actuator for p in points})
    grid = np.full((len(lats), len(bws)), np.nan)
    fig, ax = plt.subplots(figsize=(8.5, 5.2))
    for p in points:
        i, j = lats.index(p.actuator_delay), bws.index(p.f_actuator)
        if not p.metrics.get("unstable"):
            grid[i, j] = p.metrics["peak_Hz"]
    im = ax.imshow(grid, origin="lower", cmap="coolwarm", vmin=5, vmax=25, aspect="auto")
    for p in points:
        i, j = lats.index(p.actuator_delay), bws.index(p.f_actuator)
        m = p.metrics
        if m.get("unstable"):
            ax.text(j, i, "unstable", ha="center", va="center", fontsize=7, color="0.3")
            ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, color="0.85"))
            continue
        mark = ("E+" if m["ext_mean_error"] > 0 and m["ext_above"] > 0.5 else "E−") + " " + \
               ("C−" if m["comp_mean_error"] < 0 and m["comp_below"] > 0.5 else "C+")
        weight = "bold" if paper_like(m) else "normal"
        ax.text(j, i, f"{m['peak_Hz']:.1f} Hz\n{mark}", ha="center", va="center", fontsize=7, weight=weight)
        if paper_like(m):
            ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="k", lw=2))
    ax.set_xticks(range(len(bws)), [_fhz(b) for b in bws])
    ax.set_yticks(range(len(lats)), [f"{1e3 * x:g}" for x in lats])
    ax.set_xlabel("actuator bandwidth f_act (Hz), 2nd order, ζ = 0.71")
    ax.set_ylabel("actuator pure delay (ms)")
    ax.set_title(f"Rig model, minor road 14 m/s: force-spectrum peak 5–30 Hz (no rig: {base['peak_Hz']:.1f} Hz)\n"
                 "E+: extension above the demand (mean and majority), C−: compression below;\n"
                 "boxed: 15 ± 2 Hz with E+ C− (the paper's Fig. 7)", fontsize=9)
    fig.colorbar(im, ax=ax, label="force peak (Hz)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_spectra(path: Path, base: dict[str, Any], curves: Sequence[tuple[str, dict[str, Any]]]) -> None:
    """The logged force's PSD without a rig and for the (label, metrics) curves, 0-40 Hz."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.6))
    f, p = base["psd"]
    shown = (f > 0.5) & (f <= 40)
    ax.semilogy(f, p, color="k", lw=1.4, label=f"no rig (peak 5–30 Hz: {base['peak_Hz']:.1f} Hz)")
    lo, hi = p[shown].min(), p[shown].max()
    for label, m in curves:
        if m.get("unstable"):
            continue
        f, p = m["psd"]
        lo, hi = min(lo, p[shown].min()), max(hi, p[shown].max())
        ax.semilogy(f, p, lw=1, label=f"{label} (peak {m['peak_Hz']:.1f} Hz)")
    ax.axvspan(PAPER_DOMINANT_HZ - PAPER_BAND_HZ, PAPER_DOMINANT_HZ + PAPER_BAND_HZ, color="y", alpha=0.2,
               label="paper: 15 Hz (± 2 Hz)")
    ax.set_xlim(0, 40)
    ax.set_ylim(lo / 2, hi * 2)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("PSD of the logged force − mean (N²/Hz)")
    ax.set_title("Damper force spectrum on the minor road at 14 m/s, with and without a rig model", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# the robustness table's rows in docs/hil.md: (rig, tared, force controller) -> tag
ROBUST_TAGS = {("none", True, 0): "tared_ff", ("none", True, 1): "tared_pid", ("none", False, 0): "raw_ff",
               ("none", False, 1): "raw_pid", **{(f"load-cell delay {1e3 * d:g} ms", True, 0): f"lc{1e3 * d:g}"
                                                  for d in ROBUST_RIG_DELAYS}}


def headline(base: dict[str, Any], points: Sequence[SweepPoint], force_path: Sequence[tuple[float, dict[str, Any]]],
             rows: Sequence[dict[str, Any]]) -> dict[str, float]:
    """The figures the documents quote (docs/hil_rig.json): the sweep's rows of docs/hil.md (seed 3:
    none, act<delay ms>_<bandwidth Hz>, lc<load-cell delay ms>), ranges over the sweep, and the
    robustness table (robust_<row>_...: mean and standard deviation over the seeds, the peak's range,
    the seeds with the pattern); forces in kN, shares in %."""
    out: dict[str, float] = {}

    def seed3(tag: str, m: dict[str, Any]) -> None:
        out.update({f"{tag}_peak_hz": m["peak_Hz"], f"{tag}_prominence": m["prominence"],
                    f"{tag}_ext_mean_kn": m["ext_mean_error"] / 1e3, f"{tag}_ext_above_pct": 100 * m["ext_above"],
                    f"{tag}_comp_mean_kn": m["comp_mean_error"] / 1e3, f"{tag}_comp_below_pct": 100 * m["comp_below"]})

    def span(name: str, values: Sequence[float]) -> None:
        out[f"{name}_min"], out[f"{name}_max"] = min(values), max(values)

    seed3("none", base)
    stable = [p for p in points if not p.metrics.get("unstable")]
    for p in stable:
        if (p.actuator_delay, p.f_actuator) in ((0.0, 100.0), (2e-3, math.inf)):
            seed3(f"act{1e3 * p.actuator_delay:g}_{'inf' if math.isinf(p.f_actuator) else f'{p.f_actuator:g}'}",
                  p.metrics)
    for d, m in force_path:
        if not m.get("unstable") and d <= 6e-3:
            seed3(f"lc{1e3 * d:g}", m)
    lagged = [p.metrics for p in stable if p.actuator_delay > 0 or not math.isinf(p.f_actuator)]
    span("actuator_lag_ext_above_pct", [100 * m["ext_above"] for m in lagged])
    span("actuator_lag_comp_below_pct", [100 * m["comp_below"] for m in lagged])
    late = [p.metrics for p in stable if p.actuator_delay >= 4e-3]
    late += [m for d, m in force_path if d >= 4e-3 and not m.get("unstable")]
    span("lag4_peak_hz", [m["peak_Hz"] for m in late])

    robust = {ROBUST_TAGS[(r["rig"], r["tare_load_cell"], r["force_controller"])]: r for r in rows}
    for tag, r in robust.items():
        st = r["stats"]
        for key, scale, name in (("ext_mean_error", 1e-3, "ext_mean_kn"), ("ext_above", 100, "ext_above_pct"),
                                 ("comp_mean_error", 1e-3, "comp_mean_kn"), ("comp_below", 100, "comp_below_pct"),
                                 ("peak_Hz", 1, "peak_hz")):
            out[f"robust_{tag}_{name}_mean"], out[f"robust_{tag}_{name}_sd"] = scale * st[key][0], scale * st[key][1]
        out[f"robust_{tag}_peak_hz_min"], out[f"robust_{tag}_peak_hz_max"] = st["peak_Hz"][2], st["peak_Hz"][3]
        out[f"robust_{tag}_pattern"] = r["pattern_count"]
    tared = robust["tared_ff"]["stats"]
    out |= {"robust_seeds": len(robust["tared_ff"]["seeds"]),
            "robust_tared_ff_ext_mean_kn_min": tared["ext_mean_error"][2] / 1e3,
            "robust_tared_ff_ext_mean_kn_max": tared["ext_mean_error"][3] / 1e3,
            "robust_tared_ff_comp_mean_kn_min": tared["comp_mean_error"][2] / 1e3,
            "robust_tared_ff_comp_mean_kn_max": tared["comp_mean_error"][3] / 1e3,
            "robust_tared_ff_error_rms_kn": tared["error_rms"][0] / 1e3,
            "robust_tared_pid_error_rms_kn": robust["tared_pid"]["stats"]["error_rms"][0] / 1e3,
            "robust_raw_frame_comp_shift_kn": (robust["raw_ff"]["stats"]["comp_mean_error"][0]
                                               - tared["comp_mean_error"][0]) / 1e3}
    rigs = [robust[f"lc{1e3 * d:g}"] for d in ROBUST_RIG_DELAYS]
    for r, d in zip(rigs, ROBUST_RIG_DELAYS, strict=True):
        tag = f"robust_lc{1e3 * d:g}"
        out[f"{tag}_prominence_mean"], out[f"{tag}_prominence_sd"] = r["stats"]["prominence"][:2]
        out[f"{tag}_paper_like"] = r["paper_like_count"]
    span("robust_lc_peak_hz", [x for r in rigs for x in r["stats"]["peak_Hz"][2:]])
    span("robust_lc_prominence", [x for r in rigs for x in r["stats"]["prominence"][2:]])
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--duration", type=float, default=DURATION, help="recorded seconds of every sweep run")
    parser.add_argument("--robust-duration", type=float, default=ROBUST_DURATION)
    parser.add_argument("--docs", action="store_true", help="write the headline figures to docs/hil_rig.json and "
                        "copy the plots to docs/figures/")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    fmus = {"truck_fmu": args.truck_fmu, "damper_fmu": args.damper_fmu}
    base, points = sweep(duration=args.duration, **fmus)
    force_path = force_path_sweep(duration=args.duration, **fmus)
    rows = robustness(duration=args.robust_duration, **fmus)
    plot_sweep(args.out / "rig_sweep.png", base, points)
    picks = [(f"actuator delay {1e3 * q.actuator_delay:g} ms, f_act {_fhz(q.f_actuator)} Hz", q.metrics)
             for q in points if (q.actuator_delay, q.f_actuator) in ((0.0, 100.0), (2e-3, math.inf))]
    picks += [(f"load-cell delay {1e3 * d:g} ms", m) for d, m in force_path if d in (2e-3, 6e-3)]
    plot_spectra(args.out / "rig_spectra.png", base, picks)
    like: list[SweepPoint | tuple[float, dict[str, Any]]] = [
        p for p in points if not p.metrics.get("unstable") and paper_like(p.metrics)]
    like += [(d, m) for d, m in force_path if not m.get("unstable") and paper_like(m)]
    text = "\n\n".join([
        f"# The HiL rig as a model (minor road, 14 m/s, seed {SEED}, {args.duration:g} s after {SETTLE:g} s)",
        "Rig parts held fixed: real-time computer at the communication step (1 ms), load cell behind a 500 Hz "
        "2nd-order Butterworth filter. Actuator: pure delay and a 2nd-order lag (ζ = 0.71) of the given -3 dB "
        "bandwidth on the truck's damper displacement. Tracking as the rig's computer logs it: its demand against "
        "the load-cell force it received, split by the truck model's damper velocity (> 0.02 m/s, |F_dem| > 0.5 kN).",
        sweep_table(base, points, force_path),
        f"Rigs that give the paper's Fig. 7 (peak 15 ± 2 Hz and the sign pattern): {len(like)}"
        + ("" if not like else ": " + "; ".join(
            f"actuator delay {1e3 * q.actuator_delay:g} ms, f_act {_fhz(q.f_actuator)} Hz" if isinstance(q, SweepPoint)
            else f"load-cell delay {1e3 * q[0]:g} ms" for q in like)) + ".",
        f"## Robustness of the Fig. 7 statements ({len(ROBUST_SEEDS)} road seeds, "
        f"{args.robust_duration:g} s each; mean ± standard deviation [min, max])",
        robustness_table(rows),
    ]) + "\n"
    (args.out / "table.md").write_text(text, encoding="utf-8")
    results = {"no_rig": base, "fixed": RIG_FIXED,
               "sweep": [{"actuator_delay": p.actuator_delay, "f_actuator": p.f_actuator, **p.metrics} for p in points],
               "force_path": [{"load_cell_delay": d, **m} for d, m in force_path],
               "robustness": rows, "wall_time_s": time.perf_counter() - t0}
    (args.out / "results.json").write_text(json.dumps(jsonable(results, drop=("psd",)), indent=1), encoding="utf-8")
    if args.docs:
        from damper_tools import doc_figures

        doc_figures.write("hil_rig", headline(base, points, force_path, rows), ".venv/bin/damper-hil-rig --docs")
        for name in ("rig_sweep.png", "rig_spectra.png"):
            shutil.copy(args.out / name, REPO / "docs" / "figures" / name)
    print(text)
    print(f"hil_rig: wrote {args.out} in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
