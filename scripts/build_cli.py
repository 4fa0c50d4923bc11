#!/usr/bin/env python3
"""Build the `damper` program (crates/damper_cli: diagnose, calibrate, compare, generate) for Linux
and, where the Windows cross-build can run, for Windows (standard library only).

    python3 scripts/build_cli.py                        # linux64, and win64 where it can be built
    python3 scripts/build_cli.py --platforms linux64    # the Linux program only

writes target/release/damper and target/x86_64-pc-windows-gnu/release/damper.exe. The Windows
program is cross-compiled as the FMUs' Windows binaries are (cargo's x86_64-pc-windows-gnu target,
the MinGW-w64 linker of .cargo/config.toml) and needs only DLLs of Windows 10 or later. Both take
the same arguments and give the same results, bit for bit (tests/python/test_win64.py).

Building needs libclang (Debian's libclang-dev, which `bash scripts/setup.sh` installs):
the fmi crate, through which `damper --fmu` loads a packaged FMU, generates its bindings of the FMI
headers with bindgen at build time.
"""

import argparse
import os
import subprocess
import sys

# Run as a script, Python puts scripts/ first on sys.path, so the sibling is found.
import package_fmu

PROGRAM = "damper"


def program_path(platform):
    """Where cargo build --release puts the program for `platform`."""
    triple, _, library_suffix = package_fmu.PLATFORMS[platform]
    suffix = ".exe" if library_suffix == ".dll" else ""
    return package_fmu.target_dir() / (triple or "") / "release" / f"{PROGRAM}{suffix}"


def cargo_environment(triple):
    """The environment of the build for `triple`. For Windows, bindgen's libclang finds MinGW-w64's C
    headers but not GCC's own (mm_malloc.h, which MinGW's malloc.h includes): the cross-compiler
    names their directory."""
    env = dict(os.environ)
    if triple == package_fmu.PLATFORMS["win64"][0]:
        include = subprocess.run([package_fmu.WINDOWS_LINKER, "-print-file-name=include"],
                                 capture_output=True, text=True, check=True).stdout.strip()
        variable = "BINDGEN_EXTRA_CLANG_ARGS_" + triple.replace("-", "_")
        env[variable] = " ".join(filter(None, [env.get(variable), f"-I{include}"]))
    return env


def build(platforms):
    """Builds the program for each platform; returns {platform: path}."""
    package_fmu.cargo_build(platforms, ["damper_cli"], cargo_environment)
    return {platform: program_path(platform) for platform in platforms}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--platforms", default="auto",
                        help="auto (linux64, and win64 where it can be built) or a comma-separated list of "
                             f"{', '.join(package_fmu.PLATFORMS)} (default: auto)")
    args = parser.parse_args(argv)
    platforms = package_fmu.platforms_arg(args.platforms, "build_cli", product="the damper program gets")
    for platform, path in build(platforms).items():
        if not path.is_file():
            sys.exit(f"build_cli: cargo did not write {path}")
        print(f"build_cli: {platform}: {path}")


if __name__ == "__main__":
    main()
