"""Sweeps: many co-simulations of one scenario over a grid and/or distributions of parameters, run
serially in this process or as Dask tasks (dask.distributed) on a local or remote cluster.

    .venv/bin/damper-sweep sweeps/hil_200.toml              # LocalCluster, one worker per core
    .venv/bin/damper-sweep sweeps/hil_200.toml --scheduler tcp://host:8786

A sweep is a TOML file (docs/sweeps.md):

    name = "hil_small"
    scenario = "hil"               # hil (quarter truck), full_truck (FullTruck.fmu), rig (Fig. 6 force steps)
    seed = 7                       # the sweep seed: every run's seed derives from it and the point
    metrics = ["a_body_rms", "DLC"]   # optional: the metric columns to keep (default: all)
    [fixed]                        # held over the sweep
    duration = 2.0
    [grid]                         # every combination
    road = ["major", "minor"]
    Cm = [12e3, 24e3]
    [random]                       # Monte-Carlo: `samples` draws, each combined with every grid point
    samples = 16
    air_fraction = { dist = "uniform", low = 0.01, high = 0.04 }

A parameter is a setting of the scenario (SCENARIO_KEYS, e.g. road, speed, duration), or a parameter
of an FMU by its name: bare when only one FMU has it (Cm, alpha, air_fraction, k1_mount, r_port), else
with the prefix `truck.` or `damper.` (h_max is in both).

Determinism. The points are expanded on the client in a fixed order; a Monte-Carlo draw depends only
on the sweep seed, the sample number and the parameter's name; the seed of a run (its road
realisation) is a hash of the sweep seed and the point's values of `seed_from` (default: road and
replicate, so that every damper setting on a road drives over the same realisation). Nothing depends
on the worker or on the order of completion, and the FMUs are deterministic: a sweep gives the same
bits on 1 or N workers and in this process.

Resume. Each finished point is written at once to WORK/points/<point id>.json (the id hashes the
scenario, the point's values, the sweep seed and the FMUs' bytes); a point whose file exists is not
run again. `collect` merges the files into one table (one row per point, every input and metric a
column), written as Parquet by `write_parquet`.

The FMUs are shipped to the workers by a worker plugin (their bytes travel with it), written once to
each worker's local directory, extracted once per worker process (damper_tools.fmu.FmuUnit caches
the extraction). Nothing here prints.
"""

import contextlib
import hashlib
import itertools
import json
import math
import os
import tempfile
import time
import tomllib
import zlib
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np
from distributed.diagnostics.plugin import WorkerPlugin

from damper_tools import (
    FULL_TRUCK_FMU,
    TRUCK_FMU,
    FloatArray,
    cosim,
    full_truck,
    hil_scenarios,
    rig_tests,
    roads,
    runner,
    tracking_quality,
)
from damper_tools.fmu import FmuUnit

SCENARIOS = ("hil", "full_truck", "rig")
# Settings of each scenario and their defaults; everything else in a point is an FMU parameter.
SCENARIO_KEYS: dict[str, dict[str, Any]] = {
    "hil": {"road": "minor", "speed": 14.0, "mode": "fmu", "duration": 15.0, "settle": 3.0, "step": 1e-3,
            "fade_in": hil_scenarios.FADE_IN, "replicate": 0, "master": "runner",
            "tracking_delay": 0.0, "tracking_bandwidth": math.inf, "tracking_direction": "both"},
    "full_truck": {"road": "minor", "speed": 14.0, "mode": "fmu", "duration": 15.0, "settle": 3.0, "step": 1e-3,
                   "correlation": full_truck.TRACK_CORRELATION, "replicate": 0, "master": "runner",
                   "tracking_delay": 0.0, "tracking_bandwidth": math.inf, "tracking_direction": "both"},
    "rig": {"output_interval": rig_tests.OUTPUT_INTERVAL, "replicate": 0},
}
# The truck FMU of each scenario (the rig has none).
TRUCK_FMUS = {"hil": TRUCK_FMU, "full_truck": FULL_TRUCK_FMU, "rig": TRUCK_FMU}
MODES = {"fmu": cosim.MODE_EXTERNAL, "ideal": cosim.MODE_IDEAL, "passive": cosim.MODE_PASSIVE,
         "tracking": cosim.MODE_TRACKING}
TRACKING_DIRECTIONS = ("both", "extension", "compression")
# Who steps a run of the hil and full_truck scenarios: the compiled loop (damper_tools.runner; the
# quarter truck makes its own random road, the rest is fed as series), or the fmpy loop
# (damper_tools.cosim, full_truck.simulate; every road fed from Python), the reference.
MASTERS = ("runner", "fmpy")
# the `road` of the measured Belgian block (data/roads/belgian_block.crg, docs/hil.md); `duration`,
# `settle` and `fade_in` do not apply to it
CRG_ROAD = hil_scenarios.CRG_ROAD
DISTRIBUTIONS = ("uniform", "loguniform", "normal", "choice")
DEFAULT_SEED_FROM = ("road", "replicate")
PLUGIN_NAME = "damper-sweep-fmus"

HIL_METRICS = ("a_body_rms", "a_body_wk_rms", "DLC", "road_stress", "x_damper_rms", "x_damper_peak",
               "F_suspension_rms", "v_damper_max",
               "F_rms", "F_demand_rms", "force_error_rms", "force_mean_error", "extension_bias",
               "extension_above", "compression_bias", "compression_below", "force_peak_hz",
               "force_peak_wheel_hop_hz", "tracking_delay_extension", "tracking_bandwidth_extension",
               "tracking_fit_error_extension", "tracking_delay_compression", "tracking_bandwidth_compression",
               "tracking_fit_error_compression")
FULL_TRUCK_METRICS = ("a_seat_wk_rms", "a_seat_rms", "a_body_rms", "a_pitch_rms", "a_roll_rms", "DLC", "DLC_max",
                      "road_stress", "x_damper_rms", "x_damper_peak", "force_error_rms", "extension_bias",
                      "compression_bias")
RIG_METRICS = ("extension_t90", "extension_t100", "extension_overshoot_pct", "compression_t90",
               "compression_t100", "compression_overshoot_pct", "compression_to_extension_t90")
METRICS = {"hil": HIL_METRICS, "full_truck": FULL_TRUCK_METRICS, "rig": RIG_METRICS}


class SweepError(ValueError):
    """A sweep file that cannot be run, with the reason."""


# --------------------------------------------------------------------------- the description

@dataclass
class Sweep:
    name: str
    scenario: str
    seed: int
    fixed: dict[str, Any] = field(default_factory=dict)
    grid: dict[str, list[Any]] = field(default_factory=dict)
    random: dict[str, dict[str, Any]] = field(default_factory=dict)
    samples: int = 1
    metrics: list[str] | None = None
    seed_from: list[str] | None = None
    plots: dict[str, Any] = field(default_factory=dict)

    @property
    def parameters(self) -> list[str]:
        """The point's parameter names: fixed, grid axes, random, in that order."""
        return list(self.fixed) + [k for k in self.grid if k not in self.fixed] + list(self.random)

    def kept_metrics(self) -> list[str]:
        return list(self.metrics) if self.metrics else list(METRICS[self.scenario])

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "scenario": self.scenario, "seed": self.seed, "fixed": self.fixed,
                "grid": self.grid, "random": {"samples": self.samples, **self.random},
                "metrics": self.metrics, "seed_from": self.seed_from, "plots": self.plots}


def from_dict(d: dict[str, Any], name: str = "sweep") -> Sweep:
    """A Sweep from the parsed TOML (or a dict written in Python), checked."""
    known = {"name", "scenario", "seed", "fixed", "grid", "random", "metrics", "seed_from", "plots"}
    unknown = sorted(set(d) - known)
    if unknown:
        raise SweepError(f"unknown keys {unknown} (known: {sorted(known)})")
    scenario = d.get("scenario")
    if scenario not in SCENARIOS:
        raise SweepError(f"scenario must be one of {SCENARIOS}, not {scenario!r}")
    if not isinstance(d.get("seed"), int):
        raise SweepError("seed: an integer is required (every run's seed derives from it)")
    grid = {k: (list(v) if isinstance(v, list) else [v]) for k, v in dict(d.get("grid", {})).items()}
    for k, v in grid.items():
        if not v:
            raise SweepError(f"grid.{k} is empty")
    random = dict(d.get("random", {}))
    samples = int(random.pop("samples", 1 if not random else 0))
    if random and samples < 1:
        raise SweepError("random: give samples = N (the number of Monte-Carlo draws)")
    for k, dist in random.items():
        if not isinstance(dist, dict) or dist.get("dist") not in DISTRIBUTIONS:
            raise SweepError(f"random.{k}: a table with dist = one of {DISTRIBUTIONS}")
    fixed = dict(d.get("fixed", {}))
    clash = (set(fixed) & set(grid)) | (set(fixed) & set(random)) | (set(grid) & set(random))
    if clash:
        raise SweepError(f"parameters given twice (fixed, grid, random): {sorted(clash)}")
    metrics = d.get("metrics")
    if metrics is not None:
        bad = [m for m in metrics if m not in METRICS[scenario]]
        if bad:
            raise SweepError(f"metrics {bad} are not metrics of {scenario} ({', '.join(METRICS[scenario])})")
    sweep = Sweep(name=str(d.get("name", name)), scenario=scenario, seed=d["seed"], fixed=fixed, grid=grid,
                  random=random, samples=max(samples, 1), metrics=list(metrics) if metrics else None,
                  seed_from=list(d["seed_from"]) if "seed_from" in d else None, plots=dict(d.get("plots", {})))
    for k in sweep.parameters:
        if k in ("point", "point_id", "run_seed", "error", "wall_s") or k in METRICS[scenario]:
            raise SweepError(f"{k!r} is a column of the results, not a parameter name")
    return sweep


def load(path: str | Path) -> Sweep:
    """Reads a sweep file (TOML)."""
    path = Path(path)
    try:
        d = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as e:
        raise SweepError(f"{path}: {e}") from None
    try:
        return from_dict(d, name=path.stem)
    except SweepError as e:
        raise SweepError(f"{path}: {e}") from None


def _stable_int(*parts: Any) -> int:
    """A 63-bit integer from the canonical JSON of `parts` (the same on every machine and process)."""
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"))
    return int.from_bytes(hashlib.sha256(text.encode()).digest()[:8], "little") >> 1


def draw(sweep: Sweep, sample: int) -> dict[str, Any]:
    """The random parameters of Monte-Carlo sample `sample`: each from its own generator, seeded by
    the sweep seed, the sample number and the parameter's name."""
    out = {}
    for name, dist in sweep.random.items():
        rng = np.random.default_rng([sweep.seed, sample, zlib.crc32(name.encode())])
        kind = dist["dist"]
        if kind == "uniform":
            out[name] = float(rng.uniform(dist["low"], dist["high"]))
        elif kind == "loguniform":
            out[name] = float(math.exp(rng.uniform(math.log(dist["low"]), math.log(dist["high"]))))
        elif kind == "normal":
            out[name] = float(rng.normal(dist["mean"], dist["std"]))
        else:
            values = list(dist["values"])
            out[name] = values[int(rng.integers(len(values)))]
    return out


def points(sweep: Sweep) -> list[dict[str, Any]]:
    """Every point of the sweep: the grid's combinations (first axis slowest) times the Monte-Carlo
    samples, each a dict of all parameters (fixed, grid, random) plus 'sample' when random is used."""
    axes = list(sweep.grid)
    out = []
    for combo in itertools.product(*(sweep.grid[a] for a in axes)):
        for s in range(sweep.samples):
            p = dict(sweep.fixed)
            p.update(zip(axes, combo, strict=True))
            if sweep.random:
                p["sample"] = s
                p.update(draw(sweep, s))
            out.append(p)
    return out


def run_seed(sweep: Sweep, point: dict[str, Any]) -> int:
    """The seed of one run (its road realisation), from the sweep seed and the point's values of
    seed_from (all its parameters with seed_from = ["*"])."""
    keys = sweep.seed_from if sweep.seed_from is not None else DEFAULT_SEED_FROM
    if list(keys) == ["*"]:
        keys = sorted(point)
    return _stable_int("run-seed", sweep.seed, {k: point[k] for k in keys if k in point}) % (2 ** 31)


def file_digest(path: str | Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def point_id(sweep: Sweep, point: dict[str, Any], fmu_digests: dict[str, str]) -> str:
    """A name for the point's result: the scenario, its parameters, the seed and the FMUs' bytes."""
    text = json.dumps({"scenario": sweep.scenario, "seed": sweep.seed, "seed_from": sweep.seed_from,
                       "point": point, "fmus": fmu_digests}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:20]


# --------------------------------------------------------------------------- one run

def split_parameters(scenario: str, point: dict[str, Any], truck_vars: Iterable[str],
                     damper_vars: Iterable[str]) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """(settings, truck parameters, damper parameters) of a point (the module docstring's rules)."""
    truck_vars, damper_vars = set(truck_vars), set(damper_vars)
    settings = dict(SCENARIO_KEYS[scenario])
    truck, damper = {}, {}
    for k, v in point.items():
        if k in settings or k == "sample":
            settings[k] = v
        elif k.startswith("truck.") and k[6:] in truck_vars and scenario != "rig":
            truck[k[6:]] = v
        elif k.startswith("damper.") and k[7:] in damper_vars:
            damper[k[7:]] = v
        elif k in truck_vars and k in damper_vars and scenario != "rig":
            raise SweepError(f"{k!r} is a parameter of both FMUs: write truck.{k} or damper.{k}")
        elif k in truck_vars and scenario != "rig":
            truck[k] = v
        elif k in damper_vars:
            damper[k] = v
        else:
            raise SweepError(f"{k!r} is neither a setting of the {scenario} scenario "
                             f"({', '.join(SCENARIO_KEYS[scenario])}) nor a parameter of its FMUs")
    return settings, truck, damper


def _static_load(truck_unit: FmuUnit, truck: dict[str, Any]) -> float:
    def val(name: str) -> float:
        return float(truck.get(name, truck_unit.variables[name].start))

    return (val("m_body") + val("m_axle")) * val("gravity")


def _nan_if(x: float) -> float:
    return float(x) if x is not None else math.nan


def run_hil(point: dict[str, Any], seed: int, truck_fmu: Path, damper_fmu: Path) -> dict[str, float]:
    """One quarter truck on a random road (damper_tools.hil_scenarios' metrics over the record after
    the settling time)."""
    truck_unit, damper_unit = FmuUnit.load(truck_fmu), FmuUnit.load(damper_fmu)
    s, truck, damper = split_parameters("hil", point, truck_unit.variables, damper_unit.variables)
    if s["mode"] not in MODES:
        raise SweepError(f"mode must be one of {tuple(MODES)}, not {s['mode']!r}")
    if s["master"] not in MASTERS:
        raise SweepError(f"master must be one of {MASTERS}, not {s['master']!r}")
    step = float(s["step"])
    dp = {**cosim.HIL_DAMPER_PARAMETERS, **damper}
    if s["mode"] == "tracking":
        truck = {**tracking_parameters(s), **truck}
    res, window = hil_run(s, seed, truck, dp, truck_fmu, damper_fmu)
    out = hil_scenarios.vehicle_metrics(res, window, _static_load(truck_unit, truck))
    if s["mode"] == "fmu":
        force = res["damper.F_damper"][window]
        tr = hil_scenarios.tracking_metrics(force, res["F_demand"][window], res["v_damper"][window])
        f, p = hil_scenarios.force_spectrum(force, step)
        pk = hil_scenarios.spectral_peaks(f, p)
        out.update(F_rms=tr["F_rms"], F_demand_rms=tr["F_demand_rms"], force_error_rms=tr["error_rms"],
                   force_mean_error=tr["mean_error"], extension_bias=tr["extension"]["mean_error"],
                   extension_above=tr["extension"]["fraction_above"],
                   compression_bias=tr["compression"]["mean_error"],
                   compression_below=tr["compression"]["fraction_below"],
                   force_peak_hz=pk["peak_above_3Hz"], force_peak_wheel_hop_hz=pk["peak_wheel_hop_band"])
        # the force on the masses (one communication step after the damper's, Jacobi) against the demand
        fitted = tracking_quality.fit(res["F_demand"][window], res["F_suspension"][window], res["v_damper"][window],
                                      step)
        for direction, tr_fit in fitted.items():
            out[f"tracking_delay_{direction}"] = tr_fit.delay
            out[f"tracking_bandwidth_{direction}"] = tr_fit.bandwidth
            out[f"tracking_fit_error_{direction}"] = tr_fit.fit_error_rms / tr_fit.error_rms
    return {m: float(out.get(m, math.nan)) for m in HIL_METRICS}


def hil_run(s: dict[str, Any], seed: int, truck: dict[str, Any], dp: dict[str, Any], truck_fmu: Path,
             damper_fmu: Path) -> tuple[dict[str, FloatArray], slice]:
    """The coupled HiL run of a point and the window of its metrics. The generated road: the truck's
    own (road_source 1) under the runner, roads.road_case's fed by the fmpy loop. The Belgian block:
    fed by either, the metrics while the wheel is on it."""
    step, speed = float(s["step"]), float(s["speed"])
    tp = {**truck, "damper_mode": MODES[s["mode"]]}
    if s["road"] == CRG_ROAD:
        _, z_road, v_road, first, last, _ = hil_scenarios.crg_road(speed=speed, step=step)
        window, road = slice(first, last + 1), (z_road, v_road)
    else:
        duration = float(s["settle"]) + float(s["duration"])
        window = slice(int(round(float(s["settle"]) / step)), None)
        if s["master"] == "runner":
            own = runner.own_road(s["road"], speed, duration, seed, step=step, fade_in=float(s["fade_in"]))
            n_steps = int(round(duration / step))
            return runner.run_quarter_truck({**own, **tp}, step, n_steps, damper_parameters=dp,
                                            truck_fmu=truck_fmu, damper_fmu=damper_fmu), window
        case = roads.road_case(s["road"], speed, duration, seed, step=step, fade_in=float(s["fade_in"]))
        road = (case.z_road, case.v_road)
    n_steps = road[0].size - 1
    if s["master"] == "runner":
        return runner.run_quarter_truck(tp, step, n_steps, road=road, damper_parameters=dp, truck_fmu=truck_fmu,
                                        damper_fmu=damper_fmu), window
    return cosim.simulate_one(road[0], road[1], step, n_steps, tp["damper_mode"], truck, dp, truck_fmu=truck_fmu,
                              damper_fmu=damper_fmu), window


def tracking_parameters(settings: dict[str, Any]) -> dict[str, float]:
    """QuarterTruck.fmu's tracking-damper parameters from a point's `tracking_delay` (s),
    `tracking_bandwidth` (Hz; inf: no lag) and `tracking_direction` (both, extension or compression:
    the other direction then tracks ideally)."""
    direction = settings["tracking_direction"]
    if direction not in TRACKING_DIRECTIONS:
        raise SweepError(f"tracking_direction must be one of {TRACKING_DIRECTIONS}, not {direction!r}")
    delay, bandwidth = float(settings["tracking_delay"]), float(settings["tracking_bandwidth"])
    if not (delay >= 0 and bandwidth > 0):
        raise SweepError(f"tracking_delay must be >= 0 s and tracking_bandwidth > 0 Hz, not {delay}, {bandwidth}")
    tau = lag_time_constant(bandwidth)
    out = {}
    for side in ("extension", "compression"):
        on = direction in ("both", side)
        out[f"tracking_delay_{side}"] = delay if on else 0.0
        out[f"tracking_time_constant_{side}"] = tau if on else 0.0
    return out


def lag_time_constant(bandwidth: float) -> float:
    """The time constant (s) of a first-order lag of corner `bandwidth` (Hz): 0 for an infinite one,
    the truck's "no lag"."""
    return 0.0 if math.isinf(bandwidth) else 1 / (2 * math.pi * bandwidth)


def run_full_truck(point: dict[str, Any], seed: int, truck_fmu: Path, damper_fmu: Path) -> dict[str, float]:
    """The three-axle truck (FullTruck.fmu, the sweep's truck FMU) with six damper FMUs or a damper
    mode of the truck (damper_tools.full_truck's roads and metrics), after the settling time or, on
    the Belgian block, while a wheel is on it."""
    truck_unit = FmuUnit.load(truck_fmu)
    s, truck, damper = split_parameters("full_truck", point, truck_unit.variables,
                                        FmuUnit.load(damper_fmu).variables)
    if s["mode"] not in MODES:
        raise SweepError(f"mode must be one of {tuple(MODES)}, not {s['mode']!r}")
    step = float(s["step"])
    p = full_truck.parameters(truck_unit, truck)
    case = full_truck.Case(s["road"], float(s["speed"]))
    wheels, n, window = full_truck.case_roads(case, p, float(s["duration"]), float(s["settle"]), step, seed,
                                              float(s["correlation"]))
    if s["mode"] == "tracking":
        truck = {**tracking_parameters(s), **truck}
    if s["master"] not in MASTERS:
        raise SweepError(f"master must be one of {MASTERS}, not {s['master']!r}")
    simulate = runner.run_full_truck if s["master"] == "runner" else full_truck.simulate
    res = simulate(wheels, step, n, {"damper_mode": MODES[s["mode"]], **truck},
                   {**cosim.HIL_DAMPER_PARAMETERS, **damper}, full_truck_fmu=truck_fmu, damper_fmu=damper_fmu)
    out = full_truck.metrics(res, window, full_truck.static_tyre_loads(p))
    if s["mode"] == "fmu":
        tr = [hil_scenarios.tracking_metrics(res[f"{c}.damper.F_damper"][window], res[f"{c}.F_demand"][window],
                                             res[f"{c}.v_damper"][window]) for c in full_truck.CORNERS]
        out.update(force_error_rms=float(np.mean([t["error_rms"] for t in tr])),
                   extension_bias=float(np.nanmean([t["extension"]["mean_error"] for t in tr])),
                   compression_bias=float(np.nanmean([t["compression"]["mean_error"] for t in tr])))
    return out


def run_rig(point: dict[str, Any], seed: int, truck_fmu: Path, damper_fmu: Path) -> dict[str, float]:
    """The paper's Fig. 6 force steps (2 -> 12 kN at 0.15 m/s) in extension and compression with the
    point's damper parameters; times of the first step in seconds. (No randomness: seed unused.)"""
    damper_unit = FmuUnit.load(damper_fmu)
    s, _, damper = split_parameters("rig", point, (), damper_unit.variables)
    out = {}
    for direction, name in ((1, "extension"), (-1, "compression")):
        t1, t2 = rig_tests.FORCE_STEP_TIMES
        levels = [direction * f for f in rig_tests.FORCE_LEVELS]
        start = {"control_mode": 0, "x_damper_start": -direction * rig_tests.FORCE_X_DAMPER_START, **damper}
        inputs = rig_tests.input_table(rig_tests.FORCE_T_END, {"v_damper": direction * rig_tests.V_RIG},
                                       {"F_demand": (levels[0], [(t1, levels[1]), (t2, levels[2])])})
        res = rig_tests.simulate(str(damper_unit.unzipdir), start, inputs, rig_tests.FORCE_T_END,
                                 float(s["output_interval"]))
        m = rig_tests.force_step_metrics(res, direction)[0]
        out.update({f"{name}_t90": _nan_if(m["t90"]), f"{name}_t100": _nan_if(m["t100"]),
                    f"{name}_overshoot_pct": float(m["overshoot_pct"])})
    out["compression_to_extension_t90"] = out["compression_t90"] / out["extension_t90"]
    return out


RUNNERS: dict[str, Callable[[dict[str, Any], int, Path, Path], dict[str, float]]] = {
    "hil": run_hil, "full_truck": run_full_truck, "rig": run_rig}


def run_point(scenario: str, index: int, pid: str, seed: int, point: dict[str, Any],
              fmus: dict[str, Path] | None = None) -> dict[str, Any]:
    """Runs one point and returns its row: point (index), point_id, run_seed, the parameters, every
    metric of the scenario, error ('' when it ran) and wall_s. On a worker, the FMUs come from the
    worker plugin; in this process, from `fmus`."""
    fmus = fmus or worker_fmus()
    start = time.perf_counter()
    row: dict[str, Any] = {"point": index, "point_id": pid, "run_seed": seed, **point}
    try:
        row.update(RUNNERS[scenario](point, seed, Path(fmus["truck"]), Path(fmus["damper"])))
        row["error"] = ""
    except Exception as e:  # a point that fails is a row with its error, the sweep goes on
        row.update({m: math.nan for m in METRICS[scenario]})
        row["error"] = f"{type(e).__name__}: {e}"
    row["wall_s"] = time.perf_counter() - start
    return row


# --------------------------------------------------------------------------- the FMUs on the workers

class ShipFmus(WorkerPlugin):
    """Worker plugin carrying the FMUs' bytes: on every worker (also one started or restarted later)
    it writes them once under the worker's local directory; run_point finds their paths through
    worker_fmus()."""

    name = PLUGIN_NAME

    def __init__(self, fmus: dict[str, Path], library: Path | None = None) -> None:
        self.blobs = {k: Path(p).read_bytes() for k, p in fmus.items()}
        self.names = {k: Path(p).name for k, p in fmus.items()}
        self.paths: dict[str, Path] = {}
        # the compiled coupled run's library (damper_tools.runner), where it is built
        self.library = (library.name, library.read_bytes()) if library is not None and library.is_file() else None

    def setup(self, worker: Any) -> None:
        self.paths = {k: _write_once(Path(worker.local_directory) / "fmus", self.names[k], blob)
                      for k, blob in self.blobs.items()}
        if self.library is not None:
            name, blob = self.library
            os.environ[runner.ENVIRONMENT] = str(_write_once(Path(worker.local_directory) / "lib", name, blob))


def _write_once(folder: Path, name: str, blob: bytes) -> Path:
    """Writes blob to folder/<digest>/<name> unless it is there already (atomically)."""
    path = folder / hashlib.sha256(blob).hexdigest()[:16] / name
    if not path.is_file():
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            f.write(blob)
        os.replace(tmp, path)
    return path


def worker_fmus() -> dict[str, Path]:
    from distributed import get_worker

    return cast(ShipFmus, get_worker().plugins[PLUGIN_NAME]).paths


# --------------------------------------------------------------------------- the sweep

@dataclass
class Task:
    index: int
    point_id: str
    run_seed: int
    point: dict[str, Any]


@dataclass
class Outcome:
    """What run_sweep did: the rows of every point (in point order), how many ran and were skipped."""
    rows: list[dict[str, Any]]
    ran: int
    skipped: int
    failed: int
    wall_s: float


def tasks(sweep: Sweep, fmus: dict[str, Path]) -> list[Task]:
    digests = {k: file_digest(p) for k, p in sorted(fmus.items())}
    return [Task(i, point_id(sweep, p, digests), run_seed(sweep, p), p) for i, p in enumerate(points(sweep))]


def _point_file(work: Path, pid: str) -> Path:
    return work / "points" / f"{pid}.json"


def _save(work: Path, row: dict[str, Any]) -> None:
    path = _point_file(work, row["point_id"])
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(row, allow_nan=True), encoding="utf-8")
    os.replace(tmp, path)


def _finished(work: Path, task: Task) -> dict[str, Any] | None:
    path = _point_file(work, task.point_id)
    if not path.is_file():
        return None
    row: dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
    row["point"] = task.index  # the same point may sit at another index in an edited sweep
    return row


def run_sweep(sweep: Sweep, work: str | Path, fmus: dict[str, Path], client: Any = None,
              on_result: Callable[[dict[str, Any]], object] | None = None, retries: int = 3,
              limit: int | None = None) -> Outcome:
    """Runs every point not finished in `work` (serially in this process when client is None, else
    as Dask tasks on the client's cluster), saving each row as it arrives. on_result(row) is called
    for each row, finished earlier or now. A point whose run raised is a row with `error`; it is not
    saved, so a rerun tries it again. limit: run at most that many new points (for tests)."""
    work = Path(work)
    work.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    all_tasks = tasks(sweep, fmus)
    rows: dict[int, dict[str, Any]] = {}
    todo = []
    for t in all_tasks:
        row = _finished(work, t)
        if row is None:
            todo.append(t)
        else:
            rows[t.index] = row
            if on_result:
                on_result(row)
    skipped = len(rows)
    if limit is not None:
        todo = todo[:limit]

    def accept(row: dict[str, Any]) -> None:
        if not row["error"]:
            _save(work, row)
        rows[row["point"]] = row
        if on_result:
            on_result(row)

    if client is None:
        for t in todo:
            accept(run_point(sweep.scenario, t.index, t.point_id, t.run_seed, t.point, fmus))
    elif todo:
        from distributed import as_completed

        client.register_plugin(ShipFmus(fmus, runner.library_path()), name=PLUGIN_NAME)
        futures = [client.submit(run_point, sweep.scenario, t.index, t.point_id, t.run_seed, t.point,
                                 key=f"sweep-{sweep.name}-{t.point_id}", retries=retries, pure=False)
                   for t in todo]
        for fut in as_completed(futures):
            accept(fut.result())
            fut.release()
    ordered = [rows[i] for i in sorted(rows)]
    return Outcome(ordered, ran=len(todo), skipped=skipped, failed=sum(1 for r in ordered if r["error"]),
                   wall_s=time.perf_counter() - start)


def columns(sweep: Sweep, rows: Sequence[dict[str, Any]]) -> list[str]:
    params = sweep.parameters
    if sweep.random:
        params = [p for p in params if p not in sweep.random] + ["sample"] + list(sweep.random)
    return ["point", "point_id", "run_seed", *params, *sweep.kept_metrics(), "error", "wall_s"]


def table(sweep: Sweep, rows: Sequence[dict[str, Any]]) -> Any:
    """The rows as a pandas DataFrame, one row per point, columns in `columns` order."""
    import pandas as pd

    return pd.DataFrame([{c: r.get(c) for c in columns(sweep, rows)} for r in rows], columns=columns(sweep, rows))


def write_parquet(df: Any, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    df.to_parquet(path, engine="pyarrow", index=False)
    return path


def local_cluster(workers: int | None = None) -> Any:
    """A LocalCluster with one single-threaded worker process per core (or `workers`)."""
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                        dashboard_address=None)


@contextlib.contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None, serial: bool = False) -> Iterator[Any]:
    """The commands' client: None when serial, else a client of the scheduler at `scheduler`, else
    of a new LocalCluster (local_cluster(workers)); closed (with its cluster) on leaving."""
    if serial:
        yield None
        return
    from distributed import Client

    cluster = None if scheduler else local_cluster(workers)
    client = Client(scheduler or cluster)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
