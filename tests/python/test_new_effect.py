# ruff: noqa: E501  (the effect file and the XML are embedded verbatim, as a user writes them)
"""Adding an effect as docs/effects.md says: one new file in src/effects/ and the XML, nothing else.

A copy of the project gets a toy effect with a dead band, a position-sensitive bypass groove (a
laminar bypass past the piston that is open only within x_groove of mid-stroke, as the grooves of
position-sensitive dampers are), and three variables appended to modelDescription.xml. The build
stops once, naming the GUID to set and the new parameters' indices for the initial unknowns'
dependencies, as the how-to says; then the catalog-wide checks pass unedited, and
a record that hides the groove is diagnosed `effect` with the default options.

The copy builds into target/new-effect/ (kept between runs, so a second run is incremental), which
starts from the main build's compiled dependencies (scripts/cargo_seed.py).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

EFFECT = '''//! A position-sensitive bypass groove: a laminar bypass past the piston, open only within
//! x_groove of mid-stroke (a toy effect with a dead band, added by tests/python/test_new_effect.py).

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;

pub struct BypassGroove;

/// Half-width of the groove's edge (m): the bypass closes smoothly over it.
const EDGE: f64 = 5e-4;

static INFO: EffectInfo = EffectInfo {
    key: "bypass_groove",
    meaning: "a bypass groove open within x_groove of mid-stroke, G_groove·(p_ext − p_comp) (off: none)",
    equation: "Q = G_groove·(p_ext − p_comp)·w(x) from the annulus to the full bore, w = 1 within x_groove of mid-stroke, 0 beyond, a smoothstep over ±0.5 mm",
    code: CodeRef { file: "src/effects/bypass_groove.rs", function: "BypassGroove::bypass_flow" },
    fitted: &[
        FittedParameter {
            name: "G_groove",
            search: (1e-14, 1e-10),
            log: true,
            plausible: (1e-13, 1e-11),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "x_groove",
            search: (0.002, 0.08),
            log: false,
            plausible: (0.003, 0.06),
            grid: None,
            start: Start::Model,
        },
    ],
    secondary: &[],
    other: &[],
    hidden_range: (8e-13, 3e-12),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "the model too strong near mid-stroke only, at low and moderate velocity; right beyond the groove",
};

/// 1 within the groove, 0 beyond it, a smoothstep across its edge.
fn open(p: &Parameters, x: f64) -> f64 {
    let u = ((p.x_groove + EDGE - x.abs()) / (2.0 * EDGE)).clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

impl Effect for BypassGroove {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::BYPASS_FLOW
    }
    fn bypass_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        p.g_groove * open(p, s.x_damper) * (s.p_ext - s.p_comp)
    }
}
'''

VARIABLES = '''    <ScalarVariable name="effect_bypass_groove" valueReference="{boolean}" description="Effect switch: a position-sensitive bypass groove (off: none). Source: [A] a toy effect of the how-to's test." causality="parameter" variability="fixed">
      <Boolean start="false"/>
    </ScalarVariable>
    <ScalarVariable name="G_groove" valueReference="{real}" description="Laminar conductance of the bypass groove. Source: [A] of the order of a piston gap's." causality="parameter" variability="fixed">
      <Real unit="m3/(s.Pa)" min="0.0" max="1e-09" start="1.5e-12"/>
    </ScalarVariable>
    <ScalarVariable name="x_groove" valueReference="{real_next}" description="Half-length of the groove about mid-stroke. Source: [A] a comfort zone of +-10 mm." causality="parameter" variability="fixed">
      <Real unit="m" min="0.0" max="0.1" start="0.01"/>
    </ScalarVariable>
'''



def appended_variables(xml: str) -> str:
    """VARIABLES with the value references a user picks: the next free one of each type."""
    variables = ET.fromstring(xml).iter("ScalarVariable")
    used = [(int(v.get("valueReference", "0")), v[0].tag) for v in variables]

    def last(kind: str) -> int:
        return max(vr for vr, tag in used if tag == kind)
    real = last("Real") + 1
    return VARIABLES.format(boolean=last("Boolean") + 1, real=real, real_next=real + 1)


SKIP = shutil.ignore_patterns("target", ".venv", "out", "work", ".git", "__pycache__", "*.fmu")


TARGET = REPO / "target" / "new-effect"


def cargo(args: list[str], cwd: Path, **extra: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, CARGO_TARGET_DIR=str(TARGET), **extra)
    return subprocess.run(["cargo", *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=3000)


@pytest.fixture(scope="module")
def extended(tmp_path_factory: pytest.TempPathFactory, seed_target_dir: Callable[[Path, Path], None]) -> Path:
    """The project's copy with the toy effect added: one file and the XML."""
    if shutil.which("cargo") is None:
        pytest.skip("needs cargo")
    # the copy compiles only its own crates: the dependencies come from target/release
    seed_target_dir(REPO / "target", TARGET)
    copy = tmp_path_factory.mktemp("new_effect") / "project"
    shutil.copytree(REPO, copy, ignore=SKIP)
    (copy / "src" / "effects" / "bypass_groove.rs").write_text(EFFECT)
    xml = copy / "modelDescription.xml"
    text = xml.read_text()
    xml.write_text(text.replace("  </ModelVariables>", appended_variables(text) + "  </ModelVariables>"))

    # the build stops once, naming what to write: the GUID to set, and the new parameters' indices
    # for the dependencies of the initial unknowns
    first = cargo(["build", "--release", "-p", "damper_cli"], copy)
    assert first.returncode != 0, "the build accepted a changed interface under the old GUID"
    guid = re.search(r'set guid="(\{[0-9a-f-]+\})"', first.stderr)
    indices = re.search(r'append "([0-9 ]+)" to the dependencies of each Unknown of ModelStructure/InitialUnknowns',
                        first.stderr)
    assert guid and indices, first.stderr[-3000:]
    text = re.sub(r'guid="\{[0-9a-f-]+\}"', f'guid="{guid.group(1)}"', xml.read_text(), count=1)
    head, rest = text.split("<InitialUnknowns>", 1)
    unknowns, tail = rest.split("</InitialUnknowns>", 1)
    unknowns = re.sub(r'dependencies="([0-9 ]*)"', lambda m: f'dependencies="{m.group(1)} {indices.group(1)}"', unknowns)
    xml.write_text(f"{head}<InitialUnknowns>{unknowns}</InitialUnknowns>{tail}")
    second = cargo(["build", "--release", "-p", "damper_cli"], copy)
    assert second.returncode == 0, second.stderr[-3000:]
    return copy


def test_the_catalog_wide_checks_pass_unedited(extended: Path) -> None:
    """Every check of the catalog (the XML, the switches, the hooks, the Jacobian of every effect)
    holds for the new effect; the docs' tables get its row from the how-to's last step."""
    tests = ["test", "--release", "-p", "semi_active_damper", "--test", "integration", "effects::"]
    # both test programs compiled at once (side by side on two cores), run below
    built = cargo(["test", "--release", "-p", "semi_active_damper", "--lib", "--test", "integration", "--no-run"], extended)
    assert built.returncode == 0, built.stderr[-3000:]
    stale = cargo(tests, extended)
    assert stale.returncode != 0 and "bypass_groove" in stale.stdout + stale.stderr, "docs tables without the new row"
    docs = cargo(tests, extended, UPDATE_DOCS="1")
    assert docs.returncode == 0, docs.stdout[-3000:] + docs.stderr[-3000:]
    assert "bypass_groove" in (extended / "docs" / "effects.md").read_text()
    # the catalog's checks again (the docs now current), the physics and the library's unit tests
    for run in (cargo([*tests, "--", "physics::"], extended), cargo(["test", "--release", "-p", "semi_active_damper", "--lib"], extended)):
        assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]


def test_a_record_hiding_the_new_effect_is_diagnosed_effect(extended: Path, tmp_path: Path) -> None:
    damper = TARGET / "release" / "damper"
    listed = subprocess.run([damper, "effects"], capture_output=True, text=True, check=True).stdout
    assert "bypass_groove" in listed
    subprocess.run([damper, "generate", "--effect", "bypass_groove", "--seed", "1", "--out", tmp_path / "rec.csv",
                    "--truth", tmp_path / "truth.json"], check=True, capture_output=True)
    subprocess.run([damper, "diagnose", tmp_path / "rec.csv", "--out", tmp_path / "d", "--load-cell-lowpass", "400"],
                   check=True, capture_output=True)
    summary = json.loads((tmp_path / "d" / "summary.json").read_text())
    assert summary["verdict"] == "effect", summary["explanation"]
    assert summary["effects"] == ["bypass_groove"], summary["explanation"]
