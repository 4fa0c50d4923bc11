#!/usr/bin/env bash
# Builds the FMUs, reproduces the paper's rig tests (Figs. 4 and 6) into out/paper/ and runs the HiL
# scenarios (quarter truck + damper FMU on random roads and the Belgian block, Fig. 7) into out/hil/, the
# valve and force-loop transfer functions, flow map and force-velocity map into out/valve/ (about 10 s) and
# the HiL rig model sweep and the Fig. 7 robustness table into out/rig/ (about 1–2 min).
#
#   bash scripts/main.sh [damper-paper-tests options, e.g. --out DIR]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
# Builds the whole workspace for the host (the sweeps' compiled coupled runs, cosim_runner, among it;
# libclang for the importer's bindings) and the FMUs' libraries for Windows, and packs the damper's.
echo "+ python3 scripts/package_fmu.py"
python3 scripts/package_fmu.py
echo "+ python3 scripts/package_truck.py --no-build && python3 scripts/package_full_truck.py --no-build"
python3 scripts/package_truck.py --no-build
python3 scripts/package_full_truck.py --no-build
echo "+ .venv/bin/damper-paper-tests $*"
.venv/bin/damper-paper-tests "$@"
echo "+ .venv/bin/damper-hil-scenarios"
.venv/bin/damper-hil-scenarios
echo "+ .venv/bin/damper-valve-response"
.venv/bin/damper-valve-response
echo "+ .venv/bin/damper-hil-rig"
.venv/bin/damper-hil-rig
