#!/usr/bin/env bash
# Builds the FMU and reproduces the paper's rig tests (Figs. 4 and 6) into out/paper/.
#
#   bash scripts/main.sh [paper_tests.py options, e.g. --out DIR]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup_env.sh
echo "+ cargo build --release"
cargo build --release
echo "+ python3 scripts/package_fmu.py --no-build"
python3 scripts/package_fmu.py --no-build
echo "+ .venv/bin/python scripts/paper_tests.py $*"
.venv/bin/python scripts/paper_tests.py "$@"
