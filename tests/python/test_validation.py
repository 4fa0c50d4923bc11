"""The packaged FMU is valid for fmpy and for the FMU Manipulation Toolbox checker."""

import re
import subprocess
import sys
import zipfile
from pathlib import Path

from fmpy import read_model_description
from fmpy.validation import validate_fmu

FMUTOOL = Path(sys.executable).parent / "fmutool"
EXPECTED_ENTRIES = {"modelDescription.xml", "binaries/linux64/SemiActiveDamper.so", "documentation/index.html"}


def test_fmpy_validate_fmu_finds_no_problem(fmu):
    problems = validate_fmu(str(fmu))
    assert problems == []


def test_model_description_reads_with_validation(fmu):
    md = read_model_description(str(fmu), validate=True)
    assert md.fmiVersion == "2.0"
    assert md.coSimulation.modelIdentifier == "SemiActiveDamper"
    causality = {v.name: v.causality for v in md.modelVariables}
    inputs = [n for n, c in causality.items() if c == "input"]
    assert inputs == ["v_damper", "F_demand", "x_spool_demand", "a_damper", "T_oil"]
    assert causality["F_damper"] == "output"
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate


def test_archive_layout(fmu):
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
        assert EXPECTED_ENTRIES <= names
        assert all("\\" not in n for n in names)
        html = z.read("documentation/index.html").decode("utf-8")
    # The documentation carries the variable table generated from the XML.
    assert "<code>air_fraction</code>" in html and "[P]" in html


def test_fmutool_check_reports_compliant(fmu):
    proc = subprocess.run([str(FMUTOOL), "-input", str(fmu), "-check"], capture_output=True, text=True, timeout=300)
    output = proc.stdout + proc.stderr
    print(output)
    assert proc.returncode == 0, output
    assert "This FMU seems to be compliant with FMI-2.0" in output
    assert "No semantic error against the FMI-2 standard" in output
    errors = [line for line in output.splitlines() if re.match(r"(ERROR|CRITICAL)\s*\|", line)]
    assert errors == []
