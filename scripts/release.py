#!/usr/bin/env python3
"""Pack a release: the three FMUs, FMI 2.0 and FMI 3.0, and the `damper` program, for Linux and Windows,
in one zip archive (standard library only).

    python3 scripts/release.py              # build everything (package_fmu, package_truck, package_full_truck,
                                            # build_cli), then pack
    python3 scripts/release.py --no-build   # pack what target/ already holds

writes target/dist/semi-active-damper-<version>.zip, whose one folder holds

    README.txt                    what is in the archive and how to start (written here)
    LICENSE-MIT, LICENSE-APACHE   the project's licences
    fmu/SemiActiveDamper.fmu      the damper (linux64 and win64 binaries; its licences inside)
    fmu/QuarterTruck.fmu          the quarter truck with the clipped Modified Skyhook demand
    fmu/FullTruck.fmu             the three-axle truck (heave, pitch, roll) for six dampers
    fmu/fmi3/*.fmu                the same three as FMI 3.0 FMUs (x86_64-linux, x86_64-windows)
    bin/linux64/damper            the diagnosis and calibration program for Linux (glibc >= 2.34)
    bin/win64/damper.exe          the same for Windows 10 or later
    bin/THIRD-PARTY.txt           the crates compiled into the program, with their licences' text
    bin/FMI-headers.txt, rust-standard-library.html, mingw-w64-runtime.txt   the files it names
    examples/rig_valve_test.csv   a rig record to diagnose (a hidden effect: the README says which)
    docs/cli.md, docs/physics.md  the program's command line; the model's equations and parameters

The version is the crates'; the model descriptions and the program must agree with it. Entries are
sorted and carry a fixed time stamp, so the same inputs give the same archive, byte for byte.
"""

import argparse
import posixpath
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

# Run as a script, Python puts scripts/ first on sys.path, so the siblings are found.
import build_cli
import package_fmu
import package_full_truck
import package_truck

REPO = package_fmu.REPO
PLATFORMS = ("linux64", "win64")
EXAMPLE = REPO / "data" / "measurements" / "rig_valve_test.csv"
FMU_DIR = REPO / "target" / "fmu"
DOCS = ("cli.md", "physics.md")
# a Markdown link to a file (not to a web address or an anchor)
FILE_LINK = re.compile(r"\[([^\]]+)\]\(((?![a-z]+:|#)[^)\s]+)\)")

README = """Semi-active truck damper {version}: FMI 2.0 and FMI 3.0 Co-Simulation FMUs and the damper program

A model of the continuously variable semi-active damper for heavy trucks of Kitching, Cole and
Cebon, "The development of a semi-active truck damper": the master gives the damper velocity and a
force demand, the FMU returns the force its load cell measures.

fmu/SemiActiveDamper.fmu   the damper; binaries for linux64 (glibc >= 2.34) and win64 (Windows 10+).
                           Inputs v_damper [m/s, extension +], F_demand [N, tension +]; output
                           F_damper [N]. Its documentation/index.html lists every variable.
fmu/QuarterTruck.fmu       the paper's quarter truck (Table 1) with the clipped Modified Skyhook
                           demand, to couple with the damper on a road.
fmu/FullTruck.fmu          a three-axle truck whose body heaves, pitches and rolls, Table 1 at each
                           corner, to couple with six damper instances.
fmu/fmi3/                  the same three FMUs for FMI 3.0 masters (binaries x86_64-linux and
                           x86_64-windows): the same variables and value references, and the same
                           results bit for bit.
bin/linux64/damper         compares the model with a measurement and names the physical effect
bin/win64/damper.exe       the model misses (diagnose), fits nominal parameters (calibrate), makes
                           measurement-like records (generate); docs/cli.md is its help.
examples/rig_valve_test.csv  a rig record with a hidden effect, to try the diagnosis on:

    bin/linux64/damper diagnose examples/rig_valve_test.csv --out diagnosis --load-cell-lowpass 400
    bin\\win64\\damper.exe diagnose examples\\rig_valve_test.csv --out diagnosis --load-cell-lowpass 400

  then open diagnosis/report.html. With --fmu fmu/SemiActiveDamper.fmu the program runs the
  packaged FMU instead of its built-in copy of the model.

docs/physics.md            every equation and parameter, with its unit, source and reasoning (the
                           FMUs carry it too, as documentation/physics.md). A path in backticks that
                           the archive lacks, such as `docs/diagnose.md`, is in the project's
                           repository.

The Linux and Windows binaries compute the same results, bit for bit (tested with Windows'
binaries under Wine, not on Windows itself). Licence: MIT OR Apache-2.0 (LICENSE-MIT,
LICENSE-APACHE); the licences of the code compiled into the FMUs are in each FMU's
documentation/licenses/, those of the program in bin/ (THIRD-PARTY.txt and the files it names).
"""


def version():
    """The crates' version, after checking that both model descriptions and the program agree."""
    crate = tomllib.loads((REPO / "Cargo.toml").read_text(encoding="utf-8"))["package"]["version"]
    for xml in (REPO / "modelDescription.xml", package_truck.XML, package_full_truck.XML):
        found = package_fmu.read_model(xml)["version"]
        if found != crate:
            sys.exit(f"release: {xml.relative_to(REPO)} says version {found!r}, the crates {crate!r}")
    program = tomllib.loads((REPO / "crates" / "damper_cli" / "Cargo.toml").read_text(encoding="utf-8"))
    if program["package"]["version"] != crate:
        sys.exit(f"release: crates/damper_cli/Cargo.toml says version {program['package']['version']!r}, "
                 f"the damper crate {crate!r}")
    return crate


def without_dangling_links(text, shipped):
    """A document of docs/ for the archive: a link to a file the archive lacks becomes the file's
    path in the repository, as code (the README.txt says where those are)."""
    def link(match):
        path = posixpath.normpath(posixpath.join("docs", match[2].split("#")[0]))
        return match[0] if path in shipped else f"`{path}`"
    return FILE_LINK.sub(link, text)


def contents(version, fmus, programs):
    """(archive name, bytes) of every entry, sorted by name."""
    folder = f"semi-active-damper-{version}/"
    docs = {f"docs/{name}" for name in DOCS}
    files = {
        "README.txt": README.format(version=version).encode("utf-8"),
        "bin/THIRD-PARTY.txt": package_fmu.third_party_notice("damper_cli", list(programs),
                                                              "the damper program").encode("utf-8"),
        **{f"bin/{name}": data for name, data in package_fmu.common_licences(list(programs))},
        "examples/rig_valve_test.csv": EXAMPLE.read_bytes(),
        **{f"fmu/{path.relative_to(FMU_DIR).as_posix()}": path.read_bytes() for path in fmus},
        **{f"bin/{platform}/{path.name}": path.read_bytes() for platform, path in programs.items()},
        **{f"docs/{name}": without_dangling_links((REPO / "docs" / name).read_text(encoding="utf-8"),
                                                  docs).encode("utf-8") for name in DOCS},
        **{name: (REPO / name).read_bytes() for name in package_fmu.PROJECT_LICENCES},
    }
    return [(folder + name, data) for name, data in sorted(files.items())]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--no-build", action="store_true", help="pack what target/ already holds")
    parser.add_argument("--out-dir", default=str(package_fmu.target_dir() / "dist"),
                        help="folder of the archive (default: target/dist)")
    args = parser.parse_args(argv)
    release = version()
    if not args.no_build:
        for script in ("package_fmu.py", "package_truck.py", "package_full_truck.py", "build_cli.py"):
            # a release has both platforms: each script stops with the reason where one cannot be built
            subprocess.run([sys.executable, str(REPO / "scripts" / script), "--platforms", ",".join(PLATFORMS)],
                           check=True)
    fmi2 = [REPO / "target" / "fmu" / "SemiActiveDamper.fmu", package_truck.OUTPUT, package_full_truck.OUTPUT]
    fmus = fmi2 + [package_fmu.fmi3_output(path) for path in fmi2]
    programs = {platform: build_cli.program_path(platform) for platform in PLATFORMS}
    missing = [str(p) for p in [*fmus, *programs.values()] if not p.exists()]
    if missing:
        sys.exit(f"release: missing {', '.join(missing)}: run without --no-build (bash scripts/setup.sh installs "
                 "what the Windows build needs)")
    for fmu in fmus:
        folders = PLATFORMS if fmu in fmi2 else [package_fmu.FMI3_PLATFORMS[p] for p in PLATFORMS]
        with zipfile.ZipFile(fmu) as z:
            lacking = [p for p in folders if not any(n.startswith(f"binaries/{p}/") for n in z.namelist())]
        if lacking:
            sys.exit(f"release: {fmu} has no {', '.join(lacking)} binary: run without --no-build")
    archive = Path(args.out_dir) / f"semi-active-damper-{release}.zip"
    package_fmu.write_zip(archive, contents(release, fmus, programs),
                          executable=lambda name: any(f"/bin/{p}/" in name for p in PLATFORMS))
    print(f"release: wrote {archive} ({archive.stat().st_size / 1e6:.1f} MB)")


if __name__ == "__main__":
    main()
