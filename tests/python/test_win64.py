"""The FMUs' Windows binaries (binaries/win64) as a Windows importer sees them, and the `damper`
program's Windows build, under Wine.

A minimal FMI 2.0 importer in C (tests/win64/fmu_session.c) is built from one source for Linux (gcc)
and for Windows (MinGW-w64), and runs one session, the same script of calls, on each binary of the
packaged FMU: the Linux one natively, the Windows one under Wine. The transcripts must be the same,
line for line: every status, every logged message and every value, to the bit (printed with 17
digits). The model's transcendental functions come from the `libm` crate, not from the platform's C
library: glibc's and MinGW-w64's sin, cos and exp differ in the last bit, which moved the damper's
forces by up to 2e-11 N at a 16.5 kN peak before.

The `damper` program (scripts/build_cli.py builds it for both platforms) generates a record,
diagnoses it in process and compares it with the model run through the packaged FMU, on Linux and
under Wine: the files it writes and what it prints must be the same, but for the time a model run
took. The engine's transcendental functions come from the `libm` crate too.

Wine 8 (Debian 12's) lacks bcryptprimitives.dll, which every Windows since 8 has; the runner
tests/win64/wine_runner.sh builds a stand-in (tests/win64/bcryptprimitives.c) beside the test program.
"""

import json
import math
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

SOURCES = Path(__file__).resolve().parent.parent / "win64"
MINGW_GCC = "x86_64-w64-mingw32-gcc"
STEP = 1e-3


@pytest.fixture(scope="module")
def programs(tmp_path_factory):
    """The importer built for both platforms; the Windows one runs through tests/win64/wine_runner.sh
    (the runner of scripts/test.sh's Windows tests: Wine, its prefix, the stand-in DLL)."""
    assert shutil.which(MINGW_GCC), f"{MINGW_GCC} not found: bash scripts/setup.sh installs MinGW-w64"
    out = tmp_path_factory.mktemp("win64")
    source = str(SOURCES / "fmu_session.c")
    subprocess.run(["gcc", "-O2", "-Wall", "-Werror", "-o", out / "fmu_session", source, "-ldl"], check=True)
    subprocess.run([MINGW_GCC, "-O2", "-Wall", "-Werror", "-o", out / "fmu_session.exe", source], check=True)
    return {"linux64": [str(out / "fmu_session")],
            "win64": [str(SOURCES / "wine_runner.sh"), str(out / "fmu_session.exe")]}


def run_session(programs, fmu_path, platform, script, work_dir):
    """Runs `script` on the FMU's `platform` binary; the transcript's lines."""
    md = read_model_description(str(fmu_path))
    identifier = md.coSimulation.modelIdentifier
    unpacked = work_dir / platform
    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(unpacked)
    resources = (unpacked / "resources").as_uri()
    if platform == "linux64":
        binary = str(unpacked / "binaries" / "linux64" / f"{identifier}.so")
    else:
        # Wine sees the Linux file system as drive Z:.
        binary = "Z:" + str(unpacked / "binaries" / "win64" / f"{identifier}.dll").replace("/", "\\")
    result = subprocess.run(programs[platform] + [binary, identifier, md.guid, resources],
                            input="\n".join(script) + "\n", capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, f"{platform}: {result.stderr[-2000:]}"
    return result.stdout.splitlines()  # universal newlines: Windows' CRLF too


def compare(linux, windows, outputs):
    """The transcripts equal line for line; the values read, one row per `get`."""
    assert len(linux) == len(windows)
    for number, (a, b) in enumerate(zip(linux, windows, strict=True), 1):
        if a != b and a.startswith("get ") and b.startswith("get "):
            differences = [f"{name} {x} (Linux) against {y}"
                           for name, x, y in zip(outputs, a.split()[2:], b.split()[2:], strict=True) if x != y]
            pytest.fail(f"line {number}: {a.split()[1]} against {b.split()[1]}; " + "; ".join(differences))
        assert a == b, f"line {number}"
    return np.array([[float(x) for x in line.split()[2:]] for line in linux if line.startswith("get ")])


def vr(md, name):
    return next(v.valueReference for v in md.modelVariables if v.name == name)


def test_the_damper_runs_a_session_on_windows_as_on_linux(win64, programs, work_dir):
    md = read_model_description(str(win64["damper_fmu"]))
    outputs = ["F_damper", "x_spool", "i_sol", "p_ext", "p_comp"]
    get = "get " + " ".join(str(vr(md, n)) for n in outputs)
    v, f = vr(md, "v_damper"), vr(md, "F_demand")
    script = ["instantiate damper", "setup 1e-4 0", "init"]
    for k in range(3000):
        t = k * STEP
        velocity = 0.3 * math.sin(12 * t) + 0.1 * math.sin(37 * t)
        script += [f"set {v} {velocity!r} {f} {9e3 * math.cos(5 * t)!r}", f"step {t!r} {STEP!r}", get]
    # what the FMU refuses, and how it says so
    script += [f"set {v} nan", f"step 3.0 {STEP!r}", get, f"step 3.001 {-STEP!r}", "terminate", "free"]

    linux = run_session(programs, win64["damper_fmu"], "linux64", script, work_dir)
    windows = run_session(programs, win64["damper_fmu"], "win64", script, work_dir)
    values = compare(linux, windows, outputs)

    assert linux[:4] == ["version 2.0", "instantiate damper ok", "setup OK", "init OK"]
    assert linux.count("step OK") == 3001
    assert np.sqrt(np.mean(values[:3000, 0] ** 2)) > 1e3, "the damper delivered no force"
    refusals = [line for line in windows if line.startswith("log Error")]
    assert len(refusals) == 2 and "v_damper = NaN refused" in refusals[0] and "must be positive" in refusals[1]
    assert windows[-3:] == ["step Error", "terminate OK", "free"]


def test_the_quarter_truck_runs_a_session_on_windows_as_on_linux(win64, programs, work_dir):
    md = read_model_description(str(win64["truck_fmu"]))
    outputs = ["v_damper", "x_damper", "a_body", "F_tyre"]
    get = "get " + " ".join(str(vr(md, n)) for n in outputs)
    z, zdot, force = vr(md, "z_road"), vr(md, "v_road"), vr(md, "F_damper")
    script = ["instantiate truck", "setup 0 0", "init"]
    for k in range(2000):
        t = k * STEP
        script += [f"set {z} {0.02 * math.sin(9 * t)!r} {zdot} {0.18 * math.cos(9 * t)!r} {force} 0",
                   f"step {t!r} {STEP!r}", get]
    script += ["terminate", "free"]

    linux = run_session(programs, win64["truck_fmu"], "linux64", script, work_dir)
    windows = run_session(programs, win64["truck_fmu"], "win64", script, work_dir)
    values = compare(linux, windows, outputs)
    assert linux.count("step OK") == 2000 and np.abs(values[:, 0]).max() > 0.01, "the truck did not move"


def without_timings(value):
    """A summary.json value without the one entry that differs from run to run (model_run_s)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items() if k != "model_run_s"}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def test_the_damper_program_gives_on_windows_what_it_gives_on_linux(damper, damper_exe, fmus, work_dir):
    programs = {"linux64": [str(damper)], "win64": [str(SOURCES / "wine_runner.sh"), str(damper_exe)]}
    commands = [
        ["generate", "--effect", "seal_friction", "--seed", "3", "--duration", "8", "--rate", "1000",
         "--out", "record.csv", "--truth", "truth.json"],
        ["diagnose", "record.csv", "--out", "diagnosis", "--load-cell-lowpass", "400"],
        ["compare", "record.csv", "--out", "through_fmu", "--fmu", "damper.fmu", "--load-cell-lowpass", "400"],
    ]
    printed = {}
    for platform, program in programs.items():
        # the same relative paths on both: each platform runs in a directory of its own
        cwd = work_dir / platform
        cwd.mkdir()
        shutil.copy(fmus["damper_fmu"], cwd / "damper.fmu")
        printed[platform] = []
        for command in commands:
            result = subprocess.run(program + command, cwd=cwd, capture_output=True, text=True, timeout=600)
            assert result.returncode == 0, f"{platform} {command[0]}: {result.stderr[-2000:]}"
            # the path a program prints uses its platform's separator; a model run's time varies
            printed[platform] += [line.replace("\\", "/") for line in result.stdout.splitlines()
                                  if not line.startswith("model run:")]
    assert printed["linux64"] == printed["win64"]
    linux, windows = work_dir / "linux64", work_dir / "win64"
    for name in ["record.csv", "truth.json"]:
        assert (linux / name).read_bytes() == (windows / name).read_bytes(), name
    for name in ["diagnosis/summary.json", "through_fmu/summary.json"]:
        summary = [without_timings(json.loads((d / name).read_text())) for d in (linux, windows)]
        assert summary[0] == summary[1], name
    # the reports' plots too: their axes' logarithms come from the libm crate (clippy.toml)
    for name in ["diagnosis/report.html", "through_fmu/report.html"]:
        report = [re.sub(r"Model run [0-9.]+ s \([0-9]+× real time\)", "", (d / name).read_text())
                  for d in (linux, windows)]
        assert report[0] == report[1], name
    assert "verdict: effect (seal_friction)" in printed["linux64"]
