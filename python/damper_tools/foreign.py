"""Foreign dampers: synthetic dampers of another kind than the model, for the blind score.

The diagnosis explains a measurement with the semi-active damper's model plus catalog effects. On
a damper of another kind its honest answer is that the model does not fit, never a catalog effect
"explained". Two kinds, both driven by the rig inputs of damper_tools.independent and measured by
the same sensors (continuous 400 Hz load-cell filter, noise, quantisation):

- `mr`: a magnetorheological damper, the Bingham law F = c0 v + F_y(I) tanh(v/v0) with a yield force
  F_y(I) = F_y0 + (F_ymax - F_y0) tanh(I), a first-order current lag (time constant tau_I) towards
  the current that makes the demanded yield force, F_y = |F_demand| - c0 |v_measured| (the demand
  mapped to the yield force, per record sample), and a small gas force. The current's lag is linear
  with a held command, so it is integrated exactly (closed form) at the fine step.
- `passive`: a passive bleed-and-blow-off damper that ignores the demand: a quadratic bleed orifice
  in parallel with a preloaded blow-off valve (opening linearly above its preload), different in
  extension and compression, in series with the oil's and mount's stiffness k, plus an optional gas
  force growing with compression. dF/dt = k (v(t) - v_h(F)), integrated with scipy's LSODA at
  rtol 1e-9 on the continuous velocity.
"""

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.integrate import solve_ivp

from damper_tools import FloatArray, sensors

if TYPE_CHECKING:  # independent imports this module
    from damper_tools.independent import Case, RigInputs

# What a foreign damper gives back: its signals (fine force, record times, measured velocity, demand,
# true velocity, the largest stroke) and a description of the damper for the truth file.
Simulated = tuple[dict[str, Any], str]


def _sample_inputs(case: "Case", rig: "RigInputs", noise_v: FloatArray) -> tuple[
        int, FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    m = sensors.steps_per_sample(case.rate)
    n_samples = int(round(case.duration_s * case.rate)) + 1
    n_fine = (n_samples - 1) * m
    t_fine = sensors.FINE_STEP * np.arange(n_fine + 1, dtype=float)
    v_true = rig.velocity(t_fine)
    t_rec = t_fine[::m]
    v_meas = sensors.quantise(v_true[::m] + noise_v[:n_samples], sensors.SENSORS["v_damper"][1])
    return m, t_fine, v_true, t_rec, v_meas, rig.demand(t_rec, v_meas)


def mr(case: "Case", rig: "RigInputs", noise_v: FloatArray, rng: np.random.Generator) -> Simulated:
    """The MR (Bingham) damper; returns (signals, description)."""
    p = {"c0": rng.uniform(1e3, 3e3), "v0": rng.uniform(0.005, 0.02), "F_y0": rng.uniform(100.0, 400.0),
         "F_ymax": rng.uniform(8e3, 15e3), "tau_I": rng.uniform(0.005, 0.02), "F_gas": rng.uniform(200.0, 600.0)}
    m, t_fine, v_true, t_rec, v_meas, demand = _sample_inputs(case, rig, noise_v)
    span = p["F_ymax"] - p["F_y0"]
    f_y_cmd = np.clip(np.abs(demand) - p["c0"] * np.abs(v_meas) - p["F_y0"], 0.0, 0.97 * span)
    i_cmd = np.repeat(np.arctanh(f_y_cmd / span)[:-1], m)
    decay = math.exp(-sensors.FINE_STEP / p["tau_I"])
    current = np.empty(t_fine.size)
    current[0] = 0.0
    for j in range(t_fine.size - 1):  # exact for a command held over the step
        current[j + 1] = i_cmd[j] + (current[j] - i_cmd[j]) * decay
    f_y = p["F_y0"] + span * np.tanh(current)
    force = p["c0"] * v_true + f_y * np.tanh(v_true / p["v0"]) - p["F_gas"]
    x = np.concatenate([[0.0], np.cumsum(v_true[:-1]) * sensors.FINE_STEP])
    sig = {"t_fine": t_fine, "force_fine": force, "t": t_rec, "v_measured": v_meas, "demand": demand,
           "v_true": v_true[::m], "max_abs_stroke": float(np.max(np.abs(x)))}
    desc = ("foreign MR (Bingham) damper: F = c0 v + F_y(I) tanh(v/v0) - F_gas, F_y(I) = F_y0 + (F_ymax - F_y0) "
            "tanh(I), first-order current lag tau_I to the demanded yield force (closed form); parameters "
            + ", ".join(f"{k}={v:.6g}" for k, v in p.items()))
    return sig, desc


def passive(case: "Case", rig: "RigInputs", noise_v: FloatArray, rng: np.random.Generator) -> Simulated:
    """The passive bleed-and-blow-off damper; returns (signals, description)."""
    p = {"F_bleed_ext": rng.uniform(3e3, 6e3), "comp_ratio": rng.uniform(0.3, 0.6),
         "F_blowoff_ext": rng.uniform(6e3, 12e3), "blowoff_comp_ratio": rng.uniform(0.4, 0.7),
         "k": rng.uniform(1.5e7, 4e7), "gas": bool(rng.uniform() < 0.5),
         "F_gas": rng.uniform(500.0, 1200.0), "k_gas": rng.uniform(3e3, 8e3)}
    v_b = 0.1  # m/s: the bleed gives F_bleed at this velocity
    f_l, w = 50.0, 100.0  # N: the bleed's laminar width, the blow-off's smoothing
    m, t_fine, v_true, t_rec, v_meas, demand = _sample_inputs(case, rig, noise_v)

    def v_hydraulic(f: float) -> float:
        ext = f >= 0
        fb = p["F_bleed_ext"] if ext else p["F_bleed_ext"] * p["comp_ratio"]
        fpre = p["F_blowoff_ext"] if ext else p["F_blowoff_ext"] * p["blowoff_comp_ratio"]
        a = abs(f)
        root = a / math.sqrt(fb * math.sqrt(a * a + f_l * f_l))  # sqrt(|F|/F_b), laminar near 0
        gain = 0.2 / (0.5 * fpre * math.sqrt(1.5 * fpre / fb))  # +0.2 m/s at 1.5x the preload
        opening = w * math.log1p(math.exp(min((a - fpre) / w, 50.0))) if a - fpre < 50 * w else a - fpre
        return math.copysign(v_b * root + gain * opening * root, f)

    def rhs(t: float, y: FloatArray) -> list[float]:
        v = float(rig.velocity(np.array([t]))[0])
        return [p["k"] * (v - v_hydraulic(y[0])), v]

    sol = solve_ivp(rhs, (0.0, t_fine[-1]), [0.0, 0.0], method="LSODA", t_eval=t_fine, rtol=1e-9, atol=[1e-3, 1e-10],
                    max_step=0.002)
    if not sol.success:
        raise RuntimeError(f"passive damper: {sol.message}")
    f_h, x = sol.y
    force = f_h + ((-p["F_gas"] + p["k_gas"] * x) if p["gas"] else 0.0)
    sig = {"t_fine": t_fine, "force_fine": force, "t": t_rec, "v_measured": v_meas, "demand": demand,
           "v_true": v_true[::m], "max_abs_stroke": float(np.max(np.abs(x)))}
    desc = ("foreign passive damper (ignores the demand): quadratic bleed F_bleed (v/0.1 m/s)^2 in parallel with a "
            "preloaded blow-off valve, extension/compression asymmetric, series stiffness k, optional gas force; "
            "scipy LSODA rtol 1e-9; parameters " + ", ".join(f"{k}={v:.6g}" for k, v in p.items()))
    return sig, desc


def simulate(case: "Case", rig: "RigInputs", noise_v: FloatArray, rng: np.random.Generator) -> Simulated:
    """The foreign damper of `case.kind` (foreign_mr or foreign_passive)."""
    return {"foreign_mr": mr, "foreign_passive": passive}[case.kind](case, rig, noise_v, rng)
