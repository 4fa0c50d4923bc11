"""The program's printouts quoted in the documents are the program's printouts today.

A document quotes a printout in a fenced block preceded by a marker comment with the commands that
make it:

    <!-- output of: damper generate --out a.csv --seed 1; damper diagnose a.csv --out d -->

A command is `damper …`, `python -m damper_tools.<module> …` or `cat FILE`. The commands of one
document run in one folder, which holds a link to the repository's `data/`, each once and in the
order the document first gives them: a walk-through's later steps use the files of its earlier ones.
The last command's standard output must hold the block's lines in the block's order (each compared
with its runs of spaces made single); a block may leave lines out (a line `...` or `…`), and a line
that ends in ` ...` or ` …` quotes the beginning of its line. The run's wall-clock times (`in 3.3 s`,
`540× real time`) are masked on both sides: they are the one thing a printout does not repeat. Every
figure of such a block is so checked by the run that prints it; a block without a marker is not a
printout.
"""

from __future__ import annotations

import difflib
import json
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from damper_tools import report_figure

REPO = Path(__file__).resolve().parents[2]
MARKER = re.compile(r"<!-- output of: (.*?) -->\s*\n```[a-z]*\n(.*?)\n```", re.S)
# The wall-clock figures of a printout: a duration in seconds after "in" or "run:", and a speed.
TIMING = [re.compile(r"(?<=\bin )\d+(?:\.\d+)? s\b"), re.compile(r"(?<=run: )\d+(?:\.\d+)? s\b"),
          re.compile(r"\d+(?:\.\d+)?× real time")]
# A line left out, and the end of a line left out, as the documents write them.
SKIPPED = ("...", "…")


@dataclass(frozen=True)
class Transcript:
    """A quoted printout: where it is, the commands that make it and the lines it quotes."""

    document: str
    line: int
    commands: tuple[str, ...]
    quoted: tuple[str, ...]

    def __str__(self) -> str:
        return f"{self.document}:{self.line}"


def normalise(line: str) -> str:
    """The line with its runs of spaces made single and its wall-clock figures masked."""
    line = " ".join(line.split())
    for pattern in TIMING:
        line = pattern.sub("…", line)
    return line


def transcripts() -> list[Transcript]:
    """Every marked printout of README.md and docs/*.md."""
    found = []
    for path in [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]:
        text = path.read_text(encoding="utf-8")
        for m in MARKER.finditer(text):
            commands = tuple(c.strip() for c in " ".join(m.group(1).split()).split(";") if c.strip())
            line = text[:m.start(2)].count("\n") + 1
            found.append(Transcript(str(path.relative_to(REPO)), line, commands, tuple(m.group(2).splitlines())))
    return found


def missing(quoted: tuple[str, ...], printed: list[str]) -> list[str]:
    """The quoted lines that the printout does not hold in order, each with its closest printed line."""
    printed = [normalise(p) for p in printed]
    wrong, at = [], 0
    for q in quoted:
        q = normalise(q)
        if q in ("", *SKIPPED):
            continue
        prefix = any(q.endswith(" " + e) for e in SKIPPED)
        want = q.rsplit(" ", 1)[0] if prefix else q
        hit = next((i for i in range(at, len(printed))
                    if (printed[i].startswith(want) if prefix else printed[i] == want)), None)
        if hit is None:
            close = difflib.get_close_matches(want, printed[at:], n=1, cutoff=0.0)
            wrong.append(f"  quoted:  {q}\n  printed: {close[0] if close else '(nothing left)'}")
        else:
            at = hit + 1
    return wrong


def run(command: str, where: str, damper: Path, folder: Path) -> list[str]:
    """Runs one command of a marker in `folder`; its standard output, as lines."""
    words = shlex.split(command)
    if words[0] == "cat":
        return (folder / words[1]).read_text(encoding="utf-8").splitlines()
    if words[0] == "damper":
        argv = [str(damper), *words[1:]]
    elif words[:2] == ["python", "-m"] and len(words) > 2 and words[2].startswith("damper_tools."):
        argv = [sys.executable, *words[1:]]
    else:
        raise AssertionError(f"{where}: a marker runs damper, python -m damper_tools.… or cat: {command}")
    done = subprocess.run(argv, cwd=folder, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, f"{where}: {command} failed:\n{done.stderr}"
    return done.stdout.splitlines()


TRANSCRIPTS = transcripts()


def test_the_documents_mark_their_printouts():
    # a check of nothing would pass: the documents that quote printouts have their markers
    documents = {t.document for t in TRANSCRIPTS}
    expected = {"README.md", "docs/diagnose.md", "docs/calibrate.md", "docs/effects.md", "docs/real-dampers.md"}
    assert expected <= documents, documents


@dataclass
class Session:
    """A document's folder and the printout of each command run in it so far."""

    folder: Path
    printed: dict[str, list[str]]


@pytest.fixture(scope="module")
def sessions() -> dict[str, Session]:
    """Each document's session, made at its first printout."""
    return {}


def printout(transcript: Transcript, damper: Path, sessions: dict[str, Session],
             tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[str]]:
    """The transcript's folder and printout, running those of its commands not run there yet."""
    if transcript.document not in sessions:
        folder = tmp_path_factory.mktemp(Path(transcript.document).stem)
        (folder / "data").symlink_to(REPO / "data")
        sessions[transcript.document] = Session(folder, {})
    session = sessions[transcript.document]
    for command in transcript.commands:
        if command not in session.printed:
            session.printed[command] = run(command, str(transcript), damper, session.folder)
    return session.folder, session.printed[transcript.commands[-1]]


@pytest.mark.parametrize("transcript", TRANSCRIPTS, ids=str)
def test_a_quoted_printout_is_what_the_program_prints(transcript, damper, sessions, tmp_path_factory):
    _, printed = printout(transcript, damper, sessions, tmp_path_factory)
    wrong = missing(transcript.quoted, printed)
    assert not wrong, (f"{transcript}: the printout of `{transcript.commands[-1]}` differs from the quote "
                       "(run the markers' commands and quote the printout again):\n" + "\n".join(wrong))


def test_a_changed_figure_is_found():
    printed = ["verdict: effect (seal_friction)", "  ladder: baseline 0.2276 → + seal_friction 0.0246"]
    assert missing(("verdict: effect (seal_friction)", "...", "ladder: baseline 0.2276 ..."), printed) == []
    assert missing(("model run 12 runs in 3.3 s",), ["model run 12 runs in 0.9 s"]) == []
    assert missing(("…", "ladder: baseline 0.2276 …"), printed) == []
    wrong = missing(("ladder: baseline 0.2276 → + seal_friction 0.0245",), printed)
    assert len(wrong) == 1 and "0.0246" in wrong[0], wrong
    # out of order is wrong too
    assert len(missing(("ladder: baseline ...", "verdict: effect (seal_friction)"), printed)) == 1


def test_the_worked_example_of_a_new_effect_turns_unexplained_into_named(damper, sessions, tmp_path_factory):
    # docs/effects.md: before viscous_friction.rs existed (played by --skip) the residual is
    # unexplained; with it, it is named and fitted near the truth, and the error falls in the regimes
    before, after = (t for t in TRANSCRIPTS if t.document == "docs/effects.md")
    _, unexplained = printout(before, damper, sessions, tmp_path_factory)
    folder, named = printout(after, damper, sessions, tmp_path_factory)
    assert "verdict: unexplained" in unexplained
    assert "verdict: effect (viscous_friction)" in named
    fitted = float(re.search(r"^ +1 viscous_friction .* c_viscous=(\S+)", "\n".join(named), re.M).group(1))
    truth = json.loads((folder / "vf_truth.json").read_text())["changed_parameters"]["c_viscous"]
    assert abs(fitted / truth - 1) < 0.2, (fitted, truth)
    table = next(i for i, line in enumerate(named) if line.startswith("before → after"))
    regimes = [line for line in named[table + 1:] if "→" in line]
    assert regimes and all(re.search(r"\(-\d+ %\)$", line) for line in regimes), regimes
    # the page's figure is this report's before/after plots
    figure = report_figure.before_after_svg((folder / "after" / "report.html").read_text(encoding="utf-8"))
    if os.environ.get("UPDATE_DOCS") == "1":
        report_figure.DOCS_FIGURE.write_text(figure, encoding="utf-8")
    assert figure == report_figure.DOCS_FIGURE.read_text(encoding="utf-8"), (
        f"{report_figure.DOCS_FIGURE} is not this report's: rerun with UPDATE_DOCS=1")
