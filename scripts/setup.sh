#!/usr/bin/env bash
# Installs what the project needs, then creates the Python environment in .venv (idempotent).
#
#   bash scripts/setup.sh         # what every build needs: Python, the Windows linker, libclang
#   bash scripts/setup.sh --wine  # also Wine, for the tests' Windows runs (scripts/test.sh)
#
# - Rust (cargo) must be there already: rustup installs it (https://rustup.rs).
# - The FMUs' Linux binaries need cargo (and libclang, below). Their Windows binaries (binaries/win64) are
#   cross-compiled: Rust's x86_64-pc-windows-gnu target (rustup target add) and the MinGW-w64
#   linker (Debian's gcc-mingw-w64-x86-64). Without rustup, or where its server cannot be reached,
#   the FMUs are packaged for Linux alone and scripts/package_fmu.py says why.
# - The tests run the Windows binaries under Wine: Debian's wine64, installed with --wine.
# - The Rust *importer* of FMUs (the `fmi` crate, used by the compiled coupled runs, `damper --fmu`
#   and the import tests) generates its bindings with bindgen, which needs libclang: Debian's
#   libclang-dev. Every host build holds the importer (scripts/package_fmu.py builds the whole
#   workspace, its selection() says why), so it is always installed.
# - `python3 -m venv` needs ensurepip, which a Debian system Python has only with python3-venv.
# - ecospy (ecos, the tests' third co-simulation master) loads a library linked to Intel's oneTBB,
#   libtbb.so.12: Debian's libtbb12.
# Missing Debian packages are installed with apt-get when running as root; otherwise the script
# stops with the one command to run. Then .venv is filled from the pinned
# tests/python/requirements.txt, and the project's own package, damper_tools (pyproject.toml,
# python/damper_tools/), is installed into it, editable and without dependencies or build isolation
# (its build needs only the pinned setuptools), so that nothing unpinned is fetched; that install
# also writes its commands, .venv/bin/damper-* (pyproject.toml's [project.scripts]).
set -euo pipefail
cd "$(dirname "$0")/.."

PYTHON=${PYTHON:-python3}
REQUIREMENTS=tests/python/requirements.txt
IMPORTS="import fmpy, fmu_manipulation_toolbox, libcosimpy, ecospy, numpy, scipy, matplotlib, pytest, xdist, jsonschema, ruff, mypy, setuptools, dask, distributed, pandas, pyarrow, tqdm"
wine=false
for arg in "$@"; do
    case "$arg" in
        --wine) wine=true ;;
        *) echo "setup: unknown option $arg (use --wine or nothing)" >&2; exit 2 ;;
    esac
done

command -v cargo >/dev/null || { echo "setup: cargo not found: install Rust with rustup (https://rustup.rs)" >&2; exit 1; }
command -v "$PYTHON" >/dev/null || { echo "setup: $PYTHON not found: install Python >= 3.11" >&2; exit 1; }

packages=()
command -v x86_64-w64-mingw32-gcc >/dev/null || packages+=(gcc-mingw-w64-x86-64)
if $wine && ! command -v wine64 >/dev/null && ! command -v wine >/dev/null && [ ! -x /usr/lib/wine/wine64 ]; then
    packages+=(wine64)
fi
if [ -z "${LIBCLANG_PATH:-}" ]; then
    if command -v dpkg-query >/dev/null; then
        [ "$(dpkg-query -W -f='${Status}' libclang-dev 2>/dev/null)" = "install ok installed" ] || packages+=(libclang-dev)
    elif ! ldconfig -p 2>/dev/null | grep -q 'libclang[-.0-9]*\.so'; then
        echo "setup: libclang not found: install your system's libclang development package or set LIBCLANG_PATH" >&2
        exit 1
    fi
fi
# ecospy's libecosc.so links libtbb.so.12 (without it `import ecospy` fails with an OSError).
if command -v dpkg-query >/dev/null; then
    [ "$(dpkg-query -W -f='${Status}' libtbb12 2>/dev/null)" = "install ok installed" ] || packages+=(libtbb12)
elif ! ldconfig -p 2>/dev/null | grep -q 'libtbb\.so\.12'; then
    echo "setup: libtbb.so.12 not found: install your system's oneTBB runtime (Debian: libtbb12)" >&2
    exit 1
fi
venv_works() {
    local scratch status
    scratch=$(mktemp -d)
    "$PYTHON" -m venv "$scratch/venv" >/dev/null 2>&1 && status=0 || status=1
    rm -rf "$scratch"
    return $status
}
if [ ! -x .venv/bin/python ] && ! venv_works; then
    packages+=("python$("$PYTHON" -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')-venv")
fi

if [ ${#packages[@]} -gt 0 ]; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "setup: missing Debian packages; run: sudo apt-get update && sudo apt-get install -y ${packages[*]}" >&2
        exit 1
    fi
    echo "+ apt-get install ${packages[*]}"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null
fi

windows_target=x86_64-pc-windows-gnu
if [ ! -d "$(rustc --print sysroot)/lib/rustlib/$windows_target" ]; then
    if ! { command -v rustup >/dev/null && echo "+ rustup target add $windows_target" && rustup target add "$windows_target"; }; then
        echo "setup: warning: Rust's $windows_target target could not be installed; the FMUs will have no win64 binary" >&2
    fi
fi

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
# ecospy's wheel installs its proxyfmu program (ecos runs an FMU in a process of its own with it, for a
# model given as proxyfmu://localhost?file=...) without the execute bit, so ecos fails with "Unable to
# invoke proxyfmu!". Set it, in the installed package, on every run (a reinstall drops it again).
proxyfmu=$(.venv/bin/python -c 'import importlib.util, pathlib; print(pathlib.Path(importlib.util.find_spec("ecospy").origin).parent / "binaries" / "proxyfmu")')
[ -x "$proxyfmu" ] || chmod +x "$proxyfmu"
# Installed again when the package or one of its commands (pyproject.toml's [project.scripts],
# .venv/bin/damper-*) is missing, e.g. after a command was added.
missing_command=false
for command in $(sed -n 's/^\(damper-[a-z-]*\) = .*/\1/p' pyproject.toml); do
    [ -x ".venv/bin/$command" ] || missing_command=true
done
if $missing_command || ! .venv/bin/python -c "import damper_tools" 2>/dev/null; then
    echo "+ .venv/bin/pip install --no-deps --no-build-isolation -e ."
    .venv/bin/python -m pip install --quiet --no-deps --no-build-isolation -e .
fi
.venv/bin/python -c "$IMPORTS, damper_tools"
echo "setup: ready ($(.venv/bin/python --version), libclang$($wine && echo ', Wine'))"
