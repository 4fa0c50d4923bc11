#!/usr/bin/env bash
# Runs every test: the Rust tests (cargo test --release), then the Python suite on the packaged FMU.
#
#   bash scripts/test.sh [extra pytest options]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh
echo "+ cargo test --release"
cargo test --release
echo "+ python3 scripts/package_fmu.py"
python3 scripts/package_fmu.py
echo "+ .venv/bin/python -m pytest tests/python -q --fmu target/fmu/SemiActiveDamper.fmu $*"
.venv/bin/python -m pytest tests/python -q --fmu target/fmu/SemiActiveDamper.fmu "$@"
