"""The paper's rig tests as FMU simulations, and the numbers measured on them.

Kitching, Cole and Cebon, "The development of a semi-active truck damper":

* Fig. 4: closed-loop spool steps (spool-position control, force loop open) with the damper
  extending at a constant 150 mm/s; demand steps from 2.5 mm to five positions. The paper
  reports an initial 3 ms delay (power amplifier), then a fast response without significant
  overshoot.
* Fig. 6: force control at a constant 150 mm/s extension, "two consecutive demand steps of
  10 kN" (here 2 -> 12 -> 22 kN); about 25 ms before the force reaches the demand. The paper
  also says compression is slower (about three times the compressed oil volume); the same
  test is run in compression.

Used by damper_tools.paper_tests (plots, table, results.json) and by
tests/python/test_paper_rig.py (bands). Everything here runs the FMU through
fmpy.simulate_fmu, like a user would.
"""

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from fmpy import simulate_fmu
from fmpy.model_description import ModelDescription

from damper_tools import FloatArray, Records

# Communication step = output interval of every rig run [s]. Always passed explicitly: fmpy
# would otherwise derive a coarser one from the default experiment.
OUTPUT_INTERVAL = 5e-4
# Constant damper velocity of both rig tests [m/s].
V_RIG = 0.15

# Fig. 4: spool steps (control_mode = 1).
SPOOL_START = 2.5e-3                      # spool position before the step [m]
SPOOL_DEMANDS = (0.9e-3, 1.1e-3, 1.4e-3, 1.8e-3, 3.5e-3)   # demands after the step [m]
SPOOL_T_STEP = 0.15                       # time of the demand step [s]
SPOOL_T_END = 0.21                        # end of the run [s]
SPOOL_X_DAMPER_START = -0.09              # stroke at t = 0 [m] (mid-stroke is 0)
DEAD_TIME_FRACTION = 0.02                 # "moved": 2 % of the step

# Fig. 6: force steps (control_mode = 0).
FORCE_LEVELS = (2e3, 12e3, 22e3)          # |demand| before, between and after the steps [N]
FORCE_STEP_TIMES = (0.30, 0.45)           # times of the two demand steps [s]
FORCE_T_END = 0.60                        # end of the run [s]
FORCE_X_DAMPER_START = 0.045              # |stroke| at t = 0 [m]; the first step is at mid-stroke

# The paper's values and the bands this reproduction is judged by.
PAPER_DEAD_TIME = 3e-3                    # [s] "initial 3 ms delay ... from the power amplifier"
PAPER_FORCE_DELAY = 25e-3                 # [s] "approximately 25 ms" (extension, 10 kN steps)
PAPER_VOLUME_RATIO = 3.0                  # "approximately three times" the oil volume in compression
DEAD_TIME_BAND = (2.5e-3, 5e-3)           # [s] dead time of every spool step
EXT_T90_BAND = (15e-3, 35e-3)             # [s] t90 of both extension force steps
SPOOL_OVERSHOOT_MAX_PCT = 5.0             # [%] largest spool overshoot: "no significant overshoot"

OUTPUTS = ["F_damper", "x_spool", "i_sol", "p_ext", "p_comp", "p_reservoir", "Q_valve", "x_spool_ref",
           "x_damper", "F_demand_clipped", "F_flow", "delta_mount", "v_damper", "F_demand", "x_spool_demand"]
INPUTS = ("v_damper", "a_damper", "F_demand", "x_spool_demand", "T_oil")
# a_damper 0: the rig's velocity is held over each communication step (it moves in steps only)
DEFAULT_INPUTS = {"v_damper": 0.0, "a_damper": 0.0, "F_demand": 0.0, "x_spool_demand": SPOOL_START, "T_oil": 293.15}


# --------------------------------------------------------------------------- inputs and runs

def input_table(t_end: float, constants: dict[str, float],
                steps: dict[str, tuple[float, list[tuple[float, float]]]] | None = None) -> Records:
    """A structured array for fmpy's `input=`: every input of the FMU in a column, 'time' first.

    constants: {name: value} held over the run; steps: {name: (initial, [(t, value), ...])}.
    fmpy interpolates continuous inputs linearly between rows, so a step at t is written as two
    rows with the same time: the value before, then the value after.
    """
    steps = steps or {}
    values = dict(DEFAULT_INPUTS)
    values.update(constants)
    for name, (initial, _) in steps.items():
        values[name] = initial
    rows = [(0.0, dict(values))]
    events = sorted({t for _, changes in steps.values() for t, _ in changes})
    for t in events:
        if not 0.0 < t < t_end:
            raise ValueError(f"step time {t} outside (0, {t_end})")
        rows.append((t, dict(values)))
        for name, (_, changes) in steps.items():
            for tc, value in changes:
                if tc == t:
                    values[name] = value
        rows.append((t, dict(values)))
    rows.append((t_end, dict(values)))
    dtype = [("time", np.float64)] + [(name, np.float64) for name in INPUTS]
    return np.array([(t,) + tuple(v[name] for name in INPUTS) for t, v in rows], dtype=dtype)


def simulate(fmu: str | Path, start_values: dict[str, float], inputs: Records, stop_time: float,
             output_interval: float = OUTPUT_INTERVAL, output: Sequence[str] = OUTPUTS) -> Records:
    """fmpy.simulate_fmu with the communication step given explicitly."""
    result: Records = simulate_fmu(str(fmu), fmi_type="CoSimulation", start_time=0.0, stop_time=stop_time,
                                   output_interval=output_interval, start_values=dict(start_values),
                                   input=inputs, output=list(output))
    return result


def spool_step_run(fmu: str | Path, x_demand: float, v: float = V_RIG,
                   output_interval: float = OUTPUT_INTERVAL) -> Records:
    """Fig. 4: spool-position control, the demand steps from SPOOL_START to x_demand [m]."""
    start_values = {"control_mode": 1, "x_damper_start": SPOOL_X_DAMPER_START, "x_spool_start": SPOOL_START}
    inputs = input_table(SPOOL_T_END, {"v_damper": v, "F_demand": 0.0},
                         {"x_spool_demand": (SPOOL_START, [(SPOOL_T_STEP, x_demand)])})
    return simulate(fmu, start_values, inputs, SPOOL_T_END, output_interval)


def force_step_run(fmu: str | Path, direction: int, output_interval: float = OUTPUT_INTERVAL) -> Records:
    """Fig. 6: force control at direction*V_RIG with the demand direction*(2 -> 12 -> 22 kN).

    direction = +1: extension; -1: compression (negative force = resisting compression). The
    stroke starts at -direction*FORCE_X_DAMPER_START so that the first step is at mid-stroke.
    """
    if direction not in (1, -1):
        raise ValueError("direction must be +1 or -1")
    f0, f1, f2 = (direction * f for f in FORCE_LEVELS)
    t1, t2 = FORCE_STEP_TIMES
    start_values = {"control_mode": 0, "x_damper_start": -direction * FORCE_X_DAMPER_START}
    inputs = input_table(FORCE_T_END, {"v_damper": direction * V_RIG},
                         {"F_demand": (f0, [(t1, f1), (t2, f2)])})
    return simulate(fmu, start_values, inputs, FORCE_T_END, output_interval)


# --------------------------------------------------------------------------- metrics

def sample_index(t: FloatArray, t0: float) -> int:
    """Index of the output sample at time t0 (the state at t0, before a step at t0 acts)."""
    i = int(np.argmin(np.abs(t - t0)))
    if not math.isclose(t[i], t0, abs_tol=1e-9):
        raise ValueError(f"no output sample at t = {t0}")
    return i


def crossing_time(t: FloatArray, frac: FloatArray, level: float) -> float:
    """First time frac reaches level, interpolated linearly between samples; nan if never."""
    above = np.nonzero(frac >= level)[0]
    if above.size == 0:
        return math.nan
    i = above[0]
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (level - frac[i - 1]) / (frac[i] - frac[i - 1]) * (t[i] - t[i - 1]))


def step_metrics(t: FloatArray, y: FloatArray, t_step: float, y1: float,
                 t_end: float | None = None) -> dict[str, float]:
    """Response of y to a step at t_step towards y1, measured from y's value at t_step.

    Returns seconds after the step: dead (2 % of the step), t10, t50, t90, t100 (first time the
    target is reached), and overshoot_pct (largest excursion beyond y1, % of the step), y0, y1 and
    the last value y_end of the window. Works for down-steps too.
    """
    i0 = sample_index(t, t_step)
    y0 = float(y[i0])
    window = t >= t[i0]
    if t_end is not None:
        window &= t <= t_end + 1e-9
    tt, frac = t[window] - t_step, (y[window] - y0) / (y1 - y0)
    return {
        "y0": y0,
        "y1": float(y1),
        "y_end": float(y[window][-1]),
        "dead": crossing_time(tt, frac, DEAD_TIME_FRACTION),
        "t10": crossing_time(tt, frac, 0.1),
        "t50": crossing_time(tt, frac, 0.5),
        "t90": crossing_time(tt, frac, 0.9),
        "t100": crossing_time(tt, frac, 1.0),
        "overshoot_pct": 100.0 * max(0.0, float(frac.max()) - 1.0),
    }


def spool_step_metrics(result: Records, x_demand: float) -> dict[str, float]:
    """step_metrics of x_spool for a Fig. 4 run, plus the force at the end of the run."""
    m = step_metrics(result["time"], result["x_spool"], SPOOL_T_STEP, x_demand)
    m["F_end"] = float(result["F_damper"][-1])
    m["F_flow_end"] = float(result["F_flow"][-1])
    return m


def force_step_metrics(result: Records, direction: int) -> list[dict[str, float]]:
    """step_metrics of direction*F_damper for both steps of a Fig. 6 run (the first step's
    window ends at the second step)."""
    t, y = result["time"], direction * result["F_damper"]
    t1, t2 = FORCE_STEP_TIMES
    return [step_metrics(t, y, t1, FORCE_LEVELS[1], t_end=t2),
            step_metrics(t, y, t2, FORCE_LEVELS[2])]


def compressed_volume_ratio(model_description: ModelDescription) -> float:
    """(annulus + full-bore volume) / annulus volume at mid-stroke, from the start values."""
    p = {v.name: float(v.start) for v in model_description.modelVariables
         if v.causality == "parameter" and v.type == "Real"}
    a_piston = math.pi * p["D_piston"] ** 2 / 4
    a_rod = math.pi * p["D_rod"] ** 2 / 4
    length = p["L_half_stroke"] + p["L_dead"]
    v_ext = (a_piston - a_rod) * length + p["V_hose"]
    return (v_ext + a_piston * length) / v_ext


# --------------------------------------------------------------------------- all rig tests

def run_rig_tests(fmu: str | Path, output_interval: float = OUTPUT_INTERVAL) -> dict[str, Any]:
    """Runs Fig. 4 (five spool steps) and Fig. 6 (extension and compression).

    Returns {"spool": [(x_demand, result, metrics), ...],
             "force": {"extension": (result, [m1, m2]), "compression": (result, [m1, m2])}}.
    """
    spool = []
    for x_demand in SPOOL_DEMANDS:
        result = spool_step_run(fmu, x_demand, output_interval=output_interval)
        spool.append((x_demand, result, spool_step_metrics(result, x_demand)))
    force = {}
    for name, direction in (("extension", 1), ("compression", -1)):
        result = force_step_run(fmu, direction, output_interval=output_interval)
        force[name] = (result, force_step_metrics(result, direction))
    return {"spool": spool, "force": force}


def in_band(x: float, band: tuple[float, float]) -> bool:
    """lo <= x <= hi (False for nan)."""
    return band[0] <= x <= band[1]


def criteria(rig: dict[str, Any]) -> dict[str, tuple[bool, Any]]:
    """The paper's statements as pass/fail checks on the measured numbers.

    Returns {name: (passed, measured)}: dead_time (every spool step within DEAD_TIME_BAND),
    spool_overshoot (every spool step below SPOOL_OVERSHOOT_MAX_PCT), extension_t90 (both
    extension force steps within EXT_T90_BAND), compression_slower (compression t90 above
    extension t90 for both steps).
    """
    dead = [m["dead"] for _, _, m in rig["spool"]]
    over = [m["overshoot_pct"] for _, _, m in rig["spool"]]
    ext = [m["t90"] for m in rig["force"]["extension"][1]]
    comp = [m["t90"] for m in rig["force"]["compression"][1]]
    return {
        "dead_time": (all(in_band(d, DEAD_TIME_BAND) for d in dead), dead),
        "spool_overshoot": (all(o < SPOOL_OVERSHOOT_MAX_PCT for o in over), over),
        "extension_t90": (all(in_band(t, EXT_T90_BAND) for t in ext), ext),
        # A compression step that never reaches 90 % within its window is slower too.
        "compression_slower": (all(c > e or (math.isnan(c) and not math.isnan(e))
                                   for c, e in zip(comp, ext, strict=True)),
                               [c / e for c, e in zip(comp, ext, strict=True)]),
    }
