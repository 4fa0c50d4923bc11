#!/usr/bin/env python3
"""Rewrites a `damper generate` CSV (SI, `,`, uniform time) the way a rig's data logger exports it,
to exercise the measurement reader: comment lines, `;` delimiter with decimal commas, ISO 8601
timestamps with a little jitter, three dropped samples, channel names that need --map, kN, mm/s,
mm, bar and an extra oil-temperature channel.

    damper generate --out /tmp/si.csv --truth /tmp/si_truth.json --rate 500 --duration 4 --seed 21
    python3 data/measurements/make_rig_export_example.py /tmp/si.csv data/measurements/rig_export_example.csv

Values are scaled as decimal strings (no binary rounding), so the file holds exactly the
generated numbers in other units. Deterministic: the jitter comes from a seeded generator.
"""

import datetime
import random
import sys
from decimal import Decimal

START = datetime.datetime(2026, 3, 4, 10, 15, 30)
# the timestamps' clock jitters by up to ±8 µs (0.4 % of the 2 ms interval, within the reader's 1 %)
JITTER_S = 8e-6
# rows (0-based samples) the logger lost: one alone, two in a row
DROPPED = {700, 1500, 1501}

# generated column -> (exported header, factor from SI, decimals)
CHANNELS = [
    ("v_damper", "Velocity [mm/s]", Decimal("1e3"), 2),
    ("F_demand", "Force demand [kN]", Decimal("1e-3"), 4),
    ("F_damper", "Load cell [kN]", Decimal("1e-3"), 3),
    ("x_spool", "Spool [mm]", Decimal("1e3"), 4),
    ("i_sol", "Valve current [A]", Decimal(1), 3),
    ("p_ext", "p rebound [bar]", Decimal("1e-5"), 2),
    ("p_comp", "p compression [bar]", Decimal("1e-5"), 2),
]


def comma(value: Decimal, decimals: int) -> str:
    return f"{value:.{decimals}f}".replace(".", ",")


def main(src: str, dst: str) -> None:
    rng = random.Random(21)
    with open(src, encoding="utf-8") as f:
        header = f.readline().strip().split(",")
        rows = [line.strip().split(",") for line in f if line.strip()]
    index = {name: header.index(name) for name in ["time"] + [c[0] for c in CHANNELS]}
    out = [
        "# Damper test rig 2 - data logger export (synthetic: made from the damper model, see README.md)",
        "# Test: rig_export_example, force control",
        f"# Start: {START.isoformat()} (local time)",
        "# Sample rate: 500 Hz; delimiter ';', decimal separator ','",
        "Timestamp;" + ";".join(c[1] for c in CHANNELS) + ";T_oil [°C]",
    ]
    for k, row in enumerate(rows):
        jitter = rng.uniform(-JITTER_S, JITTER_S)
        if k in DROPPED:
            continue
        t = START + datetime.timedelta(seconds=float(row[index["time"]]) + jitter)
        cells = [t.isoformat(timespec="microseconds")]
        cells += [comma(Decimal(row[index[c]]) * f, d) for c, _, f, d in CHANNELS]
        cells.append(comma(Decimal("41.3") + Decimal(k) / Decimal(2000), 1))  # slowly warming oil
        out.append(";".join(cells))
    with open(dst, "w", encoding="utf-8", newline="\n") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
