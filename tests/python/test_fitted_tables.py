"""The model's tables of piecewise polynomials in src/physics/ are what scripts/fit_tables.py fits:
a maintainer who changes a fit (pieces, degree, nodes, range) regenerates the tables with the
script, and the source cannot drift from it."""

import re
import subprocess
import sys

import pytest

from damper_tools import REPO

# each table and the source file that holds it
SOURCES = {
    "KEPLER_OPENING": "src/physics/valve.rs",
    "SEGMENT_AREA": "src/physics/valve.rs",
    "MOUNT_DEFLECTION": "src/physics/mount.rs",
}


def script(*args: str) -> str:
    return subprocess.run(
        [sys.executable, "scripts/fit_tables.py", *args], cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout


def table(text: str, name: str) -> list[list[float]]:
    """The rows of coefficients of the table `name` in Rust source `text`."""
    body = re.search(rf"const {name}: \[\[f64; \d+\]; \d+\] = \[(.*?)\];", text, re.S).group(1)
    return [[float(c) for c in row.split(",") if c.strip()] for row in re.findall(r"\[([^\]]+)\]", body)]


def test_the_script_fits_every_table_and_no_other():
    assert set(re.findall(r"const (\w+): \[\[f64", script())) == set(SOURCES)


@pytest.mark.parametrize("name", SOURCES)
def test_the_table_in_the_source_is_the_scripts_fit(name):
    printed, source = script(), (REPO / SOURCES[name]).read_text()
    fitted, in_source = table(printed, name), table(source, name)
    assert [len(row) for row in in_source] == [len(row) for row in fitted]
    # the same polynomials, up to the last bits a different BLAS may give the least-squares fit
    zs = [-1.0 + k / 100 for k in range(201)]
    for mine, theirs in zip(fitted, in_source, strict=True):
        for z in zs:
            a, b = (sum(c * z**k for k, c in enumerate(row)) for row in (mine, theirs))
            assert abs(a / b - 1.0) < 1e-15, (name, z, a, b)


def test_the_ranges_in_the_source_are_the_scripts():
    sources = "".join((REPO / path).read_text() for path in set(SOURCES.values()))
    constants = re.findall(r"const \w+: f64 = [^;]+;", script())
    assert constants
    for constant in constants:
        assert constant in sources, constant


def test_the_fits_are_within_their_bounds():
    worst = dict(line.split(": worst relative error over 4000 points: ") for line in script("--check").splitlines())
    assert float(worst["KEPLER_OPENING"]) < 2e-14
    assert float(worst["SEGMENT_AREA"]) < 2e-15
    assert float(worst["MOUNT_DEFLECTION"]) < 2e-15
