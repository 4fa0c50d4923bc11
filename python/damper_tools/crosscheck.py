"""Python cross-check: the damper's physics in plain Python (numpy + scipy) against the packaged FMU.

    .venv/bin/damper-crosscheck --duration 1.0 --out out/crosscheck/

Both run one input in spool-position control (control_mode 1): a velocity that is a sum of sines,
held over each 1 ms communication step, and a spool demand stepping every 50 ms. The Python model is
docs/physics.md §3-4 written again (src/physics/plant.rs, src/control/spool_loop.rs, amplifier.rs,
the sampling of src/damper.rs) with other numerics: scipy's Radau over each controller sample
interval instead of the FMU's Rosenbrock method. Every parameter is a start value of the FMU's modelDescription.xml. It
prints the wall time per simulated second of each and their force difference, and plots both forces.
Scope: the default effects (friction and leakage off) and an untared load cell; else it refuses.
"""

import argparse
import math
import time
from collections import deque
from collections.abc import Mapping
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from damper_tools import DAMPER_FMU, FloatArray, pyplot
from damper_tools.fmu import FmuUnit, Slave, Value

P_ATM = 101_325.0  # standard atmosphere (Pa): the gauge-pressure reference of src/physics/fluid.rs
# Typical size of each state (p_A, p_B, V_g, x_s, v_s, i, x): the absolute tolerance is rtol times it.
STATE_SCALE = np.array([1e6, 1e6, 1e-4, 1e-3, 0.1, 1.0, 1e-3])
STEP = 1e-3  # communication step (s)
# The input: velocity amplitudes (m/s) and frequencies (Hz) of the sines, spool demand levels (m).
SINES = ((0.30, 2.0), (0.15, 5.0), (0.05, 13.0))
LEVELS = (2.0e-3, 4.0e-3, 1.0e-3, 3.0e-3, 0.5e-3, 3.5e-3, 1.5e-3, 2.5e-3)
LEVEL_TIME = 0.05  # s per demand level
OFF_EFFECTS = ("effect_seal_friction", "effect_piston_leakage", "effect_viscous_friction")


def parameters(unit: FmuUnit, **overrides: float) -> SimpleNamespace:
    """Every parameter's start value from the FMU's modelDescription.xml, then `overrides`."""
    p = unit.parameters() | overrides
    bad = [k for k in OFF_EFFECTS if p[k]] + (["tare_load_cell"] if p["tare_load_cell"] else [])
    if bad or p["control_mode"] != 1:
        raise ValueError(f"the cross-check ports spool-position control (control_mode 1) only, without {bad}")
    return SimpleNamespace(**p)


def smoothstep(u: float) -> float:
    u = min(max(u, 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


class Plant:
    """The continuous plant of docs/physics.md §3: y = [p_A, p_B, V_g, x_s, v_s, i, x]."""

    def __init__(self, p: SimpleNamespace) -> None:
        self.p = p
        self.A_p: float = math.pi / 4 * p.D_piston ** 2
        self.A_r: float = math.pi / 4 * p.D_rod ** 2
        self.A_a: float = self.A_p - self.A_r
        self.V_A0 = self.A_a * (p.L_half_stroke + p.L_dead) + p.V_hose
        self.V_B0 = self.A_p * (p.L_half_stroke + p.L_dead)
        self.air = p.air_fraction if p.effect_compressibility else 0.0
        self.p_crack = p.p_cv_crack if p.effect_check_valve_cracking else 0.0

    def reservoir(self, V_g: float) -> float:  # §3.5 polytropic gas
        p = self.p
        return float((p.p_reservoir0 + P_ATM) * (p.V_gas0 / max(V_g, 1e-9)) ** p.n_polytropic - P_ATM)

    def beta(self, pr: float) -> float:  # §3.2 oil with entrained air
        p, n, p_abs = self.p, self.p.n_polytropic, max(pr + P_ATM, 0.02 * P_ATM)
        r = (P_ATM / p_abs) ** (1.0 / n)
        return float((1.0 + self.air * r) / (1.0 / p.beta_oil + self.air * r / (n * p_abs)))

    def orifice(self, cd: float, area: float, dp: float) -> float:  # §3.3 with its laminar region
        return float(cd * area * math.sqrt(2.0 / self.p.rho) * dp / (dp * dp + self.p.p_transition ** 2) ** 0.25)

    def port_area(self, x_s: float) -> float:  # §3.3 circular ports uncovered by the spool
        r, h = self.p.r_port, x_s - self.p.x_lap
        if h <= 0.0 or h >= 2 * r:
            return float(self.p.n_ports * (0.0 if h <= 0.0 else math.pi * r * r))
        return float(self.p.n_ports * (r * r * math.acos((r - h) / r) - (r - h) * math.sqrt(2 * r * h - h * h)))

    def check_valve(self, dp: float) -> float:  # §3.3
        p = self.p
        area = p.A_cv_leak + p.A_cv_max * smoothstep((dp - self.p_crack) / (p.p_cv_full - self.p_crack))
        return self.orifice(p.Cd_cv, area, dp)

    def deflection(self, F: float) -> float:  # §3.4 the cubic mount inverted in closed form
        k1: float = self.p.k1_mount
        k3: float = self.p.k3_mount
        if not self.p.effect_mount_compliance or k3 == 0.0:
            return F / k1 if self.p.effect_mount_compliance else 0.0
        s = math.sqrt(k1 / k3 / 3.0)
        return -2.0 * s * math.sinh(math.asinh(-1.5 * F / k1 / s) / 3.0)

    def force(self, y: FloatArray) -> float:
        """Load-cell force F_damper (N), tension positive (no friction effect on, not tared)."""
        return float(y[0]) * self.A_a - float(y[1]) * self.A_p

    def rhs(self, t: float, y: FloatArray, v: float, i_cmd: float) -> list[float]:
        p, (A_a, A_p) = self.p, (self.A_a, self.A_p)
        p_A, p_B, V_g, x_s, v_s, i, x = y.tolist()
        p_r, delta = self.reservoir(V_g), self.deflection(p_A * A_a - p_B * A_p)
        V_A, V_B = max(self.V_A0 - A_a * (x - delta), 1e-7), max(self.V_B0 + A_p * (x - delta), 1e-7)
        dp_v, area = p_A - p_r, self.port_area(x_s)
        Q_v = self.orifice(p.Cd_valve, area + p.A_valve_leak, dp_v)
        Q_cv1, Q_cv2 = self.check_valve(p_B - p_A), self.check_valve(p_r - p_B)
        Q_rv = 0.0 if dp_v <= p.p_relief else \
            self.orifice(p.Cd_valve, p.A_relief * smoothstep((dp_v - p.p_relief) / p.dp_relief), dp_v)
        R_A, R_B = Q_cv1 - Q_v - Q_rv, -Q_cv1 + Q_cv2
        a, b = self.beta(p_A) / V_A, self.beta(p_B) / V_B
        K_h, S = a * A_a ** 2 + b * A_p ** 2, a * A_a * R_A - b * A_p * R_B
        delta_rate = (K_h * v + S) / (p.k1_mount + 3 * p.k3_mount * delta ** 2 + K_h) \
            if p.effect_mount_compliance else 0.0
        v_p = v - delta_rate  # piston velocity, the mount's deflection rate taken off
        F_flow = 2 * p.Cd_valve * p.Cv_valve * math.cos(p.theta_jet) * area * max(dp_v, 0.0) \
            if p.effect_flow_forces else 0.0
        stop = p.x_spool_min if x_s < p.x_spool_min else p.x_spool_max if x_s > p.x_spool_max else None
        F_stop = 0.0 if stop is None else p.k_stop * (x_s - stop) + p.c_stop * v_s
        F_sol = p.K_sol * i * (1 + p.kappa_sol * (x_s / p.x_spool_max - 0.5))
        return [a * (A_a * v_p + R_A), b * (-A_p * v_p + R_B), Q_cv2 - Q_v - Q_rv, v_s,
                (F_sol - p.k_spool * x_s - p.c_spool * v_s - F_flow - F_stop) / p.m_spool, (i_cmd - i) / p.tau_coil, v]

    def rest(self) -> tuple[FloatArray, float]:
        """Rest state at x_damper_start, both chambers at the reservoir's pressure, and the coil current
        that holds the spool at x_spool_start (Plant::rest_state, rest_current)."""
        p, x, x_s = self.p, self.p.x_damper_start, self.p.x_spool_start
        V_g = p.V_gas0 + self.A_r * x
        i0 = min(max(p.k_spool * x_s / (p.K_sol * (1 + p.kappa_sol * (x_s / p.x_spool_max - 0.5))), 0.0), p.I_max)
        return np.array([self.reservoir(V_g), self.reservoir(V_g), V_g, x_s, 0.0, i0, x]), i0


class SpoolController:
    """The spool PID with filtered derivative, flow-force compensation, clamp and the amplifier's delay
    line (§4.2, §4.4), sampled every T_sample."""

    def __init__(self, p: SimpleNamespace, plant: Plant, i0: float) -> None:
        self.p, self.plant, self.integral, self.rate = p, plant, i0, 0.0
        self.previous: float | None = None
        self.delay = deque([i0] * (math.floor(p.tau_amp / p.T_sample + 0.5) if p.effect_amplifier_delay else 0))

    def sample(self, F: float, x_s: float, v: float, x_dem: float) -> float:
        """The current command reaching the coil after this sample (A)."""
        p, T, pl = self.p, self.p.T_sample, self.plant
        prev = x_s if self.previous is None else self.previous  # the first sample primes the filter
        a = T / (p.tau_dx + T)
        self.rate, self.previous = (1 - a) * self.rate + a * (x_s - prev) / T, x_s
        Q = pl.A_a * max(v, 0.0) + pl.A_r * max(-v, 0.0)
        dp = {0: 0.0, 1: p.dp_fc_nominal}.get(p.flow_force_compensation, abs(F) / (pl.A_a if v >= 0 else pl.A_r))
        i_fc = p.Cv_compensation * math.cos(p.theta_jet) * math.sqrt(2 * p.rho * dp) * Q / p.K_sol
        error = x_dem - x_s
        integral = self.integral + p.Ki_x * error * T
        others = p.Kp_x * error - p.Kd_x * self.rate + i_fc
        i = others + integral
        # anti-windup by clamping: past a bound the integral moves only as far as puts i on it, and not
        # further out if it is beyond already
        for bound, past in ((p.I_max, i > p.I_max), (0.0, i < 0.0)):
            if past:
                at_bound = bound - others
                integral = min(max(integral, min(self.integral, at_bound)), max(self.integral, at_bound))
        self.integral = integral
        self.delay.append(min(max(i, 0.0), p.I_max))
        return self.delay.popleft()


def make_input(duration: float) -> tuple[FloatArray, FloatArray, FloatArray, float]:
    """Times of the steps' starts, the velocity (m/s) and spool demand (m) held over each step, and the
    start stroke that centres the motion (the sines start at 0, so the stroke is Σ A/ω (1 − cos ωt))."""
    t = np.arange(round(duration / STEP), dtype=float) * STEP
    v = np.zeros(t.size)
    for A, f in SINES:
        v = v + A * np.sin(2 * np.pi * f * t)
    x_dem = np.array(LEVELS)[(t / LEVEL_TIME + 1e-9).astype(int) % len(LEVELS)]
    return t, v, x_dem, float(-sum(A / (2 * np.pi * f) for A, f in SINES))


def run_python(p: SimpleNamespace, v: FloatArray, x_dem: FloatArray, rtol: float) -> tuple[FloatArray, float]:
    """Force at the end of every communication step, and the wall time (s)."""
    plant = Plant(p)
    y, i0 = plant.rest()
    ctrl, T = SpoolController(p, plant, i0), p.T_sample
    per_step = round(STEP / T)
    atol, h = rtol * STATE_SCALE, T
    F = np.empty(len(v))
    start = time.perf_counter()
    for k, (v_k, x_dem_k) in enumerate(zip(v.tolist(), x_dem.tolist(), strict=True)):
        for _ in range(per_step):  # sample at the interval's start, then integrate with the command held
            i_cmd = ctrl.sample(plant.force(y), float(y[3]), v_k, x_dem_k)
            sol = solve_ivp(plant.rhs, (0.0, T), y, method="Radau", rtol=rtol, atol=atol, first_step=h,
                            args=(v_k, i_cmd))
            if not sol.success:
                raise RuntimeError(f"solve_ivp failed at step {k}: {sol.message}")
            y, h = sol.y[:, -1], min(T, max(np.diff(sol.t).max(), 1e-9))
        F[k] = plant.force(y)
    return F, time.perf_counter() - start


def run_fmu(fmu: Path, overrides: Mapping[str, Value], v: FloatArray,
            x_dem: FloatArray) -> tuple[FloatArray, float, float]:
    """Force after every step, the wall time of the whole fmpy loop and of fmi2DoStep alone (s)."""
    slave = Slave(FmuUnit.load(fmu), "crosscheck")
    slave.initialize(0.0, **overrides)
    F, in_step = np.empty(len(v)), 0.0
    start = time.perf_counter()
    for k in range(len(v)):
        slave.set(v_damper=v[k], x_spool_demand=x_dem[k])
        t0 = time.perf_counter()
        slave.fmu.doStep(currentCommunicationPoint=k * STEP, communicationStepSize=STEP)
        in_step += time.perf_counter() - t0
        F[k] = slave.get(["F_damper"])[0]
    total = time.perf_counter() - start
    slave.free()
    return F, total, in_step


def crosscheck(fmu: Path = DAMPER_FMU, duration: float = 1.0, rtol: float = 1e-7,
               fmu_rtol: float | None = None) -> dict[str, Any]:
    """Runs both on the same input; returns the input, both forces and the figures of the table."""
    t, v, x_dem, x0 = make_input(duration)
    overrides = {"control_mode": 1, "x_damper_start": x0} | ({} if fmu_rtol is None else {"rtol": fmu_rtol})
    p = parameters(FmuUnit.load(fmu), **overrides)
    F_py, wall_py = run_python(p, v, x_dem, rtol)
    F_fmu, wall_fmu, wall_step = run_fmu(fmu, overrides, v, x_dem)
    sim, diff = len(t) * STEP, F_fmu - F_py
    r = {"t": t + STEP, "v": v, "x_dem": x_dem, "F_py": F_py, "F_fmu": F_fmu, "simulated": sim, "rtol": rtol,
         "fmu_rtol": p.rtol, "python_s_per_s": wall_py / sim, "fmu_s_per_s": wall_fmu / sim,
         "fmu_dostep_s_per_s": wall_step / sim, "rms_force": float(np.sqrt(np.mean(F_fmu ** 2))),
         "rms_diff": float(np.sqrt(np.mean(diff ** 2))), "max_diff": float(np.abs(diff).max())}
    return r | {"ratio": wall_py / wall_fmu, "rms_diff_percent": 100 * r["rms_diff"] / r["rms_force"]}


def table(r: dict[str, Any]) -> str:
    """The figures as a Markdown table."""
    return f"""| {r['simulated']:g} s simulated | Python (scipy Radau) | FMU (Rosenbrock, through fmpy) |
|---|---|---|
| rtol | {r['rtol']:g} | {r['fmu_rtol']:g} |
| wall time per simulated second | {r['python_s_per_s']:.3g} s | {r['fmu_s_per_s']:.3g} s \
({r['fmu_dostep_s_per_s']:.3g} s in fmi2DoStep) |
| FMU faster by | | {r['ratio']:.0f}x |
| RMS force | {np.sqrt(np.mean(r['F_py'] ** 2)):.1f} N | {r['rms_force']:.1f} N |
| force difference FMU − Python | | RMS {r['rms_diff']:.3g} N ({r['rms_diff_percent']:.2g} % of the RMS force), \
max {r['max_diff']:.3g} N |"""


def plot(path: Path, r: dict[str, Any]) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(3, 1, sharex=True, figsize=(10, 8), height_ratios=(1, 2, 1))
    ax[0].plot(r["t"], r["v"], "k", lw=0.8, label="v_damper (m/s)")
    ax[0].plot(r["t"], r["x_dem"] * 1e2, "tab:green", lw=0.8, label="x_spool_demand (cm)")
    ax[0].set_title("Input: velocity held over each 1 ms step, spool demand (control_mode 1)")
    ax[1].plot(r["t"], r["F_fmu"] / 1e3, "tab:blue", lw=1.6, label=f"FMU (Rosenbrock, rtol {r['fmu_rtol']:g})")
    ax[1].plot(r["t"], r["F_py"] / 1e3, "tab:orange", lw=0.8, ls="--", label=f"Python (Radau, rtol {r['rtol']:g})")
    ax[1].set_ylabel("F_damper (kN), tension +")
    ax[2].plot(r["t"], r["F_fmu"] - r["F_py"], "tab:red", lw=0.8)
    ax[2].set(ylabel="FMU − Python (N)", xlabel="time (s)")
    for a in ax:
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmu", type=Path, default=DAMPER_FMU, help="the damper FMU (default: %(default)s)")
    parser.add_argument("--duration", type=float, default=1.0, help="simulated time (s) (default: %(default)s)")
    parser.add_argument("--out", type=Path, default=Path("out/crosscheck"), help="output folder (default: %(default)s)")
    parser.add_argument("--rtol", type=float, default=1e-7, help="rtol of scipy's Radau (default: %(default)s)")
    parser.add_argument("--fmu-rtol", type=float, default=None, help="the FMU's rtol (default: its start value)")
    args = parser.parse_args()
    r = crosscheck(args.fmu, args.duration, args.rtol, args.fmu_rtol)
    print(table(r))
    args.out.mkdir(parents=True, exist_ok=True)
    plot(args.out / "crosscheck.png", r)
    print(f"\nwrote {args.out / 'crosscheck.png'}")


if __name__ == "__main__":
    main()
