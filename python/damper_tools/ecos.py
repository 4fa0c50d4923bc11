"""The damper FMU alone, and the quarter truck + damper, in ecos (the "Easy co-simulation" engine,
through its Python binding ecospy 0.7.2): a master beside damper_tools.cosim (fmpy), fmpy.ssp and
libcosim (damper_tools.ssp).

    .venv/bin/python -m damper_tools.ecos --road minor --speed 14 --duration 2 --step 1e-3

    from damper_tools import ecos, roads
    case = roads.road_case("minor", 14.0, 2.0, 3, step=1e-3)
    res = ecos.run_quarter_truck(case.z_road, case.v_road, 1e-3, case.t.size - 1)
    res["damper.F_damper"]                       # N, at the communication points t_k = k h

`run_damper` and `run_quarter_truck` build the system from the FMUs (an EcosSimulationStructure:
add_model, make_real_connection with ssp.CONNECTIONS, one parameter set applied at init; ecos names a
variable 'instance::variable'). `run_ssp` loads the .ssp that damper_tools.ssp writes. With
separate_processes, each FMU instance runs in a process of its own (ecos's proxyfmu).

How ecos 0.7.2 runs them, and what that means here:

1. Its fixed-step algorithm is Jacobi, as cosim.py, fmpy.ssp and libcosim are: every instance applies
   its pending sets, steps from t_k and reads its outputs; then the connections are copied. The
   force path carries one step of lag, as in the other masters.
2. A value set from Python (set_real) is kept until the next step, which applies it just before its
   doStep. So the road needs no component: z_road and v_road of sample k are set before step k, and
   the truck steps [t_k, t_k + h] with sample k, as in cosim.py.
3. communicationStepSize is h itself; currentCommunicationPoint is accumulated (t + h), exact at
   h = 2^-9 s and rounded at 1 ms, as fmpy.ssp's; our FMUs do not use it in their numerics. The
   forces equal cosim.py's bit for bit at both steps (tests/python/test_ecos.py).
4. After copying the connections ecos reads every output once more, and that is the value Python
   gets. An output with direct feedthrough from a coupled input is therefore read with the input of
   t_{k+1} already set: the truck's a_body, a_axle and F_suspension (which depend on F_damper)
   differ from cosim.py's, which reads them before the new force is set, by exactly the force's change
   over the step (divided by m_body or m_axle). The coupling itself is not affected (the values
   copied are read right after doStep), nor are the outputs that depend on the state alone.
5. Initialisation: setupExperiment (start time; no stop time, no tolerance), enterInitializationMode,
   then the parameter set (FMI 2.0 allows these parameters in initialization mode). Connections are
   copied during initialisation and after exitInitializationMode, so the first step starts from the
   FMUs' initial outputs. Row 0 of the results is read after initialisation, as cosim.py's.
6. ecos ignores the status of fmi2SetReal (seen: v_damper = 1000 m/s, an fmi2Error in fmpy, passes
   silently, the FMU keeping its previous input) and of fmi2DoStep (its source drops it): an FMU's
   refusal does not reach Python and the run goes on. So the runs here refuse inputs outside the
   variables' declared [min, max] before running, check the coupled values against the same ranges
   after it, and check the outputs for NaN.
   cosim.py, which raises `Refused`, stays the master for runs that may go unstable.
7. Parameters fail quietly: a misspelt variable in a parameter set only logs a warning, an unknown
   set name nothing, and init still succeeds. The runs read every parameter back after init.
8. The SSP (run_ssp): like libcosim, ecos fails on connections to system-level connectors ("No
   element named: "), so they are stripped from an extracted copy of the .ssd. Each component's
   inline ParameterBinding becomes a parameter set named after its ParameterSet, and init applies
   one set: the copy gives every ParameterSet one name, so that init applies all of them.
9. ecos steps the instances through std::execution::par (Intel's TBB): libecosc.so needs
   libtbb.so.12 (Debian's libtbb12), without which importing ecospy fails. The wheel installs its
   proxyfmu program without the execute bit ("Unable to create/bind proxyfmu process!");
   scripts/setup.sh sets it. proxyfmu writes its log to logs/<instance>.txt under the working
   directory.

FMI 3.0: ecos 0.7.2 loads FMI 1.0, 2.0 and, in part, 3.0 Co-Simulation FMUs (fmi4c; its FMI 3.0
slave runs without event mode or early return). Nothing here is specific to FMI 2.0 (the variables
are read with fmpy, which reads both), so the FMI 3.0 FMUs (target/fmu/fmi3/) go through the same
functions; tests/python/test_ecos.py runs both, with the same results bit for bit.
"""

import argparse
import contextlib
import math
import shutil
import tempfile
import zipfile
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any
from xml.etree import ElementTree as ET

import numpy as np
from fmpy import read_model_description
from fmpy.model_description import ModelVariable

from damper_tools import DAMPER_FMU, TRUCK_FMU, FloatArray, cosim, roads, ssp
from damper_tools.fmu import Value

TRUCK, DAMPER = ssp.TRUCK, ssp.DAMPER
# The one parameter set of a run (ecos applies one named set at init).
PARAMETER_SET = "damper_tools"
PROXY = "proxyfmu://localhost?file="
# fmpy's names of the model-description types (FMI 2.0's and 3.0's) that ecos sets as int or bool;
# every other one is a Real (FMI 3.0: Float64).
_INTEGER_TYPES = {"Integer", "Enumeration", "Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64"}
_BOOLEAN_TYPES = {"Boolean"}
COUPLING = [(f"{s_el}::{s_c}", f"{e_el}::{e_c}") for s_el, s_c, e_el, e_c in ssp.CONNECTIONS if s_el is not None]


def _ecospy() -> ModuleType:
    """ecospy, imported on first use: importing it loads libecosc.so, which needs libtbb.so.12."""
    try:
        import ecospy  # type: ignore[import-untyped]
    except OSError as e:
        raise ImportError(f"ecospy could not load its library ({e}); it needs libtbb.so.12, Debian's libtbb12 "
                          f"(bash scripts/setup.sh installs it)") from e
    module: ModuleType = ecospy
    module.EcosLib.set_log_level("warn")  # its default, info, prints lines for every model loaded
    return module


def _variables(models: Mapping[str, str | Path]) -> dict[str, ModelVariable]:
    """Every variable of the models, by ecos identifier 'instance::name'."""
    out: dict[str, ModelVariable] = {}
    for instance, fmu in models.items():
        for v in read_model_description(str(fmu)).modelVariables:
            out[f"{instance}::{v.name}"] = v
    return out


def _typed(variables: Mapping[str, ModelVariable], instance: str, values: Mapping[str, Value]) -> dict[str, Value]:
    """`values` by identifier, each a Python value of its variable's type: ecospy picks the set function
    (int, real, bool) from the Python type, so an Integer given as 0.0 or a Real given as 0 would miss."""
    out: dict[str, Value] = {}
    for name, value in values.items():
        var = variables.get(f"{instance}::{name}")
        if var is None:
            raise KeyError(f"{instance} has no variable {name!r}")
        out[f"{instance}::{name}"] = (bool(value) if var.type in _BOOLEAN_TYPES else
                                      int(value) if var.type in _INTEGER_TYPES else float(value))
    return out


def _outside(var: ModelVariable, values: FloatArray) -> int | None:
    """The index of the first value that is not finite or is outside the variable's declared
    [min, max] (the values the FMU would refuse), None if there is none."""
    lo = -math.inf if var.min is None else float(var.min)
    hi = math.inf if var.max is None else float(var.max)
    bad = np.flatnonzero(~(np.isfinite(values) & (values >= lo) & (values <= hi)))
    return int(bad[0]) if bad.size else None


@contextlib.contextmanager
def _structure_simulation(models: Mapping[str, str | Path], parameters: Mapping[str, Value], step: float,
                          separate_processes: bool) -> Iterator[Any]:
    """An EcosSimulation of the models (instance -> FMU) with the COUPLING connections among them and
    `parameters` as the parameter set PARAMETER_SET. The structure lives as long as the simulation."""
    ecospy = _ecospy()
    with contextlib.ExitStack() as stack:
        structure = ecospy.EcosSimulationStructure()
        stack.callback(structure.free)
        for instance, fmu in models.items():
            path = str(Path(fmu).resolve())
            structure.add_model(instance, PROXY + path if separate_processes else path)
        for source, sink in COUPLING:
            if source.split("::")[0] in models and sink.split("::")[0] in models:
                structure.make_real_connection(source, sink)
        if parameters:
            structure.add_parameter_set(PARAMETER_SET, dict(parameters))
        sim = ecospy.EcosSimulation(structure=structure, step_size=step)
        stack.callback(sim.free)
        yield sim


def _run(sim: Any, variables: Mapping[str, ModelVariable], parameter_set: str | None,
         parameters: Mapping[str, Value], step: float, n_steps: int, inputs: Mapping[str, FloatArray],
         record: Sequence[str]) -> dict[str, FloatArray]:
    """Initialises `sim` with the parameter set, checks that `parameters` took, then runs n_steps steps
    of `step`, setting each input series' sample k before step k. Returns 'time' and each recorded
    identifier (as 'instance.variable'), at the n_steps + 1 communication points, row 0 after init."""
    if not step > 0 or n_steps < 1:
        raise ValueError(f"need step > 0 and n_steps >= 1 (got {step}, {n_steps})")
    series = {}
    for name, s in inputs.items():
        values = np.asarray(s, float)[:n_steps]
        if values.size < n_steps:
            raise ValueError(f"{name}: {values.size} samples, {n_steps} needed")
        k = _outside(variables[name], values)
        if k is not None:  # ecos would not report the FMU's refusal (quirk 6)
            raise ValueError(f"{name}[{k}] = {float(values[k])!r} is outside the declared [{variables[name].min}, "
                             f"{variables[name].max}]: the FMU would refuse it")
        series[name] = values
    coupled = [(src, sink) for src, sink in COUPLING if src in variables and sink in variables]
    record = list(dict.fromkeys([*record, *(src for src, _ in coupled)]))
    ecos_lib = _ecospy().EcosLib
    if sim.init(0.0, parameter_set) is False:
        raise RuntimeError(f"ecos could not initialise the system: {ecos_lib.get_last_error()}")
    for name, value in parameters.items():  # a parameter that did not take is not reported (quirk 7)
        get = sim.get_bool if isinstance(value, bool) else sim.get_integer if isinstance(value, int) else sim.get_real
        if get(name) != value:
            raise RuntimeError(f"ecos did not apply {name} = {value!r} (it reads {get(name)!r})")
    out = np.empty((n_steps + 1, len(record)))
    out[0] = [sim.get_real(r) for r in record]
    t = 0.0
    for k in range(n_steps):
        for name, values in series.items():
            sim.set_real(name, float(values[k]))
        t = sim.step()
        out[k + 1] = [sim.get_real(r) for r in record]
    sim.terminate()
    if abs(t - n_steps * step) > 1e-9 * max(1.0, n_steps * step):
        raise RuntimeError(f"ecos ended at t = {t!r} s, {n_steps * step!r} s expected")
    result: dict[str, FloatArray] = {"time": step * np.arange(n_steps + 1, dtype=float)}
    for j, name in enumerate(record):
        result[name.replace("::", ".")] = out[:, j]
        if not np.all(np.isfinite(out[:, j])):
            raise RuntimeError(f"{name} is not finite from t = {np.argmin(np.isfinite(out[:, j])) * step:.6g} s")
    for source, sink in coupled:  # the values ecos set on the coupled inputs, before each step
        k = _outside(variables[sink], out[:n_steps, record.index(source)])
        if k is not None:
            raise RuntimeError(f"{source} = {float(out[k, record.index(source)])!r} at t = {k * step:.6g} s is outside "
                               f"{sink}'s declared range: the FMU refused it and ecos went on (quirk 6)")
    return result


def run_damper(v_damper: FloatArray, F_demand: FloatArray, step: float, n_steps: int,
               damper_fmu: str | Path = DAMPER_FMU, parameters: Mapping[str, Value] | None = None,
               outputs: Sequence[str] = ("F_damper",), separate_processes: bool = False) -> dict[str, FloatArray]:
    """The damper FMU alone in ecos: v_damper[k] and F_demand[k] held over step k (a_damper stays 0),
    n_steps fixed steps of `step` s. parameters: start values by name (none by default: the rig's
    untared load cell). Returns 'time' and 'damper.<output>' at the n_steps + 1 communication points."""
    models = {DAMPER: damper_fmu}
    variables = _variables(models)
    params = _typed(variables, DAMPER, parameters or {})
    with _structure_simulation(models, params, step, separate_processes) as sim:
        return _run(sim, variables, PARAMETER_SET if params else None, params, step, n_steps,
                    {f"{DAMPER}::v_damper": v_damper, f"{DAMPER}::F_demand": F_demand},
                    [f"{DAMPER}::{name}" for name in outputs])


def run_quarter_truck(z_road: FloatArray, v_road: FloatArray, step: float, n_steps: int,
                      truck_fmu: str | Path = TRUCK_FMU, damper_fmu: str | Path = DAMPER_FMU,
                      truck_parameters: Mapping[str, Value] | None = None,
                      damper_parameters: Mapping[str, Value] | None = None,
                      truck_outputs: Sequence[str] = cosim.TRUCK_OUTPUTS, damper_outputs: Sequence[str] = ("F_damper",),
                      separate_processes: bool = False) -> dict[str, FloatArray]:
    """The quarter truck and its damper coupled in ecos (ssp.CONNECTIONS between the two FMUs; the road
    z_road[k], v_road[k] set on the truck before step k), n_steps Jacobi steps of `step` s. The
    parameters default to ssp's: truck damper_mode 0, damper tare_load_cell true. Returns 'time',
    'truck.<output>' and 'damper.<output>' at the n_steps + 1 communication points, the keys of
    ssp.run_libcosim (cosim.simulate_one gives the truck's outputs under their bare names)."""
    tp = dict(ssp.DEFAULT_TRUCK_PARAMETERS if truck_parameters is None else truck_parameters)
    if int(tp.get("damper_mode", cosim.MODE_EXTERNAL)) != cosim.MODE_EXTERNAL:
        raise ValueError("the damper FMU is in the truck's force path only with damper_mode 0")
    dp = ssp.DEFAULT_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters
    models = {TRUCK: truck_fmu, DAMPER: damper_fmu}
    variables = _variables(models)
    params = {**_typed(variables, TRUCK, tp), **_typed(variables, DAMPER, dp)}
    with _structure_simulation(models, params, step, separate_processes) as sim:
        return _run(sim, variables, PARAMETER_SET, params, step, n_steps,
                    {f"{TRUCK}::z_road": z_road, f"{TRUCK}::v_road": v_road},
                    [f"{TRUCK}::{n}" for n in truck_outputs] + [f"{DAMPER}::{n}" for n in damper_outputs])


def ecos_ssd(ssd_text: str) -> str:
    """The .ssd as ecos 0.7.2 can load and parameterise it (quirk 8): without the system-level
    connectors and their connections, and with every ParameterSet named PARAMETER_SET."""
    root = ET.fromstring(ssp.strip_system_connections(ssd_text))
    for pset in root.iter(f"{{{ssp.SSV}}}ParameterSet"):
        pset.set("name", PARAMETER_SET)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def run_ssp(ssp_path: str | Path, z_road: FloatArray | None, v_road: FloatArray | None, step: float, n_steps: int,
            truck_outputs: Sequence[str] = cosim.TRUCK_OUTPUTS,
            damper_outputs: Sequence[str] = ("F_damper",)) -> dict[str, FloatArray]:
    """The .ssp written by damper_tools.ssp, loaded by ecos from an extracted copy (ecos_ssd), its
    ParameterBindings applied at init; the road set on the truck before each step as in
    run_quarter_truck, whose result dict it returns (z_road and v_road None: the SSP's truck makes
    its own road, and nothing is set)."""
    ecospy = _ecospy()
    with tempfile.TemporaryDirectory(prefix="ecos_ssp_") as tmp:
        with zipfile.ZipFile(ssp_path) as z:
            z.extractall(tmp)
        ssd = Path(tmp) / "SystemStructure.ssd"
        ssd.write_text(ecos_ssd(ssd.read_text(encoding="utf-8")), encoding="utf-8")
        root = ET.parse(ssd).getroot()
        models = {c.get("name", ""): Path(tmp) / c.get("source", "")
                  for c in root.iter(f"{{{ssp.SSD}}}Component")}
        variables = _variables(models)
        # the bindings' values, typed as the variables are, to check that init applied them (quirk 7)
        params = {}
        for p in ssp.ssd_parameter_set(ssp_path).parameters:
            instance, name = p.name.split(".", 1)
            params.update(_typed(variables, instance, {name: p.value}))
        sim = ecospy.EcosSimulation(ssp_path=tmp, step_size=step)
        try:
            road = {} if z_road is None or v_road is None else {f"{TRUCK}::z_road": z_road,
                                                                   f"{TRUCK}::v_road": v_road}
            return _run(sim, variables, PARAMETER_SET, params, step, n_steps, road,
                        [f"{TRUCK}::{n}" for n in truck_outputs] + [f"{DAMPER}::{n}" for n in damper_outputs])
        finally:
            sim.free()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--road", default="minor")
    parser.add_argument("--speed", type=float, default=14.0)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--duration", type=float, default=2.0)
    parser.add_argument("--step", type=float, default=1e-3)
    args = parser.parse_args(argv)
    case = roads.road_case(args.road, args.speed, args.duration, args.seed, step=args.step)
    n = case.t.size - 1
    fmus = {"truck_fmu": args.truck_fmu, "damper_fmu": args.damper_fmu}
    ref = cosim.simulate_one(case.z_road, case.v_road, args.step, n, **fmus)["damper.F_damper"]
    tmp = Path(tempfile.mkdtemp(prefix="ecos_"))
    try:
        runs = {"ecos (FMUs)": run_quarter_truck(case.z_road, case.v_road, args.step, n, **fmus),
                "ecos (SSP)": run_ssp(ssp.write_ssp(tmp / "QuarterTruckHiL.ssp", **fmus), case.z_road, case.v_road,
                                      args.step, n)}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for name, res in runs.items():
        d = res["damper.F_damper"] - ref
        print(f"{name:12s}: max |F_damper - cosim.py| = {np.max(np.abs(d)):.3g} N over {n} steps of {args.step:g} s "
              f"(RMS F_damper {np.sqrt(np.mean(ref ** 2)):.0f} N), bit-identical: "
              f"{np.array_equal(res['damper.F_damper'], ref)}")


if __name__ == "__main__":
    main()
