"""One FMU instance driven through fmpy's low-level API (fmpy.fmi2.FMU2Slave, fmpy.fmi3.FMU3Slave).

For more control than fmpy.simulate_fmu gives (several instances of one FMU, a co-simulation
master, FMU states, illegal calls): load the FMU once, then create `Slave`s from it.

    unit = FmuUnit.load("target/fmu/SemiActiveDamper.fmu")
    damper = Slave(unit, "damper")
    damper.initialize(0.0, tare_load_cell=True)
    damper.step(1e-3, v_damper=0.1, F_demand=2e3)
    force = damper.get(["F_damper"])[0]
    damper.free()

`drive(slave, steps, inputs_at)` steps a slave through a list of step lengths and records its outputs.

FMI 2.0 and FMI 3.0 FMUs are driven alike: an FMI 3.0 unit's Float64, Int32 and Boolean variables are
set and read through fmi3Set/GetFloat64 and their kin, its experiment given to
fmi3EnterInitializationMode.
"""

import atexit
import shutil
import sys
import tempfile
from collections.abc import Callable, Iterable, Sequence
from ctypes import Array, c_double, c_uint
from pathlib import Path
from typing import ClassVar

import numpy as np
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2Real,
    fmi2ValueReference,
)
from fmpy.fmi3 import FMU3Slave
from fmpy.model_description import ModelVariable

from damper_tools import FloatArray

# A value of an FMI 2.0 Real, Integer, Enumeration or Boolean variable (FMI 3.0 Float64, Int32, Boolean).
Value = float | int | bool
REAL_TYPES = ("Real", "Float64")
INTEGER_TYPES = ("Integer", "Enumeration", "Int32")
STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
WARNING, ERROR = 1, 3


class FmuUnit:
    """An FMU extracted once (to a temporary directory removed at exit), with its variables."""

    _cache: ClassVar[dict[tuple[Path, int | None], "FmuUnit"]] = {}

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path).resolve()
        if not self.path.is_file():
            raise FileNotFoundError(f"{self.path}: no such FMU (python3 scripts/package_fmu.py and "
                                    f"scripts/package_truck.py build them)")
        self.md = read_model_description(str(self.path))
        self.unzipdir = Path(tempfile.mkdtemp(prefix=f"{self.path.stem}_"))
        atexit.register(shutil.rmtree, self.unzipdir, True)
        extract(str(self.path), unzipdir=str(self.unzipdir))
        self.variables = {v.name: v for v in self.md.modelVariables}
        self.fmi_version = int(self.md.fmiVersion.split(".")[0])

    @classmethod
    def load(cls, path: str | Path) -> "FmuUnit":
        """The unit of `path`, extracted again only when the file has changed."""
        key = Path(path).resolve()
        stamp = key.stat().st_mtime_ns if key.is_file() else None
        if (key, stamp) not in cls._cache:
            cls._cache[(key, stamp)] = cls(key)
        return cls._cache[(key, stamp)]

    def variable(self, name: str) -> ModelVariable:
        try:
            return self.variables[name]
        except KeyError:
            raise KeyError(f"{self.path.name} has no variable {name!r}") from None

    def vr(self, name: str) -> int:
        return int(self.variable(name).valueReference)

    def outputs(self) -> list[str]:
        """Names of the Real outputs, in the order of modelDescription.xml."""
        return [v.name for v in self.md.modelVariables if v.causality == "output" and v.type in REAL_TYPES]

    def parameters(self) -> dict[str, float | int | bool]:
        """Every parameter's start value from modelDescription.xml, typed (Real, Integer, Boolean)."""
        cast: dict[str, Callable[[str], Value]] = {"Boolean": lambda s: s == "true", "Integer": int, "Real": float,
                                                   "Int32": int, "Float64": float}
        return {v.name: cast[v.type](v.start) for v in self.md.modelVariables if v.causality == "parameter"}


class Slave:
    """One FMU2Slave (or FMU3Slave) instance of a unit, with a logger that keeps the messages in
    `messages` as (status, category, text). Messages of status Warning and worse are printed to
    stderr (pytest shows them when a test fails) unless `echo` is false, all of them with logging_on.
    Variables are set and read by name; `time` is where the last step ended."""

    def __init__(self, unit: FmuUnit, instance_name: str, logging_on: bool = False, echo: bool = True) -> None:
        self.unit = unit
        self.name = instance_name
        self.logging_on = logging_on
        self.echo = echo
        self.messages: list[tuple[int, str, str]] = []
        self.time = 0.0
        # in Step Mode: fmi2Terminate is allowed there (and only there) before fmi2FreeInstance
        self.stepping = False
        # Value references and a value buffer per list of Real variables: one fmi2Get/SetReal call
        # per list, without building them again at every step of a master.
        self._reals: dict[tuple[str, ...], tuple[Array[c_uint], Array[c_double]]] = {}
        if unit.fmi_version == 3:
            self._instantiate3(unit, instance_name, logging_on)
            return
        self.fmu: FMU2Slave | FMU3Slave = FMU2Slave(
            guid=unit.md.guid, unzipDirectory=str(unit.unzipdir),
            modelIdentifier=unit.md.coSimulation.modelIdentifier, instanceName=instance_name)
        # The callbacks must live as long as the instance.
        self._logger = fmi2CallbackLoggerTYPE(self._log)
        self._callbacks = fmi2CallbackFunctions()
        self._callbacks.logger = self._logger
        self._callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self._callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        # No fmpy.logging.addLoggerProxy (which formats printf-style messages in C): it keeps one
        # logger for the whole process, so every instance's messages reached the instance made
        # last. These FMUs pass the message as a format string without arguments, '%' as '%%'.
        self.fmu.instantiate(callbacks=self._callbacks, loggingOn=logging_on)

    def _instantiate3(self, unit: FmuUnit, instance_name: str, logging_on: bool) -> None:
        """An FMU3Slave; its logger (FMI 3.0's: no instance name, plain text with '#' as '##')."""
        fmu3 = FMU3Slave(guid=unit.md.guid, unzipDirectory=str(unit.unzipdir),
                         modelIdentifier=unit.md.coSimulation.modelIdentifier, instanceName=instance_name)
        self.fmu = fmu3

        def log3(env: object, status: int, category: bytes, message: bytes) -> None:
            self._log(env, b"", status, category, message)

        # fmpy keeps the callback it wraps around log3 alive with the instance
        fmu3.instantiate(loggingOn=logging_on, logMessage=log3)

    def _log(self, env: object, instance_name: bytes, status: int, category: bytes, message: bytes) -> None:
        escaped = ("%%", "%") if self.unit.fmi_version == 2 else ("##", "#")
        text = message.decode("utf-8", "replace").replace(*escaped) if message else ""
        cat = category.decode("utf-8", "replace") if category else ""
        self.messages.append((status, cat, text))
        if (status >= WARNING and self.echo) or self.logging_on:
            label = STATUS[status] if 0 <= status < len(STATUS) else status
            print(f"[{self.name}] {label} {cat}: {text}", file=sys.stderr)

    def errors(self) -> list[tuple[int, str, str]]:
        """Messages logged with status Error or worse."""
        return [m for m in self.messages if m[0] >= ERROR]

    def vr(self, name: str) -> int:
        return self.unit.vr(name)

    def _real_buffers(self, names: Iterable[str]) -> tuple[Array[c_uint], Array[c_double]]:
        key = tuple(names)
        if key not in self._reals:
            vrs = (fmi2ValueReference * len(key))(*[self.unit.vr(n) for n in key])
            self._reals[key] = (vrs, (fmi2Real * len(key))())
        return self._reals[key]

    def set(self, **values: Value) -> None:
        """Sets variables by name, each with the set function of its type (the Reals in one call)."""
        reals = []
        for name, value in values.items():
            var = self.unit.variable(name)
            if var.type in INTEGER_TYPES:
                if isinstance(self.fmu, FMU3Slave):
                    self.fmu.setInt32([var.valueReference], [int(value)])
                else:
                    self.fmu.setInteger([var.valueReference], [int(value)])
            elif var.type == "Boolean":
                self.fmu.setBoolean([var.valueReference], [bool(value)])
            else:
                reals.append(name)
        if reals:
            vrs, buf = self._real_buffers(reals)
            buf[:] = [float(values[n]) for n in reals]
            if isinstance(self.fmu, FMU3Slave):
                self.fmu.fmi3SetFloat64(self.fmu.component, vrs, len(buf), buf, len(buf))
            else:
                self.fmu.fmi2SetReal(self.fmu.component, vrs, len(buf), buf)

    def get(self, names: Sequence[str] | None = None) -> FloatArray:
        """Values of Real variables (default: all Real outputs)."""
        vrs, buf = self._real_buffers(self.unit.outputs() if names is None else names)
        if isinstance(self.fmu, FMU3Slave):
            self.fmu.fmi3GetFloat64(self.fmu.component, vrs, len(buf), buf, len(buf))
        else:
            self.fmu.fmi2GetReal(self.fmu.component, vrs, len(buf), buf)
        return np.array(buf[:])

    def setup(self, start_time: float = 0.0, stop_time: float | None = None, **start_values: Value) -> None:
        """The experiment and start values, then Initialization Mode (FMI 2.0: fmi2SetupExperiment
        first; FMI 3.0: the times go to fmi3EnterInitializationMode)."""
        if isinstance(self.fmu, FMU3Slave):
            self.set(**start_values)
            self.fmu.enterInitializationMode(startTime=start_time, stopTime=stop_time)
        else:
            self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)
            self.set(**start_values)
            self.fmu.enterInitializationMode()
        self.time = start_time

    def initialize(self, start_time: float = 0.0, stop_time: float | None = None,
                   **start_values: Value) -> None:
        """Experiment, start values and parameters, initialization mode; afterwards the slave is at
        start_time."""
        self.setup(start_time, stop_time, **start_values)
        self.fmu.exitInitializationMode()
        self.stepping = True

    def step(self, h: float, t: float | None = None, **inputs: Value) -> None:
        """Sets the inputs, then one doStep of length h from t (default: where the last step ended).
        A master passes t = start + k h so that the time points are not accumulated."""
        self.set(**inputs)
        t = self.time if t is None else t
        self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        self.time = t + h

    def free(self) -> None:
        """Terminates an instance in Step Mode that has reported no error, then frees it. After an
        error the standard allows freeing (or resetting) it, not terminating it: an instance that
        refused to initialise is still in Initialization Mode."""
        try:
            if self.stepping and not self.errors():
                self.fmu.terminate()
        finally:
            self.fmu.freeInstance()


def drive(slave: Slave, steps: Iterable[float], inputs_at: Callable[[float], dict[str, float]],
          names: Sequence[str] | None = None) -> tuple[FloatArray, FloatArray]:
    """Steps a slave through the step lengths `steps`, setting inputs_at(t) before each step;
    returns (times, outputs) recorded after every step (outputs: `names`, default all Real outputs)."""
    times, rows = [], []
    for h in steps:
        slave.step(h, **inputs_at(slave.time))
        times.append(slave.time)
        rows.append(slave.get(names))
    return np.array(times), np.array(rows)
