"""scripts/compare_builds.py as a developer runs it after changing the damper: the last commit
against the working tree, alternated process by process."""

import subprocess
import sys

from damper_tools import REPO


def test_compares_the_last_commit_with_the_working_tree():
    out = subprocess.run(
        [sys.executable, "scripts/compare_builds.py", "HEAD", "--rounds", "2"],
        cwd=REPO, check=True, capture_output=True, text=True,
    ).stdout
    rows = [line.split("|")[1:-1] for line in out.splitlines() if line.startswith("| ") and "median" not in line]
    assert len(rows) == 2, out
    for _label, median, _spread, forces in rows:
        assert float(median.strip().rstrip("x")) > 0, out
        assert len(forces.strip()) == 16, out
    unchanged = subprocess.run(["git", "diff", "--quiet", "HEAD", "--", "src"], cwd=REPO).returncode == 0
    # a clean clone (CI) builds the same damper twice: the same forces, bit for bit
    if unchanged:
        assert "the same forces, bit for bit" in out, out
