"""What a coupled HiL run costs against the damper FMU's own time, in one run (issue: campaigns at
the FMUs' own speed). Prints, and writes to out/benchmark/coupled.json (with --docs to
docs/coupled_benchmark.json, the figures docs/sweeps.md quotes):

1. the damper FMU's own time on the 15 s HiL record (minor road, 14 m/s, 1 ms): the packaged FMU
   loaded by rust-fmi and fed the velocity and demand the coupled run gave it, nothing else in the
   loop (`cargo bench --bench fmu_replay`), timed as the coupled runs are, whole: from its
   instantiation to fmi2Terminate;
2. the coupled run of the same 15 s: the compiled runner (damper_tools.runner) with the truck's own
   road and with the road fed as a series, the fmpy loop (damper_tools.cosim), and, for the choice
   of master, ecos's execution (step_until, nothing recorded) and libcosim's (simulate_until, seven
   variables observed). 1 and 2 take turns in 6 rounds, each figure the fastest of its rounds;
3. the sweep's throughput: the HiL points of sweeps/hil_200.toml (18 s records and every metric),
   run one after another in this process, through the runner and through the fmpy loop, in runs per
   second per worker; where a point's time goes (its coupled run, its tracking fit, the rest); the
   same points with the truck's RK4 in 1 ms steps (truck.h_max, what it saves and changes); and the
   whole 200-point sweep through each on a LocalCluster of --workers workers.

    .venv/bin/python -m damper_tools.coupled_benchmark            # about 4 minutes on 2 cores
    .venv/bin/python -m damper_tools.coupled_benchmark --quick    # no whole sweep, fewer repeats

Timed here, never asserted in a test: a loaded machine gives other numbers (the output names the
load average before and after).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from damper_tools import (
    DAMPER_FMU,
    REPO,
    TRUCK_FMU,
    cosim,
    doc_figures,
    hil_scenarios,
    roads,
    runner,
    ssp,
    sweep,
    tracking_quality,
)
from damper_tools.fmu import FmuUnit

STEP = 1e-3
DURATION = 15.0
SPEED = 14.0
ROAD = "minor"
SEED = 1
RECORDED = ("a_body", "F_suspension", "v_damper", "F_demand", "x_damper", "F_tyre")
COMMAND = ".venv/bin/python -m damper_tools.coupled_benchmark --docs"
COARSE_H_MAX = 1e-3  # s: the truck's RK4 step for the coarse variant, one per 1 ms communication step


def fastest(f: Callable[[], object], repeat: int) -> float:
    """The least wall time (s) of `repeat` calls."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - start)
    return best


def damper_inputs(record: dict[str, np.ndarray], folder: Path) -> Path:
    """The velocity and demand the coupled run gave the damper, as fmu_replay reads them."""
    n = int(round(DURATION / STEP))
    path = folder / "damper_inputs.csv"
    np.savetxt(path, np.column_stack([record["v_damper"][:n], record["F_demand"][:n]]), delimiter=",",
               header="v_damper,F_demand", comments="", fmt="%.17g")
    return path


def damper_own_time(inputs: Path, damper_fmu: Path, repeat: int) -> float:
    """The damper FMU alone on `inputs` (fmu_replay: a process of its own), the fastest of `repeat` (s)."""
    out = subprocess.run(["cargo", "bench", "-q", "--bench", "fmu_replay", "--", str(damper_fmu), str(inputs),
                          "--set", "tare_load_cell=true", "--repeat", str(repeat)],
                         cwd=REPO, check=True, capture_output=True, text=True).stdout
    return float(json.loads(out.strip().splitlines()[-1])["fastest_s"])


def ecos_time(truck_fmu: Path, damper_fmu: Path, params: dict[str, Any], n: int) -> float:
    """ecos's execution of the coupled system to n steps (step_until; nothing recorded)."""
    from damper_tools import ecos

    models = {ssp.TRUCK: truck_fmu, ssp.DAMPER: damper_fmu}
    variables = ecos._variables(models)
    typed = {**ecos._typed(variables, ssp.TRUCK, params), **ecos._typed(variables, ssp.DAMPER,
                                                                        cosim.HIL_DAMPER_PARAMETERS)}
    with ecos._structure_simulation(models, typed, STEP, False) as sim:
        start = time.perf_counter()
        sim.init(0.0, ecos.PARAMETER_SET)
        sim.step_until(n * STEP)
        sim.terminate()
        return time.perf_counter() - start


def libcosim_time(truck_fmu: Path, damper_fmu: Path, params: dict[str, Any], n: int) -> float:
    """libcosim's execution to n steps with a time-series observer on seven variables."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    ex = CosimExecution.from_step_size(step_size=int(round(STEP * 1e9)))
    index = {name: ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name=name))
             for name, fmu in ((ssp.TRUCK, truck_fmu), (ssp.DAMPER, damper_fmu))}
    vr = {name: {v.name.decode(): v.reference for v in ex.slave_variables(i)} for name, i in index.items()}
    for s_el, s_c, e_el, e_c in runner.COUPLING:
        ex.connect_real_variables(index[s_el], vr[s_el][s_c], index[e_el], vr[e_el][e_c])
    for name, value in params.items():
        kind = type(value)
        set_initial = ex.integer_initial_value if kind is int else ex.real_initial_value
        set_initial(index[ssp.TRUCK], vr[ssp.TRUCK][name], value)
    ex.boolean_initial_value(index[ssp.DAMPER], vr[ssp.DAMPER]["tare_load_cell"], True)
    observer = CosimObserver.create_time_series(buffer_size=n + 10)
    ex.add_observer(observer)
    for name in RECORDED:
        observer.start_time_series(index[ssp.TRUCK], vr[ssp.TRUCK][name], CosimVariableType.REAL)
    observer.start_time_series(index[ssp.DAMPER], vr[ssp.DAMPER]["F_damper"], CosimVariableType.REAL)
    start = time.perf_counter()
    ex.simulate_until(int(round(n * STEP * 1e9)))
    return time.perf_counter() - start


def coupled_times(truck_fmu: Path, damper_fmu: Path, rounds: int) -> dict[str, float]:
    """The 15 s run through every master and the damper's own time on it (s): each the fastest over
    `rounds` rounds, the measures taking turns in every round so that a spell of load on the shared
    machine falls on all of them alike."""
    n = int(round(DURATION / STEP))
    case = roads.road_case(ROAD, SPEED, DURATION, SEED, step=STEP, fade_in=hil_scenarios.FADE_IN)
    own = runner.own_road(ROAD, SPEED, DURATION, SEED, step=STEP, fade_in=hil_scenarios.FADE_IN)
    road = (case.z_road, case.v_road)

    def through_runner(truck: dict[str, Any], fed: tuple[np.ndarray, np.ndarray] | None) -> dict[str, np.ndarray]:
        return runner.run_quarter_truck(truck, STEP, n, road=fed, truck_fmu=truck_fmu, damper_fmu=damper_fmu)

    def through_fmpy() -> dict[str, np.ndarray]:
        return cosim.simulate_one(case.z_road, case.v_road, STEP, n, cosim.MODE_EXTERNAL, {},
                                  cosim.HIL_DAMPER_PARAMETERS, truck_fmu=truck_fmu, damper_fmu=damper_fmu)

    with tempfile.TemporaryDirectory() as tmp:
        inputs = damper_inputs(through_runner({}, road), Path(tmp))
        measures: dict[str, Callable[[], float]] = {
            "damper_own_s": lambda: damper_own_time(inputs, damper_fmu, 3),
            "runner_own_road_s": lambda: fastest(lambda: through_runner(own, None), 3),
            "runner_fed_road_s": lambda: fastest(lambda: through_runner({}, road), 3),
            "fmpy_loop_s": lambda: fastest(through_fmpy, 1),
            "ecos_s": lambda: ecos_time(truck_fmu, damper_fmu, dict(own), n),
            "libcosim_s": lambda: libcosim_time(truck_fmu, damper_fmu, dict(own), n),
        }
        best = dict.fromkeys(measures, float("inf"))
        for _ in range(rounds):
            for name, measure in measures.items():
                best[name] = min(best[name], measure())
    return best


def hil_200_points(truck_fmu: Path, damper_fmu: Path, points: int) -> tuple[sweep.Sweep, dict[str, Path],
                                                                             list[sweep.Task]]:
    """sweeps/hil_200.toml, the FMUs as run_point takes them, and its first `points` tasks."""
    s = sweep.load(REPO / "sweeps" / "hil_200.toml")
    fmus = {"truck": truck_fmu, "damper": damper_fmu}
    return s, fmus, sweep.tasks(s, fmus)[:points]


def sweep_throughput(truck_fmu: Path, damper_fmu: Path, points: int) -> dict[str, float]:
    """Runs per second per worker over the first `points` of hil_200 (every metric), in this process."""
    s, fmus, tasks = hil_200_points(truck_fmu, damper_fmu, points)
    out = {}
    for master in sweep.MASTERS:
        start = time.perf_counter()
        for t in tasks:
            row = sweep.run_point(s.scenario, t.index, t.point_id, t.run_seed, {**t.point, "master": master}, fmus)
            if row["error"]:
                raise RuntimeError(f"hil_200 point {t.index} through {master}: {row['error']}")
        out[f"{master}_runs_per_s"] = len(tasks) / (time.perf_counter() - start)
    return out


def point_costs(truck_fmu: Path, damper_fmu: Path, points: int) -> tuple[dict[str, float], list[dict[str, Any]]]:
    """Where a hil_200 point's time goes through the runner (ms, the mean over the first `points`): the
    whole point (sweep.run_point), its coupled run alone (sweep.hil_run) and its tracking fit alone
    (tracking_quality.fit on that run's record); the rest is the other metrics and the bookkeeping.
    Also the points' rows."""
    s, fmus, tasks = hil_200_points(truck_fmu, damper_fmu, points)
    spent = {"total": 0.0, "run": 0.0, "fit": 0.0}
    rows = []
    for t in tasks:
        start = time.perf_counter()
        rows.append(sweep.run_point(s.scenario, t.index, t.point_id, t.run_seed, t.point, fmus))
        spent["total"] += time.perf_counter() - start
        settings, truck, damper = sweep.split_parameters(s.scenario, t.point, FmuUnit.load(truck_fmu).variables,
                                                         FmuUnit.load(damper_fmu).variables)
        start = time.perf_counter()
        res, window = sweep.hil_run(settings, t.run_seed, truck, {**cosim.HIL_DAMPER_PARAMETERS, **damper},
                                    truck_fmu, damper_fmu)
        spent["run"] += time.perf_counter() - start
        start = time.perf_counter()
        tracking_quality.fit(res["F_demand"][window], res["F_suspension"][window], res["v_damper"][window], STEP)
        spent["fit"] += time.perf_counter() - start
    ms = {f"point_{k}_ms": 1e3 * v / len(tasks) for k, v in spent.items()}
    ms["point_rest_ms"] = ms["point_total_ms"] - ms["point_run_ms"] - ms["point_fit_ms"]
    return ms, rows


def coarse_truck_steps(truck_fmu: Path, damper_fmu: Path, fine: list[dict[str, Any]],
                       h_max: float = COARSE_H_MAX) -> dict[str, float]:
    """The first hil_200 points again, those whose rows `fine` holds (point_costs'), with the truck's
    RK4 in steps of `h_max` (one per communication step) instead of its default 0.25 ms: the mean cost
    of a point (ms), the largest relative change of a metric against `fine`, and on how many points a
    fitted delay or bandwidth changed."""
    s, fmus, tasks = hil_200_points(truck_fmu, damper_fmu, len(fine))
    fitted = [m for m in sweep.HIL_METRICS if m.startswith(("tracking_delay", "tracking_bandwidth"))]
    others = [m for m in sweep.HIL_METRICS if m not in fitted]
    spent, change, fits_changed = 0.0, 0.0, 0
    for t, before in zip(tasks, fine, strict=True):
        start = time.perf_counter()
        coarse = sweep.run_point(s.scenario, t.index, t.point_id, t.run_seed, {**t.point, "truck.h_max": h_max}, fmus)
        spent += time.perf_counter() - start
        fits_changed += any(coarse[m] != before[m] for m in fitted)
        for m in others:
            if before[m] != 0 and np.isfinite(before[m]):
                change = max(change, abs(coarse[m] - before[m]) / abs(before[m]))
    return {"coarse_point_total_ms": 1e3 * spent / len(tasks), "coarse_metric_rel_change_max": change,
            "coarse_points_fit_changed": float(fits_changed), "coarse_points": float(len(tasks))}


def whole_sweep(truck_fmu: Path, damper_fmu: Path, workers: int, master: str) -> dict[str, float]:
    """The 200-point sweep through `master` on a LocalCluster of `workers` single-threaded workers, in
    a fresh folder; the cluster's start is not counted (run_sweep's own wall time)."""
    s = sweep.load(REPO / "sweeps" / "hil_200.toml")
    s.fixed["master"] = master
    with tempfile.TemporaryDirectory() as work, sweep.dask_client(workers=workers) as client:
        outcome = sweep.run_sweep(s, work, {"truck": truck_fmu, "damper": damper_fmu}, client=client)
    if outcome.failed:
        raise RuntimeError(f"{outcome.failed} points of hil_200 failed through {master}")
    return {f"hil_200_{master}_workers_{workers}_s": outcome.wall_s}


def main(argv: list[str] | None = None) -> None:
    if os.environ.get("OPENBLAS_NUM_THREADS") != "1":
        # one BLAS thread, as dask's workers run (their nanny sets it): OpenBLAS's idle threads spin
        # on the other core and slow the runs being timed
        given = sys.argv[1:] if argv is None else argv
        os.execve(sys.executable, [sys.executable, "-m", "damper_tools.coupled_benchmark", *given],
                  {**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--quick", action="store_true", help="fewer repetitions and points, no whole sweep")
    parser.add_argument("--docs", action="store_true", help="write the figures to docs/coupled_benchmark.json")
    args = parser.parse_args(argv)
    load_before = os.getloadavg()[0]
    times = coupled_times(args.truck_fmu, args.damper_fmu, 2 if args.quick else 6)
    own = times.pop("damper_own_s")
    figures: dict[str, float] = {"damper_own_ms": own * 1e3}
    figures.update({k.removesuffix("_s") + "_ms": v * 1e3 for k, v in times.items()})
    figures.update({k.removesuffix("_s") + "_over_damper": v / own for k, v in times.items()})
    # what the truck FMU (its road, made at initialisation, among it) and the loop add to the damper's
    # own run, per communication step
    figures["runner_extra_us_per_step"] = (times["runner_own_road_s"] - own) / round(DURATION / STEP) * 1e6
    figures.update(sweep_throughput(args.truck_fmu, args.damper_fmu, 6 if args.quick else 20))
    figures["sweep_speedup"] = figures["runner_runs_per_s"] / figures["fmpy_runs_per_s"]
    costs, rows = point_costs(args.truck_fmu, args.damper_fmu, 6 if args.quick else 20)
    figures.update(costs)
    figures.update(coarse_truck_steps(args.truck_fmu, args.damper_fmu, rows))
    if not args.quick:
        for master in sweep.MASTERS:
            figures.update(whole_sweep(args.truck_fmu, args.damper_fmu, args.workers, master))
        w = args.workers
        figures["hil_200_speedup"] = figures[f"hil_200_fmpy_workers_{w}_s"] / figures[f"hil_200_runner_workers_{w}_s"]
    figures["load_before"], figures["load_after"] = load_before, os.getloadavg()[0]
    out = REPO / "out" / "benchmark" / "coupled.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
    width = max(map(len, figures))
    for k, v in figures.items():
        print(f"{k:<{width}}  {v:.4g}")
    print(f"coupled_benchmark: wrote {out}")
    if args.docs:
        print(f"coupled_benchmark: wrote {doc_figures.write('coupled_benchmark', figures, COMMAND)}")


if __name__ == "__main__":
    main()
