"""The quarter truck + damper as an SSP (System Structure and Parameterization, SSP 1.0), run by
fmpy.ssp and by libcosim.

    .venv/bin/damper-ssp --output out/ssp/QuarterTruckHiL.ssp            # write the SSP
    .venv/bin/damper-ssp --output out/ssp/QuarterTruckHiL.ssp --compare \
        --road minor --speed 14 --duration 3 --step 1e-3      # run it in the three masters

The .ssp is a zip of

    SystemStructure.ssd              system "QuarterTruckHiL": components truck and damper
    resources/QuarterTruck.fmu
    resources/SemiActiveDamper.fmu

with the connections truck.v_damper -> damper.v_damper, truck.F_demand -> damper.F_demand,
damper.F_damper -> truck.F_damper, the system-level input connectors z_road and v_road connected to
the truck, and the parameter values as inline ParameterBindings (damper.tare_load_cell = true,
truck.damper_mode = 0 by default).

fmpy.ssp (0.3.32) quirks, handled here rather than in the FMUs:

1. simulate_ssp ignores the ParameterBindings of the .ssd (it parses them but applies only a
   `parameter_set` argument, with names prefixed by the component name). `run_fmpy_ssp` builds that
   ParameterSet from the .ssd's own bindings. Its Boolean conversion (`value != 0.0`) would turn the
   text "false" into True, so the values are converted to Python types first.
2. A system input reaches the component one step late: simulate_ssp sets the system connector from
   input(t_k), steps all components, and only then copies connector values along the connections,
   so the truck would step [t_k, t_k + h] with z_road(t_{k-1}). `run_fmpy_ssp` hands fmpy the road
   one sample ahead (input(t_k) returns sample k + 1), so the truck steps with sample k, as in
   damper_tools.cosim and libcosim. Sample 0 reaches the truck as the connector's initial value 0.0,
   which is exact because the road fades in from 0.
3. Time is accumulated (time += step_size, loop while time < stop_time), so after n steps of 1e-3 s
   the time can be a rounding error short of stop_time and one extra step would run. `run_fmpy_ssp`
   passes stop_time = (n - 1/2) step, which gives exactly n steps. setupExperiment gets no stopTime
   (so an FMU's stop-time check is not exercised), and currentCommunicationPoint is the accumulated
   time (our FMUs accept it).
4. The result rows carry the time at the START of the step but the outputs at its END;
   `run_fmpy_ssp` shifts the time by one step and prepends the initial row (all zeros at rest).
5. All connector values start at 0.0, not at the FMUs' initial outputs. At rest with a tared load
   cell these are 0 (an untared damper's -1 kN gas force would be missed for the first step).

libcosim (libcosimpy 0.0.6): `run_libcosim` loads the same .ssp (CosimExecution.from_ssp_file with an
explicit step) or adds the two FMUs as local slaves and connects them (`from_ssp=False`). The road is
applied with an override manipulator before every step. libcosim's fixed-step algorithm is Jacobi too:
all slaves step, then outputs are copied to the connected inputs. Its quirks:

6. It fails to load an .ssd with connections to system-level connectors ("No such node
   (<xmlattr>.startElement)"); `run_libcosim` strips them (and the system connectors) from the
   extracted copy. It does not drive system inputs anyway.
7. communicationStepSize is t_{k+1} - t_k of two time points converted from nanoseconds, a few ulp
   off h unless h and every t_k are exact binary fractions (h = 2^-9 s is): results then differ from
   the other masters by ~1e-10 relative instead of 0.
8. The slaves are initialised in the first step: the last-value observer has nothing before it, so
   the first row of the result is NaN.
9. connect_real_variables returns the C status (0 = success), unlike the other calls used here,
   which return a bool.
"""

import argparse
import tempfile
import zipfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING
from xml.etree import ElementTree as ET

import numpy as np
from fmpy.model_description import ModelVariable

from damper_tools import DAMPER_FMU, TRUCK_FMU, FloatArray, cosim, roads
from damper_tools.fmu import FmuUnit, Value

if TYPE_CHECKING:
    from fmpy.ssp.ssd import ParameterSet

SSD = "http://ssp-standard.org/SSP1/SystemStructureDescription"
SSC = "http://ssp-standard.org/SSP1/SystemStructureCommon"
SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"
ET.register_namespace("ssd", SSD)
ET.register_namespace("ssc", SSC)
ET.register_namespace("ssv", SSV)

SYSTEM_NAME = "QuarterTruckHiL"
TRUCK, DAMPER = "truck", "damper"
CONNECTIONS = [  # (start element, start connector, end element, end connector); None = the system
    (None, "z_road", TRUCK, "z_road"),
    (None, "v_road", TRUCK, "v_road"),
    (TRUCK, "v_damper", DAMPER, "v_damper"),
    (TRUCK, "F_demand", DAMPER, "F_demand"),
    (DAMPER, "F_damper", TRUCK, "F_damper"),
]
DEFAULT_TRUCK_PARAMETERS = {"damper_mode": cosim.MODE_EXTERNAL}
DEFAULT_DAMPER_PARAMETERS = dict(cosim.HIL_DAMPER_PARAMETERS)
SSP_ZIP_DATE = (1980, 1, 1, 0, 0, 0)


def _q(ns: str, tag: str) -> str:
    return f"{{{ns}}}{tag}"


def _connector(parent: ET.Element, name: str, kind: str, unit: str | None = None) -> None:
    c = ET.SubElement(parent, _q(SSD, "Connector"), name=name, kind=kind)
    real = ET.SubElement(c, _q(SSC, "Real"))
    if unit:
        real.set("unit", unit)


def _parameter_binding(parent: ET.Element, set_name: str, values: dict[str, Value],
                       variables: dict[str, ModelVariable]) -> None:
    bindings = ET.SubElement(parent, _q(SSD, "ParameterBindings"))
    binding = ET.SubElement(bindings, _q(SSD, "ParameterBinding"))
    pv = ET.SubElement(binding, _q(SSD, "ParameterValues"))
    pset = ET.SubElement(pv, _q(SSV, "ParameterSet"), version="1.0", name=set_name)
    params = ET.SubElement(pset, _q(SSV, "Parameters"))
    for name, value in values.items():
        var = variables.get(name)
        if var is None:
            raise KeyError(f"parameter {name!r} is not a variable of {set_name}")
        p = ET.SubElement(params, _q(SSV, "Parameter"), name=name)
        if var.type == "Boolean":
            ET.SubElement(p, _q(SSV, "Boolean"), value="true" if value else "false")
        elif var.type in ("Integer", "Enumeration"):
            ET.SubElement(p, _q(SSV, "Integer"), value=str(int(value)))
        else:
            ET.SubElement(p, _q(SSV, "Real"), value=repr(float(value)))


def own_road(truck_parameters: dict[str, Value]) -> bool:
    """Whether the truck makes its own road (road_source 1): the system then has no road inputs."""
    return int(truck_parameters.get("road_source", 0)) == 1


def ssd_xml(truck_unit: FmuUnit, damper_unit: FmuUnit, truck_parameters: dict[str, Value],
            damper_parameters: dict[str, Value], step: float | None = None, stop_time: float | None = None) -> str:
    """The SystemStructure.ssd text of the quarter truck + damper system: with the road inputs z_road
    and v_road, or self-contained when the truck makes its own road."""
    fed = not own_road(truck_parameters)
    root = ET.Element(_q(SSD, "SystemStructureDescription"), version="1.0", name=SYSTEM_NAME)
    road = "road input z_road, v_road" if fed else "the truck's own ISO 8608 road (road_source = 1), no inputs"
    system = ET.SubElement(root, _q(SSD, "System"), name=SYSTEM_NAME,
                           description="Quarter truck (Kitching, Cole & Cebon, Table 1) with the semi-active "
                                       f"damper FMU in its force path; {road}.")
    if fed:
        conns = ET.SubElement(system, _q(SSD, "Connectors"))
        _connector(conns, "z_road", "input", "m")
        _connector(conns, "v_road", "input", "m/s")
    links = [c for c in CONNECTIONS if fed or c[0] is not None]
    elements = ET.SubElement(system, _q(SSD, "Elements"))
    for name, unit, params in ((TRUCK, truck_unit, truck_parameters), (DAMPER, damper_unit, damper_parameters)):
        comp = ET.SubElement(elements, _q(SSD, "Component"), name=name, type="application/x-fmu-sharedlibrary",
                             source=f"resources/{unit.md.coSimulation.modelIdentifier}.fmu")
        cc = ET.SubElement(comp, _q(SSD, "Connectors"))
        for _, _, e_el, e_c in links:
            if e_el == name:
                _connector(cc, e_c, "input", unit.variables[e_c].unit)
        for s_el, s_c, _, _ in links:
            if s_el == name:
                _connector(cc, s_c, "output", unit.variables[s_c].unit)
        if params:
            _parameter_binding(comp, name, params, unit.variables)
    connections = ET.SubElement(system, _q(SSD, "Connections"))
    for s_el, s_c, e_el, e_c in links:
        attrs = {"startConnector": s_c, "endElement": e_el, "endConnector": e_c}
        if s_el is not None:
            attrs = {"startElement": s_el, **attrs}
        ET.SubElement(connections, _q(SSD, "Connection"), attrib=attrs)
    if stop_time is not None:
        ET.SubElement(root, _q(SSD, "DefaultExperiment"), startTime="0.0", stopTime=repr(float(stop_time)))
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_ssp(path: str | Path, truck_fmu: str | Path = TRUCK_FMU, damper_fmu: str | Path = DAMPER_FMU,
              truck_parameters: dict[str, Value] | None = None, damper_parameters: dict[str, Value] | None = None,
              stop_time: float | None = None) -> Path:
    """Writes the .ssp (the two FMUs copied into resources/). Returns its path."""
    truck_unit, damper_unit = FmuUnit.load(truck_fmu), FmuUnit.load(damper_fmu)
    tp = dict(DEFAULT_TRUCK_PARAMETERS if truck_parameters is None else truck_parameters)
    dp = dict(DEFAULT_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters)
    if int(tp.get("damper_mode", 0)) != cosim.MODE_EXTERNAL:
        raise ValueError("the SSP couples the damper FMU: truck damper_mode must be 0")
    xml = ssd_xml(truck_unit, damper_unit, tp, dp, stop_time=stop_time)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".ssp.tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
        files = [("SystemStructure.ssd", xml.encode("utf-8"))]
        files += [(f"resources/{u.md.coSimulation.modelIdentifier}.fmu", u.path.read_bytes())
                  for u in (truck_unit, damper_unit)]
        for name, data in files:
            info = zipfile.ZipInfo(name, date_time=SSP_ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, data)
    tmp.replace(path)
    return path


# --------------------------------------------------------------------------- fmpy.ssp

def _typed(value_text: str, kind: str) -> Value:
    if kind == "Boolean":
        text = str(value_text).strip().lower()
        if text not in ("true", "false", "1", "0"):
            raise ValueError(f"not a Boolean: {value_text!r}")
        return text in ("true", "1")
    if kind in ("Integer", "Enumeration"):
        return int(value_text)
    return float(value_text)


def ssd_parameter_set(ssp_path: str | Path) -> "ParameterSet":
    """A fmpy ParameterSet holding every inline ParameterBinding value of the .ssd's components, named
    '<component>.<variable>' and converted to bool/int/float (workaround for quirk 1)."""
    from fmpy.ssp.ssd import Parameter, ParameterSet, find_components, read_ssd

    ssd = read_ssd(str(ssp_path))
    pset = ParameterSet(name="from SystemStructure.ssd")
    for comp in find_components(ssd.system):
        for binding in comp.parameterBindings:
            prefix = binding.prefix or ""
            for values in binding.parameterValues:
                for p in values.parameters:
                    name = p.name[len(prefix):] if prefix and p.name.startswith(prefix) else p.name
                    q = Parameter(name=f"{comp.name}.{name}")
                    q.type = p.type
                    q.value = _typed(p.value, p.type)
                    pset.parameters.append(q)
    return pset


def run_fmpy_ssp(ssp_path: str | Path, z_road: FloatArray, v_road: FloatArray, step: float,
                 n_steps: int) -> dict[str, FloatArray]:
    """Runs the .ssp with fmpy.ssp.simulate_ssp for n_steps steps of `step` s (workarounds 1-4 of the
    module docstring). Returns a dict: time (n_steps + 1 points from 0) and every connector as
    'element.connector' (e.g. 'damper.F_damper', 'truck.F_demand')."""
    from fmpy.ssp.simulation import simulate_ssp

    z_road, v_road = np.asarray(z_road, float), np.asarray(v_road, float)
    if z_road[0] != 0.0 or v_road.size < n_steps + 1:
        raise ValueError("the road must start at 0 (fmpy.ssp starts the truck's input at 0.0) and have "
                         "n_steps + 1 samples")

    def ahead(samples: FloatArray) -> Callable[[float], float]:
        # called with the accumulated time t_k; returns sample k + 1 (quirk 2)
        return lambda t: float(samples[min(int(round(t / step)) + 1, n_steps)])

    rows = simulate_ssp(str(ssp_path), start_time=0.0, stop_time=(n_steps - 0.5) * step, step_size=step,
                        parameter_set=ssd_parameter_set(ssp_path),
                        input={"z_road": ahead(z_road), "v_road": ahead(v_road)})
    if rows.size != n_steps:
        raise RuntimeError(f"fmpy.ssp made {rows.size} steps, {n_steps} expected")
    out: dict[str, FloatArray] = {"time": step * np.arange(n_steps + 1, dtype=float)}
    for name in rows.dtype.names[1:]:  # 'z_road' (system connector), 'truck.z_road', 'damper.F_damper', ...
        out[name] = np.concatenate(([0.0], rows[name].astype(float)))
    return out


# --------------------------------------------------------------------------- libcosim

def strip_system_connections(ssd_text: str) -> str:
    """The .ssd without the system-level connectors and the connections that start or end at the
    system itself: libcosim 0.0.6 fails on them ("No such node (<xmlattr>.startElement)"), and it
    does not drive system inputs anyway (the road goes in through the override manipulator)."""
    root = ET.fromstring(ssd_text)
    system = root.find(_q(SSD, "System"))
    assert system is not None, "an .ssd has a System"
    connectors = system.find(_q(SSD, "Connectors"))
    if connectors is not None:
        system.remove(connectors)
    connections = system.find(_q(SSD, "Connections"))
    assert connections is not None, "write_ssd writes the System's Connections"
    for c in list(connections):
        if c.get("startElement") is None or c.get("endElement") is None:
            connections.remove(c)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def run_libcosim(ssp_path: str | Path, z_road: FloatArray | None, v_road: FloatArray | None, step: float, n_steps: int,
                 from_ssp: bool = True, truck_fmu: str | Path | None = None, damper_fmu: str | Path | None = None,
                 truck_parameters: dict[str, Value] | None = None, damper_parameters: dict[str, Value] | None = None,
                 record: Sequence[tuple[str, Sequence[str]]] = (("truck", cosim.TRUCK_OUTPUTS),
                                                                ("damper", ("F_damper",)))) -> dict[str, FloatArray]:
    """Runs the system in libcosim with a fixed step (ns) for n_steps steps. from_ssp: load the .ssp
    (CosimExecution.from_ssp_file); else add the two FMUs as local slaves, connect them and set the
    parameters as initial values. The road is set with an override manipulator before every step
    (z_road and v_road None: the truck makes its own, and nothing is set).
    Returns a dict: time and 'element.variable' for the recorded variables, at the n_steps + 1
    communication points; the first row is NaN (libcosim initialises the slaves in its first step, and
    its last-value observer has nothing before that)."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    step_ns = int(round(step * 1e9))
    if abs(step_ns * 1e-9 - step) > 1e-15:
        raise ValueError(f"step {step} s is not a whole number of nanoseconds")
    tmpdir = None
    fmus: dict[str, str | Path] = {}
    if from_ssp:
        # libcosim reads the .ssd from a directory or an .ssp archive; give it the extracted directory
        tmpdir = tempfile.TemporaryDirectory(prefix="ssp_")
        with zipfile.ZipFile(ssp_path) as z:
            z.extractall(tmpdir.name)
        ssd_path = Path(tmpdir.name) / "SystemStructure.ssd"
        ssd_path.write_text(strip_system_connections(ssd_path.read_text(encoding="utf-8")), encoding="utf-8")
        execution = CosimExecution.from_ssp_file(ssp_path=tmpdir.name, step_size=step_ns)
        if not execution:
            from libcosimpy._internal import get_last_error_message
            raise RuntimeError(f"libcosim could not load {ssp_path}: {get_last_error_message()}")
        index = {info.name.decode(): info.index for info in execution.slave_infos()}
    else:
        execution = CosimExecution.from_step_size(step_size=step_ns)
        if truck_fmu is None or damper_fmu is None:
            raise ValueError("from_ssp=False needs truck_fmu and damper_fmu")
        fmus = {TRUCK: truck_fmu, DAMPER: damper_fmu}
        index = {}
        for name, fmu in fmus.items():
            index[name] = execution.add_local_slave(CosimLocalSlave(fmu_path=str(Path(fmu).resolve()),
                                                                    instance_name=name))
    variables = {name: {v.name.decode(): v for v in execution.slave_variables(i)} for name, i in index.items()}

    def vr(element: str, name: str) -> int:
        return int(variables[element][name].reference)

    if not from_ssp:
        for s_el, s_c, e_el, e_c in CONNECTIONS:
            if s_el is not None:
                # returns the C status (0 = success), unlike most libcosimpy calls that return a bool
                assert execution.connect_real_variables(index[s_el], vr(s_el, s_c), index[e_el], vr(e_el, e_c)) == 0
        params = {TRUCK: DEFAULT_TRUCK_PARAMETERS if truck_parameters is None else truck_parameters,
                  DAMPER: DEFAULT_DAMPER_PARAMETERS if damper_parameters is None else damper_parameters}
        for element, values in params.items():
            unit = FmuUnit.load(fmus[element])
            for name, value in values.items():
                kind = unit.variables[name].type
                i, r = index[element], vr(element, name)
                ok = (execution.boolean_initial_value(i, r, bool(value)) if kind == "Boolean" else
                      execution.integer_initial_value(i, r, int(value)) if kind in ("Integer", "Enumeration") else
                      execution.real_initial_value(i, r, float(value)))
                assert ok, f"libcosim refused the initial value {element}.{name} = {value}"

    manipulator = CosimManipulator.create_override()
    assert execution.add_manipulator(manipulator=manipulator)
    observer = CosimObserver.create_last_value()
    assert execution.add_observer(observer=observer)
    truck_index = index[TRUCK]
    road_vrs = [vr(TRUCK, "z_road"), vr(TRUCK, "v_road")]
    rec_vrs = [(index[el], [vr(el, n) for n in names]) for el, names in record]
    out: dict[str, FloatArray] = {"time": step * np.arange(n_steps + 1, dtype=float)}
    series = [np.empty((n_steps + 1, len(names))) for _, names in record]

    for k in range(n_steps + 1):
        if k > 0:
            assert execution.step(), f"libcosim step {k} failed"
            for j, (i, vrs) in enumerate(rec_vrs):
                series[j][k] = observer.last_real_values(i, vrs)
        else:
            # libcosim initialises the slaves in its first step: nothing to observe before it
            for j in range(len(series)):
                series[j][0] = np.nan
        if k < n_steps and z_road is not None and v_road is not None:
            assert manipulator.slave_real_values(truck_index, road_vrs, [float(z_road[k]), float(v_road[k])])
    execution.stop()
    for j, (el, names) in enumerate(record):
        for c, name in enumerate(names):
            out[f"{el}.{name}"] = series[j][:, c]
    if tmpdir is not None:
        tmpdir.cleanup()
    return out


def compare_own_road(path: Path, truck_parameters: dict[str, Value], args: argparse.Namespace) -> None:
    """The self-contained SSP in libcosim and ecos (nothing fed) against the compiled runner."""
    from damper_tools import ecos, runner

    n = int(round(args.duration / args.step))
    ref = runner.run_quarter_truck(truck_parameters, args.step, n, truck_fmu=args.truck_fmu,
                                   damper_fmu=args.damper_fmu)["damper.F_damper"]
    for name, res in (("libcosim (SSP)", run_libcosim(path, None, None, args.step, n)),
                      ("ecos (SSP)", ecos.run_ssp(path, None, None, args.step, n))):
        d = res["damper.F_damper"][1:] - ref[1:]
        same = np.array_equal(res["damper.F_damper"][1:], ref[1:])
        print(f"{name:15s}: max |F_damper - runner| = {np.max(np.abs(d)):.3g} N (RMS F_damper "
              f"{np.sqrt(np.mean(ref ** 2)):.0f} N), bit-identical: {same}")


def main(argv: list[str] | None = None) -> None:

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--output", type=Path, required=True, help="the .ssp to write")
    parser.add_argument("--compare", action="store_true", help="run cosim.py, fmpy.ssp and libcosim and compare")
    parser.add_argument("--road", default="minor")
    parser.add_argument("--speed", type=float, default=14.0)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--duration", type=float, default=3.0)
    parser.add_argument("--step", type=float, default=1e-3)
    parser.add_argument("--own-road", action="store_true",
                        help="a self-contained SSP: the truck makes the road of --road, --speed, --duration, --seed "
                             "and --step itself (road_source 1), the system has no inputs")
    args = parser.parse_args(argv)
    if args.own_road:
        from damper_tools import runner

        tp = {**DEFAULT_TRUCK_PARAMETERS, **runner.own_road(args.road, args.speed, args.duration, args.seed, args.step)}
        path = write_ssp(args.output, args.truck_fmu, args.damper_fmu, truck_parameters=tp,
                         stop_time=args.duration)
        print(f"ssp: wrote {path} (self-contained: the truck makes its own road)")
        if args.compare:
            compare_own_road(path, tp, args)
        return
    path = write_ssp(args.output, args.truck_fmu, args.damper_fmu)
    print(f"ssp: wrote {path}")
    if not args.compare:
        return
    case = roads.road_case(args.road, args.speed, args.duration, args.seed, step=args.step)
    n = case.t.size - 1
    ref = cosim.simulate_one(case.z_road, case.v_road, args.step, n, truck_fmu=args.truck_fmu,
                             damper_fmu=args.damper_fmu)
    f_ref = ref["damper.F_damper"]
    runs = {"fmpy.ssp": run_fmpy_ssp(path, case.z_road, case.v_road, args.step, n),
            "libcosim (SSP)": run_libcosim(path, case.z_road, case.v_road, args.step, n)}
    for name, res in runs.items():  # from the first step on (libcosim has no row before it)
        d = res["damper.F_damper"][1:] - f_ref[1:]
        print(f"{name:15s}: max |F_damper - cosim.py| = {np.max(np.abs(d)):.3g} N, RMS "
              f"{np.sqrt(np.mean(d ** 2)):.3g} N (RMS F_damper {np.sqrt(np.mean(f_ref ** 2)):.0f} N), "
              f"bit-identical: {np.array_equal(res['damper.F_damper'][1:], f_ref[1:])}")


if __name__ == "__main__":
    main()
