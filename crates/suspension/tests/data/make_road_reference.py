"""Writes the numpy reference values that crates/suspension/tests/road_reference.rs compares the
Rust road source (crates/suspension/src/road.rs) with:

    .venv/bin/python crates/suspension/tests/data/make_road_reference.py

It imports the repository's own python/damper_tools/roads.py (not an installed copy) and writes,
next to itself, six CSV files (340 kB), each starting with one `# ...` comment line (the numpy version),
then a header line; floats are written with repr (the shortest text that reads back to the same
bits), integers in decimal:

    road_rng.csv         seed, index, raw, uniform_0_2pi, uniform_m1p5_2p5: numpy's PCG64 outputs
                         (PCG64(seed).random_raw), default_rng(seed).uniform(0, 2 pi) and
                         default_rng(seed).uniform(-1.5, 2.5), the first 64 draws of each seed
    road_seeds.csv       seed, w0 .. w7: SeedSequence(seed).generate_state(8) (uint32 words), the
                         words PCG64 is seeded from
    road_profiles.csv    case, i, z: roads.generate_profile(...) of each case in PROFILES, every
                         `stride`-th sample (z in m)
    road_profile_cases.csv   case, length, gd0, seed, dx, w, n_min, n_max, n0, n_samples, stride, rms
    road_series.csv      case, k, z_road, v_road (at t_k = k step): roads.road_case(...), or
                         roads.time_series(...) where there is an offset or no speed, of each case
                         in SERIES, every `stride`-th step
    road_series_cases.csv    case, profile, speed, step, n_steps, fade_in, offset, stride

(road_profile_cases.csv and road_series_cases.csv are the cases' parameters.) The series cases
name the profile case they drive on; where that profile is stored whole (stride 1), the Rust test
also interpolates numpy's own profile and compares the time series bit for bit (but for the
fade's cosine, libm's against numpy's). Rerun it after a change of roads.py, and check that
`cargo test --release -p suspension --test road_reference` still passes.
"""

import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[3]
sys.path.insert(0, str(REPO / "python"))

from damper_tools import roads  # noqa: E402  (after the path of this repository's own copy)

# SeedSequence words are 32 bits: seeds below 2^32 are one word, the rest two; 2^63 and above
# cover the u64 range (sweep.py's _stable_int gives 63-bit values).
SEEDS = [0, 1, 3, 7, 42, 2024, 2**31 - 1, 2**32 - 1, 2**32, 2**32 + 5, 6_149_276_533_466_932_421,
         2**63 - 25, 2**63, 12_345_678_901_234_567_890, 2**64 - 1]
N_DRAWS = 64

# (length m, gd0 m^3, seed, dx m, w, n_min, n_max, n0 cycle/m, stride)
PROFILES = [
    (20.0, 16e-6, 0, 0.02, 2.0, 0.01, 10.0, 0.1, 1),           # odd sample count (1001)
    (25.0, 128e-6, 42, 0.02, 2.0, 0.01, 10.0, 0.1, 1),
    (10.01, 256e-6, 7, 0.05, 2.5, 0.05, 5.0, 0.2, 1),          # even count (202), other spectrum
    (50.0, 64e-6, 2**32 + 5, 0.1, 2.0, 0.01, 5.0, 0.1, 1),     # n_max at the Nyquist frequency
    (20.15, 1024e-6, 2**31 - 1, 0.02, 2.0, 0.01, 10.0, 0.1, 1),  # a prime count (1009)
    (5.0, 128e-6, 12_345_678_901_234_567_890, 0.02, 2.0, 0.01, 10.0, 0.1, 1),  # a seed above 2^63
    (14.0 * 600 * 1e-3 + 1.0, 128e-6, 3, 0.02, 2.0, 0.01, 10.0, 0.1, 1),  # road_case(minor, 14 m/s, 0.6 s, 3)
    (25.0 * 18000 * 1e-3 + 1.0, 128e-6, 2024, 0.02, 2.0, 0.01, 10.0, 0.1, 25),  # road_case(minor, 25 m/s, 18 s)
]

# (profile case, speed m/s, step s, n_steps, fade_in s, offset m, stride); fade_start is `step`,
# as roads.time_series has it.
SERIES = [
    (6, 14.0, 1e-3, 600, 0.5, 0.0, 1),       # road_case("minor", 14, 0.6, 3, fade_in=0.5)
    (6, 14.0, 1e-3, 600, 0.0, 0.0, 1),       # the same without a fade: interpolation alone
    (1, 10.0, 2e-3, 500, 0.3, 3.3, 1),       # time_series with an offset
    (0, 0.0, 1e-3, 200, 0.1, 7.5, 1),        # standing still at 7.5 m
    (7, 25.0, 1e-3, 18000, 1.0, 0.0, 50),    # road_case("minor", 25, 18, 2024), fade_in 1 s
]


def comment() -> str:
    return f"# written by make_road_reference.py with numpy {np.__version__}\n"


def write(name: str, header: list[str], rows: list[list[object]]) -> None:
    text = [comment(), ",".join(header) + "\n"]
    for row in rows:
        text.append(",".join(repr(float(v)) if isinstance(v, float) else str(v) for v in row) + "\n")
    (HERE / name).write_text("".join(text), encoding="utf-8")
    print(f"wrote {HERE / name} ({len(rows)} rows)")


def rng_rows() -> list[list[object]]:
    rows: list[list[object]] = []
    for seed in SEEDS:
        raw = np.random.PCG64(seed).random_raw(N_DRAWS)
        u = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, N_DRAWS)
        v = np.random.default_rng(seed).uniform(-1.5, 2.5, N_DRAWS)
        rows += [[seed, i, int(raw[i]), float(u[i]), float(v[i])] for i in range(N_DRAWS)]
    return rows


def profile(case: int) -> tuple[np.ndarray, np.ndarray]:
    length, gd0, seed, dx, w, n_min, n_max, n0, _ = PROFILES[case]
    return roads.generate_profile(length, gd0, seed, dx=dx, w=w, n_min=n_min, n_max=n_max, n0=n0)


def main() -> None:
    write("road_rng.csv", ["seed", "index", "raw", "uniform_0_2pi", "uniform_m1p5_2p5"], rng_rows())
    write("road_seeds.csv", ["seed"] + [f"w{i}" for i in range(8)],
          [[seed] + [int(w) for w in np.random.SeedSequence(seed).generate_state(8)] for seed in SEEDS])

    cases, samples = [], []
    for case, (length, gd0, seed, dx, w, n_min, n_max, n0, stride) in enumerate(PROFILES):
        x, z = profile(case)
        assert x.size == math.ceil(length / dx) + 1
        rms = float(np.sqrt(np.mean(z * z)))
        cases.append([case, length, gd0, seed, dx, w, n_min, n_max, n0, int(z.size), stride, rms])
        samples += [[case, i, float(z[i])] for i in range(0, z.size, stride)]
    write("road_profile_cases.csv", ["case", "length", "gd0", "seed", "dx", "w", "n_min", "n_max", "n0",
                                     "n_samples", "stride", "rms"], cases)
    write("road_profiles.csv", ["case", "i", "z"], samples)

    cases, samples = [], []
    for case, (p, speed, step, n_steps, fade_in, offset, stride) in enumerate(SERIES):
        length, gd0, seed, dx, *_ = PROFILES[p]
        if offset == 0.0 and speed > 0:
            # what a co-simulation gets: road_case builds its own profile, of the stored case's length
            duration = n_steps * step
            rc = roads.road_case(gd0, speed, duration, seed, step=step, fade_in=fade_in, dx=dx)
            assert speed * n_steps * step + 1.0 == length and round(duration / step) == n_steps, case
            t, zr, vr = rc.t, rc.z_road, rc.v_road
        else:
            x, z = profile(p)
            t, zr, vr = roads.time_series(x, z, speed, step, n_steps, fade_in=fade_in, offset=offset)
        cases.append([case, p, speed, step, n_steps, fade_in, offset, stride])
        assert (t == np.arange(n_steps + 1) * step).all()
        samples += [[case, k, float(zr[k]), float(vr[k])] for k in range(0, t.size, stride)]
    write("road_series_cases.csv", ["case", "profile", "speed", "step", "n_steps", "fade_in", "offset",
                                    "stride"], cases)
    write("road_series.csv", ["case", "k", "z_road", "v_road"], samples)


if __name__ == "__main__":
    main()
