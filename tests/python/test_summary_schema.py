"""summary.json, as `damper compare` and `damper diagnose` write it, is valid against
docs/summary.schema.json, the schema a user's own tools read it by; and the schema tells the two
summaries apart and knows every key. (The Rust tests read the same files back into the typed
structs; the schema is checked here, with the reference implementation of JSON Schema, so that the
Rust tests need no validator crate, whose dependencies would change the features the damper program
is compiled with in the tests.)"""

import copy
import json
import subprocess
from pathlib import Path
from typing import Any

import pytest
from jsonschema import Draft202012Validator

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def validator() -> Draft202012Validator:
    schema = json.loads((REPO / "docs" / "summary.schema.json").read_text(encoding="utf-8"))
    Draft202012Validator.check_schema(schema)
    return Draft202012Validator(schema)


@pytest.fixture(scope="module")
def summaries(damper: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, dict[str, Any]]:
    """compare's and diagnose's summary.json of a record with seal friction hidden in it."""
    work = tmp_path_factory.mktemp("summaries")

    def run(*args: str) -> None:
        subprocess.run([str(damper), *args, "--quiet"], cwd=work, check=True, capture_output=True, text=True)

    run("generate", "--out", "m.csv", "--truth", "m.json", "--effect", "seal_friction", "--duration", "5")
    out = {}
    for command in ("compare", "diagnose"):
        run(command, "m.csv", "--out", command, "--load-cell-lowpass", "400")
        out[command] = json.loads((work / command / "summary.json").read_text(encoding="utf-8"))
    return out


def errors(validator: Draft202012Validator, summary: dict[str, Any]) -> list[str]:
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in validator.iter_errors(summary)]


def test_both_summaries_follow_the_schema(validator, summaries):
    assert errors(validator, summaries["compare"]) == []
    assert errors(validator, summaries["diagnose"]) == []
    assert summaries["compare"]["verdict"] is None
    assert summaries["diagnose"]["verdict"] == "effect"


def test_the_schema_tells_compare_from_diagnose(validator, summaries):
    with_diagnosis = {**summaries["compare"], "explanation": "compare explains nothing"}
    assert errors(validator, with_diagnosis), "compare's summary with a diagnosis key"
    without_ladder = copy.deepcopy(summaries["diagnose"])
    del without_ladder["ladder"]
    assert errors(validator, without_ladder), "diagnose's summary without the ladder"


def test_the_schema_knows_every_key(validator, summaries):
    unknown = copy.deepcopy(summaries["compare"])
    unknown["whiteness"]["colour"] = "pink"
    assert errors(validator, unknown), "an unknown key"


def test_a_number_that_is_not_finite_is_null(validator, summaries):
    # a regime without samples has no RMS: the program writes null, which the schema takes
    empty = copy.deepcopy(summaries["compare"])
    empty["regimes"][0]["rms_residual"] = None
    assert errors(validator, empty) == []
    empty["regimes"][0]["rms_residual"] = "NaN"
    assert errors(validator, empty), "a number as a string"
