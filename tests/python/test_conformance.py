"""Conformance of the packaged FMUs, FMI 2.0 and FMI 3.0, beyond what fmpy's validation checks.

- Each binary (linux64 and win64; FMI 3.0: x86_64-linux and x86_64-windows) exports exactly its
  standard's Co-Simulation functions: nothing foreign (a symbol of a linked C helper would clash with
  a host's or another FMU's), nothing missing. The Windows one needs no DLL that Windows does not
  have (no MinGW runtime).
- The Linux binary takes no transcendental function from the C library: the model's come from the
  `libm` crate, so that both platforms compute the same bits (test_win64.py compares them).
- ModelStructure tells the truth: for every output, the inputs that change it *without* a doStep
  (direct feedthrough) are probed on the running FMU and compared with the declared
  `dependencies`. A master that trusts a declared "no dependency" reads a stale value otherwise.
  The same for `InitialUnknowns`: the inputs and parameters (the knowns of Initialization Mode)
  that change each output there.
"""

import re
import shutil
import subprocess
import zipfile
from xml.etree import ElementTree

import numpy as np
import pytest
from fmpy import read_model_description

from damper_tools.fmu import FmuUnit, Slave

# FMI 2.0.4, section 2.1 (fmi2Functions.h): the common functions and those of Co-Simulation.
CO_SIMULATION_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal", "fmi2GetInteger",
    "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
    "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
    "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus",
}


# FMI 3.0 (fmi3Functions.h): every function of the standard, Co-Simulation's with those of Model
# Exchange and Scheduled Execution, which a Co-Simulation FMU exports too (and refuses).
FMI3_FUNCTIONS = {"fmi3" + name for name in """
    GetVersion SetDebugLogging InstantiateModelExchange InstantiateCoSimulation InstantiateScheduledExecution
    FreeInstance EnterInitializationMode ExitInitializationMode EnterEventMode Terminate Reset
    GetFloat32 GetFloat64 GetInt8 GetUInt8 GetInt16 GetUInt16 GetInt32 GetUInt32 GetInt64 GetUInt64
    GetBoolean GetString GetBinary GetClock SetFloat32 SetFloat64 SetInt8 SetUInt8 SetInt16 SetUInt16
    SetInt32 SetUInt32 SetInt64 SetUInt64 SetBoolean SetString SetBinary SetClock
    GetNumberOfVariableDependencies GetVariableDependencies GetFMUState SetFMUState FreeFMUState
    SerializedFMUStateSize SerializeFMUState DeserializeFMUState GetDirectionalDerivative
    GetAdjointDerivative EnterConfigurationMode ExitConfigurationMode GetIntervalDecimal
    GetIntervalFraction GetShiftDecimal GetShiftFraction SetIntervalDecimal SetIntervalFraction
    SetShiftDecimal SetShiftFraction EvaluateDiscreteStates UpdateDiscreteStates EnterContinuousTimeMode
    CompletedIntegratorStep SetTime SetContinuousStates GetContinuousStateDerivatives GetEventIndicators
    GetContinuousStates GetNominalsOfContinuousStates GetNumberOfEventIndicators
    GetNumberOfContinuousStates EnterStepMode GetOutputDerivatives DoStep ActivateModelPartition
    """.split()}
FUNCTIONS = {"2": CO_SIMULATION_FUNCTIONS, "3": FMI3_FUNCTIONS}
# Each FMI 2.0 platform folder's FMI 3.0 name.
PLATFORM_TUPLES = {"linux64": "x86_64-linux", "win64": "x86_64-windows"}

# DLLs of every 64-bit Windows since Windows 10 (bcryptprimitives.dll: ProcessPrng, which Rust's
# standard library imports since Rust 1.78, and which sets that floor).
WINDOWS_SYSTEM_DLLS = {"kernel32.dll", "ntdll.dll", "msvcrt.dll", "userenv.dll", "ws2_32.dll",
                       "bcryptprimitives.dll", "api-ms-win-core-synch-l1-2-0.dll"}


def extract_binary(fmu_path, platform, work_dir):
    """The binary of `platform` (an FMI 2.0 platform folder) of an FMI 2.0 or 3.0 FMU."""
    md = read_model_description(str(fmu_path))
    suffix = {"linux64": ".so", "win64": ".dll"}[platform]
    folder = platform if md.fmiVersion == "2.0" else PLATFORM_TUPLES[platform]
    with zipfile.ZipFile(fmu_path) as z:
        return z.extract(f"binaries/{folder}/{md.coSimulation.modelIdentifier}{suffix}", work_dir / md.fmiVersion)


def linux_exports(library):
    """Defined dynamic symbols of an ELF library (binutils' nm, which comes with the C toolchain
    that links Rust)."""
    out = subprocess.run([shutil.which("nm") or "nm", "-D", "--defined-only", library],
                         check=True, capture_output=True, text=True).stdout
    return {line.split()[-1] for line in out.splitlines() if line.strip()}


# The C library's functions whose results differ in the last bit from one C library to another (sqrt,
# fabs and the like are exact everywhere).
C_MATH = {"sin", "cos", "tan", "sincos", "asin", "acos", "atan", "atan2", "sinh", "cosh", "tanh",
          "asinh", "acosh", "atanh", "exp", "exp2", "expm1", "log", "log2", "log10", "log1p", "pow",
          "cbrt", "hypot", "erf", "erfc", "lgamma", "tgamma"}


def linux_imports(library):
    """Undefined dynamic symbols of an ELF library, without their versions (binutils' nm)."""
    out = subprocess.run([shutil.which("nm") or "nm", "-D", "--undefined-only", library],
                         check=True, capture_output=True, text=True).stdout
    return {line.split()[-1].split("@")[0] for line in out.splitlines() if line.strip()}


def newest_glibc(library):
    """The newest glibc symbol version an ELF library needs (binutils' objdump)."""
    out = subprocess.run([shutil.which("objdump") or "objdump", "-T", library],
                         check=True, capture_output=True, text=True).stdout
    return max(tuple(int(x) for x in v.split(".")) for v in re.findall(r"GLIBC_(\d+(?:\.\d+)+)", out))


def windows_exports_and_imports(library):
    """The export names and the imported DLLs of a PE library (MinGW-w64's objdump, which comes
    with the cross-linker that scripts/setup.sh installs)."""
    objdump = shutil.which("x86_64-w64-mingw32-objdump")
    assert objdump, "x86_64-w64-mingw32-objdump not found: bash scripts/setup.sh installs MinGW-w64"
    out = subprocess.run([objdump, "-p", library], check=True, capture_output=True, text=True).stdout
    table = out.split("[Ordinal/Name Pointer] Table", 1)[1].split("\n\n", 1)[0]
    exports = {line.split()[-1] for line in table.splitlines() if line.strip().startswith("[")}
    imports = {line.split(":", 1)[1].strip().lower() for line in out.splitlines() if "DLL Name:" in line}
    return exports, imports


FIXTURES = {"damper": "fmu", "truck": "truck_fmu", "full_truck": "full_truck_fmu"}
# The same FMUs' FMI 3.0 builds.
FIXTURES3 = {which: f"{fixture}3" for which, fixture in FIXTURES.items()}
# (which, FMI version) → the fixture of its FMU.
BOTH = {(which, "2"): fixture for which, fixture in FIXTURES.items()} | {
    (which, "3"): fixture for which, fixture in FIXTURES3.items()}


@pytest.mark.parametrize("platform", ["linux64", "win64"])
@pytest.mark.parametrize("which,version", BOTH)
def test_the_binary_exports_exactly_its_standard_s_co_simulation_functions(which, version, platform, work_dir,
                                                                            request):
    if platform == "win64":
        request.getfixturevalue("win64")
    library = extract_binary(request.getfixturevalue(BOTH[which, version]), platform, work_dir)
    expected = FUNCTIONS[version]
    if platform == "linux64":
        symbols = linux_exports(library)
        assert newest_glibc(library) <= (2, 34), "the docs promise glibc 2.34 or later"
        assert linux_imports(library) & C_MATH == set(), "math from the C library: use the libm crate"
    else:
        symbols, imports = windows_exports_and_imports(library)
        assert imports - WINDOWS_SYSTEM_DLLS == set(), "the Windows binary needs DLLs that Windows lacks"
    assert symbols - expected == set(), "foreign symbols exported"
    assert expected - symbols == set(), "FMI functions missing"


# Each probe: start values, the inputs held while the FMU runs into a generic state, and a
# perturbation per input large enough to move any output that depends on it directly.
DAMPER_PROBES = [
    ({}, {"v_damper": 0.31, "F_demand": 6e3, "x_spool_demand": 1.5e-3, "T_oil": 330.0}),
    ({"effect_seal_friction": True, "effect_viscous_friction": True},
     {"v_damper": -0.22, "F_demand": -4e3, "x_spool_demand": 1.5e-3, "T_oil": 330.0}),
    ({"control_mode": 1}, {"v_damper": 0.15, "F_demand": 0.0, "x_spool_demand": 1.2e-3, "T_oil": 330.0}),
    # the measured oil temperature acts on the gas and the viscous friction at once
    ({"effect_oil_temperature": True, "effect_viscous_friction": True},
     {"v_damper": 0.25, "F_demand": 5e3, "x_spool_demand": 1.5e-3, "T_oil": 330.0}),
    # a passive damper: the valve held, a rebound and a compression valve
    ({"control_mode": 2, "x_spool_start": 0.0, "effect_rebound_valve": True, "effect_compression_valve": True,
      "effect_oil_temperature": True},
     {"v_damper": -0.2, "F_demand": 0.0, "x_spool_demand": 0.0, "T_oil": 330.0}),
]
DAMPER_DELTA = {"v_damper": 0.05, "F_demand": 2e3, "x_spool_demand": 4e-4, "T_oil": 15.0}
TRUCK_PROBES = [
    ({"damper_mode": mode, "c_tyre": c_tyre}, {"z_road": 0.012, "v_road": 0.08, "F_damper": 1.5e3})
    for mode in (0, 1, 2) for c_tyre in (0.0, 2e3)
]
TRUCK_DELTA = {"z_road": 0.01, "v_road": 0.1, "F_damper": 2e3}
CORNERS = ("front_left", "front_right", "drive1_left", "drive1_right", "drive2_left", "drive2_right")
FULL_TRUCK_PROBES = [
    ({"damper_mode": mode, "c_tyre": c_tyre},
     {f"{c}.{name}": value * (1 + 0.1 * k) for k, c in enumerate(CORNERS)
      for name, value in (("z_road", 0.012), ("v_road", 0.08), ("F_damper", 1.5e3))})
    for mode in (0, 1, 2) for c_tyre in (0.0, 2e3)
]
FULL_TRUCK_DELTA = {f"{c}.{name}": TRUCK_DELTA[name] for c in CORNERS for name in TRUCK_DELTA}
PROBES = {"damper": (DAMPER_PROBES, DAMPER_DELTA), "truck": (TRUCK_PROBES, TRUCK_DELTA),
          "full_truck": (FULL_TRUCK_PROBES, FULL_TRUCK_DELTA)}


def observed_feedthrough(unit, start_values, inputs, delta):
    """{output: set of inputs that change it between two doSteps}, probed on one running instance."""
    slave = Slave(unit, "probe")
    outputs = [u.variable.name for u in unit.md.outputs]
    slave.initialize(**start_values)
    for k in range(40):
        # vary the inputs so the state is generic, then hold them
        slave.step(1e-3, **{name: value * (1.0 + 0.3 * np.sin(0.7 * k)) for name, value in inputs.items()})
    slave.set(**inputs)
    before = slave.get(outputs)
    found = {name: set() for name in outputs}
    for name, value in inputs.items():
        slave.set(**{name: value + delta[name]})
        after = slave.get(outputs)
        slave.set(**{name: value})
        np.testing.assert_array_equal(slave.get(outputs), before, err_msg=f"outputs not restored after {name}")
        for out, b, a in zip(outputs, before, after, strict=True):
            if a != b:
                found[out].add(name)
    slave.free()
    return found


def declared_feedthrough(md):
    return {u.variable.name: {v.name for v in (u.dependencies or [])} for u in md.outputs}


# Configurations for Initialization Mode: those above, from a generic start state (a start value
# of 0 would hide what multiplies it), and the effects and modes that put more inputs into the
# initial outputs (the end stops touched at the start stroke, the gas charge off).
DAMPER_START = {"x_damper_start": 0.021, "x_spool_start": 1.7e-3}
TRUCK_START = {"z_body_start": 0.011, "v_body_start": 0.05, "z_axle_start": -0.004, "v_axle_start": -0.12}
FULL_TRUCK_START = {"z_body_start": 0.011, "pitch_start": 0.003, "roll_start": -0.002}
INITIAL_PROBES = {
    "damper": [({**DAMPER_START, **start}, inputs) for start, inputs in DAMPER_PROBES] + [
        ({"effect_end_stops": True, "x_damper_start": 0.092, "tare_load_cell": True, "effect_piston_leakage": True},
         {"v_damper": 0.1, "F_demand": 1e3, "x_spool_demand": 1e-3, "T_oil": 300.0}),
        ({**DAMPER_START, "effect_gas_charge": False, "effect_mount_compliance": False, "force_controller": 1},
         {"v_damper": -0.1, "F_demand": -1e3, "x_spool_demand": 1e-3, "T_oil": 300.0}),
    ],
    "truck": [({**TRUCK_START, **start}, inputs) for start, inputs in TRUCK_PROBES]
    + [({**TRUCK_START, "damper_mode": 3}, {"z_road": 0.012, "v_road": 0.08, "F_damper": 1.5e3})],
    "full_truck": [({**FULL_TRUCK_START, **start}, inputs) for start, inputs in FULL_TRUCK_PROBES],
}


def observed_initial_feedthrough(unit, start_values, inputs, delta):
    """{output: set of inputs that change it in Initialization Mode}, probed on one instance."""
    slave = Slave(unit, "probe")
    outputs = [u.variable.name for u in unit.md.outputs]
    slave.setup(0.0, **start_values)
    slave.set(**inputs)
    before = slave.get(outputs)
    found = {name: set() for name in outputs}
    for name, value in inputs.items():
        slave.set(**{name: value + delta[name]})
        after = slave.get(outputs)
        slave.set(**{name: value})
        np.testing.assert_array_equal(slave.get(outputs), before, err_msg=f"outputs not restored after {name}")
        for out, b, a in zip(outputs, before, after, strict=True):
            if a != b:
                found[out].add(name)
    slave.fmu.exitInitializationMode()
    slave.free()
    return found


@pytest.mark.parametrize("which,version", BOTH)
def test_declared_initial_dependencies_are_the_probed_inputs_and_every_parameter(which, version, request):
    """In Initialization Mode the knowns are the inputs and the parameters. The inputs an output
    depends on there are probed as at communication points; every parameter is declared, since
    the model's outputs at rest come from most of them and a parameter never closes a loop."""
    path = request.getfixturevalue(BOTH[which, version])
    _, delta = PROBES[which]
    unit = FmuUnit.load(path)
    assert_every_unknown_declares_its_dependencies(path)
    parameters = {v.name for v in unit.md.modelVariables if v.causality == "parameter"}
    declared = {u.variable.name: {v.name for v in (u.dependencies or [])} for u in unit.md.initialUnknowns}
    union = {name: set() for name in declared}
    for start_values, inputs in INITIAL_PROBES[which]:
        for out, deps in observed_initial_feedthrough(unit, start_values, inputs, delta).items():
            union[out] |= deps
    for out, deps in declared.items():
        assert deps & parameters == parameters, f"{out}: parameters {sorted(parameters - deps)} not declared"
        assert deps - parameters == union[out], \
            f"{out}: declares the inputs {sorted(deps - parameters)}, Initialization Mode shows {sorted(union[out])}"


def assert_every_unknown_declares_its_dependencies(path):
    """Every output and initial unknown declares its dependencies explicitly (no attribute means
    "depends on every known"): FMI 2.0's Unknown elements, FMI 3.0's Output and InitialUnknown."""
    with zipfile.ZipFile(path) as z:
        root = ElementTree.fromstring(z.read("modelDescription.xml"))
    fmi2 = root.get("fmiVersion") == "2.0"
    paths = (["ModelStructure/Outputs/Unknown", "ModelStructure/InitialUnknowns/Unknown"] if fmi2
             else ["ModelStructure/Output", "ModelStructure/InitialUnknown"])
    for xpath in paths:
        unknowns = list(root.iterfind(xpath))
        assert unknowns and all("dependencies" in u.attrib for u in unknowns), xpath


@pytest.mark.parametrize("which,version", BOTH)
def test_declared_output_dependencies_match_the_probed_feedthrough(which, version, request):
    path = request.getfixturevalue(BOTH[which, version])
    probes, delta = PROBES[which]
    unit = FmuUnit.load(path)
    declared = declared_feedthrough(unit.md)
    assert_every_unknown_declares_its_dependencies(path)
    union = {name: set() for name in declared}
    for start_values, inputs in probes:
        observed = observed_feedthrough(unit, start_values, inputs, delta)
        for out, deps in observed.items():
            assert deps <= declared[out], \
                f"{out} changes with {sorted(deps - declared[out])} without a doStep ({start_values}), " \
                f"but declares dependencies {sorted(declared[out])}"
            union[out] |= deps
    # and nothing is declared that no configuration shows (a needless algebraic loop for masters)
    assert union == declared
