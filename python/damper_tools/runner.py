"""Coupled runs at the FMUs' own speed: the fixed-step Jacobi loop of crates/cosim_runner (Rust, over
rust-fmi's importer), called through its C ABI with ctypes. No Python runs per step; the road is the
truck's own (road_source = 1) or a series handed over once.

    from damper_tools import runner
    res = runner.run_quarter_truck(runner.own_road("minor", 14.0, 15.0, seed=3), step=1e-3, n_steps=15000)
    res["damper.F_damper"]                 # N, at the communication points t_k = k h

The calls, their order and the time points are damper_tools.cosim's, so the same road fed as a
series gives cosim.simulate_one's numbers bit for bit (tests/python/test_runner.py); with the truck's
own road the road differs from roads.road_case's by the inverse FFT's rounding (about 1e-15 of its
RMS), and the results by what that rounding grows into (docs/sweeps.md).

The library is target/release/libcosim_runner.so (`cargo build --release -p cosim_runner`;
scripts/main.sh and scripts/test.sh build it), or the file DAMPER_COSIM_RUNNER names (the sweeps'
workers get it that way). A refused call raises cosim.Refused with the FMU's message, as cosim.py does.
"""

import ctypes
import functools
import json
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from damper_tools import DAMPER_FMU, REPO, TRUCK_FMU, FloatArray, cosim, roads, ssp
from damper_tools.fmu import Value

LIBRARY = REPO / "target" / "release" / "libcosim_runner.so"
ENVIRONMENT = "DAMPER_COSIM_RUNNER"
OK, REFUSED, BAD_JOB, INTERNAL = 0, 1, 2, 3
MESSAGE_BYTES = 4096
_DOUBLES = ctypes.POINTER(ctypes.c_double)
# ssp.CONNECTIONS between the two FMUs (the road ones are the system's inputs)
COUPLING = [(s_el, s_c, e_el, e_c) for s_el, s_c, e_el, e_c in ssp.CONNECTIONS if s_el is not None]


def library_path() -> Path:
    """The runner's shared library: $DAMPER_COSIM_RUNNER, else the build in target/release/."""
    named = os.environ.get(ENVIRONMENT)
    return Path(named) if named else LIBRARY


@functools.cache
def _resolve(path: Path) -> Path:
    return path.resolve()


@functools.cache
def _library(path: Path) -> ctypes.CDLL:
    if not path.is_file():
        raise FileNotFoundError(f"{path}: the coupled-run library is not built; run "
                                f"`cargo build --release -p cosim_runner` (or set {ENVIRONMENT})")
    lib = ctypes.CDLL(str(path))
    size, int32, text = ctypes.c_size_t, ctypes.c_int32, ctypes.c_char_p
    signatures = {  # the C functions of crates/cosim_runner/src/c_api.rs, each ending in (message, its capacity)
        "cosim_runner_run": [text, ctypes.POINTER(_DOUBLES), size, size, _DOUBLES, size],
        "cosim_runner_tracking_sse": [_DOUBLES, size, size, _DOUBLES, ctypes.POINTER(size), size, size, int32,
                                      _DOUBLES],
        "cosim_runner_first_order_lags": [_DOUBLES, size, _DOUBLES, size, _DOUBLES],
    }
    for name, arguments in signatures.items():
        f = getattr(lib, name)
        f.argtypes, f.restype = [*arguments, text, size], int32
    return lib


def _call(name: str, *arguments: Any) -> None:
    """Calls the library's function `name` with `arguments` and a message buffer; any status but OK
    raises with the function's message: cosim.Refused for REFUSED (its JSON names the instance, the
    call and the time), ValueError for BAD_JOB, RuntimeError otherwise."""
    message = ctypes.create_string_buffer(MESSAGE_BYTES)
    status = getattr(_library(_resolve(library_path())), name)(*arguments, message, MESSAGE_BYTES)
    if status == OK:
        return
    text = message.value.decode(errors="replace")
    if status == REFUSED:
        why = json.loads(text)
        time = math.nan if why["time"] is None else float(why["time"])
        raise cosim.Refused(why["instance"], time, f"{why['call']}: {why['message']}")
    raise (ValueError if status == BAD_JOB else RuntimeError)(text)


def run(models: Sequence[tuple[str, str | Path, Mapping[str, Value]]], step: float, n_steps: int,
        record: Sequence[tuple[str, str]], connections: Sequence[tuple[str, str, str, str]] = (),
        inputs: Mapping[tuple[str, str], FloatArray] | None = None,
        start_time: float = 0.0) -> FloatArray:
    """Runs the models ((instance, fmu, start values) each) coupled by `connections` (source instance,
    output, sink instance, input) for n_steps steps of `step` s, feeding each `inputs` series (at least
    n_steps samples; sample k before step k). Returns the recorded variables, an array of
    (n_steps + 1) rows (row k at t_k, row 0 after initialisation) and one column per `record` entry."""
    series = {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in (inputs or {}).items()}
    length = min((s.size for s in series.values()), default=0)
    job = {"step": float(step), "n_steps": int(n_steps), "start_time": float(start_time),
           "models": [{"name": name, "fmu": str(_resolve(Path(fmu))), "parameters": _jsonable(params)}
                      for name, fmu, params in models],
           "connections": [list(c) for c in connections], "inputs": [list(k) for k in series],
           "record": [list(r) for r in record]}
    out = np.empty((n_steps + 1, len(record)))
    pointers = (_DOUBLES * max(len(series), 1))(*(s.ctypes.data_as(_DOUBLES) for s in series.values()))
    _call("cosim_runner_run", json.dumps(job).encode(), pointers, len(series), length, out.ctypes.data_as(_DOUBLES),
          out.size)
    return out


def first_order_lags(demand: FloatArray, poles: Sequence[float]) -> FloatArray:
    """The demand through first-order lags, compiled (crates/cosim_runner/src/tracking_fit.rs): row j
    is scipy.signal.lfilter([1 - p], [1, -p], demand, zi=[p * demand[0]])[0] for p = poles[j], bit for
    bit (p = 0: the demand itself)."""
    demand = np.ascontiguousarray(demand, dtype=np.float64)
    p = np.ascontiguousarray(poles, dtype=np.float64)
    out = np.empty((p.size, demand.size))
    _call("cosim_runner_first_order_lags", demand.ctypes.data_as(_DOUBLES), demand.size, p.ctypes.data_as(_DOUBLES),
          p.size, out.ctypes.data_as(_DOUBLES))
    return out


def tracking_sse(lags: FloatArray, force: FloatArray, samples: npt.NDArray[np.intp], n_delays: int,
                 extension: bool) -> FloatArray:
    """The tracking fit's sums of squared errors, compiled (crates/cosim_runner/src/tracking_fit.rs):
    for every row b of `lags` (the demand through bandwidth b's lag) and delay n < n_delays samples,
    Σ over `samples` of (clip(lag_b[i - n]) - force[i])², the lag's first value held before the start;
    clip is max(·, 0) for extension, min(·, 0) for compression. An array of shape (bandwidths, delays)."""
    lags = np.ascontiguousarray(lags, dtype=np.float64)
    force = np.ascontiguousarray(force, dtype=np.float64)
    idx = np.ascontiguousarray(samples, dtype=np.uintp)
    out = np.empty((lags.shape[0], n_delays))
    _call("cosim_runner_tracking_sse", lags.ctypes.data_as(_DOUBLES), lags.shape[0], force.size,
          force.ctypes.data_as(_DOUBLES), idx.ctypes.data_as(ctypes.POINTER(ctypes.c_size_t)), idx.size, int(n_delays),
          int(extension), out.ctypes.data_as(_DOUBLES))
    return out


def _jsonable(params: Mapping[str, Value]) -> dict[str, Any]:
    """Start values as JSON: numpy scalars as Python numbers; a float that is a whole number stays a
    float (the runner types it by the model description)."""
    return {k: (v.item() if isinstance(v, np.generic) else v) for k, v in params.items()}


def own_road(road: str | float, speed: float, duration: float, seed: int, step: float = 1e-3,
             fade_in: float = 1.0) -> dict[str, Value]:
    """The truck parameters that make it generate roads.road_case(road, speed, duration, seed, step,
    fade_in) itself (road_source = 1): the same spectrum, phases, length, fade and time points."""
    gd0 = roads.gd0_of(road)
    n_steps = int(round(duration / step))
    return {"road_source": 1, "road_gd0": gd0, "road_seed": int(seed), "road_speed": float(speed),
            "road_length": speed * n_steps * step + 1.0, "road_dx": roads.DX, "road_n_min": roads.N_MIN,
            "road_n_max": roads.N_MAX, "road_n0": roads.N0, "road_waviness": roads.WAVINESS,
            "road_fade_in": float(fade_in), "road_fade_start": float(step), "road_offset": 0.0}


def run_quarter_truck(truck_parameters: Mapping[str, Value], step: float, n_steps: int,
                      road: tuple[FloatArray, FloatArray] | None = None,
                      damper_parameters: Mapping[str, Value] | None = None,
                      truck_fmu: str | Path = TRUCK_FMU, damper_fmu: str | Path = DAMPER_FMU,
                      damper_outputs: Sequence[str] = ("F_damper",)) -> dict[str, FloatArray]:
    """The quarter truck and, for damper_mode 0, its damper, coupled as ssp.CONNECTIONS says: the
    truck's own road (truck_parameters from own_road) or `road` = (z_road, v_road) fed as series.
    Returns cosim.simulate_one's keys: 'time', the truck's outputs (cosim.TRUCK_OUTPUTS) under their
    names, the damper's as 'damper.<name>', and 'z_road', 'v_road' where the road was fed."""
    external = int(truck_parameters.get("damper_mode", cosim.MODE_EXTERNAL)) == cosim.MODE_EXTERNAL
    models: list[tuple[str, str | Path, Mapping[str, Value]]] = [(ssp.TRUCK, truck_fmu, truck_parameters)]
    record = [(ssp.TRUCK, name) for name in cosim.TRUCK_OUTPUTS]
    if external:
        dp = cosim.HIL_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters
        models.append((ssp.DAMPER, damper_fmu, dp))
        record += [(ssp.DAMPER, name) for name in damper_outputs]
    inputs = None if road is None else {(ssp.TRUCK, "z_road"): road[0], (ssp.TRUCK, "v_road"): road[1]}
    out = run(models, step, n_steps, record, COUPLING if external else (), inputs)
    res: dict[str, FloatArray] = {"time": step * np.arange(n_steps + 1, dtype=float)}
    if road is not None:
        res.update(z_road=np.asarray(road[0][:n_steps + 1], float), v_road=np.asarray(road[1][:n_steps + 1], float))
    for j, (instance, name) in enumerate(record):
        res[name if instance == ssp.TRUCK else f"damper.{name}"] = out[:, j]
    return res


def run_full_truck(wheels: dict[str, tuple[FloatArray, FloatArray]], step: float, n_steps: int,
                   truck_parameters: Mapping[str, Value] | None = None,
                   damper_parameters: Mapping[str, Value] | None = None,
                   full_truck_fmu: str | Path | None = None,
                   damper_fmu: str | Path = DAMPER_FMU) -> dict[str, FloatArray]:
    """The three-axle truck with, for damper_mode 0, a damper instance per corner (its v_damper and
    F_demand from the corner, its F_damper back), each corner's road fed as a series: the calls and
    the result dict of full_truck.simulate (the fmpy loop), bit for bit."""
    from damper_tools import FULL_TRUCK_FMU, full_truck

    tp = dict(truck_parameters or {})
    corners = full_truck.CORNERS
    if set(wheels) != set(corners) or any(min(len(z), len(v)) < n_steps + 1 for z, v in wheels.values()):
        raise ValueError(f"need the road of each of {corners} with {n_steps + 1} samples")
    truck = "full_truck"
    models: list[tuple[str, str | Path, Mapping[str, Value]]] = [(truck, full_truck_fmu or FULL_TRUCK_FMU, tp)]
    truck_out = [f"{c}.{n}" for c in corners for n in full_truck.CORNER_OUTPUTS] + list(full_truck.BODY_OUTPUTS)
    record = [(truck, name) for name in truck_out]
    connections: list[tuple[str, str, str, str]] = []
    if int(tp.get("damper_mode", cosim.MODE_EXTERNAL)) == cosim.MODE_EXTERNAL:
        dp = cosim.HIL_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters
        for c in corners:
            damper = f"{c}.damper"
            models.append((damper, damper_fmu, dp))
            connections += [(truck, f"{c}.v_damper", damper, "v_damper"),
                            (truck, f"{c}.F_demand", damper, "F_demand"),
                            (damper, "F_damper", truck, f"{c}.F_damper")]
            record.append((damper, "F_damper"))
    inputs = {(truck, f"{c}.{name}"): wheels[c][j] for c in corners for j, name in enumerate(("z_road", "v_road"))}
    out = run(models, step, n_steps, record, connections, inputs)
    res: dict[str, FloatArray] = {"time": step * np.arange(n_steps + 1, dtype=float)}
    for c in corners:
        res[f"{c}.z_road"] = np.asarray(wheels[c][0][:n_steps + 1], float)
    for j, (instance, name) in enumerate(record):
        res[name if instance == truck else f"{instance}.{name}"] = out[:, j]
    return res
