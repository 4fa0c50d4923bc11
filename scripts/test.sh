#!/usr/bin/env bash
# Runs every test: formatting, lints and the API docs' links, the Rust tests (cargo test --release),
# then the Python lint (ruff, configured in pyproject.toml) and suite on the packaged FMUs.
#
#   bash scripts/test.sh [extra pytest options]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh --importer
echo "+ cargo fmt --check && cargo clippy --release --all-targets -- -D warnings && cargo doc (warnings denied)"
cargo fmt --check
cargo clippy --release --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace
echo "+ cargo test --release"
cargo test --release
echo "+ python3 scripts/package_fmu.py && python3 scripts/package_truck.py --no-build"
python3 scripts/package_fmu.py
python3 scripts/package_truck.py --no-build
echo "+ .venv/bin/ruff check python scripts tests/python"
.venv/bin/ruff check python scripts tests/python
echo "+ .venv/bin/python -m pytest tests/python -q --fmu target/fmu/SemiActiveDamper.fmu --truck-fmu target/fmu/QuarterTruck.fmu $*"
.venv/bin/python -m pytest tests/python -q --fmu target/fmu/SemiActiveDamper.fmu --truck-fmu target/fmu/QuarterTruck.fmu "$@"
