"""HiL scenarios: the quarter truck on random roads (and a measured Belgian-block track) with three
dampers side by side, as in the paper's hardware-in-the-loop tests (Fig. 7).

    .venv/bin/damper-hil-scenarios [--out out/hil] [--duration 15] [--step 1e-3]

For every road and speed it co-simulates (damper_tools.cosim, Jacobi, step 1 ms by default)

    (i)   passive dampers, truck damper_mode 2, c_passive swept over 5-60 kNs/m
    (ii)  the ideal semi-active damper, damper_mode 1: the clipped Modified Skyhook demand exactly
          (Cm 24 kNs/m, alpha 0.8, the paper's values)
    (iii) our damper FMU, damper_mode 0 + SemiActiveDamper.fmu (tare_load_cell = true) following the
          same demand (the truck's F_demand output)

on the same road realisation, and writes to the output directory

    fig7_<road>_<speed>.png        demanded vs achieved damper force over a 1 s window (like Fig. 7)
    force_spectrum.png             Welch PSD of the damper force, demand and ideal force
    tradeoff.png                   passive ride-vs-DLC curve with the two semi-active points
    belgian_block.png              the OpenCRG Belgian-block run
    table.md, results.json         every metric (table.md is also printed)

and with --docs the headline figures the documents quote to docs/hil_scenarios.json.

Metrics, over the record after the settling time:
    ride          RMS sprung-mass acceleration a_body (m/s^2), also ISO 2631-1 Wk-weighted (damper_tools.ride)
    DLC           dynamic load coefficient std(F_tyre) / ((m_body + m_axle) g)
    road stress   mean((W + F_tyre)^4) / W^4 with W = (m_body + m_axle) g: fourth-power road damage
    working space RMS and peak |x_damper| (suspension deflection from static equilibrium)
    best passive  the c_passive with the lowest RMS a_body among the passive settings whose DLC is not
                  above the ideal semi-active's; if none is, the passive setting with the lowest DLC
                  (the table says which rule applied)
    tracking      F = damper F_damper, Fd = the truck's F_demand, both at the same communication
                  point. Extension: v_damper > 0.02 m/s and Fd > 0.5 kN; compression: v_damper <
                  -0.02 m/s and Fd < -0.5 kN (as the slow Python reference of docs/physics.md §6.5). Mean signed error
                  mean(|F| - |Fd|) and the fraction of time |F| > |Fd| (above) in each direction.
    spectrum      Welch (2 s Hann segments) of F - mean(F); the largest value above 3 Hz (as hil_run)
                  and the largest in the wheel-hop band 5-30 Hz.
"""

import argparse
import json
import math
import shutil
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from damper_tools import DAMPER_FMU, REPO, TRUCK_FMU, FloatArray, cosim, jsonable, pyplot, ride, roads
from damper_tools.fmu import FmuUnit

OUT = REPO / "out" / "hil"
CRG = REPO / "data" / "roads" / "belgian_block.crg"
CRG_ROAD = "belgian_block"  # the road name of the measured track, where a road name is asked for

# (road, speed m/s): the three headline cases first, then the rest of the grid
HEADLINE = [("minor", 14.0), ("major", 20.0), ("motorway", 25.0)]
GRID = HEADLINE + [("minor", 20.0), ("major", 14.0), ("major", 25.0), ("motorway", 14.0), ("motorway", 20.0),
                   ("minor", 25.0)]
C_PASSIVE = np.arange(5e3, 60e3 + 1, 2.5e3)  # N s/m
SEED = 3
STEP = 1e-3  # s, communication step
FADE_IN = 1.0  # s, raised-cosine fade-in of the road
SETTLE = 3.0  # s, not counted in the metrics (fade-in + decay of the body mode)
DURATION = 15.0  # s, recorded after SETTLE
EXT_V, EXT_F = 0.02, 500.0  # m/s, N: thresholds of the extension/compression classes
SPECTRUM_SEGMENT = 2.0  # s
PEAK_MIN_HZ = 3.0
WHEEL_HOP_BAND = (5.0, 30.0)  # Hz
FIG7_WINDOW = 1.0  # s
PAPER_DOMINANT_HZ = 15.0
CRG_V = 0.0  # m, lateral offset of the Belgian-block section
CRG_SPEED = 3.0  # m/s: faster, the linear tyre would need to pull (F_tyre below -static load)
CRG_ENVELOPE = 0.2  # m, tyre contact length of the envelope filter [A]
CRG_LEAD = 1.0  # s of level road before the track (the truck at rest)
CRG_BLEND = 0.5  # m, the track rises from 0 over its first metres (raised cosine)
CRG_RUNOUT = 1.0  # s of level road after it


def truck_constants(truck_fmu: str | Path = TRUCK_FMU) -> dict[str, float]:
    """m_body, m_axle, gravity, k_susp, k_tyre: the truck FMU's start values."""
    unit = FmuUnit.load(truck_fmu)
    return {name: float(unit.variables[name].start) for name in ("m_body", "m_axle", "gravity", "k_susp", "k_tyre",
                                                                  "Cm", "alpha")}


# --------------------------------------------------------------------------- metrics

def vehicle_metrics(res: dict[str, FloatArray], window: slice, static_load: float) -> dict[str, float]:
    """Ride, DLC and working space of a result dict over the samples in `window` (a slice)."""
    x = res["x_damper"][window]
    step = float(res["time"][1] - res["time"][0])
    return {
        "a_body_rms": float(np.std(res["a_body"][window])),
        "a_body_wk_rms": ride.wk_rms(res["a_body"][window], step),
        "DLC": float(np.std(res["F_tyre"][window]) / static_load),
        "road_stress": ride.road_stress_factor(res["F_tyre"][window], static_load),
        "x_damper_rms": float(np.std(x)),
        "x_damper_peak": float(np.max(np.abs(x))),
        "F_suspension_rms": float(np.std(res["F_suspension"][window])),
        "v_damper_max": float(np.max(np.abs(res["v_damper"][window]))),
    }


def tracking_metrics(force: Sequence[float] | FloatArray, demand: Sequence[float] | FloatArray,
                     v: Sequence[float] | FloatArray) -> dict[str, Any]:
    """Tracking of a demand by a force, split into extension and compression (module docstring)."""
    force, demand, v = map(np.asarray, (force, demand, v))
    ext = (v > EXT_V) & (demand > EXT_F)
    com = (v < -EXT_V) & (demand < -EXT_F)
    out: dict[str, Any] = {
        "F_rms": float(np.std(force)), "F_demand_rms": float(np.std(demand)),
        "error_rms": float(np.sqrt(np.mean((force - demand) ** 2))),
        "mean_error": float(np.mean(force - demand)),
        "F_max": float(np.max(np.abs(force))), "v_max": float(np.max(np.abs(v))),
    }
    for name, m in (("extension", ext), ("compression", com)):
        above = np.abs(force[m]) > np.abs(demand[m])
        out[name] = {
            "fraction_of_time": float(np.mean(m)),
            "mean_error": float(np.mean(np.abs(force[m]) - np.abs(demand[m]))) if m.any() else math.nan,
            "fraction_above": float(np.mean(above)) if m.any() else math.nan,
            "fraction_below": float(np.mean(~above)) if m.any() else math.nan,
        }
    return out


def force_spectrum(signal: FloatArray, step: float, segment: float = SPECTRUM_SEGMENT) -> tuple[FloatArray, FloatArray]:
    from scipy.signal import welch

    x = np.asarray(signal, float)
    return welch(x - x.mean(), fs=1.0 / step, nperseg=min(x.size, int(round(segment / step))))


def spectral_peaks(f: FloatArray, p: FloatArray) -> dict[str, float]:
    above = f > PEAK_MIN_HZ
    band = (f >= WHEEL_HOP_BAND[0]) & (f <= WHEEL_HOP_BAND[1])
    return {"peak_above_3Hz": float(f[above][np.argmax(p[above])]),
            "peak_wheel_hop_band": float(f[band][np.argmax(p[band])])}


def pareto_mask(x: FloatArray, y: FloatArray) -> npt.NDArray[np.bool_]:
    """True for the points not dominated when both x and y are to be small."""
    order = np.lexsort((y, x))
    mask = np.zeros(x.size, dtype=np.bool_)
    best = math.inf
    for i in order:
        if y[i] < best:
            mask[i] = True
            best = y[i]
    return mask


def pareto_front(sweep: list[dict[str, Any]], ride: str = "a_body_rms") -> list[dict[str, Any]]:
    """The settings not dominated in (DLC, `ride`), sorted by DLC."""
    mask = pareto_mask(np.array([s["DLC"] for s in sweep]), np.array([s[ride] for s in sweep]))
    return sorted((s for s, m in zip(sweep, mask, strict=True) if m), key=lambda s: (s["DLC"], s[ride]))


def passive_ride_at_dlc(sweep: list[dict[str, Any]], dlc: float, ride: str = "a_body_rms") -> float | None:
    """`ride` of the passive Pareto front interpolated at a DLC (linear in DLC), or None if the
    DLC is outside the front's range."""
    front = pareto_front(sweep, ride)
    d = np.array([s["DLC"] for s in front])
    a = np.array([s[ride] for s in front])
    if not d[0] <= dlc <= d[-1]:
        return None
    return float(np.interp(dlc, d, a))


def best_passive(sweep: list[dict[str, Any]], dlc_limit: float) -> tuple[dict[str, Any], str]:
    """(setting, rule): the best passive setting (module docstring)."""
    ok = [s for s in sweep if s["DLC"] <= dlc_limit]
    if ok:
        return min(ok, key=lambda s: s["a_body_rms"]), "lowest RMS a_body with DLC <= the ideal semi-active's"
    return min(sweep, key=lambda s: s["DLC"]), "no passive DLC <= the ideal semi-active's: the lowest-DLC setting"


# --------------------------------------------------------------------------- runs

def run_three(z_road: FloatArray, v_road: FloatArray, step: float, window: slice,
              c_values: Sequence[float] | FloatArray, truck_fmu: str | Path, damper_fmu: str | Path,
              consts: dict[str, float]) -> tuple[dict[str, Any], dict[str, Any]]:
    """Passive sweep, ideal semi-active and damper FMU on one road, metrics over the samples in
    `window` (a slice); returns (summary, series)."""
    n = len(z_road) - 1
    static_load = (consts["m_body"] + consts["m_axle"]) * consts["gravity"]
    sweep = []
    for c in c_values:
        r = cosim.simulate_one(z_road, v_road, step, n, cosim.MODE_PASSIVE, {"c_passive": float(c)},
                               truck_fmu=truck_fmu, damper_fmu=damper_fmu)
        sweep.append({"c_passive": float(c), **vehicle_metrics(r, window, static_load)})
    ideal = cosim.simulate_one(z_road, v_road, step, n, cosim.MODE_IDEAL, truck_fmu=truck_fmu, damper_fmu=damper_fmu)
    fmu = cosim.simulate_one(z_road, v_road, step, n, cosim.MODE_EXTERNAL, truck_fmu=truck_fmu, damper_fmu=damper_fmu,
                             damper_outputs=("F_damper", "F_demand_clipped", "x_spool"))
    ideal_m = vehicle_metrics(ideal, window, static_load)
    fmu_m = vehicle_metrics(fmu, window, static_load)
    best, rule = best_passive(sweep, ideal_m["DLC"])
    best_run = cosim.simulate_one(z_road, v_road, step, n, cosim.MODE_PASSIVE, {"c_passive": best["c_passive"]},
                                  truck_fmu=truck_fmu, damper_fmu=damper_fmu)
    track = tracking_metrics(fmu["damper.F_damper"][window], fmu["F_demand"][window], fmu["v_damper"][window])
    f, p_fmu = force_spectrum(fmu["damper.F_damper"][window], step)
    _, p_dem = force_spectrum(fmu["F_demand"][window], step)
    _, p_ideal = force_spectrum(ideal["F_suspension"][window], step)
    _, p_tyre = force_spectrum(fmu["F_tyre"][window], step)
    summary = {
        "passive_sweep": sweep,
        "best_passive": {"c_passive": best["c_passive"], "rule": rule, **best},
        "ideal": ideal_m,
        "fmu": fmu_m,
        "passive_a_body_rms_at_ideal_DLC": passive_ride_at_dlc(sweep, ideal_m["DLC"]),
        "passive_a_body_rms_at_fmu_DLC": passive_ride_at_dlc(sweep, fmu_m["DLC"]),
        "tracking": track,
        "spectrum": {"damper_force": spectral_peaks(f, p_fmu), "demand": spectral_peaks(f, p_dem),
                     "ideal_force": spectral_peaks(f, p_ideal), "tyre_force_fmu": spectral_peaks(f, p_tyre)},
    }
    series = {"ideal": ideal, "fmu": fmu, "best_passive": best_run,
              "psd": {"f": f, "fmu": p_fmu, "demand": p_dem, "ideal": p_ideal, "tyre": p_tyre}}
    return summary, series


def run_scenario(road: str, speed: float, seed: int = SEED, duration: float = DURATION, settle: float = SETTLE,
                 step: float = STEP, c_values: Sequence[float] | FloatArray = C_PASSIVE,
                 truck_fmu: str | Path = TRUCK_FMU,
                 damper_fmu: str | Path = DAMPER_FMU) -> tuple[dict[str, Any], dict[str, Any]]:
    """One random road at one speed: returns (summary dict, series for the plots)."""
    consts = truck_constants(truck_fmu)
    case = roads.road_case(road, speed, settle + duration, seed, step=step, fade_in=FADE_IN)
    first = int(round(settle / step))
    n_fit, g_fit = roads.profile_psd(case.z_road[first:], speed * step, segment_length=min(100.0, speed * duration / 4))
    gd0_fit, _ = roads.fit_gd0(n_fit, g_fit, band=(0.1, 5.0))
    summary, series = run_three(case.z_road, case.v_road, step, slice(first, None), c_values, truck_fmu, damper_fmu,
                                consts)
    summary = {"road": road, "label": roads.road_label(road), "speed": speed, "gd0": case.gd0, "seed": seed,
               "gd0_of_realisation": gd0_fit, "step": step, "settle": settle, "duration": duration, **summary}
    series["time"] = case.t
    series["first"] = first
    return summary, series


def crg_road(path: str | Path = CRG, v: float = CRG_V, speed: float = CRG_SPEED, envelope: float = CRG_ENVELOPE,
             step: float = STEP) -> tuple[FloatArray, FloatArray, FloatArray, int, int, roads.CrgTrack]:
    """The Belgian-block section as a time series: level lead-in, the track (rising from 0 over its
    first CRG_BLEND m), level run-out. Returns (t, z_road, v_road, first, last) with [first, last)
    the samples while the wheel is on the track."""
    track = roads.crg_track(roads.read_crg(path), v=v, envelope=envelope)
    blend = np.clip(track.x / CRG_BLEND, 0.0, 1.0)
    z = track.z * 0.5 * (1 - np.cos(np.pi * blend))
    lead = speed * CRG_LEAD
    x = np.concatenate(([0.0], lead + track.x, [lead + track.x[-1] + speed * CRG_RUNOUT]))
    z = np.concatenate(([0.0], z, [z[-1]]))
    n_steps = int(round((CRG_LEAD + track.x[-1] / speed + CRG_RUNOUT) / step)) - 1
    t, zr, vr = roads.time_series(x, z, speed, step, n_steps)
    first = int(round(CRG_LEAD / step))
    last = int(round((CRG_LEAD + track.x[-1] / speed) / step))
    return t, zr, vr, first, last, track


def run_crg(path: str | Path = CRG, speed: float = CRG_SPEED, step: float = STEP,
            c_values: Sequence[float] | FloatArray = C_PASSIVE,
            truck_fmu: str | Path = TRUCK_FMU,
            damper_fmu: str | Path = DAMPER_FMU) -> tuple[dict[str, Any], dict[str, Any]]:
    """The three dampers on the Belgian-block track; metrics while the wheel is on the track."""
    consts = truck_constants(truck_fmu)
    t, zr, vr, first, last, track = crg_road(path, speed=speed, step=step)
    window = slice(first, last + 1)
    summary, series = run_three(zr, vr, step, window, c_values, truck_fmu, damper_fmu, consts)
    static_load = (consts["m_body"] + consts["m_axle"]) * consts["gravity"]
    for key in ("ideal", "fmu", "best_passive"):
        r = series[key]
        summary[key]["a_body_peak"] = float(np.max(np.abs(r["a_body"][window])))
        summary[key]["F_tyre_peak_over_static"] = float(np.max(np.abs(r["F_tyre"][window])) / static_load)
    summary = {"road": "Belgian block (OpenCRG)", "section_v": track.v, "speed": speed, "envelope": track.envelope,
               "track_length": float(track.x[-1]), "track_std": float(track.z.std()), "step": step,
               "on_track": [float(t[first]), float(t[last])], **summary}
    series.update(time=t, first=first, last=last, z_road=zr)
    return summary, series


# --------------------------------------------------------------------------- plots

def plot_fig7(path: Path, summary: dict[str, Any], series: dict[str, Any], start: float | None = None) -> None:
    plt = pyplot()
    t = series["time"]
    fmu = series["fmu"]
    t0 = start if start is not None else t[series["first"]] + 5.0
    m = (t >= t0) & (t <= t0 + FIG7_WINDOW)
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(10, 8), sharex=True, gridspec_kw={"height_ratios": [3, 1.3, 1.3]})
    F, Fd, v = fmu["damper.F_damper"][m] / 1e3, fmu["F_demand"][m] / 1e3, fmu["v_damper"][m]
    a1.plot(t[m], Fd, "--", color="tab:orange", lw=1.5, label="demanded (clipped MSD, truck F_demand)")
    a1.plot(t[m], F, color="tab:blue", lw=1.5, label="achieved (damper FMU F_damper, tared)")
    a1.axhline(0, color="0.6", lw=0.6)
    a1.set_ylabel("damper force (kN, tension +)")
    tr = summary["tracking"]
    a1.set_title(f"{summary['label']} at {summary['speed']:g} m/s, MSD Cm = 24 kNs/m, alpha = 0.8 — "
                 f"extension {1e-3 * tr['extension']['mean_error']:+.2f} kN "
                 f"({100 * tr['extension']['fraction_above']:.0f} % above), "
                 f"compression {1e-3 * tr['compression']['mean_error']:+.2f} kN "
                 f"({100 * tr['compression']['fraction_below']:.0f} % below)", fontsize=9)
    a1.legend(loc="upper right", fontsize=8)
    a2.plot(t[m], F - Fd, color="tab:red", lw=1.0)
    a2.axhline(0, color="0.6", lw=0.6)
    a2.set_ylabel("F − F_dem (kN)")
    a3.plot(t[m], v, color="tab:green", lw=1.0)
    a3.axhline(0, color="0.6", lw=0.6)
    a3.fill_between(t[m], v.min(), v.max(), where=v > 0, color="tab:green", alpha=0.08, label="extending")
    a3.set_ylabel("v_damper (m/s)")
    a3.set_xlabel("time (s)")
    a3.legend(loc="upper right", fontsize=8)
    for ax in (a1, a2, a3):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_spectra(path: Path, cases: list[tuple[dict[str, Any], dict[str, Any]]], nat_hz: float) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, len(cases), figsize=(5 * len(cases), 4.2), squeeze=False)
    for ax, (summary, series) in zip(axes[0], cases, strict=True):
        psd = series["psd"]
        f = psd["f"]
        m = (f > 0) & (f <= 40)
        ax.semilogy(f[m], psd["fmu"][m], color="tab:blue", label="damper FMU force")
        ax.semilogy(f[m], psd["demand"][m], "--", color="tab:orange", label="its demand")
        ax.semilogy(f[m], psd["ideal"][m], color="0.4", lw=1, label="ideal semi-active force")
        pk = summary["spectrum"]["damper_force"]
        ax.axvline(nat_hz, color="tab:purple", ls=":", label=f"undamped wheel hop {nat_hz:.1f} Hz")
        ax.axvline(PAPER_DOMINANT_HZ, color="tab:red", ls=":", label="paper: dominant 15 Hz")
        ax.axvline(pk["peak_wheel_hop_band"], color="tab:blue", ls="-.", lw=0.8,
                   label=f"FMU force peak 5–30 Hz: {pk['peak_wheel_hop_band']:.1f} Hz")
        ax.set_title(f"{summary['label']}, {summary['speed']:g} m/s", fontsize=10)
        ax.set_xlabel("frequency (Hz)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, loc="lower left")
    axes[0][0].set_ylabel("PSD of force − mean (N²/Hz)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_tradeoff(path: Path, summaries: list[dict[str, Any]]) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(1, len(summaries), figsize=(5 * len(summaries), 4.4), squeeze=False)
    for ax, s in zip(axes[0], summaries, strict=True):
        sw = s["passive_sweep"]
        d = [p["DLC"] for p in sw]
        a = [p["a_body_rms"] for p in sw]
        ax.plot(d, a, "o-", color="0.5", ms=3, lw=1, label="passive, c = 5–60 kNs/m")
        for p in sw:
            if p["c_passive"] % 10e3 == 0 or p["c_passive"] == sw[0]["c_passive"]:
                ax.annotate(f"{p['c_passive'] / 1e3:g}", (p["DLC"], p["a_body_rms"]), fontsize=7,
                            textcoords="offset points", xytext=(4, 2), color="0.35")
        b = s["best_passive"]
        ax.plot(b["DLC"], b["a_body_rms"], "s", mfc="none", mec="k", ms=9,
                label=f"best passive ({b['c_passive'] / 1e3:g} kNs/m)")
        ax.plot(s["ideal"]["DLC"], s["ideal"]["a_body_rms"], "*", color="tab:green", ms=13, label="ideal semi-active")
        ax.plot(s["fmu"]["DLC"], s["fmu"]["a_body_rms"], "D", color="tab:blue", ms=7, label="damper FMU")
        lo, hi = min(d + [s["ideal"]["DLC"], s["fmu"]["DLC"]]), max(d)
        ax.set_xlim(lo - 0.03 * (hi - lo), lo + 0.45 * (hi - lo))
        amin = min(a + [s["ideal"]["a_body_rms"], s["fmu"]["a_body_rms"]])
        ax.set_ylim(0.95 * amin, 1.35 * min(a))
        ax.set_title(f"{s['label']}, {s['speed']:g} m/s", fontsize=10)
        ax.set_xlabel("DLC = std(F_tyre) / static wheel load")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper right")
    axes[0][0].set_ylabel("RMS body acceleration (m/s²)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_crg(path: Path, summary: dict[str, Any], series: dict[str, Any]) -> None:
    plt = pyplot()
    t = series["time"]
    fig, (a0, a1, a2) = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    a0.plot(t, 1e3 * series["z_road"], color="k", lw=1)
    a0.set_ylabel("z_road (mm)")
    a0.set_title(f"OpenCRG Belgian block, section v = {summary['section_v']:g} m, {summary['speed']:g} m/s, "
                 f"tyre envelope {summary['envelope']:g} m", fontsize=10)
    passive_label = f"best passive ({summary['best_passive']['c_passive'] / 1e3:g} kNs/m)"
    for key, label, style in (("best_passive", passive_label, "0.5"),
                              ("ideal", "ideal semi-active", "tab:green"), ("fmu", "damper FMU", "tab:blue")):
        a1.plot(t, series[key]["a_body"], color=style, lw=1, label=label)
    a1.set_ylabel("a_body (m/s²)")
    a1.legend(fontsize=8, loc="upper right")
    fmu = series["fmu"]
    a2.plot(t, fmu["F_demand"] / 1e3, "--", color="tab:orange", label="demanded")
    a2.plot(t, fmu["damper.F_damper"] / 1e3, color="tab:blue", label="achieved (damper FMU)")
    a2.set_ylabel("damper force (kN)")
    a2.set_xlabel("time (s)")
    a2.legend(fontsize=8, loc="upper right")
    for ax in (a0, a1, a2):
        ax.axvspan(t[series["first"]], t[series["last"]], color="y", alpha=0.08)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------- tables

def _pct(x: float | None) -> str:
    return "n/a" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{100 * x:.0f} %"


def _kn(x: float | None) -> str:
    return "n/a" if x is None or math.isnan(x) else f"{x / 1e3:+.2f} kN"


def vehicle_table(summaries: list[dict[str, Any]]) -> str:
    rows = ["| road, speed | damper | RMS a_body (m/s²) | DLC | RMS x_damper (mm) | peak abs x_damper (mm) | "
            "RMS F_susp (kN) |", "|---|---|---|---|---|---|---|"]
    for s in summaries:
        b = s["best_passive"]
        for name, m in ((f"best passive, c = {b['c_passive'] / 1e3:g} kNs/m", b),
                        ("ideal semi-active (MSD)", s["ideal"]), ("damper FMU (MSD)", s["fmu"])):
            rows.append(f"| {s['label']}, {s['speed']:g} m/s | {name} | {m['a_body_rms']:.3f} | {m['DLC']:.4f} | "
                        f"{1e3 * m['x_damper_rms']:.1f} | {1e3 * m['x_damper_peak']:.1f} | "
                        f"{m['F_suspension_rms'] / 1e3:.2f} |")
    return "\n".join(rows)


def tracking_table(summaries: list[dict[str, Any]]) -> str:
    rows = ["| road, speed | RMS F / F_dem (kN) | RMS error (kN) | mean(F − F_dem), whole record | "
            "extension: mean(F−F_dem), time above | "
            "compression: mean(abs F − abs F_dem), time below | force PSD peak > 3 Hz / in 5–30 Hz | "
            "max abs v_damper (m/s) | max abs F (kN) |", "|---|---|---|---|---|---|---|---|---|"]
    for s in summaries:
        tr, pk = s["tracking"], s["spectrum"]["damper_force"]
        rows.append(f"| {s['label']}, {s['speed']:g} m/s | {tr['F_rms'] / 1e3:.2f} / {tr['F_demand_rms'] / 1e3:.2f} | "
                    f"{tr['error_rms'] / 1e3:.2f} | {_kn(tr['mean_error'])} | {_kn(tr['extension']['mean_error'])}, "
                    f"{_pct(tr['extension']['fraction_above'])} | {_kn(tr['compression']['mean_error'])}, "
                    f"{_pct(tr['compression']['fraction_below'])} | {pk['peak_above_3Hz']:.1f} Hz / "
                    f"{pk['peak_wheel_hop_band']:.1f} Hz | {tr['v_max']:.2f} | {tr['F_max'] / 1e3:.1f} |")
    return "\n".join(rows)


def comparison_table(s: dict[str, Any], nat_hz: float) -> tuple[str, bool]:
    """The paper's statements (minor road, 14 m/s) against this run."""
    tr, pk = s["tracking"], s["spectrum"]
    ext, com = tr["extension"], tr["compression"]
    sign_ok = (ext["mean_error"] > 0 and ext["fraction_above"] > 0.5
               and com["mean_error"] < 0 and com["fraction_below"] > 0.5)
    at = s["passive_a_body_rms_at_ideal_DLC"]
    def verdict(ok: bool) -> str:
        return "yes (sign)" if ok else "**no**"

    rows = ["| Quantity | Paper (Fig. 7, minor road 14 m/s) | Slow Python reference (docs/physics.md §6.5) "
            "| This run | Reproduced? |",
            "|---|---|---|---|---|",
            f"| Dominant frequency of the damper force | 15 Hz, wheel hop | 12.0 Hz (0.5 ms exchange, "
            f"no extra latency); 16.5 Hz with 5 ms extra latency | largest PSD value above 3 Hz at "
            f"{pk['damper_force']['peak_above_3Hz']:.1f} Hz; "
            f"in 5–30 Hz at {pk['damper_force']['peak_wheel_hop_band']:.1f} Hz (undamped wheel hop {nat_hz:.1f} Hz, "
            f"ideal semi-active force {pk['ideal_force']['peak_wheel_hop_band']:.1f} Hz) | "
            f"{'yes' if abs(pk['damper_force']['peak_wheel_hop_band'] - 15) <= 1.5 else '**no**'} |",
            f"| Extension: measured force above the demand | often | +0.71 kN, 73 % of the time | "
            f"{_kn(ext['mean_error'])}, {_pct(ext['fraction_above'])} of the time | "
            f"{verdict(ext['mean_error'] > 0 and ext['fraction_above'] > 0.5)} |",
            f"| Compression: measured force below the demand | often | −0.63 kN, 69 % of the time | "
            f"{_kn(com['mean_error'])}, {_pct(com['fraction_below'])} of the time | "
            f"{verdict(com['mean_error'] < 0 and com['fraction_below'] > 0.5)} |",
            f"| Mean force error over the whole record, mean(F − F_dem) | — | not reported | {_kn(tr['mean_error'])} "
            f"(extension above and compression below both make F − F_dem positive; under a symmetric viscous "
            f"demand the tared damper has no bias, tests/python/test_tare.py) | — |",
            f"| RMS force / demand, RMS error | — | 2.99 / 2.59 kN, 1.41 kN | {tr['F_rms'] / 1e3:.2f} / "
            f"{tr['F_demand_rms'] / 1e3:.2f} kN, {tr['error_rms'] / 1e3:.2f} kN | — |",
            f"| Ideal semi-active against the best passive damper (ride at equal or lower DLC) | not measured "
            f"(\"subject of on-going research\") | — | ideal {s['ideal']['a_body_rms']:.3f} m/s², "
            f"DLC {s['ideal']['DLC']:.4f}; best passive ({s['best_passive']['c_passive'] / 1e3:g} kNs/m) "
            f"{s['best_passive']['a_body_rms']:.3f} m/s², "
            f"DLC {s['best_passive']['DLC']:.4f}; passive curve at the ideal's DLC: "
            f"{'below its DLC range' if at is None else f'{at:.3f} m/s²'} | "
            f"ride {100 * (1 - s['ideal']['a_body_rms'] / s['best_passive']['a_body_rms']):.0f} % better |",
            f"| Damper FMU against the best passive damper | — | — | FMU {s['fmu']['a_body_rms']:.3f} m/s², DLC "
            f"{s['fmu']['DLC']:.4f}: "
            f"ride {100 * (s['fmu']['a_body_rms'] / s['best_passive']['a_body_rms'] - 1):+.0f} %, "
            f"DLC {100 * (s['fmu']['DLC'] / s['best_passive']['DLC'] - 1):+.1f} % | — |"]
    return "\n".join(rows), sign_ok


def best_passive_note(summaries: list[dict[str, Any]]) -> str:
    rules = {s["best_passive"]["rule"] for s in summaries}
    if len(rules) == 1:
        return f"Best passive, in every case: {rules.pop()}."
    return "Best passive: " + "; ".join(f"{s['label']} {s['speed']:g} m/s: {s['best_passive']['rule']}"
                                        for s in summaries) + "."


def crg_table(c: dict[str, Any]) -> str:
    rows = ["| damper | RMS a_body (m/s²) | peak abs a_body (m/s²) | DLC | peak abs F_tyre / static load | "
            "peak abs x_damper (mm) | max abs v_damper (m/s) |", "|---|---|---|---|---|---|---|"]
    b = c["best_passive"]
    for name, m in ((f"best passive, c = {b['c_passive'] / 1e3:g} kNs/m", b), ("ideal semi-active", c["ideal"]),
                    ("damper FMU", c["fmu"])):
        rows.append(f"| {name} | {m['a_body_rms']:.2f} | {m['a_body_peak']:.2f} | {m['DLC']:.3f} | "
                    f"{m['F_tyre_peak_over_static']:.2f} | {1e3 * m['x_damper_peak']:.1f} | {m['v_damper_max']:.2f} |")
    return "\n".join(rows)


def natural_frequencies(consts: dict[str, float]) -> tuple[float, ...]:
    """Undamped body and wheel-hop frequencies (Hz) of the two-mass model."""
    ms, mu, ks, kt = consts["m_body"], consts["m_axle"], consts["k_susp"], consts["k_tyre"]
    k = np.array([[ks, -ks], [-ks, ks + kt]])
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(np.diag([ms, mu]), k)).real)
    return tuple(float(x) for x in np.sqrt(w2) / (2 * np.pi))


def headline(summaries: list[dict[str, Any]], crg: dict[str, Any]) -> dict[str, float]:
    """The figures the documents quote (docs/hil_scenarios.json): the three headline cases' vehicle
    metrics (<road>_<speed>_<passive|ideal|fmu>_...), the minor road's tracking and spectrum at 14 m/s,
    ranges over every case, the Belgian block's; forces in kN, shares and changes in %."""
    out: dict[str, float] = {}
    for s in summaries:
        if (s["road"], s["speed"]) not in HEADLINE:
            continue
        tag, b = f"{s['road']}_{s['speed']:g}", s["best_passive"]
        out[f"{tag}_best_passive_kns_m"] = b["c_passive"] / 1e3
        for name, m in (("passive", b), ("ideal", s["ideal"]), ("fmu", s["fmu"])):
            out |= {f"{tag}_{name}_a_body_rms": m["a_body_rms"], f"{tag}_{name}_dlc": m["DLC"],
                    f"{tag}_{name}_x_rms_mm": 1e3 * m["x_damper_rms"],
                    f"{tag}_{name}_x_peak_mm": 1e3 * m["x_damper_peak"]}
        for name in ("ideal", "fmu"):
            out[f"{tag}_{name}_ride_change_pct"] = 100 * (s[name]["a_body_rms"] / b["a_body_rms"] - 1)
    minor = next(s for s in summaries if (s["road"], s["speed"]) == HEADLINE[0])
    tr, pk = minor["tracking"], minor["spectrum"]
    out |= {"minor_ext_mean_error_kn": tr["extension"]["mean_error"] / 1e3,
            "minor_ext_above_pct": 100 * tr["extension"]["fraction_above"],
            "minor_comp_mean_error_kn": tr["compression"]["mean_error"] / 1e3,
            "minor_comp_below_pct": 100 * tr["compression"]["fraction_below"],
            "minor_mean_error_kn": tr["mean_error"] / 1e3, "minor_f_rms_kn": tr["F_rms"] / 1e3,
            "minor_f_demand_rms_kn": tr["F_demand_rms"] / 1e3, "minor_error_rms_kn": tr["error_rms"] / 1e3,
            "minor_peak_above_3_hz": pk["damper_force"]["peak_above_3Hz"],
            "minor_peak_band_hz": pk["damper_force"]["peak_wheel_hop_band"],
            "minor_ideal_peak_band_hz": pk["ideal_force"]["peak_wheel_hop_band"]}

    def span(name: str, values: list[float]) -> None:
        out[f"{name}_min"], out[f"{name}_max"] = min(values), max(values)

    others = [s for s in summaries if s is not minor]
    span("others_peak_above_3_hz", [s["spectrum"]["damper_force"]["peak_above_3Hz"] for s in others])
    span("others_peak_band_hz", [s["spectrum"]["damper_force"]["peak_wheel_hop_band"] for s in others])
    span("ext_mean_error_kn", [s["tracking"]["extension"]["mean_error"] / 1e3 for s in summaries])
    span("ext_above_pct", [100 * s["tracking"]["extension"]["fraction_above"] for s in summaries])
    span("comp_mean_error_kn", [s["tracking"]["compression"]["mean_error"] / 1e3 for s in summaries])
    span("comp_below_pct", [100 * s["tracking"]["compression"]["fraction_below"] for s in summaries])
    span("ideal_benefit_pct", [100 * (1 - s["ideal"]["a_body_rms"] / s["best_passive"]["a_body_rms"])
                               for s in summaries])
    span("fmu_ride_change_pct", [100 * (s["fmu"]["a_body_rms"] / s["best_passive"]["a_body_rms"] - 1)
                                 for s in summaries])
    span("fmu_dlc_change_pct", [100 * (s["fmu"]["DLC"] / s["best_passive"]["DLC"] - 1) for s in summaries])
    span("fmu_v_max", [s["tracking"]["v_max"] for s in summaries])
    span("best_passive_kns_m", [s["best_passive"]["c_passive"] / 1e3 for s in summaries])
    out["crg_best_passive_kns_m"] = crg["best_passive"]["c_passive"] / 1e3
    for name in ("best_passive", "ideal", "fmu"):
        key = "passive" if name == "best_passive" else name
        out[f"crg_{key}_a_body_rms"], out[f"crg_{key}_dlc"] = crg[name]["a_body_rms"], crg[name]["DLC"]
    out["crg_fmu_v_max"], out["crg_fmu_f_max_kn"] = crg["tracking"]["v_max"], crg["tracking"]["F_max"] / 1e3
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--duration", type=float, default=DURATION, help="recorded seconds after the settling time")
    parser.add_argument("--settle", type=float, default=SETTLE)
    parser.add_argument("--step", type=float, default=STEP, help="communication step (s)")
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--crg-speed", type=float, default=CRG_SPEED, help="m/s on the Belgian-block track")
    parser.add_argument("--headline-only", action="store_true", help="only minor 14, major 20, motorway 25 m/s")
    parser.add_argument("--docs", action="store_true", help="write the headline figures to docs/hil_scenarios.json "
                        "and copy the plots to docs/figures/ (the whole grid at the defaults only)")
    args = parser.parse_args(argv)

    t_start = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    consts = truck_constants(args.truck_fmu)
    nat = natural_frequencies(consts)
    cases = []
    for road, speed in (HEADLINE if args.headline_only else GRID):
        t0 = time.perf_counter()
        summary, series = run_scenario(road, speed, args.seed, args.duration, args.settle, args.step,
                                       truck_fmu=args.truck_fmu, damper_fmu=args.damper_fmu)
        summary["wall_time_s"] = time.perf_counter() - t0
        cases.append((summary, series))
        print(f"hil_scenarios: {summary['label']} at {speed:g} m/s done in {summary['wall_time_s']:.1f} s", flush=True)
    headline_cases = [c for c in cases if (c[0]["road"], c[0]["speed"]) in HEADLINE]
    for summary, series in headline_cases:
        plot_fig7(args.out / f"fig7_{summary['road']}_{summary['speed']:g}.png", summary, series)
    plot_spectra(args.out / "force_spectrum.png", headline_cases, nat[1])
    plot_tradeoff(args.out / "tradeoff.png", [c[0] for c in headline_cases])
    crg_summary, crg_series = run_crg(CRG, args.crg_speed, args.step, truck_fmu=args.truck_fmu,
                                      damper_fmu=args.damper_fmu)
    plot_crg(args.out / "belgian_block.png", crg_summary, crg_series)

    summaries = [c[0] for c in cases]
    minor = next(s for s in summaries if s["road"] == "minor" and s["speed"] == 14.0)
    comp, sign_ok = comparison_table(minor, nat[1])
    text = "\n\n".join([
        f"# HiL scenarios: quarter truck + damper FMU (step {args.step * 1e3:g} ms, Jacobi, records of "
        f"{args.duration:g} s after {args.settle:g} s, seed {args.seed})",
        f"Undamped natural frequencies of the truck: body {nat[0]:.2f} Hz, wheel hop {nat[1]:.2f} Hz.",
        "## The paper's Fig. 7 statements (minor road, 14 m/s)", comp,
        "## Vehicle metrics", vehicle_table(summaries),
        best_passive_note(summaries),
        "## Force tracking of the damper FMU", tracking_table(summaries),
        f"## OpenCRG Belgian block ({crg_summary['track_length']:.0f} m, section v = {crg_summary['section_v']:g} m, "
        f"{crg_summary['speed']:g} m/s, envelope {crg_summary['envelope']:g} m; metrics while on the track)",
        crg_table(crg_summary),
        tracking_table([{**crg_summary, "label": "Belgian block"}]),
    ]) + "\n"
    (args.out / "table.md").write_text(text, encoding="utf-8")
    results = {"step": args.step, "seed": args.seed, "settle": args.settle, "duration": args.duration,
               "natural_frequencies_Hz": nat, "paper_sign_pattern_reproduced": bool(sign_ok),
               "scenarios": summaries, "belgian_block": crg_summary,
               "wall_time_s": time.perf_counter() - t_start}
    (args.out / "results.json").write_text(json.dumps(jsonable(results), indent=1), encoding="utf-8")
    if args.docs:
        if args.headline_only:
            raise SystemExit("hil_scenarios: --docs needs the whole grid (the documents quote its ranges)")
        from damper_tools import doc_figures

        doc_figures.write("hil_scenarios", headline(summaries, crg_summary),
                          ".venv/bin/damper-hil-scenarios --docs")
        for name in ("fig7_minor_14.png", "force_spectrum.png", "tradeoff.png", "belgian_block.png"):
            shutil.copy(args.out / name, REPO / "docs" / "figures" / f"hil_{name}")
    print(text)
    print(f"hil_scenarios: wrote {args.out} in {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
