"""The port-law tables in src/physics/valve.rs are what scripts/fit_port_tables.py fits: a
maintainer who changes a fit (pieces, degree, nodes) regenerates the tables with the script."""

import re
import subprocess
import sys

import pytest

from damper_tools import REPO

# each table's name and the upper end of its variable (the lower is 0)
TABLES = {"KEPLER_OPENING": "KEPLER_T_MAX", "SEGMENT_AREA": None}


def script(*args: str) -> str:
    return subprocess.run(
        [sys.executable, "scripts/fit_port_tables.py", *args],
        cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout


def table(text: str, name: str) -> tuple[float, list[list[float]]]:
    """The upper end of the table's variable, and its rows of coefficients."""
    limit = TABLES[name]
    x_max = float(re.search(rf"const {limit}: f64 = ([^;]+);", text).group(1)) if limit else 1.0
    body = re.search(rf"const {name}: \[\[f64; \d+\]; \w+\] = \[(.*?)\];", text, re.S).group(1)
    rows = [[float(c) for c in row.split(",") if c.strip()] for row in re.findall(r"\[([^\]]+)\]", body)]
    return x_max, rows


def values(x_max: float, rows: list[list[float]], xs: list[float]) -> list[float]:
    """A table's polynomial at xs, as valve.rs evaluates it."""
    out = []
    for x in xs:
        piece = min(int(x * len(rows) / x_max), len(rows) - 1)
        z = x * 2.0 * len(rows) / x_max - (2 * piece + 1)
        out.append(sum(c * z**k for k, c in enumerate(rows[piece])))
    return out


@pytest.mark.parametrize("name", TABLES)
def test_the_table_in_the_source_is_the_scripts_fit(name):
    (x_max, fitted) = table(script(), name)
    (x_max_source, in_source) = table((REPO / "src/physics/valve.rs").read_text(), name)
    assert x_max == x_max_source
    assert [len(row) for row in in_source] == [len(row) for row in fitted]
    # the same polynomials, up to the last bits a different BLAS may give the least-squares fit
    xs = [x_max * k / 2000 for k in range(1, 2001)]
    for mine, theirs in zip(values(x_max, fitted, xs), values(x_max, in_source, xs), strict=True):
        assert abs(mine / theirs - 1.0) < 1e-15, (mine, theirs)


def test_the_fits_are_within_their_bounds():
    worst = dict(line.split(": worst relative error over 4000 points: ") for line in script("--check").splitlines())
    assert float(worst["KEPLER_OPENING"]) < 2e-14
    assert float(worst["SEGMENT_AREA"]) < 2e-15
