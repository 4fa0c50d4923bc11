"""A short run of random FMI call sequences against the packaged binaries through ctypes, as a C
importer calls them (the long run is Rust's tests/call_sequences.rs, docs/robustness.md): no
fmi2Fatal, no OK step with a bad step size, finite values whenever a getter says OK, the FMU takes
back what it serialized and refuses the other FMU's states, and no call runs over 1 s."""

import ctypes as ct
import math
import random
import threading
import time
import zipfile

import pytest
from fmpy import read_model_description

OK, DISCARD, ERROR, FATAL = 0, 2, 3, 4
HANG = 1.0  # s: a call longer than this is a hang (the criterion)
SEQUENCES = 300


class Binary:
    """One FMU's shared library and model description."""

    def __init__(self, fmu, tmp):
        md = read_model_description(str(fmu))
        name = md.coSimulation.modelIdentifier
        with zipfile.ZipFile(fmu) as z:
            z.extract(f"binaries/linux64/{name}.so", tmp)
        self.lib = ct.CDLL(str(tmp / "binaries" / "linux64" / f"{name}.so"))
        self.guid = md.guid.encode()
        self.reals = [v for v in md.modelVariables if v.type == "Real"]
        self.outputs = [v.valueReference for v in self.reals if v.causality == "output"]
        self.params = [v for v in self.reals if v.causality in ("parameter", "input")]
        c, p, d, u, s = ct.c_void_p, ct.POINTER, ct.c_double, ct.c_uint, ct.c_size_t
        for fn, args in {
            "fmi2Instantiate": [ct.c_char_p, ct.c_int, ct.c_char_p, ct.c_char_p, c, ct.c_int, ct.c_int],
            "fmi2FreeInstance": [c],
            "fmi2SetupExperiment": [c, ct.c_int, d, d, ct.c_int, d],
            "fmi2EnterInitializationMode": [c], "fmi2ExitInitializationMode": [c],
            "fmi2Terminate": [c], "fmi2Reset": [c],
            "fmi2GetReal": [c, p(u), s, p(d)], "fmi2SetReal": [c, p(u), s, p(d)],
            "fmi2DoStep": [c, d, d, ct.c_int],
            "fmi2GetFMUstate": [c, p(c)], "fmi2SetFMUstate": [c, c], "fmi2FreeFMUstate": [c, p(c)],
            "fmi2SerializedFMUstateSize": [c, c, p(s)], "fmi2SerializeFMUstate": [c, c, ct.c_char_p, s],
            "fmi2DeSerializeFMUstate": [c, ct.c_char_p, s, p(c)],
        }.items():
            f = getattr(self.lib, fn)
            f.argtypes = args
            f.restype = c if fn == "fmi2Instantiate" else (None if fn == "fmi2FreeInstance" else ct.c_int)

    running = None  # (start time, call) of the call under way, for the watchdog

    def call(self, fn, *args):
        Binary.running = (time.perf_counter(), f"{fn}{args[1:]}")
        result = getattr(self.lib, fn)(*args)
        Binary.running = None
        assert result != FATAL, f"{fn}{args[1:]}: fmi2Fatal (a panic)"
        return result

    def instantiate(self):
        # a NULL callbacks struct: the FMU logs nothing
        c = self.call("fmi2Instantiate", b"py", 1, self.guid, None, None, 0, 0)
        assert c
        return c

    def state(self, c):
        s = ct.c_void_p()
        assert self.call("fmi2GetFMUstate", c, ct.byref(s)) == OK
        return s

    def serialize(self, c, s):
        size = ct.c_size_t()
        assert self.call("fmi2SerializedFMUstateSize", c, s, ct.byref(size)) == OK
        buffer = ct.create_string_buffer(size.value)
        assert self.call("fmi2SerializeFMUstate", c, s, buffer, size.value) == OK
        return buffer.raw

    def deserialize(self, c, data):
        s = ct.c_void_p()
        status = self.call("fmi2DeSerializeFMUstate", c, data, len(data), ct.byref(s))
        if status == OK:
            assert self.call("fmi2FreeFMUstate", c, ct.byref(s)) == OK
        return status


@pytest.fixture(scope="module")
def binaries(fmu, truck_fmu, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("so")
    return Binary(fmu, tmp / "damper"), Binary(truck_fmu, tmp / "truck")


def value(rng, v):
    lo = float(v.min) if v.min is not None else -1e3
    hi = float(v.max) if v.max is not None else 1e3
    return rng.choice([math.nan, math.inf, -math.inf, 1e308, 5e-324, -1e300, lo, hi,
                       lo + (hi - lo) * rng.random(), lo + (hi - lo) * rng.random()])


def one_sequence(rng, b):
    c = b.instantiate()
    n = len(b.outputs)
    vrs = (ct.c_uint * n)(*b.outputs)
    values = (ct.c_double * n)()
    t, initialised = 0.0, False
    for _ in range(rng.randrange(10, 40)):
        op = rng.random()
        if op < 0.25:
            v = rng.choice(b.params)
            b.call("fmi2SetReal", c, ct.byref(ct.c_uint(v.valueReference)), 1, ct.byref(ct.c_double(value(rng, v))))
        elif op < 0.35 and not initialised:
            b.call("fmi2SetupExperiment", c, 0, 0.0, 0.0, 0, 0.0)
            b.call("fmi2EnterInitializationMode", c)
            initialised = b.call("fmi2ExitInitializationMode", c) == OK
        elif op < 0.75:
            h = rng.choice([1e-3, 5e-4, 2e-3, 0.0, -1e-3, math.nan, math.inf, 1e10, 1e100, 1.7e308, 5e-324])
            status = b.call("fmi2DoStep", c, t, h, 0)
            if status == OK:
                assert h > 0 and math.isfinite(h), f"DoStep OK with step {h}"
                t += h
                assert b.call("fmi2GetReal", c, vrs, n, values) == OK
                assert all(math.isfinite(x) for x in values), list(values)
            elif status == DISCARD:
                initialised = False  # StepFailed: no more steps
        elif op < 0.85:
            if b.call("fmi2GetReal", c, vrs, n, values) == OK:
                assert all(math.isfinite(x) for x in values), list(values)
        elif op < 0.95:
            s = b.state(c)
            data = b.serialize(c, s)
            assert b.deserialize(c, data) == OK, "the FMU refused a state it serialized"
            mutated = bytearray(data)
            mutated[rng.randrange(len(data))] ^= 1 << rng.randrange(8)
            b.deserialize(c, bytes(mutated))
            assert b.call("fmi2FreeFMUstate", c, ct.byref(s)) == OK
        else:
            b.call("fmi2Reset", c)
            t, initialised = 0.0, False
    b.call("fmi2FreeInstance", c)


def test_random_call_sequences_through_ctypes(binaries):
    # ctypes releases the GIL during a call: the sequences run on a worker thread, and this thread
    # fails the test when one call has run for more than HANG (the worker cannot be stopped)
    rng, failure = random.Random(11), []

    def work():
        try:
            for k in range(SEQUENCES):
                one_sequence(rng, binaries[k % 2])
        except AssertionError as e:
            failure.append(e)

    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    while worker.is_alive():
        worker.join(0.02)
        running = Binary.running
        assert running is None or time.perf_counter() - running[0] < HANG, f"hang: {running[1]}"
    assert not failure, failure[0]


def test_each_fmu_refuses_the_others_state(binaries):
    damper, truck = binaries
    d, t = damper.instantiate(), truck.instantiate()
    ds, ts = damper.state(d), truck.state(t)
    assert truck.call("fmi2SetFMUstate", t, ds) == ERROR
    assert damper.call("fmi2SetFMUstate", d, ts) == ERROR
    assert truck.deserialize(t, damper.serialize(d, ds)) == ERROR
    assert damper.deserialize(d, truck.serialize(t, ts)) == ERROR
    assert damper.call("fmi2FreeFMUstate", d, ct.byref(ds)) == OK
    assert truck.call("fmi2FreeFMUstate", t, ct.byref(ts)) == OK
    damper.call("fmi2FreeInstance", d)
    truck.call("fmi2FreeInstance", t)
