"""Start a second cargo target directory from what the first already compiled.

Cargo names a dependency's artifacts by a hash of its version, features, profile and compiler, not
of the target directory, so a second target directory (a copy of the project, a git worktree of
another revision) can reuse the first's compiled dependencies and compile only the workspace's own
crates, whose paths differ. On a fresh machine that saves building every dependency a second time,
minutes of the test command (tests/python/test_new_effect.py, scripts/compare_builds.py).
"""

import os
import shutil
from pathlib import Path


def seed_target_dir(built: Path, target: Path, profile: str = "release") -> None:
    """Seed `target` (a new target directory) from `built`'s `profile` directory: the compiled
    artifacts (deps/, about 1 GB) as hard links, the small bookkeeping a build may rewrite in place
    (the build scripts' output, the fingerprints) as copies; nothing when `target` exists already."""
    source = built / profile
    if target.exists() or not source.is_dir():
        return
    for part, copy in (("deps", os.link), ("build", shutil.copy2), (".fingerprint", shutil.copy2)):
        if (source / part).is_dir():
            shutil.copytree(source / part, target / profile / part, copy_function=copy, symlinks=True)
