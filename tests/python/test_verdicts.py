"""The one rule of a right verdict (damper_tools.verdicts), which the blind score, the campaign's
table and the dyno score apply: its cases, its docstring's examples, and the verdict strings."""

import doctest
import json
import re

import pytest

from damper_tools import REPO, verdicts
from damper_tools.verdicts import Verdict, right


def test_the_verdicts_are_summary_jsons_strings():
    assert [str(v) for v in Verdict] == ["none", "effect", "partial", "does_not_fit", "unexplained"]
    assert Verdict("does_not_fit") is Verdict.DOES_NOT_FIT and Verdict.NONE == "none"


def test_the_schema_and_the_rust_enum_name_the_same_verdicts():
    schema = json.loads((REPO / "docs" / "summary.schema.json").read_text(encoding="utf-8"))
    assert set(schema["properties"]["verdict"]["enum"]) - {None} == set(Verdict)
    rust = (REPO / "crates" / "damper_engine" / "src" / "verdict.rs").read_text(encoding="utf-8")
    assert set(re.findall(r'Verdict::\w+ => "(\w+)"', rust)) == set(Verdict)


@pytest.mark.parametrize(("expected", "verdict", "named", "first", "is_right"), [
    ((), "none", [], False, True),
    ((), "none", ["seal_friction"], False, False),  # something named on a clean record
    ((), "effect", [], False, False),
    ((), "partial", [], False, False),
    (("a",), "effect", ["a"], False, True),
    (("a",), "effect", ["b", "a"], False, True),  # others may be named too
    (("a",), "effect", ["b", "a"], True, False),  # ... but not before it, with first
    (("a",), "effect", ["a", "b"], True, True),
    (("a", "b"), "effect", ["b", "a", "c"], True, True),
    (("a", "b"), "effect", ["a", "c", "b"], True, False),
    (("a", "b"), "effect", ["a"], False, False),  # a pair needs both
    (("a",), "partial", ["a"], False, False),
    (("a",), "does_not_fit", ["a"], False, False),
    (("a",), None, ["a"], False, False),  # no summary
    (("a",), "error", ["a"], False, False),
])
def test_a_right_verdict(expected, verdict, named, first, is_right):
    assert right(expected, verdict, named, first=first) is is_right


def test_the_docstring_examples():
    assert doctest.testmod(verdicts).failed == 0
