"""Compare the damper's speed in two revisions, on a machine whose speed drifts.

Builds the benchmark (`benches/realtime.rs`) of each revision and runs the builds alternately, one
process at a time, each printing the fastest of 20 runs of the benchmark's input at one tolerance
(`cargo bench --bench realtime -- quick`). On the shared machines of this project the speed moves
by ±25 % from one process to the next (docs/performance.md), so one run of each build says little;
alternated processes see the same minutes, and the medians compare. The forces' hash tells whether
the two builds compute the same forces, bit for bit.

    python3 scripts/compare_builds.py HEAD~1            # HEAD~1 against the working tree
    python3 scripts/compare_builds.py A B --rounds 12 --rtol 3e-5

A revision is checked out in a git worktree under target/compare/ and built with the working
tree's benchmark, so that only the damper differs (the working tree itself is built in place);
the builds share target/compare/target.
"""

import argparse
import re
import shutil
import statistics
import subprocess
import sys
from pathlib import Path

# Run as a script, Python puts scripts/ first on sys.path, so the sibling is found.
import cargo_seed

ROOT = Path(__file__).resolve().parent.parent
WORK = ROOT / "target" / "compare"
QUICK_LINE = re.compile(r"rtol \S+: (\d+)x real time, forces ([0-9a-f]{16})")


def build(revision: str | None) -> Path:
    """The benchmark's executable for `revision` (None: the working tree), copied out of cargo's
    target directory so that the next build cannot overwrite it."""
    source, target = ROOT, ROOT / "target"
    name = "working-tree"
    if revision is not None:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", revision], cwd=ROOT, check=True, capture_output=True, text=True
        ).stdout.strip()
        name, source, target = commit, WORK / commit, WORK / "target"
        if not source.exists():
            subprocess.run(["git", "worktree", "add", "--detach", str(source), commit], cwd=ROOT, check=True)
        # the same benchmark on both sides: only the damper differs (and older revisions lack `quick`)
        shutil.copy(ROOT / "benches" / "realtime.rs", source / "benches" / "realtime.rs")
        # the revision compiles only its own crates: the dependencies come from the working tree's
        # build, made first (main) with the same command
        cargo_seed.seed_target_dir(ROOT / "target", target)
    built = subprocess.run(
        ["cargo", "bench", "--bench", "realtime", "--no-run", "--target-dir", str(target)],
        cwd=source,
        check=True,
        capture_output=True,
        text=True,
    )
    executable = re.search(r"Executable benches/realtime\.rs \((.+)\)", built.stderr)
    if executable is None:
        sys.exit(f"compare_builds: cargo did not name the benchmark's executable:\n{built.stderr}")
    WORK.mkdir(parents=True, exist_ok=True)
    copy = WORK / f"realtime-{name}"
    shutil.copy2(source / executable.group(1), copy)
    return copy


def quick(executable: Path, rtol: float) -> tuple[int, str]:
    out = subprocess.run([str(executable), "quick", str(rtol)], check=True, capture_output=True, text=True).stdout
    match = QUICK_LINE.search(out)
    if match is None:
        sys.exit(f"compare_builds: {executable.name} printed no result line:\n{out}")
    return int(match.group(1)), match.group(2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a", help="a git revision")
    parser.add_argument("b", nargs="?", help="a git revision (default: the working tree)")
    parser.add_argument("--rounds", type=int, default=8, help="processes per build (default 8)")
    parser.add_argument("--rtol", type=float, default=3e-4, help="tolerance (default 3e-4, the FMU's)")
    args = parser.parse_args()
    # the working tree first, so that a revision's build starts from its compiled dependencies
    built_b = build(args.b)
    builds = {args.a: build(args.a), args.b or "working tree": built_b}
    factors: dict[str, list[int]] = {label: [] for label in builds}
    hashes: dict[str, str] = {}
    for _ in range(args.rounds):
        for label, executable in builds.items():
            factor, hashes[label] = quick(executable, args.rtol)
            factors[label].append(factor)
    print(f"rtol {args.rtol:g}, {args.rounds} processes per build, alternated; each the fastest of 20 runs")
    print("| build | median | range | forces |")
    print("|---|---|---|---|")
    for label, values in factors.items():
        print(f"| {label} | {statistics.median(values):.0f}x | {min(values)}-{max(values)}x | {hashes[label]} |")
    same = len(set(hashes.values())) == 1
    print("the same forces, bit for bit" if same else "the forces differ")


if __name__ == "__main__":
    main()
