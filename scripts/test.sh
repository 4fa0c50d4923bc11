#!/usr/bin/env bash
# Runs every test: formatting, lints and the API docs' links, the Rust tests (cargo test --release;
# the FMI layer's also as a Windows program under Wine), then the Python lint (ruff), the type check
# (mypy --strict on damper_tools; both configured in pyproject.toml) and suite on the packaged FMUs.
#
#   bash scripts/test.sh [extra pytest options]
set -euo pipefail
cd "$(dirname "$0")/.."

# Each step's command, with the time the script has run so far (CI's log then shows where it goes).
step() { echo "+ [$((SECONDS / 60))m$((SECONDS % 60))s] $*"; }

bash scripts/setup.sh --wine
# clippy in the dev profile, as cargo doc checks: the two share the dependencies' checked metadata
# (no code has a cfg(debug_assertions) branch, so the profile changes nothing clippy sees)
step "cargo fmt --check && cargo clippy --all-targets --features damper_engine/study -- -D warnings && cargo doc (warnings denied)"
cargo fmt --check
cargo clippy --all-targets --features damper_engine/study -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace
# The unit and integration tests (one program per crate, tests/integration.rs) and the doc examples, in
# one cargo command. (Two commands, --tests then --doc, resolve the dependencies' features differently
# and compile some thirty crates twice.) The engine's example, a study, waits for its feature `study`:
# clippy compiled it above.
step "cargo test --release"
cargo test --release
# The FMI layer's own tests (the panic guard among them) as a Windows program, under Wine, where
# package_fmu.py can build for Windows (its windows_missing() names what is missing otherwise).
reason=$(python3 -c 'import sys; sys.path.insert(0, "scripts"); import package_fmu; print(package_fmu.windows_missing() or "")')
if [ -z "$reason" ]; then
    step "cargo test --release -p fmi_slave --target x86_64-pc-windows-gnu (under Wine: tests/win64/wine_runner.sh)"
    CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER="$PWD/tests/win64/wine_runner.sh" \
        cargo test --release -p fmi_slave --target x86_64-pc-windows-gnu
else
    echo "test.sh: the Windows tests of the FMI layer are skipped: $reason"
fi
# package_fmu.py builds the whole workspace for the host (its selection() says why): the FMUs, the
# sweeps' compiled coupled runs (cosim_runner) and the damper program
step "python3 scripts/package_fmu.py && python3 scripts/package_truck.py --no-build && python3 scripts/package_full_truck.py --no-build"
python3 scripts/package_fmu.py
python3 scripts/package_truck.py --no-build
python3 scripts/package_full_truck.py --no-build
step "python3 scripts/build_cli.py (the damper program; for Windows too where it can be built)"
python3 scripts/build_cli.py
step ".venv/bin/ruff check python scripts tests/python"
.venv/bin/ruff check python scripts tests/python
step ".venv/bin/mypy (strict, on python/damper_tools: pyproject.toml's [tool.mypy])"
.venv/bin/mypy
FMUS=(--fmu target/fmu/SemiActiveDamper.fmu --truck-fmu target/fmu/QuarterTruck.fmu --full-truck-fmu target/fmu/FullTruck.fmu)
# Two pytest workers (pytest-xdist), each taking a whole test file at a time (--dist loadfile: a
# module's fixtures are made once): test_new_effect.py compiles a copy of the project for three
# minutes, mostly on one core, while the other worker runs the rest.
step ".venv/bin/python -m pytest tests/python -q -n 2 --dist loadfile ${FMUS[*]} $*"
.venv/bin/python -m pytest tests/python -q -n 2 --dist loadfile "${FMUS[@]}" "$@"
step "every test passed"
