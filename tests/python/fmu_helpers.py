"""Small helpers for driving the FMU through fmpy's low-level API (fmpy.fmi2.FMU2Slave).

A test that needs more control than fmpy.simulate_fmu (several instances, FMU states, illegal
calls) creates a `Slave`: an FMU2Slave whose log messages are collected in `slave.messages`
and printed (pytest shows them when a test fails).
"""

from ctypes import byref

import numpy as np
from fmpy import calloc, free
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy

STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
OUTPUTS = ("F_damper", "x_spool", "i_sol", "p_ext", "p_comp", "p_reservoir", "Q_valve", "x_spool_ref",
           "x_damper", "F_demand_clipped", "F_flow", "delta_mount")


class Slave:
    """One FMU instance from an extracted FMU directory, with a logger that keeps the messages."""

    def __init__(self, unzipdir, model_description, instance_name, logging_on=True):
        self.md = model_description
        self.vr = {v.name: v.valueReference for v in model_description.modelVariables}
        self.types = {v.name: v.type for v in model_description.modelVariables}
        self.messages = []  # (status, category, message)
        self.fmu = FMU2Slave(guid=model_description.guid, unzipDirectory=str(unzipdir),
                             modelIdentifier=model_description.coSimulation.modelIdentifier,
                             instanceName=instance_name)
        # Keep the callbacks alive as long as the instance.
        self._logger = fmi2CallbackLoggerTYPE(self._log)
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = self._logger
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(self.callbacks))
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=logging_on)
        self.time = None

    def _log(self, env, instance_name, status, category, message):
        text = message.decode("utf-8", "replace") if message else ""
        cat = category.decode("utf-8", "replace") if category else ""
        name = instance_name.decode("utf-8", "replace") if instance_name else ""
        self.messages.append((status, cat, text))
        print(f"[{name}] {STATUS[status] if 0 <= status < len(STATUS) else status} {cat}: {text}")

    def errors(self):
        """Messages logged with status Error or worse."""
        return [m for m in self.messages if m[0] >= 3]

    def set(self, **values):
        for name, value in values.items():
            if self.types[name] == "Integer":
                self.fmu.setInteger([self.vr[name]], [int(value)])
            elif self.types[name] == "Boolean":
                self.fmu.setBoolean([self.vr[name]], [bool(value)])
            else:
                self.fmu.setReal([self.vr[name]], [float(value)])

    def get(self, names=OUTPUTS):
        return np.array(self.fmu.getReal([self.vr[n] for n in names]))

    def initialize(self, start_time=0.0, stop_time=None, **start_values):
        """setupExperiment, parameters, initialization mode; afterwards the slave is at start_time."""
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)
        self.set(**start_values)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.time = start_time

    def step(self, h, **inputs):
        """Sets the inputs, then one doStep of length h from the present time."""
        self.set(**inputs)
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=h)
        self.time += h

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def drive(slave, steps, inputs_at, names=OUTPUTS):
    """Steps a slave through the step lengths `steps`, setting inputs_at(t) before each step;
    returns (times, outputs) recorded after every step."""
    times, rows = [], []
    for h in steps:
        slave.step(h, **inputs_at(slave.time))
        times.append(slave.time)
        rows.append(slave.get(names))
    return np.array(times), np.array(rows)
