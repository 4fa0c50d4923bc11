"""The inverse port law's table in src/physics/valve.rs is what scripts/fit_valve_inverse.py fits:
a maintainer who changes the fit (pieces, degree, nodes) regenerates the table with the script."""

import re
import subprocess
import sys

from damper_tools import REPO


def rust_table(text: str) -> tuple[float, list[list[float]]]:
    t_max = float(re.search(r"const KEPLER_T_MAX: f64 = ([^;]+);", text).group(1))
    body = re.search(r"const KEPLER_OPENING: \[\[f64; \d+\]; \w+\] = \[(.*?)\];", text, re.S).group(1)
    rows = [[float(c) for c in row.split(",") if c.strip()] for row in re.findall(r"\[([^\]]+)\]", body)]
    return t_max, rows


def values(t_max: float, rows: list[list[float]], ts: list[float]) -> list[float]:
    """W(t) from a table, as valve.rs evaluates it."""
    out = []
    for t in ts:
        piece = min(int(t * len(rows) / t_max), len(rows) - 1)
        z = t * 2.0 * len(rows) / t_max - (2 * piece + 1)
        out.append(sum(c * z**k for k, c in enumerate(rows[piece])))
    return out


def test_the_table_in_the_source_is_the_scripts_fit():
    printed = subprocess.run(
        [sys.executable, "scripts/fit_valve_inverse.py"], cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout
    source = (REPO / "src/physics/valve.rs").read_text()
    (t_max, fitted), (t_max_source, in_source) = rust_table(printed), rust_table(source)
    assert t_max == t_max_source
    assert [len(row) for row in in_source] == [len(row) for row in fitted]
    # the same polynomials, up to the last bits a different BLAS may give the least-squares fit
    ts = [t_max * k / 2000 for k in range(1, 2001)]
    for mine, theirs in zip(values(t_max, fitted, ts), values(t_max, in_source, ts), strict=True):
        assert abs(mine / theirs - 1.0) < 1e-15, (mine, theirs)


def test_the_fit_is_within_its_bound():
    out = subprocess.run(
        [sys.executable, "scripts/fit_valve_inverse.py", "--check"],
        cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout
    worst = float(out.rsplit(":", 1)[1])
    assert worst < 2e-14, out
