"""Reproduce the rig tests of Kitching, Cole and Cebon (Figs. 4 and 6) with the packaged FMU.

    .venv/bin/damper-paper-tests [--fmu target/fmu/SemiActiveDamper.fmu] [--out out/paper]

Writes into the output directory:

    fig4_spool_steps.png       five closed-loop spool steps at 0.15 m/s (control_mode = 1)
    fig6_force_steps.png       2 -> 12 -> 22 kN demand steps at +-0.15 m/s: force, spool, pressures
    fig6_force_step_zoom.png   the four force steps normalised, extension against compression
    table.md                   the paper's statements against the measured numbers (also printed)
    results.json               every measured number

and with --docs the headline figures the documents quote to docs/paper_tests.json (damper_tools.doc_figures).

The scenarios and metrics live in damper_tools.rig_tests, shared with the pytest suite.
"""

import argparse
import json
import math
import shutil
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib
import matplotlib.pyplot as plt
from fmpy import extract, read_model_description

from damper_tools import DAMPER_FMU, REPO, doc_figures
from damper_tools import rig_tests as rt

BAR = 1e5


def ms(x: float | None) -> str:
    return "n/a" if x is None or math.isnan(x) else f"{1e3 * x:.1f} ms"


def ms_range(values: Sequence[float]) -> str:
    if any(math.isnan(v) for v in values):
        return "n/a (not reached)"
    lo, hi = f"{1e3 * min(values):.1f}", f"{1e3 * max(values):.1f}"
    return f"{lo} ms" if lo == hi else f"{lo}–{hi} ms"


def yes_no(ok: bool) -> str:
    return "yes" if ok else "**no**"


# --------------------------------------------------------------------------- tables

def summary_rows(rig: dict[str, Any], volume_ratio: float) -> list[tuple[str, ...]]:
    """Rows of the main table: quantity, paper, this FMU, band, reproduced?"""
    crit = rt.criteria(rig)
    spool = [m for _, _, m in rig["spool"]]
    ext = rig["force"]["extension"][1]
    comp = rig["force"]["compression"][1]
    rows: list[tuple[str, ...]] = [(
        "Valve dead time (spool moved 2 % of the step), Fig. 4",
        "3 ms, from the power amplifier",
        f"{ms_range([m['dead'] for m in spool])} (five steps)",
        f"{1e3 * rt.DEAD_TIME_BAND[0]:g}–{1e3 * rt.DEAD_TIME_BAND[1]:g} ms",
        yes_no(crit["dead_time"][0]),
    ), (
        "Spool t50 / t90 after the step, Fig. 4",
        "fast (no number given)",
        f"t50 {ms_range([m['t50'] for m in spool])}, t90 {ms_range([m['t90'] for m in spool])}",
        "—", "—",
    ), (
        "Spool overshoot, Fig. 4",
        "no significant overshoot",
        f"largest {max(m['overshoot_pct'] for m in spool):.1f} %",
        f"< {rt.SPOOL_OVERSHOOT_MAX_PCT:g} %",
        yes_no(crit["spool_overshoot"][0]),
    )]
    for label, m in (("2 → 12 kN", ext[0]), ("12 → 22 kN", ext[1])):
        rows.append((
            f"Extension force step {label} at 0.15 m/s, Fig. 6",
            "≈25 ms before the force reaches the demand",
            f"t90 {ms(m['t90'])}, t100 {ms(m['t100'])} (t10 {ms(m['t10'])}, t50 {ms(m['t50'])}), "
            f"overshoot {m['overshoot_pct']:.0f} %",
            f"t90 {1e3 * rt.EXT_T90_BAND[0]:g}–{1e3 * rt.EXT_T90_BAND[1]:g} ms",
            yes_no(rt.in_band(m["t90"], rt.EXT_T90_BAND)),
        ))
    ratios = ", ".join(f"{r:.2f}" for r in crit["compression_slower"][1])
    rows.append((
        "Compression against extension (same steps at −0.15 m/s)",
        "compression slower: the compressed oil volume is ≈3×",
        f"t90 {ms(comp[0]['t90'])} / {ms(comp[1]['t90'])}; t90 ratio compression/extension {ratios}",
        "compression t90 > extension t90 (both steps)",
        yes_no(crit["compression_slower"][0]),
    ))
    rows.append((
        "Compressed oil volume, compression/extension (mid-stroke)",
        "≈3×",
        f"{volume_ratio:.2f} (from the parameters)",
        "—", "—",
    ))
    return rows


def markdown(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def spool_rows(rig: dict[str, Any]) -> list[tuple[str, ...]]:
    rows: list[tuple[str, ...]] = []
    for x_demand, _, m in rig["spool"]:
        rows.append((f"{1e3 * rt.SPOOL_START:.1f} → {1e3 * x_demand:.1f}", ms(m["dead"]), ms(m["t50"]),
                     ms(m["t90"]), f"{m['overshoot_pct']:.1f}", f"{1e3 * m['y_end']:.3f}",
                     f"{m['F_end'] / 1e3:.1f}", f"{m['F_flow_end']:.1f}"))
    return rows


def force_rows(rig: dict[str, Any]) -> list[tuple[str, ...]]:
    rows: list[tuple[str, ...]] = []
    for name in ("extension", "compression"):
        for label, m in zip(("2 → 12 kN", "12 → 22 kN"), rig["force"][name][1], strict=True):
            rows.append((name, label, f"{m['y0'] / 1e3:.2f}", ms(m["t10"]), ms(m["t50"]), ms(m["t90"]),
                         ms(m["t100"]), f"{m['overshoot_pct']:.1f}", f"{m['y_end'] / 1e3:.2f}"))
    return rows


def report(rig: dict[str, Any], volume_ratio: float, output_interval: float) -> str:
    text = ["# Rig tests of the paper, reproduced with the FMU", "",
            markdown(("Quantity", "Paper", "This FMU", "Band", "Reproduced?"), summary_rows(rig, volume_ratio)),
            "", "## Fig. 4: spool steps at 0.15 m/s extension (control_mode = 1)", "",
            markdown(("x_spool demand [mm]", "dead time (2 %)", "t50", "t90", "overshoot [%]",
                      "x_spool at the end [mm]", "F_damper at the end [kN]", "F_flow at the end [N]"),
                     spool_rows(rig)),
            "", "## Fig. 6: force steps at ±0.15 m/s (control_mode = 0)", "",
            "Magnitudes of F_damper (compression forces are negative); each step is measured from the force at "
            "the step to the new demand; the first step's window ends at the second step.", "",
            markdown(("direction", "demand step (magnitude)", "force at the step [kN]", "t10", "t50", "t90",
                      "t100", "overshoot [%]", "force at the window end [kN]"), force_rows(rig)),
            "", f"Communication step {1e3 * output_interval:g} ms; crossing times are interpolated linearly "
            "between output samples. t100 is the first time the force reaches the demand.", ""]
    return "\n".join(text)


def results_json(rig: dict[str, Any], volume_ratio: float, output_interval: float) -> dict[str, Any]:
    def clean(m: dict[str, float]) -> dict[str, float | None]:
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in m.items()}
    crit = rt.criteria(rig)
    return {
        "units": "SI: seconds, metres, newtons; overshoot in % of the step",
        "output_interval": output_interval,
        "fig4_spool_steps": [dict(x_demand=x, **clean(m)) for x, _, m in rig["spool"]],
        "fig6_force_steps": {name: [dict(step=label, **clean(m)) for label, m in
                                    zip(("2->12 kN", "12->22 kN"), rig["force"][name][1], strict=True)]
                             for name in ("extension", "compression")},
        "compressed_volume_ratio": volume_ratio,
        "bands": {"dead_time": rt.DEAD_TIME_BAND, "extension_t90": rt.EXT_T90_BAND,
                  "spool_overshoot_max_pct": rt.SPOOL_OVERSHOOT_MAX_PCT},
        "reproduced": {name: bool(ok) for name, (ok, _) in crit.items()},
    }


def headline(rig: dict[str, Any], volume_ratio: float) -> dict[str, float]:
    """The figures the documents quote (docs/paper_tests.json): times in ms, overshoots in %."""
    spool = [m for _, _, m in rig["spool"]]
    out: dict[str, float] = {}
    for key in ("dead", "t50", "t90"):
        values = [1e3 * m[key] for m in spool]
        out[f"spool_{key}_min_ms"], out[f"spool_{key}_max_ms"] = min(values), max(values)
    out["spool_overshoot_max_pct"] = max(m["overshoot_pct"] for m in spool)
    for name, keys in (("extension", ("t10", "t50", "t90", "t100")), ("compression", ("t90",))):
        for k, m in enumerate(rig["force"][name][1], 1):
            for key in keys:
                out[f"{name}_step{k}_{key}_ms"] = 1e3 * m[key]
            out[f"{name}_step{k}_overshoot_pct"] = m["overshoot_pct"]
    for k, ratio in enumerate(rt.criteria(rig)["compression_slower"][1], 1):
        out[f"t90_ratio_step{k}"] = ratio
    out["compressed_volume_ratio"] = volume_ratio
    return out


# --------------------------------------------------------------------------- plots

def plot_spool_steps(rig: dict[str, Any], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.axvspan(0, rt.PAPER_DEAD_TIME * 1e3, color="0.9", label="paper: 3 ms amplifier delay")
    for x_demand, result, m in rig["spool"]:
        t = (result["time"] - rt.SPOOL_T_STEP) * 1e3
        line, = ax.plot(t, result["x_spool"] * 1e3,
                        label=f"{1e3 * rt.SPOOL_START:.1f} → {1e3 * x_demand:.1f} mm "
                              f"(dead {1e3 * m['dead']:.1f} ms, t90 {1e3 * m['t90']:.1f} ms)")
        # x_spool_ref at t_k was held over the step ending at t_k.
        ax.plot(t, result["x_spool_ref"] * 1e3, "--", color=line.get_color(), lw=0.8, drawstyle="steps-pre")
    ax.set_xlim(-10, (rt.SPOOL_T_END - rt.SPOOL_T_STEP) * 1e3)
    ax.set_ylim(0, 4.2)
    ax.set_xlabel("time after the demand step [ms]")
    ax.set_ylabel("spool position x_spool [mm]")
    ax.set_title("Fig. 4: closed-loop spool steps, damper extending at 0.15 m/s\n"
                 "(control_mode = 1; solid: x_spool, dashed: demand)")
    ax.grid(True, alpha=0.4)
    # Between the 1.8 mm and 3.5 mm lines, where no curve runs after the step.
    ax.legend(fontsize=8, loc="upper right", bbox_to_anchor=(1.0, 0.79))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_force_steps(rig: dict[str, Any], path: Path) -> None:
    fig, axes = plt.subplots(3, 2, figsize=(12, 9), sharex=True)
    t_from = rt.FORCE_STEP_TIMES[0] - 0.05
    for col, name in enumerate(("extension", "compression")):
        result, _ = rig["force"][name]
        t = result["time"]
        window = t >= t_from
        t = t[window]
        r = {k: result[k][window] for k in ("F_demand", "F_damper", "x_spool", "x_spool_ref", "p_ext", "p_comp",
                                            "p_reservoir")}
        v = result["v_damper"][0]
        ax = axes[0, col]
        ax.plot(t, r["F_demand"] / 1e3, "k--", label="F_demand", drawstyle="steps-pre")
        ax.plot(t, r["F_damper"] / 1e3, "C0", label="F_damper (load cell)")
        ax.set_ylabel("force [kN] (tension +)")
        ax.set_title(f"{name}, v_damper = {v:+.2f} m/s")
        ax.legend(fontsize=8, loc="upper left" if name == "extension" else "lower left")
        ax = axes[1, col]
        ax.plot(t, r["x_spool_ref"] * 1e3, "k--", lw=0.8, label="x_spool_ref (force loop)", drawstyle="steps-pre")
        ax.plot(t, r["x_spool"] * 1e3, "C1", label="x_spool")
        ax.set_ylabel("spool position [mm]")
        ax.legend(fontsize=8, loc="upper right")
        ax = axes[2, col]
        ax.plot(t, r["p_ext"] / BAR, "C3", label="p_ext (annulus)")
        ax.plot(t, r["p_comp"] / BAR, "C2", label="p_comp (full bore)")
        ax.plot(t, r["p_reservoir"] / BAR, "C7", label="p_reservoir")
        ax.set_ylabel("gauge pressure [bar]")
        ax.set_xlabel("time [s]")
        ax.legend(fontsize=8, loc="upper left")
        for ax in axes[:, col]:
            ax.grid(True, alpha=0.4)
            for ts in rt.FORCE_STEP_TIMES:
                ax.axvline(ts, color="0.6", lw=0.6)
    axes[0, 0].set_xlim(t_from, rt.FORCE_T_END)
    fig.suptitle("Fig. 6: two consecutive 10 kN demand steps (2 → 12 → 22 kN) at constant 0.15 m/s, control_mode = 0")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_force_step_zoom(rig: dict[str, Any], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(8, 5))
    styles = {"extension": "-", "compression": "--"}
    for name, direction in (("extension", 1), ("compression", -1)):
        result, metrics = rig["force"][name]
        t = result["time"]
        for k, (ts, m) in enumerate(zip(rt.FORCE_STEP_TIMES, metrics, strict=True)):
            window = (t >= ts - 0.005) & (t <= ts + 0.15 + 1e-9)
            frac = (direction * result["F_damper"][window] - m["y0"]) / (m["y1"] - m["y0"])
            label = ("2 → 12 kN", "12 → 22 kN")[k]
            ax.plot((t[window] - ts) * 1e3, frac, styles[name], color=f"C{k}",
                    label=f"{name} {label}: t90 {1e3 * m['t90']:.1f} ms")
    ax.axhline(0.9, color="0.5", lw=0.6)
    ax.axhline(1.0, color="0.3", lw=0.6)
    ax.axvline(rt.PAPER_FORCE_DELAY * 1e3, color="k", ls=":", label="paper: ≈25 ms (extension)")
    ax.set_xlim(-5, 150)
    ax.set_xlabel("time after the demand step [ms]")
    ax.set_ylabel("fraction of the force step [–]")
    ax.set_title("Force steps at ±0.15 m/s, normalised: (|F| − |F|₀)/(|F_demand| − |F|₀)\n"
                 "compression (3× oil volume under pressure) is slower")
    ax.grid(True, alpha=0.4)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# --------------------------------------------------------------------------- main

def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--out", type=Path, default=REPO / "out" / "paper")
    parser.add_argument("--output-interval", type=float, default=rt.OUTPUT_INTERVAL,
                        help=f"communication step [s] (default {rt.OUTPUT_INTERVAL})")
    parser.add_argument("--strict", action="store_true", help="exit 1 if a paper statement is not reproduced")
    parser.add_argument("--docs", action="store_true", help="write the headline figures to docs/paper_tests.json "
                        "and copy the plots to docs/figures/")
    args = parser.parse_args(argv)
    matplotlib.use("Agg")  # the plots are files: no display needed
    if not args.fmu.is_file():
        sys.exit(f"paper_tests: {args.fmu} not found (run python3 scripts/package_fmu.py)")
    args.out.mkdir(parents=True, exist_ok=True)

    model_description = read_model_description(str(args.fmu), validate=True)
    unzipdir = extract(str(args.fmu))
    try:
        rig = rt.run_rig_tests(unzipdir, output_interval=args.output_interval)
    finally:
        shutil.rmtree(unzipdir, ignore_errors=True)
    volume_ratio = rt.compressed_volume_ratio(model_description)

    plot_spool_steps(rig, args.out / "fig4_spool_steps.png")
    plot_force_steps(rig, args.out / "fig6_force_steps.png")
    plot_force_step_zoom(rig, args.out / "fig6_force_step_zoom.png")
    text = report(rig, volume_ratio, args.output_interval)
    (args.out / "table.md").write_text(text, encoding="utf-8")
    results = results_json(rig, volume_ratio, args.output_interval)
    (args.out / "results.json").write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")
    if args.docs:
        doc_figures.write("paper_tests", headline(rig, volume_ratio), ".venv/bin/damper-paper-tests --docs")
        for name in ("fig4_spool_steps.png", "fig6_force_steps.png", "fig6_force_step_zoom.png"):
            shutil.copy(args.out / name, REPO / "docs" / "figures" / name)
    print(text)
    print(f"paper_tests: wrote {args.out}/ (fig4_spool_steps.png, fig6_force_steps.png, "
          "fig6_force_step_zoom.png, table.md, results.json)")
    if args.strict and not all(ok for ok, _ in rt.criteria(rig).values()):
        sys.exit(1)


if __name__ == "__main__":
    main()
