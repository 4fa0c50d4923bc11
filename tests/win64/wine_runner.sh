#!/usr/bin/env bash
# Cargo's runner for Windows test programs (x86_64-pc-windows-gnu) on Linux: runs EXE under Wine,
# in a Wine prefix of its own under target/, with the bcryptprimitives.dll stand-in that Debian 12's
# Wine 8 lacks (tests/win64/bcryptprimitives.c) beside it. scripts/test.sh uses it as
#   CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER=tests/win64/wine_runner.sh cargo test --target x86_64-pc-windows-gnu ...
# and tests/python/test_win64.py to run its Windows importer.
#
#   tests/win64/wine_runner.sh EXE [ARGS...]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
exe=$1
shift
wine=$(command -v wine64 || command -v wine || echo /usr/lib/wine/wine64)
[ -x "$wine" ] || { echo "wine_runner: Wine not found: bash scripts/setup.sh --wine installs it" >&2; exit 127; }
shim="$(dirname "$exe")/bcryptprimitives.dll"
if [ ! -f "$shim" ] || [ "$here/bcryptprimitives.c" -nt "$shim" ]; then
    x86_64-w64-mingw32-gcc -O2 -shared -o "$shim" "$here/bcryptprimitives.c" -ladvapi32
fi
export WINEPREFIX=${WINEPREFIX:-$here/../../target/wineprefix} WINEDEBUG=-all DISPLAY=
exec "$wine" "$exe" "$@"
