"""FMU state: get/set and serialize/deserialize restore the damper bit for bit (fmpy's
test_fmu_state pattern, with the low-level API)."""

import math

import numpy as np

from damper_tools.fmu import Slave, drive

STEP = 1e-3
T_SAVE = 0.2        # s, state saved here
T_END = 0.4         # s, continuations run to here


def inputs_at(t):
    """A drive that keeps the valve and both loops busy across the saved point."""
    return {"v_damper": 0.25 * math.sin(2 * math.pi * 4 * t) + 0.02,
            "F_demand": 10e3 * math.sin(2 * math.pi * 4 * t) + 1e3}


N_BEFORE = round(T_SAVE / STEP)
N_AFTER = round((T_END - T_SAVE) / STEP)


def test_set_state_repeats_the_continuation_bit_for_bit(damper_unit):
    s = Slave(damper_unit, "state")
    try:
        s.initialize(x_damper_start=-0.02)
        drive(s, [STEP] * N_BEFORE, inputs_at)
        state = s.fmu.getFMUstate()
        t_saved = s.time
        first = drive(s, [STEP] * N_AFTER, inputs_at)

        s.fmu.setFMUstate(state)
        s.time = t_saved
        second = drive(s, [STEP] * N_AFTER, inputs_at)

        serialized = s.fmu.serializeFMUstate(state)
        s.fmu.freeFMUstate(state)
        restored = s.fmu.deSerializeFMUstate(serialized)
        s.fmu.setFMUstate(restored)
        s.fmu.freeFMUstate(restored)
        s.time = t_saved
        third = drive(s, [STEP] * N_AFTER, inputs_at)
    finally:
        s.free()

    assert np.all(np.isfinite(first[1]))
    assert np.array_equal(first[0], second[0])
    assert np.array_equal(first[1], second[1])
    assert np.array_equal(first[1], third[1])

    # Into a second, fresh instance: instantiate, de-serialize, set, continue (no initialisation).
    fresh = Slave(damper_unit, "fresh")
    try:
        state = fresh.fmu.deSerializeFMUstate(serialized)
        fresh.fmu.setFMUstate(state)
        fresh.fmu.freeFMUstate(state)
        fresh.time = t_saved
        fourth = drive(fresh, [STEP] * N_AFTER, inputs_at)
    finally:
        fresh.free()
    assert np.array_equal(first[1], fourth[1])


def test_serialized_state_is_stable(damper_unit):
    """Serializing a restored state gives the same bytes again."""
    s = Slave(damper_unit, "bytes")
    try:
        s.initialize()
        drive(s, [STEP] * 50, inputs_at)
        state = s.fmu.getFMUstate()
        blob = s.fmu.serializeFMUstate(state)
        again = s.fmu.deSerializeFMUstate(blob)
        assert s.fmu.serializeFMUstate(again) == blob
        s.fmu.freeFMUstate(state)
        s.fmu.freeFMUstate(again)
    finally:
        s.free()
