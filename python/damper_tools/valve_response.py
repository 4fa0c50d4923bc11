"""The valve's and the force loop's frequency responses, the valve's flow map and the damper's
force-velocity map, measured on the packaged FMU.

Kitching, Cole and Cebon validated their valve model "against measured step responses and transfer
functions (solenoid current to spool position)" and their orifice model with "measurements of
pressure drop, flow rate and spool position"; they give no number for either. This module measures
the same quantities on the FMU, as a rig would:

* Valve transfer functions (control_mode = 1, the spool-position loop alone): the input
  `x_spool_demand` is a periodic multisine about a mean opening, at a small and a large (near the
  stops and the current limit) amplitude, with the damper extending at V_VALVE (0.15 m/s, the
  velocity of the paper's Fig. 4 valve test: flow forces act and are compensated). Two transfer
  functions come from the same run: spool demand -> spool position (the closed inner loop) and
  solenoid current -> spool position (the valve's own dynamics, seen inside the closed loop: with
  no noise in a simulation the H1 estimate of a plant inside a loop is unbiased).
* The force loop (control_mode = 0): `F_demand` a multisine about a mean force at a constant
  velocity, extension and compression (the demand has the velocity's sign: the other is clipped).
* Flow map: constant velocities at fixed spool demands (control_mode = 1); the steady valve flow
  `Q_valve` against the valve's pressure drop `p_ext - p_reservoir`, with the sharp-edged orifice law
  Q = C_d A(x) sqrt(2 dp / rho) of the start values in modelDescription.xml drawn over it; the same
  runs give the steady load-cell force against velocity (the catalogue force-velocity map).

Estimator: the multisine is periodic; REALIZATIONS runs with different random phases are made, the
first TRANSIENT_PERIODS periods of each are discarded and the cross- and auto-spectra are averaged
over the remaining periods of all runs (Welch, rectangular window, one period per segment: no
leakage at the excited lines). H1 is then the best linear approximation at this amplitude, and the
coherence falls below 1 where the nonlinear distortions (which change with the phases) are large.
H1 = S_uy / S_uu, coherence |S_uy|^2 / (S_uu S_yy), both at the excited lines only. From H:
    -3 dB bandwidth   first frequency where |H| / |H(f_lowest line)| falls below 1/sqrt(2)
                      (interpolated linearly in log f between lines); nan if not within the lines
    -90 deg frequency first frequency where the unwrapped phase reaches -90 deg (interpolated)
    equivalent delay  -d(phase)/d(omega) at low frequency: least-squares slope through the origin of
                      the phase over the lines with a phase lag of at most DELAY_FIT_MAX_DEG
                      (for a lag 1/(1 + s tau) and a pure delay T it is about tau + T)
Sampling: inputs are held over each communication step (the FMU does not interpolate) and outputs
are read at the communication points; u[k] is the input over [t_k, t_k + h], y[k] the output at t_k.
The zero-order hold adds h/2 to every delay measured against the input (0.25 ms at h = 0.5 ms).

Computing functions here print nothing; `main` (damper-valve-response) plots
and tabulates. SI units throughout (m, s, N, Pa, m3/s, A).
"""

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from damper_tools import DAMPER_FMU, FloatArray, jsonable, pyplot
from damper_tools.fmu import FmuUnit, Slave

# Bin numbers (multiples of 1/period) and a frequency response's complex values.
IntArray = npt.NDArray[np.int_]
ComplexArray = npt.NDArray[np.complex128]

# ----------------------------------------------------------------------------- parameters
STEP = 5e-4              # s, communication step = the controller's sample time T_sample [A]
PERIOD = 0.25            # s, multisine period: line spacing 4 Hz [A] (stroke limits the record)
TRANSIENT_PERIODS = 1    # periods discarded before averaging (the valve settles in ~20 ms) [A]
F_MIN, F_MAX = 4.0, 400.0   # Hz, band of the excited lines (f_max < Nyquist 1 kHz / 2.5) [A]
N_LINES = 32             # excited lines, log-spaced bins of 1/PERIOD within [F_MIN, F_MAX] [A]
DELAY_FIT_MAX_DEG = 30.0  # deg, largest phase lag of the lines used for the delay slope [A]
SEED = 14                # random phases of the first multisine realization (crest factor not optimised)
REALIZATIONS = 3         # multisine realizations (random phases SEED, SEED + 1, ...) per case [A]

# Valve (control_mode = 1)
V_VALVE = 0.15           # m/s, extension: the paper's Fig. 4 valve test velocity [P]
X_DAMPER_START = -0.095  # m: 1.25 s at 0.15 m/s ends at +0.0925 m, inside the 100 mm half stroke
VALVE_PERIODS = 4        # averaged periods (after the transient) [A]
SPOOL_MEANS = (1.0e-3, 2.5e-3, 3.5e-3)    # m, mean spool positions of the 4.5 mm stroke [A]
SPOOL_SMALL = 0.1e-3     # m, small-signal peak amplitude [A]
SPOOL_MARGIN_LO, SPOOL_MARGIN_HI = 0.2e-3, 4.4e-3   # m: large amplitude = up to 0.2 mm / 4.4 mm [A]

# Force loop (control_mode = 0)
FORCE_VELOCITIES = (0.05, 0.15, 0.25)   # m/s, magnitudes; each run in extension and compression [A]
FORCE_MEAN = 6e3         # N, |mean demand| (mid-range of the minor-road MSD forces) [A]
FORCE_AMPLITUDES = (1e3, 3e3)   # N, peak amplitudes: small, large (the demand keeps its sign) [A]
FORCE_PERIODS = 2        # averaged periods; 0.75 s at 0.25 m/s = 0.19 m of stroke [A]
FORCE_SETTLE = 0.25      # s, constant mean demand before the multisine starts [A]
FORCE_F_MAX = 100.0      # Hz, top line of the force-loop multisine (its bandwidth is tens of Hz) [A]
FORCE_X_START = 0.094    # m, |stroke| at t = 0 (starts at the far end, moves through mid-stroke)

# Flow map (control_mode = 1, constant velocities)
FLOW_SPOOL = (0.8e-3, 1.2e-3, 1.8e-3, 2.8e-3, 4.2e-3)   # m, spool demands [A]
FLOW_VELOCITIES = (0.01, 0.02, 0.05, 0.1, 0.15, 0.25, 0.4, 0.6, 0.8, 1.0)   # m/s magnitudes [A]
FLOW_T_RUN = 0.6         # s per point at most: compression at a small opening settles with ~50 ms [A]
FLOW_STROKE = 0.18       # m of stroke per point at most (from the stroke end; 0.18 s at 1 m/s) [A]
FLOW_T_AVG = 0.02        # s, steady values: the mean over the last 20 ms [A]
FLOW_DP_MAX = 15e6       # Pa, points above are dropped (the relief valve cracks at 20 MPa) [A]
TURBULENT_DP = 2e5       # Pa, drop above which the orifice law is turbulent (>> p_transition 5 kPa)

VALVE_OUTPUTS = ("x_spool", "i_sol", "x_spool_ref", "F_damper", "Q_valve", "p_ext", "p_reservoir", "F_flow",
                 "x_damper")
FORCE_OUTPUTS = ("F_damper", "F_demand_clipped", "x_spool", "x_spool_ref", "x_damper")


# ----------------------------------------------------------------------------- estimator

def multisine_lines(period: float = PERIOD, f_min: float = F_MIN, f_max: float = F_MAX,
                    n_lines: int = N_LINES) -> IntArray:
    """Integer bin numbers (multiples of 1/period) of about n_lines log-spaced lines in [f_min, f_max]."""
    df = 1.0 / period
    bins: IntArray = np.unique(np.round(np.geomspace(f_min / df, f_max / df, n_lines)).astype(int))
    return bins[bins >= 1]


def multisine(step: float, period: float = PERIOD, bins: IntArray | None = None,
              seed: int = SEED) -> FloatArray:
    """One period (round(period/step) samples) of a unit-peak multisine with equal amplitudes at the
    bins (random phases, then scaled so that max |u| = 1)."""
    n = int(round(period / step))
    bins = multisine_lines(period) if bins is None else bins
    rng = np.random.default_rng(seed)
    phases = rng.uniform(0, 2 * np.pi, bins.size)
    k = np.arange(n)
    u = np.sum(np.cos(2 * np.pi * np.outer(bins, k) / n + phases[:, None]), axis=0)
    unit_peak: FloatArray = u / np.max(np.abs(u))
    return unit_peak


@dataclass
class Frf:
    """A frequency response at the excited lines: f (Hz), H (complex), coherence (-)."""
    f: FloatArray
    H: ComplexArray
    coherence: FloatArray

    @property
    def magnitude(self) -> FloatArray:
        return np.abs(self.H)

    @property
    def phase_deg(self) -> FloatArray:
        """Unwrapped phase (deg), starting within (-180, 180] at the lowest line."""
        return np.degrees(np.unwrap(np.angle(self.H)))


def estimate_frf(u: FloatArray, y: FloatArray, step: float, period: float, bins: IntArray,
                 skip_periods: int = TRANSIENT_PERIODS) -> Frf:
    """H1 = S_uy / S_uu and the coherence at the excited bins, averaged over the whole periods of
    u and y after skip_periods (rectangular window, one period per segment)."""
    return pooled_frf([(u, y)], step, period, bins, skip_periods)


def pooled_frf(records: Sequence[tuple[FloatArray, FloatArray]], step: float, period: float, bins: IntArray,
               skip_periods: int = TRANSIENT_PERIODS) -> Frf:
    """H1 and coherence from the periods of several records (u, y), each after its own skip_periods.

    Records of multisines with different random phases (realizations) give the best linear
    approximation of a nonlinear system, and a coherence below 1 where its nonlinear distortions
    (which change with the phases) are large; the periods of one realization repeat exactly in a
    simulation, so their coherence shows only what is not periodic (drift)."""
    n = int(round(period / step))
    us, ys = [], []
    for u, y in records:
        u, y = np.asarray(u, float), np.asarray(y, float)
        m = (min(u.size, y.size) // n) - skip_periods
        if m < 1:
            raise ValueError(f"need more than {skip_periods} periods of {n} samples (got {u.size})")
        seg = slice(skip_periods * n, (skip_periods + m) * n)
        us.append(np.fft.rfft((u[seg] - u[seg].mean()).reshape(m, n), axis=1)[:, bins])
        ys.append(np.fft.rfft((y[seg] - y[seg].mean()).reshape(m, n), axis=1)[:, bins])
    U, Y = np.concatenate(us), np.concatenate(ys)
    suu = np.mean(np.abs(U) ** 2, axis=0)
    syy = np.mean(np.abs(Y) ** 2, axis=0)
    suy = np.mean(np.conj(U) * Y, axis=0)
    coh = np.abs(suy) ** 2 / (suu * syy) if U.shape[0] > 1 else np.ones(bins.size)
    return Frf(f=bins / period, H=suy / suu, coherence=np.minimum(coh, 1.0))


def _crossing(f: FloatArray, values: FloatArray, level: float, log_f: bool = True) -> float:
    """First frequency where values falls to or below level (values[0] above it), interpolated
    linearly (in log f if log_f); nan if it never does."""
    below = np.nonzero(values <= level)[0]
    if below.size == 0 or below[0] == 0:
        return math.nan
    i = below[0]
    x0, x1 = (np.log(f[i - 1]), np.log(f[i])) if log_f else (f[i - 1], f[i])
    x = x0 + (level - values[i - 1]) / (values[i] - values[i - 1]) * (x1 - x0)
    return float(np.exp(x) if log_f else x)


def bode_metrics(frf: Frf, reference_gain: float | None = None,
                 delay_fit_max_deg: float = DELAY_FIT_MAX_DEG) -> dict[str, float]:
    """Low-frequency gain, -3 dB bandwidth, -90 deg frequency and equivalent delay (module docstring).

    reference_gain: the gain the -3 dB level refers to; None: the lowest line's (a plant of unknown
    static gain); 1 for a loop with integral action (its static gain is 1). With fewer than two lines
    within delay_fit_max_deg the delay is the lowest line's phase delay -phase/omega
    (delay_fit_lines = 1)."""
    mag, ph = frf.magnitude, frf.phase_deg
    gain0 = float(mag[0])
    ref = gain0 if reference_gain is None else reference_gain
    f3 = _crossing(frf.f, mag / ref, 1 / math.sqrt(2))
    f90 = _crossing(frf.f, ph, -90.0)
    over = np.nonzero(ph < -delay_fit_max_deg)[0]
    low = np.arange(over[0] if over.size else ph.size)   # the lines before the lag first exceeds the limit
    w = 2 * np.pi * frf.f[low]
    if low.size < 2:
        low = np.array([0])
        w = 2 * np.pi * frf.f[low]
    delay = float(-np.sum(w * np.radians(ph[low])) / np.sum(w * w))
    return {"gain_low": gain0, "f_low": float(frf.f[0]), "reference_gain": ref, "f_3dB": f3, "f_90deg": f90,
            "delay": delay, "delay_fit_lines": int(low.size), "peak_gain_ratio": float(mag.max() / ref),
            "coherence_min": float(frf.coherence.min())}


# ----------------------------------------------------------------------------- FMU runs

def _run(unit: FmuUnit, start_values: dict[str, Any], inputs: Callable[[int], dict[str, float]], n_steps: int,
         outputs: Sequence[str], step: float = STEP) -> dict[str, FloatArray]:
    """Steps one damper instance n_steps times with inputs(k) over step k; returns the outputs at
    t_0 .. t_{n-1} (before each step: y[k] pairs with the input held over [t_k, t_k + h]) and the
    inputs, as arrays."""
    slave = Slave(unit, "valve_response")
    try:
        slave.initialize(0.0, n_steps * step, **start_values)
        ys = np.empty((n_steps, len(outputs)))
        us: dict[str, list[float]] = {}
        for k in range(n_steps):
            ys[k] = slave.get(outputs)
            values = inputs(k)
            for name, value in values.items():
                us.setdefault(name, []).append(value)
            slave.step(step, k * step, **values)
        if slave.errors():
            raise RuntimeError(f"FMU errors: {slave.errors()[:3]}")
    finally:
        slave.free()
    res = {name: ys[:, i] for i, name in enumerate(outputs)}
    res.update({name: np.array(v) for name, v in us.items()})
    res["time"] = step * np.arange(n_steps, dtype=float)
    return res


@dataclass
class ValveCase:
    """One valve multisine run: mean and peak amplitude of the spool demand (m), damper velocity (m/s)."""
    mean: float
    amplitude: float
    velocity: float = V_VALVE
    label: str = ""
    result: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    closed_loop: Frf | None = None     # x_spool_demand -> x_spool
    valve: Frf | None = None           # i_sol -> x_spool
    # each FRF's bode_metrics, and the range [min, max] of i_sol and x_spool
    metrics: dict[str, Any] = field(default_factory=dict)


def large_amplitude(mean: float) -> float:
    """Peak amplitude that takes the demand to SPOOL_MARGIN_LO or SPOOL_MARGIN_HI, whichever is nearer."""
    return min(mean - SPOOL_MARGIN_LO, SPOOL_MARGIN_HI - mean)


def valve_run(unit: FmuUnit, mean: float, amplitude: float, velocity: float = V_VALVE, step: float = STEP,
              period: float = PERIOD, periods: int = VALVE_PERIODS, seed: int = SEED,
              realizations: int = REALIZATIONS) -> ValveCase:
    """Spool-position control (control_mode = 1), x_spool_demand = mean + amplitude * multisine,
    at a constant damper velocity, one run per multisine realization; both transfer functions and
    their metrics (`result`: the first realization's run)."""
    bins = multisine_lines(period)
    x_start = X_DAMPER_START if velocity >= 0 else -X_DAMPER_START
    runs = []
    for r in range(realizations):
        shape = multisine(step, period, bins, seed + r)
        n_per = shape.size
        def inputs(k: int, shape: FloatArray = shape, n_per: int = n_per) -> dict[str, float]:
            return {"v_damper": velocity, "x_spool_demand": mean + amplitude * shape[k % n_per]}

        runs.append(_run(unit, {"control_mode": 1, "x_damper_start": x_start, "x_spool_start": mean},
                         inputs, (TRANSIENT_PERIODS + periods) * n_per, VALVE_OUTPUTS, step))
    case = ValveCase(mean, amplitude, velocity, result=runs[0])
    case.closed_loop = pooled_frf([(r["x_spool_demand"], r["x_spool"]) for r in runs], step, period, bins)
    case.valve = pooled_frf([(r["i_sol"], r["x_spool"]) for r in runs], step, period, bins)
    case.metrics = {"closed_loop": bode_metrics(case.closed_loop, 1.0), "valve": bode_metrics(case.valve),
                    **{f"{name}_range": [float(min(r[name].min() for r in runs)),
                                         float(max(r[name].max() for r in runs))] for name in ("i_sol", "x_spool")}}
    return case


def valve_cases(unit: FmuUnit, means: Sequence[float] = SPOOL_MEANS, velocity: float = V_VALVE) -> list[ValveCase]:
    """Small and large amplitude about every mean, plus a small-amplitude run at rest (v = 0: no flow,
    no flow force) about the middle mean."""
    cases = []
    for mean in means:
        for name, amp in (("small", SPOOL_SMALL), ("large", large_amplitude(mean))):
            c = valve_run(unit, mean, amp, velocity)
            c.label = f"{1e3 * mean:.1f} mm ± {1e3 * amp:.2f} mm ({name}), v {velocity:g} m/s"
            cases.append(c)
    mid = means[len(means) // 2]
    c = valve_run(unit, mid, SPOOL_SMALL, 0.0)
    c.label = f"{1e3 * mid:.1f} mm ± {1e3 * SPOOL_SMALL:.2f} mm (small), v 0 (no flow)"
    cases.append(c)
    return cases


@dataclass
class ForceCase:
    """One force-loop multisine run: signed velocity (m/s), |mean| and peak amplitude of the demand (N)."""
    velocity: float
    mean: float
    amplitude: float
    force_controller: int = 0
    result: dict[str, FloatArray] = field(default_factory=dict, repr=False)
    frf: Frf | None = None
    metrics: dict[str, float] = field(default_factory=dict)

    @property
    def direction(self) -> str:
        return "extension" if self.velocity > 0 else "compression"


def force_run(unit: FmuUnit, velocity: float, mean: float = FORCE_MEAN, amplitude: float = FORCE_AMPLITUDES[-1],
              force_controller: int = 0, step: float = STEP, period: float = PERIOD,
              periods: int = FORCE_PERIODS, seed: int = SEED, realizations: int = REALIZATIONS) -> ForceCase:
    """Force control (control_mode = 0, raw load cell as on the paper's rig) at a constant velocity;
    F_demand = sign(v) (mean + amplitude * multisine) after FORCE_SETTLE s at the mean, one run per
    multisine realization; F_demand -> F_damper. The settling part counts as the transient: the
    estimator skips it. `result`: the first realization's run."""
    if velocity == 0 or amplitude >= mean:
        raise ValueError("need a nonzero velocity and amplitude < mean (the demand must keep the velocity's sign)")
    s = 1.0 if velocity > 0 else -1.0
    bins = multisine_lines(period, F_MIN, FORCE_F_MAX, N_LINES // 2)
    n_per = int(round(period / step))
    n_settle = int(round(FORCE_SETTLE / step))
    n = n_settle + periods * n_per
    start = {"control_mode": 0, "x_damper_start": -s * FORCE_X_START, "tare_load_cell": False,
             "force_controller": force_controller}
    # The same run at the constant mean demand: the gas force and the chamber volumes change with
    # the stroke, a slow drift that is not periodic; it is subtracted before the estimate.
    base = _run(unit, start, lambda k: {"v_damper": velocity, "F_demand": s * mean}, n, ("F_damper",), step)
    runs = []
    for r in range(realizations):
        shape = multisine(step, period, bins, seed + r)

        def inputs(k: int, shape: FloatArray = shape) -> dict[str, float]:
            x = 0.0 if k < n_settle else shape[(k - n_settle) % n_per]
            return {"v_damper": velocity, "F_demand": s * (mean + amplitude * x)}

        res = _run(unit, start, inputs, n, FORCE_OUTPUTS, step)
        res["F_damper_baseline"] = base["F_damper"]
        runs.append(res)
    case = ForceCase(velocity, mean, amplitude, force_controller, result=runs[0])
    # the estimator's segments start after the settling part
    case.frf = pooled_frf([(r["F_demand"][n_settle:], (r["F_damper"] - base["F_damper"])[n_settle:]) for r in runs],
                          step, period, bins, skip_periods=0)
    case.metrics = bode_metrics(case.frf, 1.0)
    return case


def force_cases(unit: FmuUnit, velocities: Sequence[float] = FORCE_VELOCITIES,
                amplitudes: Sequence[float] = FORCE_AMPLITUDES, force_controller: int = 0) -> list[ForceCase]:
    return [force_run(unit, s * v, FORCE_MEAN, a, force_controller)
            for v in velocities for s in (1.0, -1.0) for a in amplitudes]


# ----------------------------------------------------------------------------- flow map

def port_area(x_spool: FloatArray | float, p: dict[str, float]) -> FloatArray:
    """Open area (m^2) of n_ports circular ports of radius r_port uncovered by the spool edge at
    x_spool (opening h = x_spool - x_lap): n [r^2 acos((r-h)/r) - (r-h) sqrt(2rh - h^2)] (0 below,
    n pi r^2 above 2r), plus the closed valve's leakage area (docs/physics.md §3.3)."""
    r, n = p["r_port"], p["n_ports"]
    h = np.clip(np.asarray(x_spool, float) - p["x_lap"], 0.0, 2 * r)
    seg = r * r * np.arccos((r - h) / r) - (r - h) * np.sqrt(np.maximum(2 * r * h - h * h, 0.0))
    return n * seg + p["A_valve_leak"]


def orifice_flow(x_spool: FloatArray | float, dp: FloatArray | float, p: dict[str, float]) -> FloatArray:
    """Sharp-edged orifice law (turbulent) Q = C_d A(x) sqrt(2 dp / rho), m^3/s."""
    flow: FloatArray = p["Cd_valve"] * port_area(x_spool, p) * np.sqrt(
        2 * np.maximum(np.asarray(dp, float), 0.0) / p["rho"])
    return flow


def flow_point(unit: FmuUnit, x_spool: float, velocity: float, t_run: float = FLOW_T_RUN,
               step: float = STEP) -> dict[str, float]:
    """One steady point: spool demand x_spool (control_mode = 1) at a constant damper velocity for
    t_run s or FLOW_STROKE of stroke, whichever is shorter; means over the last FLOW_T_AVG s of the
    valve flow, valve pressure drop, spool position, load-cell force."""
    n = int(round(min(t_run, FLOW_STROKE / abs(velocity)) / step))
    x0 = X_DAMPER_START if velocity > 0 else -X_DAMPER_START
    res = _run(unit, {"control_mode": 1, "x_damper_start": x0, "x_spool_start": x_spool},
               lambda k: {"v_damper": velocity, "x_spool_demand": x_spool}, n, VALVE_OUTPUTS, step)
    last = slice(n - int(round(FLOW_T_AVG / step)), None)
    dp = res["p_ext"][last] - res["p_reservoir"][last]
    return {"x_spool_demand": x_spool, "velocity": velocity, "Q_valve": float(res["Q_valve"][last].mean()),
            "dp": float(dp.mean()), "x_spool": float(res["x_spool"][last].mean()),
            "F_damper": float(res["F_damper"][last].mean()),
            # steadiness: the spread of the force over the averaging window relative to its mean
            "F_spread": float(np.ptp(res["F_damper"][last])), "p_ext": float(res["p_ext"][last].mean())}


def flow_map(unit: FmuUnit, spools: Sequence[float] = FLOW_SPOOL,
             velocities: Sequence[float] = FLOW_VELOCITIES) -> list[dict[str, float]]:
    """flow_point for every spool demand and velocity, extension (+) and compression (-); for each
    spool and direction the velocities stop at the first point whose drop exceeds FLOW_DP_MAX."""
    points = []
    for x in spools:
        for s in (1.0, -1.0):
            for v in velocities:
                pt = flow_point(unit, x, s * v)
                if pt["dp"] > FLOW_DP_MAX:
                    break
                points.append(pt)
    return points


def orifice_law_deviation(points: Sequence[dict[str, float]], p: dict[str, float],
                          dp_min: float = TURBULENT_DP) -> FloatArray:
    """Relative deviation Q_valve / (C_d A(x_spool) sqrt(2 dp / rho)) - 1 of the points with a drop
    above dp_min (turbulent), the area at the measured spool position."""
    pts = [q for q in points if q["dp"] > dp_min]
    q = np.array([pt["Q_valve"] for pt in pts])
    law = orifice_flow(np.array([pt["x_spool"] for pt in pts]), np.array([pt["dp"] for pt in pts]), p)
    return q / law - 1.0


def load(fmu: str | Path) -> FmuUnit:
    return FmuUnit.load(fmu)


# ----------------------------------------------------------------------------- report (plots, tables)

def _bode(axes: Any, frf: Frf, label: str, scale: float = 1.0, **style: Any) -> None:
    a0, a1 = axes
    a0.loglog(frf.f, scale * frf.magnitude, marker="o", ms=2.5, lw=1, label=label, **style)
    a1.semilogx(frf.f, frf.phase_deg, marker="o", ms=2.5, lw=1, **style)


def plt_close(fig: Any) -> None:
    pyplot().close(fig)


def plot_valve_bode(path: Path, cases: Sequence[ValveCase]) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(2, 2, figsize=(12, 7.5), sharex=True)
    for i, c in enumerate(cases):
        style = {"color": f"C{i}", "ls": "--" if "large" in c.label else "-"}
        m = c.metrics
        assert c.valve is not None and c.closed_loop is not None  # set by valve_run
        _bode(axes[:, 0], c.valve, f"{c.label}: −3 dB {m['valve']['f_3dB']:.0f} Hz, −90° "
              f"{m['valve']['f_90deg']:.0f} Hz", 1e3, **style)
        _bode(axes[:, 1], c.closed_loop, f"{c.label}: −3 dB {m['closed_loop']['f_3dB']:.0f} Hz, "
              f"delay {1e3 * m['closed_loop']['delay']:.1f} ms", 1.0, **style)
    axes[0, 0].set_title("solenoid current i_sol → spool position x_spool (inside the loop)", fontsize=9)
    axes[0, 1].set_title("spool demand → spool position (closed inner loop, control_mode = 1)", fontsize=9)
    axes[0, 1].axhline(1 / math.sqrt(2), color="0.4", lw=0.7, ls=":")
    axes[0, 0].set_ylabel("|x_spool / i_sol| (mm/A)")
    axes[0, 1].set_ylabel("|x_spool / x_demand| (–)")
    for a in axes[1]:
        a.axhline(-90, color="0.4", lw=0.7, ls=":")
        a.set_ylabel("phase (deg)")
        a.set_xlabel("frequency (Hz)")
    for a in axes.flat:
        a.grid(alpha=0.3, which="both")
    axes[0, 0].legend(fontsize=6.5, loc="lower left")
    axes[0, 1].legend(fontsize=6.5, loc="lower left")
    axes[1, 1].set_ylim(-720, 10)
    fig.suptitle("Valve transfer functions, multisine about three mean openings, small (solid) and large (dashed) "
                 f"amplitude; damper extending at {V_VALVE} m/s unless marked", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_force_bode(path: Path, cases: Sequence[ForceCase]) -> None:
    plt = pyplot()
    fig, axes = plt.subplots(2, 1, figsize=(8.5, 7.5), sharex=True)
    big = [c for c in cases if c.amplitude == max(x.amplitude for x in cases)]
    speeds = sorted({abs(c.velocity) for c in big})
    for c in big:
        i = speeds.index(abs(c.velocity))
        style = {"color": f"C{i}", "ls": "-" if c.velocity > 0 else "--"}
        m = c.metrics
        assert c.frf is not None  # set by force_run
        _bode(axes, c.frf, f"{c.direction} {abs(c.velocity):g} m/s: −3 dB {m['f_3dB']:.0f} Hz, −90° "
              f"{m['f_90deg']:.0f} Hz", 1.0, **style)
    axes[0].axhline(1 / math.sqrt(2), color="0.4", lw=0.7, ls=":")
    axes[0].set_ylabel("|F_damper / F_demand| (–)")
    axes[1].axhline(-90, color="0.4", lw=0.7, ls=":")
    axes[1].set_ylabel("phase (deg)")
    axes[1].set_xlabel("frequency (Hz)")
    axes[1].set_ylim(-400, 10)
    for a in axes:
        a.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Force loop (control_mode = 0, feedforward + PI): demand {FORCE_MEAN / 1e3:g} ± "
                 f"{max(FORCE_AMPLITUDES) / 1e3:g} kN multisine at constant velocities\n"
                 "solid: extension, dashed: compression", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_flow_map(path: Path, points: Sequence[dict[str, float]], p: dict[str, float]) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    spools = sorted({q["x_spool_demand"] for q in points})
    dp = np.geomspace(1e3, 2e7, 200)
    for i, x in enumerate(spools):
        ext = [q for q in points if q["x_spool_demand"] == x and q["velocity"] > 0]
        com = [q for q in points if q["x_spool_demand"] == x and q["velocity"] < 0]
        ax.loglog(dp / 1e5, 1e3 * orifice_flow(x, dp, p) * 60, color=f"C{i}", lw=1,
                  label=f"orifice law, x = {1e3 * x:.1f} mm (A = {1e6 * port_area(x, p):.1f} mm²)")
        ax.loglog([q["dp"] / 1e5 for q in ext], [1e3 * 60 * q["Q_valve"] for q in ext], "o", color=f"C{i}", ms=5)
        ax.loglog([q["dp"] / 1e5 for q in com], [1e3 * 60 * q["Q_valve"] for q in com], "x", color=f"C{i}", ms=6)
    ax.plot([], [], "ko", ms=5, label="FMU, steady, extension")
    ax.plot([], [], "kx", ms=6, label="FMU, steady, compression")
    ax.axvline(p["p_transition"] / 1e5, color="0.5", ls=":", lw=0.8, label="p_transition (laminar below)")
    ax.set_xlabel("valve pressure drop p_ext − p_reservoir (bar)")
    ax.set_ylabel("valve flow Q_valve (l/min)")
    ax.set_xlim(5e-3, 200)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper left")
    ax.set_title(f"Valve flow map: steady points at constant velocity and fixed spool demand, against\n"
                 f"Q = C_d A(x) sqrt(2 Δp / ρ) (C_d {p['Cd_valve']:g}, ρ {p['rho']:g} kg/m³, "
                 f"{p['n_ports']:g} ports r {1e3 * p['r_port']:g} mm, lap {1e3 * p['x_lap']:g} mm)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_force_velocity(path: Path, points: Sequence[dict[str, float]]) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    spools = sorted({q["x_spool_demand"] for q in points})
    for i, x in enumerate(spools):
        pts = sorted((q for q in points if q["x_spool_demand"] == x), key=lambda q: q["velocity"])
        ax.plot([q["velocity"] for q in pts], [q["F_damper"] / 1e3 for q in pts], "o-", color=f"C{i}", ms=4,
                label=f"spool {1e3 * x:.1f} mm")
    ax.axhline(0, color="k", lw=0.6)
    ax.axvline(0, color="k", lw=0.6)
    ax.set_xlabel("damper velocity (m/s), extension +")
    ax.set_ylabel("load-cell force F_damper (kN), tension +")
    ax.set_title("Force–velocity map at fixed spool positions (control_mode = 1, steady values, raw load cell:\n"
                 "includes the reservoir gas force ≈ −1 kN; points above 150 bar valve drop left out)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _ms(x: float) -> str:
    return "n/a" if math.isnan(x) else f"{1e3 * x:.1f}"


def _hz(x: float) -> str:
    return "> lines" if math.isnan(x) else f"{x:.0f}"


def valve_table(cases: Sequence[ValveCase]) -> str:
    rows = ["| run | i_sol range (A) | i → x: gain at 4 Hz (mm/A) | i → x: −3 dB (Hz) | i → x: −90° (Hz) | "
            "i → x: delay (ms) | closed loop: −3 dB (Hz) | closed loop: −90° (Hz) | closed loop: delay (ms) | "
            "min coherence |", "|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        v, cl = c.metrics["valve"], c.metrics["closed_loop"]
        lo, hi = c.metrics["i_sol_range"]
        rows.append(f"| {c.label} | {lo:.2f}–{hi:.2f} | {1e3 * v['gain_low']:.2f} | {_hz(v['f_3dB'])} | "
                    f"{_hz(v['f_90deg'])} | {_ms(v['delay'])} | {_hz(cl['f_3dB'])} | {_hz(cl['f_90deg'])} | "
                    f"{_ms(cl['delay'])} | {min(v['coherence_min'], cl['coherence_min']):.3f} |")
    return "\n".join(rows)


def force_table(cases: Sequence[ForceCase]) -> str:
    rows = ["| direction | velocity (m/s) | demand (kN) | gain at 4 Hz | −3 dB (Hz) | −90° (Hz) | "
            "delay (ms; phase at 4 Hz if 1 line) | min coherence |", "|---|---|---|---|---|---|---|---|"]
    for c in cases:
        m = c.metrics
        rows.append(f"| {c.direction} | {c.velocity:+g} | {c.mean / 1e3:g} ± {c.amplitude / 1e3:g} | "
                    f"{m['gain_low']:.2f} | {_hz(m['f_3dB'])} | {_hz(m['f_90deg'])} | {_ms(m['delay'])} "
                    f"({m['delay_fit_lines']} line{'s' if m['delay_fit_lines'] != 1 else ''}) | "
                    f"{m['coherence_min']:.2f} |")
    return "\n".join(rows)


def flow_summary(points: Sequence[dict[str, float]], p: dict[str, float]) -> dict[str, float]:
    dev = orifice_law_deviation(points, p)
    return {"points": len(points), "turbulent_points": int(dev.size), "max_abs_deviation": float(np.abs(dev).max()),
            "dp_min_turbulent": TURBULENT_DP}


def headline(vcases: Sequence[ValveCase], fcases: Sequence[ForceCase], points: Sequence[dict[str, float]],
             fs: dict[str, float]) -> dict[str, float]:
    """The figures the documents quote (docs/valve_response.json): the valve table per run
    (valve_<mean in 0.1 mm>_<small|large|rest>_...), its ranges at the small (1 mm) and the mid and
    large openings, the closed loop's ranges, the force-loop table per velocity at the large amplitude
    (force_<|v| in cm/s>_<ext|comp>_...), the flow map's; frequencies in Hz, delays in ms."""
    out: dict[str, float] = {}
    tags = {}
    for c in vcases:
        kind = "rest" if c.velocity == 0 else ("small" if c.amplitude == SPOOL_SMALL else "large")
        tags[f"{round(1e4 * c.mean)}_{kind}"] = c
    for tag, vc in tags.items():
        v, cl = vc.metrics["valve"], vc.metrics["closed_loop"]
        out |= {f"valve_{tag}_gain_mm_a": 1e3 * v["gain_low"], f"valve_{tag}_f3db_hz": v["f_3dB"],
                f"valve_{tag}_f90_hz": v["f_90deg"], f"valve_{tag}_delay_ms": 1e3 * v["delay"],
                f"valve_{tag}_loop_f3db_hz": cl["f_3dB"], f"valve_{tag}_loop_f90_hz": cl["f_90deg"],
                f"valve_{tag}_loop_delay_ms": 1e3 * cl["delay"]}

    def span(name: str, values: Sequence[float]) -> None:
        out[f"{name}_min"], out[f"{name}_max"] = min(values), max(values)

    small = [c for c in vcases if c.mean == min(SPOOL_MEANS)]
    mid = [c for c in vcases if c.mean > min(SPOOL_MEANS)]
    for name, sel in (("small", small), ("mid", mid)):
        span(f"valve_{name}_gain_mm_a", [1e3 * c.metrics["valve"]["gain_low"] for c in sel])
        span(f"valve_{name}_f3db_hz", [c.metrics["valve"]["f_3dB"] for c in sel])
        span(f"valve_{name}_f90_hz", [c.metrics["valve"]["f_90deg"] for c in sel])
    span("valve_mid_delay_ms", [1e3 * c.metrics["valve"]["delay"] for c in mid])
    span("loop_f3db_hz", [c.metrics["closed_loop"]["f_3dB"] for c in vcases])
    span("loop_f90_hz", [c.metrics["closed_loop"]["f_90deg"] for c in vcases])
    span("loop_delay_ms", [1e3 * c.metrics["closed_loop"]["delay"] for c in vcases])
    out["loop_gain_max"] = max(c.metrics["closed_loop"]["peak_gain_ratio"] for c in vcases)
    span("i_sol_large_a", [x for c in vcases if c.amplitude > SPOOL_SMALL for x in c.metrics["i_sol_range"]])
    coherence = {tag: min(vc.metrics["valve"]["coherence_min"], vc.metrics["closed_loop"]["coherence_min"])
                 for tag, vc in tags.items()}
    out["valve_coherence_mid_min"] = min(v for tag, v in coherence.items() if not tag.startswith("10_"))
    out["valve_coherence_10_small"], out["valve_coherence_10_large"] = coherence["10_small"], coherence["10_large"]

    large = [fc for fc in fcases if fc.amplitude == max(FORCE_AMPLITUDES)]
    for fc in large:
        tag = f"force_{round(100 * abs(fc.velocity)):03d}_{'ext' if fc.velocity > 0 else 'comp'}"
        out[f"{tag}_f3db_hz"], out[f"{tag}_f90_hz"] = fc.metrics["f_3dB"], fc.metrics["f_90deg"]
    pairs = [(a, b) for a in fcases for b in fcases if a.velocity == b.velocity and a.amplitude < b.amplitude]
    out["force_amplitude_max_diff_hz"] = max(abs(a.metrics[k] - b.metrics[k]) for a, b in pairs
                                             for k in ("f_3dB", "f_90deg"))
    fast = [c for c in fcases if abs(c.velocity) > min(FORCE_VELOCITIES)]
    span("force_gain_low", [c.metrics["gain_low"] for c in fcases])
    span("force_fast_peak_8_40hz", [float(c.frf.magnitude[(c.frf.f >= 8) & (c.frf.f <= 40)].max())
                                    for c in fast if c.frf is not None])
    slowest = next(c for c in large if c.velocity == -min(FORCE_VELOCITIES))
    out["force_coherence_005_comp_large"] = slowest.metrics["coherence_min"]
    span("force_coherence", [c.metrics["coherence_min"] for c in fcases if c is not slowest])

    out["flow_turbulent_points"] = fs["turbulent_points"]
    out["flow_max_dev_pct"] = 100 * fs["max_abs_deviation"]
    widest = [q for q in points
              if q["x_spool_demand"] == max(FLOW_SPOOL) and abs(q["velocity"]) == max(FLOW_VELOCITIES)]
    span("flow_spool_at_widest_fastest_mm", [1e3 * q["x_spool"] for q in widest])
    out["force_velocity_smallest_01_kn"] = next(q["F_damper"] for q in points if q["x_spool_demand"] == min(FLOW_SPOOL)
                                                 and q["velocity"] == 0.1) / 1e3
    return out


def main(argv: list[str] | None = None) -> None:
    import argparse
    import json
    import shutil
    import time

    from damper_tools import REPO

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--out", type=Path, default=REPO / "out" / "valve")
    parser.add_argument("--docs", action="store_true", help="write the headline figures to docs/valve_response.json "
                        "and copy the plots to docs/figures/")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    args.out.mkdir(parents=True, exist_ok=True)
    unit = load(args.fmu)
    p = unit.parameters()
    vcases = valve_cases(unit)
    fcases = force_cases(unit)
    points = flow_map(unit)
    plot_valve_bode(args.out / "valve_bode.png", vcases)
    plot_force_bode(args.out / "force_loop_bode.png", fcases)
    plot_flow_map(args.out / "flow_map.png", points, p)
    plot_force_velocity(args.out / "force_velocity.png", points)
    fs = flow_summary(points, p)
    text = "\n\n".join([
        "# Valve and force-loop frequency responses, valve flow map (SemiActiveDamper.fmu)",
        f"Multisine: {len(multisine_lines())} log-spaced lines {F_MIN:g}–{F_MAX:g} Hz (force loop up to "
        f"{FORCE_F_MAX:g} Hz), period {PERIOD:g} s, H1 and coherence pooled over {REALIZATIONS} realizations "
        f"(random phases), whole periods after the first of each; communication step "
        f"{1e3 * STEP:g} ms. Delay: phase slope over the lines with at most {DELAY_FIT_MAX_DEG:g}° lag.",
        "## Valve (control_mode = 1)", valve_table(vcases),
        "## Force loop (control_mode = 0, raw load cell, feedforward + PI)", force_table(fcases),
        f"## Flow map\n\n{fs['points']} steady points; the {fs['turbulent_points']} with a drop above "
        f"{fs['dp_min_turbulent'] / 1e5:g} bar lie on the orifice law (at the measured spool position) within "
        f"{100 * fs['max_abs_deviation']:.3f} %.",
    ]) + "\n"
    (args.out / "table.md").write_text(text, encoding="utf-8")

    results = {"valve": [{"label": c.label, "mean": c.mean, "amplitude": c.amplitude, "velocity": c.velocity,
                          **c.metrics} for c in vcases],
               "force_loop": [{"velocity": c.velocity, "mean": c.mean, "amplitude": c.amplitude, **c.metrics}
                              for c in fcases],
               "flow_map": points, "flow_summary": fs, "wall_time_s": time.perf_counter() - t0}
    (args.out / "results.json").write_text(json.dumps(jsonable(results), indent=1), encoding="utf-8")
    if args.docs:
        from damper_tools import doc_figures

        doc_figures.write("valve_response", headline(vcases, fcases, points, fs),
                          ".venv/bin/damper-valve-response --docs")
        for name in ("valve_bode.png", "force_loop_bode.png", "flow_map.png", "force_velocity.png"):
            shutil.copy(args.out / name, REPO / "docs" / "figures" / name)
    print(text)
    print(f"valve_response: wrote {args.out} in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
