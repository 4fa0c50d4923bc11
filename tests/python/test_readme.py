"""The README and docs/ as a newcomer reads them: short, every link resolves, and the README's
interface table says what the FMU's modelDescription.xml says."""

import itertools
import re
import subprocess
from pathlib import Path
from xml.etree import ElementTree

REPO = Path(__file__).resolve().parents[2]
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def relative_files(targets):
    """The files that link targets point to (the part before any #anchor): web addresses and links
    within the page left out. For the documents shipped outside the repository (test_docs,
    test_release)."""
    return {t.partition("#")[0] for t in targets if not re.match(r"[a-z]+:|#", t)}


def markdown_files() -> list[Path]:
    tracked = subprocess.run(["git", "ls-files", "*.md"], cwd=REPO, check=True, capture_output=True,
                             text=True).stdout.split()
    return [REPO / name for name in tracked]


def anchors(path: Path) -> set[str]:
    """GitHub's anchors of a Markdown file's headings."""
    found = set()
    for line in path.read_text(encoding="utf-8").splitlines():
        if m := re.match(r"^#{1,6} (.*)", line):
            slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
            found.add(slug)
    return found


def test_readme_fits_on_a_few_screens():
    assert len((REPO / "README.md").read_text(encoding="utf-8").splitlines()) <= 200


def test_every_relative_link_in_the_markdown_resolves():
    broken = []
    for md in markdown_files():
        text = md.read_text(encoding="utf-8")
        text = re.sub(r"```.*?```", "", text, flags=re.S)  # code blocks hold no links
        for target in LINK.findall(text):
            if re.match(r"^[a-z]+:", target):
                continue  # an external URL: not checked offline
            file_part, _, anchor = target.partition("#")
            resolved = (md.parent / file_part).resolve() if file_part else md
            if not resolved.exists():
                broken.append(f"{md.relative_to(REPO)}: {target}")
            elif anchor and resolved.suffix == ".md" and anchor not in anchors(resolved):
                broken.append(f"{md.relative_to(REPO)}: {target} (no such heading)")
    assert broken == []


def test_no_internal_issue_numbers_in_user_facing_text():
    hits = [f"{md.relative_to(REPO)}: {m.group(0)}" for md in markdown_files()
            for m in re.finditer(r"\b[Ii]ssue \d+", md.read_text(encoding="utf-8"))]
    assert hits == []


def test_the_readme_interface_table_matches_the_model_description():
    root = ElementTree.parse(REPO / "modelDescription.xml").getroot()
    variables = {}
    for sv in root.iter("ScalarVariable"):
        typed = next(iter(sv))
        variables[sv.get("name")] = (sv.get("causality"), typed.get("unit", "1"))
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    table = readme[readme.index("| variable | causality | unit | meaning |"):]
    rows = list(itertools.takewhile(lambda line: line.startswith("|"), table.splitlines()[2:]))
    assert len(rows) >= 10
    for row in rows:
        names_cell, causality, units = (c.strip() for c in row.strip("|").split("|")[:3])
        names = re.findall(r"`([^`]+)`", names_cell)
        unit_list = [u.strip() for u in units.split(",")]
        for k, name in enumerate(names):
            unit = unit_list[min(k, len(unit_list) - 1)]
            assert name in variables, f"README names {name}, which the FMU does not have"
            assert variables[name][0] == causality, f"{name}: README {causality}, XML {variables[name][0]}"
            xml_unit = variables[name][1]
            assert xml_unit == ("1" if unit == "–" else unit), f"{name}: README {unit}, XML {xml_unit}"
