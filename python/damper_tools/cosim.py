"""A Python co-simulation master for QuarterTruck.fmu and SemiActiveDamper.fmu (fmpy's FMU2Slave).

    .venv/bin/damper-cosim --road minor --speed 14 --duration 5 --step 1e-3 \
        --mode fmu --output out/cosim/minor_14.csv

One quarter truck and its damper are coupled output to input:

    road            -> truck.z_road, truck.v_road
    truck.v_damper  -> damper.v_damper
    truck.F_demand  -> damper.F_demand        (clipped Modified Skyhook demand)
    damper.F_damper -> truck.F_damper         (truck damper_mode = 0)

Coupling: Jacobi with a fixed communication step h. At each communication point t_k both slaves get
the other's outputs of t_k (computed by the step that ended there) and then step from t_k to t_k + h
independently. So the force that acts on the truck during [t_k, t_k + h] is the damper's force at
t_k: the coupling adds ONE STEP of lag (h) to the force path, and the damper sees the truck's
velocity of t_k held over the step. fmpy.ssp and libcosim's fixed-step algorithm couple the same way
(see damper_tools.ssp). The road is not lagged: the truck gets z_road(t_k) and the rate v_road_k that
takes it to z_road(t_{k+1}) at the end of the step.

Several quarter trucks (each with its own damper, or a truck alone with damper_mode 1 or 2) can run
in one master: `simulate` steps all of them in one loop (`Car` describes each one). Step sizes are
always explicit; time points are t_k = start + k h (not accumulated), passed as
currentCommunicationPoint, and setupExperiment gets stopTime = start + n h.
"""

import argparse
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from fmpy.fmi1 import FMICallException

from damper_tools import DAMPER_FMU, TRUCK_FMU, FloatArray, roads
from damper_tools.fmu import FmuUnit, Slave, Value

TRUCK_OUTPUTS = ("v_damper", "F_demand", "x_damper", "v_body", "a_body", "a_axle", "z_body", "z_axle",
                 "F_tyre", "F_suspension")
DAMPER_OUTPUTS = ("F_damper", "F_demand_clipped", "x_spool", "x_damper")
MODE_EXTERNAL, MODE_IDEAL, MODE_PASSIVE, MODE_TRACKING = 0, 1, 2, 3
# A damper in a HiL loop is tared: the gas force at rest is removed from F_damper.
HIL_DAMPER_PARAMETERS: dict[str, Value] = {"tare_load_cell": True}


@dataclass
class Car:
    """One quarter truck in the master: its road samples at t_k (k = 0..n), its truck parameters
    (damper_mode etc.) and, for damper_mode 0, the parameters of its damper FMU instance."""
    name: str
    z_road: FloatArray
    v_road: FloatArray
    truck_parameters: dict[str, Value] = field(default_factory=dict)
    damper_parameters: dict[str, Value] = field(default_factory=lambda: dict(HIL_DAMPER_PARAMETERS))
    # What the damper is given at step k from the truck's (v_damper, F_demand): by default the truck's
    # values; a measurement chain (sensor noise on the velocity, a demand held at a logger's rate)
    # replaces them, e.g. damper_tools.independent. An optional third value is the damper's a_damper
    # over the step (the velocity's ramp; 0 holds it).
    damper_inputs: Callable[[int, float, float], tuple[float, ...]] | None = None
    # What the truck is given at step k from the damper's load-cell force F_damper(t_k): by default
    # that force; a rig's force path (load-cell filter, the real-time computer's latency and sample,
    # damper_tools.hil_rig) replaces it.
    truck_force: Callable[[int, float], float] | None = None

    @property
    def has_damper(self) -> bool:
        return int(self.truck_parameters.get("damper_mode", MODE_EXTERNAL)) == MODE_EXTERNAL


class Refused(RuntimeError):
    """An FMU refused a call of the master (fmi2Error): the instance, the communication point and the
    message it logged. A run that goes unstable ends this way, on an input out of the FMU's range."""

    def __init__(self, instance: str, time: float, message: str) -> None:
        super().__init__(f"{instance} at t = {time:.3f} s: {message}")
        self.instance, self.time, self.message = instance, time, message


def simulate(cars: Sequence[Car], step: float, n_steps: int, truck_fmu: str | Path = TRUCK_FMU,
             damper_fmu: str | Path = DAMPER_FMU, start_time: float = 0.0,
             damper_outputs: Sequence[str] = ("F_damper",), logging_on: bool = False,
             echo: bool = True) -> list[dict[str, FloatArray]]:
    """Runs the cars (one truck instance each, plus a damper instance for damper_mode 0) for n_steps
    Jacobi steps of `step` seconds. Returns one dict per car: 'time' (n_steps + 1 points), the road,
    the truck outputs (TRUCK_OUTPUTS) and the damper outputs (damper_outputs), each at the
    communication points, the first row being the initial values after initialisation.
    A call an FMU refuses raises `Refused`; its warnings and errors go to stderr unless echo is false
    (for runs expected to fail, such as a sweep's unstable points)."""
    if not step > 0 or n_steps < 1:
        raise ValueError(f"need step > 0 and n_steps >= 1 (got {step}, {n_steps})")
    for car in cars:
        if len(car.z_road) < n_steps + 1 or len(car.v_road) < n_steps + 1:
            raise ValueError(f"{car.name}: the road has {len(car.z_road)} samples, {n_steps + 1} needed")
    truck_unit = FmuUnit.load(truck_fmu)
    damper_unit = FmuUnit.load(damper_fmu) if any(c.has_damper for c in cars) else None
    stop_time = start_time + n_steps * step
    times = start_time + step * np.arange(n_steps + 1)

    trucks: list[Slave] = []
    dampers: list[Slave | None] = []
    t = start_time
    try:
        for car in cars:
            truck = Slave(truck_unit, f"{car.name}.truck", logging_on, echo)
            trucks.append(truck)
            truck.initialize(start_time, stop_time, **car.truck_parameters)
            damper = None
            if car.has_damper:
                assert damper_unit is not None  # loaded above when any car has a damper
                damper = Slave(damper_unit, f"{car.name}.damper", logging_on, echo)
                damper.initialize(start_time, stop_time, **car.damper_parameters)
            dampers.append(damper)

        rec_t = [np.empty((n_steps + 1, len(TRUCK_OUTPUTS))) for _ in cars]
        rec_d: list[FloatArray | None] = [np.empty((n_steps + 1, len(damper_outputs))) if d else None
                                          for d in dampers]
        i_v, i_fd = TRUCK_OUTPUTS.index("v_damper"), TRUCK_OUTPUTS.index("F_demand")
        i_f = damper_outputs.index("F_damper") if "F_damper" in damper_outputs else None
        if i_f is None and damper_unit is not None:
            raise ValueError("damper_outputs must contain F_damper")

        def record(k: int) -> None:
            for j, truck in enumerate(trucks):
                rec_t[j][k] = truck.get(TRUCK_OUTPUTS)
                damper, rec = dampers[j], rec_d[j]
                if damper is not None and rec is not None:
                    rec[k] = damper.get(damper_outputs)

        record(0)
        for k in range(n_steps):
            t = times[k]
            for j, car in enumerate(cars):
                damper, rec = dampers[j], rec_d[j]
                force: float = rec[k, i_f] if damper is not None and rec is not None and i_f is not None else 0.0
                if damper is not None and car.truck_force is not None:
                    force = car.truck_force(k, force)
                trucks[j].set(z_road=car.z_road[k], v_road=car.v_road[k], F_damper=force)
                if damper is not None:
                    v_in: float = rec_t[j][k, i_v]
                    f_in: float = rec_t[j][k, i_fd]
                    a_in = 0.0
                    if car.damper_inputs is not None:
                        v_in, f_in, *ramp = car.damper_inputs(k, v_in, f_in)
                        a_in = ramp[0] if ramp else 0.0
                    damper.set(v_damper=v_in, F_demand=f_in, a_damper=a_in)
            for j in range(len(cars)):
                trucks[j].step(step, t)
                damper = dampers[j]
                if damper is not None:
                    damper.step(step, t)
            record(k + 1)
    except FMICallException as e:
        # the one instance with an error is the one that refused (a master stops at its first error)
        culprit = next((s for s in trucks + dampers if s is not None and s.errors()), None)
        if culprit is None:
            raise
        raise Refused(culprit.name, float(t), culprit.errors()[-1][2]) from e
    finally:
        for inst in trucks + [d for d in dampers if d]:
            inst.free()

    results: list[dict[str, FloatArray]] = []
    for j, car in enumerate(cars):
        res = {"time": times, "z_road": np.asarray(car.z_road[:n_steps + 1], float),
               "v_road": np.asarray(car.v_road[:n_steps + 1], float)}
        res.update({name: rec_t[j][:, i] for i, name in enumerate(TRUCK_OUTPUTS)})
        rec = rec_d[j]
        if rec is not None:
            res.update({f"damper.{name}": rec[:, i] for i, name in enumerate(damper_outputs)})
        results.append(res)
    return results


def simulate_one(z_road: FloatArray, v_road: FloatArray, step: float, n_steps: int, mode: int = MODE_EXTERNAL,
                 truck_parameters: dict[str, Value] | None = None, damper_parameters: dict[str, Value] | None = None,
                 **kwargs: Any) -> dict[str, FloatArray]:
    """One quarter truck (with its damper FMU if mode is 0); returns the result dict."""
    tp = {"damper_mode": mode, **(truck_parameters or {})}
    dp = dict(HIL_DAMPER_PARAMETERS) if damper_parameters is None else damper_parameters
    return simulate([Car("qt", z_road, v_road, tp, dp)], step, n_steps, **kwargs)[0]


def write_result_csv(path: str | Path, result: dict[str, FloatArray], header_comment: str = "") -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = list(result)
    with path.open("w", encoding="utf-8") as f:
        if header_comment:
            f.write(f"# {header_comment}\n")
        f.write(",".join(names) + "\n")
        for row in zip(*(result[n] for n in names), strict=True):
            f.write(",".join(repr(float(v)) for v in row) + "\n")
    return path


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--road", default="minor", help="class A-H, motorway, major, minor or G_d(n0) (m^3)")
    parser.add_argument("--speed", type=float, default=14.0, help="m/s")
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--duration", type=float, default=5.0, help="s")
    parser.add_argument("--step", type=float, required=True, help="communication step (s)")
    parser.add_argument("--mode", choices=("fmu", "ideal", "passive"), default="fmu",
                        help="damper FMU (damper_mode 0), ideal semi-active (1) or passive c_passive (2)")
    parser.add_argument("--c-passive", type=float, default=None, help="N s/m, with --mode passive")
    parser.add_argument("--no-tare", action="store_true", help="tare_load_cell = false (raw load cell)")
    parser.add_argument("--output", type=Path, required=True, help="CSV of the results")
    args = parser.parse_args(argv)

    case = roads.road_case(args.road, args.speed, args.duration, args.seed, step=args.step)
    mode = {"fmu": MODE_EXTERNAL, "ideal": MODE_IDEAL, "passive": MODE_PASSIVE}[args.mode]
    tp: dict[str, Value] = {} if args.c_passive is None else {"c_passive": args.c_passive}
    dp: dict[str, Value] = {"tare_load_cell": not args.no_tare}
    n = case.t.size - 1
    res = simulate_one(case.z_road, case.v_road, args.step, n, mode, tp, dp,
                       truck_fmu=args.truck_fmu, damper_fmu=args.damper_fmu)
    write_result_csv(args.output, res, f"cosim: mode={args.mode}, step={args.step:g} s; {case.header()}")
    print(f"cosim: wrote {args.output} ({n} steps of {args.step:g} s); RMS a_body "
          f"{np.std(res['a_body']):.3f} m/s^2, RMS F_suspension {np.std(res['F_suspension']) / 1e3:.2f} kN")


if __name__ == "__main__":
    main()
