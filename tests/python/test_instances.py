"""Several instances in one process are independent: two instances driven with different
parameters and inputs, interleaved step by step, give bit for bit the outputs of each alone."""

import math

import numpy as np

from damper_tools.fmu import Slave, drive

STEP = 1e-3
N_STEPS = 300

# Two different dampers and drives.
CASES = {
    "a": ({"x_damper_start": -0.02}, lambda t: {"v_damper": 0.2 * math.sin(2 * math.pi * 3 * t) + 0.05,
                                                "F_demand": 8e3 * math.sin(2 * math.pi * 3 * t) + 2e3}),
    "b": ({"x_damper_start": 0.03, "air_fraction": 0.05, "force_controller": 1},
          lambda t: {"v_damper": -0.3 * math.cos(2 * math.pi * 5 * t),
                     "F_demand": -12e3 * math.cos(2 * math.pi * 5 * t)}),
}


def run_alone(damper_unit, key):
    params, inputs_at = CASES[key]
    s = Slave(damper_unit, f"alone_{key}")
    try:
        s.initialize(**params)
        return drive(s, [STEP] * N_STEPS, inputs_at)
    finally:
        s.free()


def test_interleaved_instances_equal_solo_runs_bit_for_bit(damper_unit):
    alone = {key: run_alone(damper_unit, key) for key in CASES}

    slaves = {key: Slave(damper_unit, f"interleaved_{key}") for key in CASES}
    try:
        for key, s in slaves.items():
            s.initialize(**CASES[key][0])
        rows = {key: [] for key in CASES}
        for _ in range(N_STEPS):
            for key, s in slaves.items():
                s.step(STEP, **CASES[key][1](s.time))
                rows[key].append(s.get())
    finally:
        for s in slaves.values():
            s.free()

    for key in CASES:
        together = np.array(rows[key])
        assert np.all(np.isfinite(together))
        assert np.array_equal(together, alone[key][1]), f"instance {key} differs when run beside the other"
    # The two cases are really different (the comparison above is not trivially true).
    assert not np.array_equal(alone["a"][1], alone["b"][1])
