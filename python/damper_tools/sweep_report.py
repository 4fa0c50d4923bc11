"""The `damper-sweep` command and what it draws: runs a sweep file (damper_tools.sweep) on
a Dask cluster and writes, in the output directory (default out/sweeps/<name>/):

    results.parquet        one row per point: point, point_id, run_seed, every parameter, every metric,
                           error ('' when the run worked), wall_s
    plots/tradeoff.png     the ride-vs-DLC trade-off over the grid (one panel per road), Pareto front
    plots/heatmap_*.png    a metric over two parameters (mean over the others), one panel per road
    plots/sensitivity.png  which parameter moves each metric most (first-order Sobol index, tornado)
    sensitivity.csv        the indices behind it
    index.html             the page with all of it
    run.json               workers, wall time, points run and skipped (resume)
    work/points/*.json     one file per finished point: a rerun skips them

    .venv/bin/damper-sweep sweeps/hil_200.toml              # LocalCluster, 1 worker/core
    .venv/bin/damper-sweep sweeps/hil_200.toml --workers 1  # for a timing
    .venv/bin/damper-sweep sweeps/hil_200.toml --scheduler tcp://host:8786
    .venv/bin/damper-sweep sweeps/tiny.toml --serial        # no Dask: this process

Sensitivity: for a parameter X and a metric Y, S = Var(E[Y | X]) / Var(Y), the first-order Sobol
index estimated by the correlation ratio: E[Y | X] is the mean of Y over the points sharing X's value
(a grid axis, a category) or falling in the same tenth of X's range of ranks (a Monte-Carlo
parameter). On a full grid it is the share of the variance the parameter's main effect explains; the
bar's colour gives the sign of Spearman's rank correlation (Y rises or falls with X).
"""

import argparse
import html
import json
import math
import os
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from damper_tools import DAMPER_FMU, REPO, hil_scenarios, pyplot, sweep

OUT = REPO / "out" / "sweeps"
RANK_BINS = 10
MAX_GROUP_LEVELS = 12


def varying(df: Any, names: list[str]) -> list[str]:
    """The names among `names` whose column takes more than one value."""
    return [n for n in names if n in df and df[n].nunique(dropna=False) > 1]


def _numeric(df: Any, name: str) -> bool:
    import pandas as pd

    return pd.api.types.is_numeric_dtype(df[name]) and not pd.api.types.is_bool_dtype(df[name])


# --------------------------------------------------------------------------- numbers

def first_order_index(x: Any, y: npt.ArrayLike) -> tuple[float, float]:
    """(S, no-effect level): S = Var(E[y | x]) / Var(y) (module docstring), grouping by x's values or
    by rank bins of x; the no-effect level (k - 1)/(n - 1) for k groups of n points is what S
    averages to when y does not depend on x at all (the estimator's bias): below it, no effect shows."""
    import pandas as pd

    xs = pd.Series(x).reset_index(drop=True)
    ys = pd.Series(np.asarray(y, float)).reset_index(drop=True)
    ok = ys.notna()
    xs, ys = xs[ok], ys[ok]
    if ys.size < 2 or ys.var(ddof=0) == 0:
        return math.nan, math.nan
    if xs.nunique() > MAX_GROUP_LEVELS:
        xs = pd.Series(np.minimum((xs.rank(method="first") - 1) * RANK_BINS // xs.size, RANK_BINS - 1),
                       index=xs.index)
    means = ys.groupby(xs).transform("mean")
    return float(((means - ys.mean()) ** 2).mean() / ys.var(ddof=0)), (xs.nunique() - 1) / (ys.size - 1)


def sensitivity(df: Any, params: list[str], metrics: list[str], random: Sequence[str] = ()) -> Any:
    """One row per (metric, parameter): index, spearman (nan for a category), and for the Monte-Carlo
    parameters (`random`) the no_effect_level of first_order_index. (A grid axis of a full grid is
    balanced against the other axes: their variance does not leak into its group means, and there
    is no such chance level to show.)"""
    import pandas as pd

    rows = []
    for m in metrics:
        # a metric that is infinite by definition on some rows (a fitted bandwidth "no lag") is
        # ranked over its finite rows
        d = df[np.isfinite(df[m].to_numpy(dtype=float))]
        for p in params:
            rho = (float(d[p].corr(d[m], method="spearman")) if _numeric(d, p) else math.nan)
            index, level = first_order_index(d[p], d[m].to_numpy())
            rows.append({"metric": m, "parameter": p, "index": index,
                         "no_effect_level": level if p in random else math.nan, "spearman": rho})
    return pd.DataFrame(rows, columns=["metric", "parameter", "index", "no_effect_level", "spearman"])


# --------------------------------------------------------------------------- plots

def _facets(df: Any, facet: str | Sequence[str] | None) -> list[list[tuple[str, Any]]]:
    """Panels as rows of (title, frame): by one parameter (one row), or by two (rows by the first,
    columns by the second); a parameter with one value is not a facet."""
    names = [facet] if isinstance(facet, str) else list(facet or [])
    names = [n for n in names if n in df and df[n].nunique() > 1][:2]
    if not names:
        return [[("", df)]]
    if len(names) == 1:
        n = names[0]
        return [[(f"{n} = {v:g}" if isinstance(v, float) else f"{n} = {v}", df[df[n] == v])
                 for v in df[n].drop_duplicates()]]
    a, b = names
    return [[(f"{a} = {va}, {b} = {vb:g}" if isinstance(vb, float) else f"{a} = {va}, {b} = {vb}",
              df[(df[a] == va) & (df[b] == vb)]) for vb in df[b].drop_duplicates()] for va in df[a].drop_duplicates()]


def plot_tradeoff(df: Any, path: Path, x: str = "DLC", y: str = "a_body_rms", color: str | None = None,
                  facet: str | Sequence[str] | None = "road", size: str | None = None) -> Path:
    """y against x for every point, coloured by a parameter (and sized by another), the Pareto front
    (both small) of each panel as a line."""
    plt = pyplot()
    grid = _facets(df, facet)
    nrow, ncol = len(grid), len(grid[0])
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.9 * ncol + 1.2, 3.3 * nrow + 0.6), squeeze=False)
    coloured = bool(color and color in df and _numeric(df, color))
    vmin, vmax = (float(df[color].min()), float(df[color].max())) if coloured else (None, None)
    sizes = None
    if size and size in df and _numeric(df, size):
        lo, hi = float(df[size].min()), float(df[size].max())
        sizes = (lambda v: 8 + 50 * (v - lo) / (hi - lo)) if hi > lo else (lambda v: 22 + 0 * v)
    sc = None
    for r, row in enumerate(grid):
        for c, (title, d) in enumerate(row):
            ax = axes[r][c]
            d = d[d[x].notna() & d[y].notna()]
            xs, ys = d[x].to_numpy(float), d[y].to_numpy(float)
            s = sizes(d[size].to_numpy(float)) if sizes else 22
            if coloured:
                sc = ax.scatter(xs, ys, c=d[color].to_numpy(float), cmap="viridis", vmin=vmin, vmax=vmax, s=s,
                                edgecolors="none")
            else:
                ax.scatter(xs, ys, color="tab:blue", s=s, edgecolors="none")
            if xs.size:
                front = hil_scenarios.pareto_mask(xs, ys)
                order = np.argsort(xs[front])
                ax.plot(xs[front][order], ys[front][order], "-", color="tab:red", lw=1.0,
                        label=f"Pareto front ({int(front.sum())})")
                ax.legend(fontsize=7, loc="upper left")
            ax.set_title(title or f"{len(d)} points", fontsize=9)
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
            if r == nrow - 1:
                ax.set_xlabel(x, fontsize=8)
            if c == 0:
                ax.set_ylabel(y, fontsize=8)
    if coloured and sc is not None:
        fig.colorbar(sc, ax=axes.ravel().tolist(), label=color, shrink=0.8)
    note = f"; marker size: {size} ({df[size].min():g} small to {df[size].max():g} large)" if sizes else ""
    fig.suptitle(f"Trade-off: {y} against {x}, every point of the sweep{note}", fontsize=10)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return path


def plot_heatmap(df: Any, path: Path, x: str, y: str, metric: str, facet: str | None = "road",
                 others: list[str] | None = None) -> Path:
    """The mean of `metric` over the points sharing (x, y) (so over the parameters `others`), one
    panel per facet value, one colour scale."""
    plt = pyplot()
    panels = [p for row in _facets(df, facet) for p in row]
    facets = [facet] if isinstance(facet, str) else list(facet or [])
    others = [o for o in (others or []) if o not in (x, y, *facets)]
    fig, axes = plt.subplots(1, len(panels), figsize=(5.0 * len(panels) + 1.0, 4.4), squeeze=False)
    pivots = [d.pivot_table(index=y, columns=x, values=metric, aggfunc="mean") for _, d in panels]
    vmin = min(float(np.nanmin(p.to_numpy())) for p in pivots)
    vmax = max(float(np.nanmax(p.to_numpy())) for p in pivots)
    for ax, (title, _), pv in zip(axes[0], panels, pivots, strict=True):
        im = ax.imshow(pv.to_numpy(float), origin="lower", aspect="auto", cmap="viridis", vmin=vmin, vmax=vmax)
        ax.set_xticks(range(pv.shape[1]), [f"{v:g}" if isinstance(v, float) else str(v) for v in pv.columns],
                      fontsize=8)
        ax.set_yticks(range(pv.shape[0]), [f"{v:g}" if isinstance(v, float) else str(v) for v in pv.index],
                      fontsize=8)
        for (i, j), v in np.ndenumerate(pv.to_numpy(float)):
            if np.isfinite(v):
                bright = (v - vmin) / (vmax - vmin) > 0.6 if vmax > vmin else False
                ax.text(j, i, f"{v:.3g}", ha="center", va="center", fontsize=7, color="k" if bright else "w")
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        ax.set_title(title, fontsize=10)
    fig.colorbar(im, ax=list(axes[0]), label=metric)
    fig.suptitle(f"{metric} over {x} and {y}" + (f" (mean over {', '.join(others)})" if others else ""), fontsize=10)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def plot_sensitivity(sens: Any, path: Path) -> Path:
    """Tornado chart: per metric, the parameters by their first-order index, largest on top."""
    plt = pyplot()
    metrics = list(dict.fromkeys(sens["metric"]))
    ncol = min(3, len(metrics))
    nrow = math.ceil(len(metrics) / ncol)
    n_par = sens["parameter"].nunique()
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 0.9 + 0.38 * n_par * nrow + 0.6 * nrow),
                             squeeze=False)
    for ax in axes.flat[len(metrics):]:
        ax.axis("off")
    for ax, m in zip(axes.flat, metrics, strict=False):
        s = sens[sens["metric"] == m].sort_values("index", na_position="first")
        colors = ["tab:red" if r > 0 else "tab:blue" if r < 0 else "0.6" for r in s["spearman"].fillna(0)]
        ax.barh(range(len(s)), s["index"].fillna(0), color=colors)
        ax.plot(s["no_effect_level"], range(len(s)), "|", color="k", ms=12, mew=1.5)
        ax.set_yticks(range(len(s)), list(s["parameter"]), fontsize=8)
        ax.set_xlim(0, 1)
        ax.set_title(m, fontsize=10)
        ax.grid(alpha=0.3, axis="x")
    for ax in axes[-1]:
        ax.set_xlabel("first-order index Var(E[Y|X]) / Var(Y)")
    fig.suptitle("Sensitivity: share of each metric's variance explained by one parameter alone\n"
                 "(red: the metric rises with the parameter, blue: it falls, grey: a category; "
                 "black tick: the level a Monte-Carlo parameter without effect reaches by chance)", fontsize=10)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_specs(spec: sweep.Sweep, df: Any) -> dict[str, Any]:
    """What to draw: the sweep file's [plots] table over these defaults."""
    metrics = spec.kept_metrics()
    params = varying(df, spec.parameters + (["sample"] if spec.random else []))
    params = [p for p in params if p != "sample"]
    numeric_axes = [a for a in spec.grid if a in params and _numeric(df, a)]
    facet = "road" if "road" in params else None
    plots = dict(spec.plots)
    tradeoff = None
    if "DLC" in metrics and "a_body_rms" in metrics:
        tradeoff = {"x": "DLC", "y": "a_body_rms", "color": numeric_axes[0] if numeric_axes else None,
                    "size": numeric_axes[1] if len(numeric_axes) > 1 else None, "facet": facet}
    heatmaps = []
    if len(numeric_axes) >= 2:
        heatmaps = [{"x": numeric_axes[0], "y": numeric_axes[1], "metric": m, "facet": facet} for m in metrics[:2]]
    plots.setdefault("tradeoff", tradeoff)
    plots.setdefault("heatmaps", heatmaps)
    plots.setdefault("sensitivity", metrics[:6])
    plots["parameters"] = params
    return plots


def draw(spec: sweep.Sweep, df: Any, out: Path) -> dict[str, Any]:
    """Draws the plots and writes sensitivity.csv; returns {'images': [(title, path)], 'sensitivity': df}."""
    plots = plot_specs(spec, df)
    ok = df[df["error"] == ""] if "error" in df else df
    images = []
    if plots["tradeoff"] and len(ok):
        t = {"facet": None, "color": None, "size": None, **plots["tradeoff"]}
        images.append(("Trade-off", plot_tradeoff(ok, out / "plots" / "tradeoff.png", t["x"], t["y"], t["color"],
                                                  t["facet"], t["size"])))
    for h in plots["heatmaps"]:
        if len(ok):
            h = {"facet": None, **h}
            name = f"heatmap_{h['metric']}_{h['x']}_{h['y']}.png"
            images.append((f"{h['metric']} over {h['x']} and {h['y']}",
                           plot_heatmap(ok, out / "plots" / name, h["x"], h["y"], h["metric"], h["facet"],
                                        plots["parameters"])))
    sens = None
    if plots["parameters"] and plots["sensitivity"] and len(ok) > 2:
        sens = sensitivity(ok, plots["parameters"], list(plots["sensitivity"]), list(spec.random))
        sens.to_csv(out / "sensitivity.csv", index=False)
        images.append(("Sensitivity", plot_sensitivity(sens, out / "plots" / "sensitivity.png")))
    return {"images": images, "sensitivity": sens}


def write_html(path: Path, spec: sweep.Sweep, df: Any, images: list[tuple[str, Path]], sens: Any,
               run: dict[str, Any]) -> Path:
    esc = html.escape
    failed = df[df["error"] != ""] if "error" in df else df.iloc[0:0]
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>Sweep {esc(spec.name)}</title>",
             "<style>body{font-family:sans-serif;max-width:1300px;margin:1em auto}table{border-collapse:collapse;"
             "font-size:12px}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}img{max-width:100%}"
             "</style></head><body>",
             f"<h1>Sweep {esc(spec.name)}: {esc(spec.scenario)}, {len(df)} points</h1>",
             f"<p>Seed {spec.seed}; grid {esc(', '.join(f'{k} ({len(v)})' for k, v in spec.grid.items()) or '-')}"
             + (f"; Monte-Carlo {esc(', '.join(spec.random))} ({spec.samples} samples). " if spec.random else ". ")
             + f"This run: {run['ran']} points run, {run['skipped']} taken from earlier runs, {len(failed)} failed; "
             + (f"{run['workers']} workers" if run["workers"] != "serial" else "serially")
             + f", {run['wall_s']:.1f} s. "
             "Results: <a href='results.parquet'>results.parquet</a>"
             + (", <a href='sensitivity.csv'>sensitivity.csv</a>" if sens is not None else "") + ".</p>"]
    for title, img in images:
        parts.append(f"<h2>{esc(title)}</h2><img src='{esc(os.path.relpath(img, path.parent))}'>")
    if sens is not None:
        top = sens.sort_values("index", ascending=False).groupby("metric", sort=False).head(3)
        parts.append("<h2>Largest first-order indices</h2>" + top.to_html(index=False, float_format="%.3f"))
    if len(failed):
        parts.append("<h2>Failed points</h2>" + failed[["point", "point_id", "error"]].to_html(index=False))
    finite = df[spec.kept_metrics()].replace([np.inf, -np.inf], np.nan)  # counts and spreads of finite values
    parts.append("<h2>Metrics over the sweep</h2>" + finite.describe().T.to_html(float_format="%.4g"))
    parts.append("</body></html>")
    path.write_text("\n".join(parts), encoding="utf-8")
    return path


# --------------------------------------------------------------------------- the command

def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("sweep_file", type=Path, help="the sweep (TOML), e.g. sweeps/hil_200.toml")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default out/sweeps/<name>)")
    cluster = parser.add_mutually_exclusive_group()
    cluster.add_argument("--scheduler", default=None, help="address of a running scheduler, e.g. tcp://host:8786")
    cluster.add_argument("--workers", type=int, default=None,
                       help="workers of the LocalCluster (default: one per core)")
    cluster.add_argument("--serial", action="store_true", help="no Dask: every point in this process")
    parser.add_argument("--truck-fmu", type=Path, default=None,
                        help="the scenario's truck FMU (default: QuarterTruck.fmu, FullTruck.fmu for full_truck)")
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--retries", type=int, default=3, help="retries of a task that raised")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.add_argument("--docs", action="store_true", help="write this run's wall time to docs/sweep.json, as the "
                        "section <sweep>_workers_<N> (<sweep>_workers_<N>_scheduler with --scheduler)")
    args = parser.parse_args(argv)

    try:
        spec = sweep.load(args.sweep_file)
    except (OSError, sweep.SweepError) as e:
        print(f"sweep: {e}", file=sys.stderr)
        return 2
    out = args.out or OUT / spec.name
    truck_fmu = args.truck_fmu or sweep.TRUCK_FMUS[spec.scenario]
    fmus = {"truck": truck_fmu.resolve(), "damper": args.damper_fmu.resolve()}
    for path in fmus.values():
        if not path.is_file():
            print(f"sweep: {path}: no such FMU (python3 scripts/package_fmu.py, scripts/package_truck.py, "
                  "scripts/package_full_truck.py)", file=sys.stderr)
            return 2
    from tqdm import tqdm

    n = len(sweep.points(spec))
    bar = tqdm(total=n, unit="point", desc=spec.name, disable=args.quiet, smoothing=0.1)
    start = time.perf_counter()
    try:
        with sweep.dask_client(args.scheduler, args.workers, args.serial) as client:
            workers = len(client.nthreads()) if client else 0
            outcome = sweep.run_sweep(spec, out / "work", fmus, client, on_result=lambda _row: bar.update(1),
                                      retries=args.retries)
    except KeyboardInterrupt:
        bar.close()
        done = len(list((out / "work" / "points").glob("*.json")))
        print(f"sweep: interrupted; {done} finished points are kept in {out / 'work'}: run the same command "
              f"again to resume", file=sys.stderr)
        return 130
    finally:
        bar.close()
    df = sweep.table(spec, outcome.rows)
    sweep.write_parquet(df, out / "results.parquet")
    wall_s, cpu_s = round(time.perf_counter() - start, 2), round(float(df["wall_s"].sum()), 2)
    run = {"sweep": str(args.sweep_file), "spec": spec.to_dict(), "points": n, "ran": outcome.ran,
           "skipped": outcome.skipped,
           "failed": outcome.failed, "workers": workers or "serial", "scheduler": args.scheduler or "local",
           "wall_s": wall_s, "sweep_wall_s": round(outcome.wall_s, 2), "cpu_s_of_runs": cpu_s}
    history = out / "run.json"
    runs = json.loads(history.read_text(encoding="utf-8")).get("runs", []) if history.is_file() else []
    history.write_text(json.dumps({**run, "runs": [*runs, run]}, indent=1) + "\n", encoding="utf-8")
    if args.docs and not outcome.skipped and not outcome.failed:
        from damper_tools import doc_figures

        figures = {"points": float(n), "wall_s": wall_s, "cpu_s_of_runs": cpu_s}
        where_run = f"--scheduler {args.scheduler} ({workers} workers started by hand)" if args.scheduler else \
            f"--workers {workers or 'serial'}"
        command = f"damper-sweep {args.sweep_file} {where_run} --docs (a fresh out/ folder: no point resumed)"
        section = f"{spec.name}_workers_{workers or 0}" + ("_scheduler" if args.scheduler else "")
        doc_figures.write("sweep", figures, command, section=section)
    if not args.no_plots:
        drawn = draw(spec, df, out)
        write_html(out / "index.html", spec, df, drawn["images"], drawn["sensitivity"], run)
    where = (f"on {workers} worker" + ("s" if workers > 1 else "")) if workers else "serially"
    print(f"sweep: {spec.name}: {n} points ({outcome.ran} run, {outcome.skipped} resumed, {outcome.failed} failed) "
          f"{where} in {run['wall_s']:.1f} s; wrote {out / 'results.parquet'}"
          + ("" if args.no_plots else f" and {out / 'index.html'}"))
    for r in outcome.rows:
        if r["error"]:
            print(f"  point {r['point']} failed: {r['error']}", file=sys.stderr)
    return 1 if outcome.failed else 0
