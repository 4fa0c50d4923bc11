"""The model's physics document, docs/physics.md, is the one the repository and the FMUs cite.

- No tracked file refers to the team's brief outside the repository or to another path outside it:
  a clone and an FMU user could not open it.
- Its parameter tables (§5.1 damper, §5.2 quarter truck, §5.4 full truck) list exactly the parameters
  of the modelDescription.xml files, with the XML's unit, start value and source tags.
- Every "physics.md §x" citation names a section that exists.
- The three packaged FMUs carry it as documentation/physics.md, linked from documentation/index.html.
"""

import posixpath
import re
import subprocess
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest

from test_readme import LINK, relative_files

REPO = Path(__file__).resolve().parents[2]
PHYSICS = REPO / "docs" / "physics.md"
DAMPER_XML = REPO / "modelDescription.xml"
TRUCK_XML = REPO / "crates" / "quarter_truck" / "modelDescription.xml"
FULL_TRUCK_XML = REPO / "crates" / "full_truck" / "modelDescription.xml"

# Built from pieces so that this file does not match itself.
OUTSIDE_REFERENCES = [
    ("the team's brief outside the repository", re.compile(re.escape("PHYSICS" + ".md"))),
    ("a sibling folder of the repository", re.compile(re.escape(".." + "/shared"))),
    ("an absolute path of the team's machine", re.compile(r"(?<![\w.])" + re.escape("/" + "work/"))),
    ("the slow reference script, not in the repository", re.compile(re.escape("damper_" + "reference"))),
]
# Directories that hold build output, not sources (used only without git).
UNTRACKED_DIRS = {".git", "target", ".venv", "out", "work", "__pycache__", ".pytest_cache"}

TAG = re.compile(r"\[([PSAC])\]")
ROW = re.compile(r"^\| `([^`]+)` \| ([^|]+?) \| ([^|]+?) \| ([^|]+?) \| ([^|]+?) \|$")
CITATION = re.compile(r"physics\.md ((?:§\d[\d.–-]*(?:,\s*|\s+and\s+)?)+)")


def tracked_files():
    """The repository's files: git's list in a checkout, else every file outside build folders."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO, capture_output=True, check=True).stdout
        names = [n for n in out.decode().split("\0") if n]
    except (OSError, subprocess.CalledProcessError):
        names = [str(p.relative_to(REPO)) for p in REPO.rglob("*")
                 if p.is_file() and not UNTRACKED_DIRS.intersection(p.relative_to(REPO).parts)]
    assert len(names) > 50, f"only {len(names)} files found in {REPO}"
    return [REPO / n for n in names if (REPO / n).is_file()]


def text_files():
    """(path, text) of every tracked file that is UTF-8 text (images and binary road files are not)."""
    for path in tracked_files():
        try:
            yield path, path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue


def parameters(xml_path):
    """name -> (unit, start text, type, set of source tags) of every parameter in a modelDescription.xml."""
    result = {}
    for sv in ET.parse(xml_path).getroot().find("ModelVariables"):
        if sv.get("causality") != "parameter":
            continue
        typ = next(iter(sv))
        description = sv.get("description", "")
        assert "Source:" in description, f"{sv.get('name')}: no 'Source:' in its description"
        tags = set(TAG.findall(description.split("Source:", 1)[1]))
        result[sv.get("name")] = (typ.get("unit", ""), typ.get("start"), typ.tag, tags)
    return result


def section_text(markdown, number):
    """The text of the section whose heading starts with `### <number> ` up to the next heading."""
    match = re.search(rf"^### {re.escape(number)} .*?$(.*?)(?=^##)", markdown, re.S | re.M)
    assert match, f"docs/physics.md has no section {number}"
    return match.group(1)


def table(markdown, number):
    """name -> (unit, default, source, reasoning) of the parameter table in section `number`."""
    rows = {}
    for line in section_text(markdown, number).splitlines():
        match = ROW.match(line.strip())
        if match:
            name, *cells = (c.strip() for c in match.groups())
            assert name not in rows, f"§{number}: {name} listed twice"
            rows[name] = tuple(cells)
    return rows


def same_value(xml_type, start, default):
    if xml_type == "Boolean":
        return default == start
    if xml_type == "Integer":
        return re.fullmatch(r"-?\d+", default) is not None and int(default) == int(start)
    try:
        return float(default) == float(start)
    except ValueError:
        return False


def test_no_file_refers_to_a_file_outside_the_repository():
    hits = []
    for path, text in text_files():
        for number, line in enumerate(text.splitlines(), 1):
            for what, pattern in OUTSIDE_REFERENCES:
                if pattern.search(line):
                    hits.append(f"{path.relative_to(REPO)}:{number}: {what}: {line.strip()[:120]}")
    assert hits == [], "cite docs/physics.md instead:\n" + "\n".join(hits)


def test_the_outside_reference_patterns_match_what_they_should():
    # The scan above is only as good as its patterns: each must catch its case and spare the
    # repository's own paths (tests/python/work/ is a folder inside the repository).
    bad = ["see " + "PHYSICS" + ".md §3", "../" + "shared" + "/paper", "/" + "work/" + "shared" + "/x",
           "damper_" + "reference.py"]
    for text in bad:
        assert any(p.search(text) for _, p in OUTSIDE_REFERENCES), text
    for text in ["docs/physics.md §3", "tests/python/work/", "/tests/python/work/", "physics.md"]:
        assert not any(p.search(text) for _, p in OUTSIDE_REFERENCES), text


@pytest.mark.parametrize("number, xml_path", [("5.1", DAMPER_XML), ("5.2", TRUCK_XML), ("5.4", FULL_TRUCK_XML)],
                         ids=["damper", "truck", "full_truck"])
def test_parameter_table_matches_model_description(number, xml_path):
    rows = table(PHYSICS.read_text(encoding="utf-8"), number)
    xml = parameters(xml_path)
    assert sorted(set(xml) - set(rows)) == [], f"§{number} lacks these parameters of {xml_path.name}"
    assert sorted(set(rows) - set(xml)) == [], f"§{number} lists parameters {xml_path.name} does not have"
    problems = []
    for name, (unit, start, xml_type, tags) in xml.items():
        doc_unit, default, source, reasoning = rows[name]
        if doc_unit != (unit or "-"):
            problems.append(f"{name}: unit {doc_unit!r}, XML {unit or '-'!r}")
        if not same_value(xml_type, start, default):
            problems.append(f"{name}: default {default!r}, XML start {start!r}")
        if set(TAG.findall(source)) != tags or not tags:
            problems.append(f"{name}: source {source!r}, XML tags {sorted(tags)}")
        if len(reasoning) < 10:
            problems.append(f"{name}: no reasoning")
    assert problems == [], "\n".join(problems)


def test_table_comparison_catches_a_wrong_default():
    # The comparison must tell values apart, not only parse them.
    assert same_value("Real", "1500000000.0", "1.5e9") and not same_value("Real", "1500000000.0", "1.5e8")
    assert same_value("Integer", "2", "2") and not same_value("Integer", "2", "2.5")
    assert same_value("Boolean", "true", "true") and not same_value("Boolean", "true", "false")
    assert not same_value("Real", "0.07", "7 cm")


def test_every_citation_names_an_existing_section():
    markdown = PHYSICS.read_text(encoding="utf-8")
    sections = set(re.findall(r"^##+ (\d+(?:\.\d+)?)[. ]", markdown, re.M))
    assert {"3.2", "4", "4.3", "6.4", "6.5", "8", "9"} <= sections, sorted(sections)
    cited, missing = 0, []
    for path, text in text_files():
        for match in CITATION.finditer(text):
            for number in re.findall(r"§(\d+(?:\.\d+)?)", match.group(1)):
                cited += 1
                if number not in sections:
                    missing.append(f"{path.relative_to(REPO)}: physics.md §{number}")
    assert cited >= 17, f"only {cited} citations of physics.md found"
    assert missing == [], "\n".join(missing)


@pytest.mark.parametrize("which", ["fmu", "truck_fmu", "full_truck_fmu"])
def test_fmu_ships_the_physics_document(which, request):
    fmu = request.getfixturevalue(which)
    with zipfile.ZipFile(fmu) as z:
        assert "documentation/physics.md" in z.namelist(), f"{fmu.name}: {sorted(z.namelist())}"
        shipped = z.read("documentation/physics.md")
        index = z.read("documentation/index.html").decode("utf-8")
        names = set(z.namelist())
    assert shipped == PHYSICS.read_bytes(), f"{fmu.name} carries an outdated physics.md: repackage it"
    assert 'href="physics.md"' in index
    # a user of the FMU has no repository: its documents link only to what the FMU holds
    local = relative_files(LINK.findall(shipped.decode("utf-8")) + re.findall(r'href="([^"]+)"', index))
    assert {t for t in local if posixpath.normpath(f"documentation/{t}") not in names} == set()


def test_the_architecture_map_names_every_module_and_script():
    """docs/architecture.md is the map a maintainer starts from: every crate, every Rust module (but
    the one-per-effect files, which docs/effects.md lists, and lib.rs/mod.rs), every Python module
    and every script is named on it."""
    text = (REPO / "docs" / "architecture.md").read_text(encoding="utf-8")
    named = set(re.findall(r"[\w.-]+\.(?:rs|py|sh)\b", text))
    missing = []
    for path in tracked_files():
        rel = path.relative_to(REPO)
        parts = rel.parts
        rust = rel.suffix == ".rs" and (parts[0] == "src" or (parts[0] == "crates" and parts[2] == "src"))
        if rust and "effects" not in parts and rel.name not in ("lib.rs", "mod.rs"):
            missing += [] if rel.name in named else [str(rel)]
        python = parts[:2] == ("python", "damper_tools") and rel.suffix == ".py" and rel.name != "__init__.py"
        script = parts[0] == "scripts" and rel.suffix in (".py", ".sh")
        if (python or script) and rel.name not in named:
            missing.append(str(rel))
        if parts[0] == "crates" and rel.name == "Cargo.toml" and f"{parts[1]}/" not in text:
            missing.append(str(rel.parent))
    assert missing == [], "docs/architecture.md does not name: " + ", ".join(sorted(missing))
