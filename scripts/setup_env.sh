#!/usr/bin/env bash
# Creates the Python environment of the scripts and tests in .venv (idempotent).
#
#   bash scripts/setup_env.sh
#
# If .venv is missing it is created with `python3 -m venv` and filled from the pinned
# tests/python/requirements.txt. An existing .venv is only re-filled when one of the
# packages cannot be imported. Debian packages (libclang-dev for fmi-sys' bindgen) are
# installed by .ci/run, not here.
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON=${PYTHON:-python3}
REQUIREMENTS=tests/python/requirements.txt
IMPORTS="import fmpy, fmu_manipulation_toolbox, libcosimpy, numpy, scipy, matplotlib, pytest"

if [ ! -x .venv/bin/python ]; then
    echo "+ $PYTHON -m venv .venv"
    "$PYTHON" -m venv .venv
    echo "+ .venv/bin/pip install -r $REQUIREMENTS"
    .venv/bin/python -m pip install --quiet --upgrade pip
    .venv/bin/python -m pip install --quiet -r "$REQUIREMENTS"
elif ! .venv/bin/python -c "$IMPORTS" 2>/dev/null; then
    echo "+ .venv/bin/pip install -r $REQUIREMENTS (packages missing)"
    .venv/bin/python -m pip install --quiet -r "$REQUIREMENTS"
fi
.venv/bin/python -c "$IMPORTS"
echo "setup_env: .venv ready ($(.venv/bin/python --version))"
