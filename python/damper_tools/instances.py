"""Many damper instances in one master: six quarter trucks, each with its own damper FMU instance.

    .venv/bin/python -m damper_tools.instances [--road minor --speed 14 --duration 5 --step 1e-3] [--out out/instances]

The six corners of a three-axle truck as six independent quarter trucks (Table 1 each; no pitch or
roll coupling through the body: damper_tools.full_truck runs the truck with its body,
FullTruck.fmu), front, first and second drive axle, left and right, to show that damper instances
in one master do not interact. The roads are damper_tools.full_truck's: correlated left and right
tracks, each axle on the front axle's tracks later.

The script then shows that the instances are independent (each pair of the six-pair run equals, bit
for bit, the same pair run alone in its own master) and times 1, 2, 4, 6 and 8 pairs to show that
the cost grows linearly with the number of instances (pairs 7 and 8 reuse the roads of 1 and 2).
Writes out/instances/instances.png and results.json; with --docs the timings the documents quote to
docs/instances.json (damper_tools.doc_figures).
"""

import argparse
import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np

from damper_tools import DAMPER_FMU, REPO, TRUCK_FMU, FloatArray, cosim, full_truck, pyplot
from damper_tools.fmu import Value

OUT = REPO / "out" / "instances"
# m behind the front axle: FullTruck.fmu's defaults (this demo runs quarter trucks, not that FMU)
AXLE_X = {"front": 0.0, "drive1": 3.8, "drive2": 5.15}
SCALING_PAIRS = (1, 2, 4, 6, 8)


def wheel_roads(road: str, speed: float, duration: float, seed: int, step: float,
                correlation: float = full_truck.TRACK_CORRELATION) -> tuple[full_truck.Wheels, int]:
    """{corner: (z_road, v_road)} sampled at t_k = k step, k = 0..n (damper_tools.full_truck)."""
    return full_truck.random_wheel_roads(road, speed, duration, seed, step, AXLE_X, correlation)


def quarter_truck_cars(wheels: full_truck.Wheels,
                       damper_parameters: dict[str, Value] | None = None) -> list[cosim.Car]:
    dp = dict(cosim.HIL_DAMPER_PARAMETERS) if damper_parameters is None else damper_parameters
    return [cosim.Car(corner, zr, vr, {"damper_mode": cosim.MODE_EXTERNAL}, dict(dp))
            for corner, (zr, vr) in wheels.items()]


def independence(cars: list[cosim.Car], step: float, n_steps: int,
                 **kw: Any) -> tuple[list[dict[str, FloatArray]], dict[str, bool]]:
    """Runs all cars in one master, then each alone; returns {car: bit-identical?}."""
    together = cosim.simulate(cars, step, n_steps, **kw)
    same = {}
    for car, res in zip(cars, together, strict=True):
        alone = cosim.simulate([car], step, n_steps, **kw)[0]
        same[car.name] = all(np.array_equal(res[k], alone[k]) for k in res)
    return together, same


def scaling(cars: list[cosim.Car], step: float, n_steps: int, pairs: tuple[int, ...] = SCALING_PAIRS, repeat: int = 3,
            **kw: Any) -> tuple[list[dict[str, float]], float, float]:
    """Wall time (best of `repeat`, after one warm-up run) of N damper+truck pairs; cars are reused
    cyclically."""
    cosim.simulate(cars[:1], step, n_steps, **kw)
    rows = []
    for n in pairs:
        subset = [cars[i % len(cars)] for i in range(n)]
        subset = [cosim.Car(f"{c.name}_{i}", c.z_road, c.v_road, c.truck_parameters, c.damper_parameters)
                  for i, c in enumerate(subset)]
        best = math.inf
        for _ in range(repeat):
            t0 = time.perf_counter()
            cosim.simulate(subset, step, n_steps, **kw)
            best = min(best, time.perf_counter() - t0)
        rows.append({"pairs": n, "wall_s": best, "per_pair_s": best / n,
                     "per_pair_per_step_us": 1e6 * best / n / n_steps})
    slope, intercept = np.polyfit([r["pairs"] for r in rows], [r["wall_s"] for r in rows], 1)
    return rows, float(slope), float(intercept)


def plot(path: Path, results: list[dict[str, FloatArray]], cars: list[cosim.Car], t: FloatArray, title: str) -> None:
    plt = pyplot()

    fig, axes = plt.subplots(3, 2, figsize=(11, 8), sharex=True, sharey="row")
    m = t >= t[-1] - 2.0
    for col, side in enumerate(full_truck.SIDES):
        for row_, axle in enumerate(full_truck.AXLES):
            i = next(j for j, c in enumerate(cars) if c.name == f"{axle}_{side}")
            r = results[i]
            ax = axes[row_][col]
            ax.plot(t[m], r["F_demand"][m] / 1e3, "--", color="tab:orange", lw=1, label="demand")
            ax.plot(t[m], r["damper.F_damper"][m] / 1e3, color="tab:blue", lw=1, label="damper FMU")
            ax2 = ax.twinx()
            ax2.plot(t[m], 1e3 * r["z_road"][m], color="0.6", lw=0.8)
            ax2.set_ylim(-60, 60)
            ax2.tick_params(labelsize=7, colors="0.5")
            ax.set_title(f"{axle} axle, {side}", fontsize=9)
            ax.grid(alpha=0.3)
            if col == 0:
                ax.set_ylabel("force (kN)")
            if row_ == 0 and col == 1:
                ax.legend(fontsize=7, loc="upper right")
    for ax in axes[-1]:
        ax.set_xlabel("time (s)   (grey, right axis: z_road in mm)")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--road", default="minor")
    parser.add_argument("--speed", type=float, default=14.0)
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--duration", type=float, default=5.0)
    parser.add_argument("--step", type=float, default=1e-3)
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--docs", action="store_true", help="write the timings to docs/instances.json")
    args = parser.parse_args(argv)
    kw = {"truck_fmu": args.truck_fmu, "damper_fmu": args.damper_fmu}

    wheels, n_steps = wheel_roads(args.road, args.speed, args.duration, args.seed, args.step)
    cars = quarter_truck_cars(wheels)
    results, same = independence(cars, args.step, n_steps, **kw)
    front_l = dict(zip([c.name for c in cars], results, strict=True))["front_left"]
    rear_l = dict(zip([c.name for c in cars], results, strict=True))["drive2_left"]
    delay_s = AXLE_X["drive2"] / args.speed
    t = front_l["time"]
    later = t >= delay_s
    # the front road at t - delay, interpolated between samples (the delay is not a whole number of steps)
    mismatch = np.max(np.abs(rear_l["z_road"][later] - np.interp(t[later] - delay_s, t, front_l["z_road"])))
    delayed_ok = bool(mismatch < 0.02 * np.std(front_l["z_road"]))
    print(f"instances: {len(cars)} quarter trucks with {len(cars)} damper FMU instances, {args.road} road, "
          f"{args.speed:g} m/s, {n_steps} steps of {args.step:g} s")
    for name, ok in same.items():
        print(f"  {name:13s} together == alone, bit for bit: {ok}")
    print(f"  rear axle sees the front axle's road {delay_s * 1e3:.1f} ms later: {delayed_ok} (largest difference "
          f"{1e6 * mismatch:.1f} um, interpolation between samples; road std {1e3 * np.std(front_l['z_road']):.2f} mm)")
    rows, slope, intercept = scaling(cars, args.step, n_steps, **kw)
    print("  pairs | wall time (s) | per pair (s) | per pair and step (us)")
    for r in rows:
        print(f"  {r['pairs']:5d} | {r['wall_s']:13.3f} | {r['per_pair_s']:12.3f} | {r['per_pair_per_step_us']:.1f}")
    print(f"  linear fit: {slope:.3f} s per pair + {intercept:.3f} s "
          f"({1e6 * slope / n_steps:.1f} us per pair and step; {args.duration / slope:.0f}x real time per pair)")

    args.out.mkdir(parents=True, exist_ok=True)
    plot(args.out / "instances.png", results, cars, results[0]["time"],
         f"Six quarter trucks + six damper FMUs in one master ({args.road} road, {args.speed:g} m/s, "
         f"left/right correlation {full_truck.TRACK_CORRELATION:g})")
    summary = {"road": args.road, "speed": args.speed, "seed": args.seed, "step": args.step, "n_steps": n_steps,
               "axles_m_behind_front": AXLE_X, "track_correlation": full_truck.TRACK_CORRELATION,
               "independent_bit_for_bit": same, "rear_sees_front_road_delayed": bool(delayed_ok),
               "scaling": rows, "seconds_per_pair": slope, "seconds_fixed": intercept,
               "F_damper_rms_kN": {c.name: float(np.std(r["damper.F_damper"]) / 1e3)
                                   for c, r in zip(cars, results, strict=True)}}
    (args.out / "results.json").write_text(json.dumps(summary, indent=1), encoding="utf-8")
    if args.docs:
        from damper_tools import doc_figures

        per_pair = [r["per_pair_s"] for r in rows]
        figures = {"per_pair_s_min": min(per_pair), "per_pair_s_max": max(per_pair),
                   "per_pair_step_us_min": min(r["per_pair_per_step_us"] for r in rows),
                   "per_pair_step_us_max": max(r["per_pair_per_step_us"] for r in rows),
                   "realtime_per_pair_min": args.duration / max(per_pair),
                   "realtime_per_pair_max": args.duration / min(per_pair)}
        doc_figures.write("instances", figures, ".venv/bin/python -m damper_tools.instances --docs")
    print(f"instances: wrote {args.out}")


if __name__ == "__main__":
    main()
