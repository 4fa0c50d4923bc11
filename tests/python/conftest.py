"""Session fixtures of the Python suite.

The FMUs under test are built (cargo build --release of the workspace, package_fmu.py's) and packaged once
per session into tests/python/work/ by the packaging commands a user runs (python3
scripts/package_fmu.py, scripts/package_truck.py, scripts/package_full_truck.py), or taken from
`--fmu PATH` (the damper), `--truck-fmu PATH` (the quarter truck) and `--full-truck-fmu PATH` (the
full truck). Their FMI 3.0 builds (`fmu3`, `truck_fmu3`, `full_truck_fmu3`) are the packaging
commands' fmi3/ beside each FMI 2.0 FMU, or `--fmu3`, `--truck-fmu3`, `--full-truck-fmu3`. The tests
import the scenario and metric code of the scripts from the installed package damper_tools
(scripts/setup.sh installs it). `damper` is the `damper` program (target/release/damper,
built by cargo; `damper_exe` its Windows build, from scripts/build_cli.py), `dask_client` a Dask
client of a real LocalCluster of two single-threaded worker processes (the sweep and campaign tests),
and `runner_library` (every session) the coupled-run library of crates/cosim_runner, built by cargo.
"""

import importlib.util
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from fmpy import read_model_description

from damper_tools import REPO
from damper_tools.fmu import FmuUnit

WORK = Path(__file__).resolve().parent / "work"
DAMPER = REPO / "target" / "release" / "damper"
DAMPER_EXE = REPO / "target" / "x86_64-pc-windows-gnu" / "release" / "damper.exe"


def package(script: str, output: Path, build: bool) -> Path:
    """Runs a packaging command of scripts/ (standard library only) and returns the FMU it wrote."""
    command = [sys.executable, str(REPO / "scripts" / script), "--output", str(output)]
    subprocess.run(command + ([] if build else ["--no-build"]), cwd=REPO, check=True)
    return output


def pytest_addoption(parser):
    parser.addoption("--fmu", action="store", default=None,
                     help="test this FMU instead of building and packaging target/release's library")
    parser.addoption("--truck-fmu", action="store", default=None,
                     help="use this quarter-truck FMU instead of packaging target/release/libquarter_truck.so")
    parser.addoption("--full-truck-fmu", action="store", default=None,
                     help="use this full-truck FMU instead of packaging target/release/libfull_truck.so")
    for option, what in (("--fmu3", "damper"), ("--truck-fmu3", "quarter-truck"), ("--full-truck-fmu3", "full-truck")):
        parser.addoption(option, action="store", default=None,
                         help=f"the FMI 3.0 {what} FMU (default: fmi3/ beside the FMI 2.0 one)")


def given(request, option):
    """The FMU named by a command-line option, resolved; None if the option is not given."""
    value = request.config.getoption(option)
    if not value:
        return None
    path = Path(value).resolve()
    if not path.is_file():
        pytest.exit(f"{option} {value}: no such file", returncode=4)
    return path


@pytest.fixture(scope="session")
def fmu(request):
    """Path of the packaged FMU."""
    path = given(request, "--fmu")
    if path:
        return path
    WORK.mkdir(exist_ok=True)
    # Builds the workspace (the three FMUs' libraries among it), so the trucks are packaged without building.
    return package("package_fmu.py", WORK / "SemiActiveDamper.fmu", build=True)


def truck(request, option, script, name):
    """A truck FMU: the option's, or packaged from the library the damper's cargo build made (with
    --fmu given nothing has been built in this session: the packaging script runs cargo build)."""
    path = given(request, option)
    if path:
        return path
    WORK.mkdir(exist_ok=True)
    return package(script, WORK / name, build=request.config.getoption("--fmu") is not None)


@pytest.fixture(scope="session")
def truck_fmu(request, fmu):
    """Path of the packaged quarter-truck FMU."""
    return truck(request, "--truck-fmu", "package_truck.py", "QuarterTruck.fmu")


@pytest.fixture(scope="session")
def full_truck_fmu(request, fmu):
    """Path of the packaged full-truck FMU."""
    return truck(request, "--full-truck-fmu", "package_full_truck.py", "FullTruck.fmu")


def fmi3_beside(request, option, fmi2_path):
    """An FMI 3.0 FMU: the option's, or the packaging commands' fmi3/ beside the FMI 2.0 one."""
    path = given(request, option) or fmi2_path.parent / "fmi3" / fmi2_path.name
    if not path.is_file():
        pytest.fail(f"{path}: no FMI 3.0 FMU (the packaging commands write it beside the FMI 2.0 one; "
                    f"or give {option})")
    return path


@pytest.fixture(scope="session")
def fmu3(request, fmu):
    """Path of the damper's FMI 3.0 FMU."""
    return fmi3_beside(request, "--fmu3", fmu)


@pytest.fixture(scope="session")
def truck_fmu3(request, truck_fmu):
    """Path of the quarter truck's FMI 3.0 FMU."""
    return fmi3_beside(request, "--truck-fmu3", truck_fmu)


@pytest.fixture(scope="session")
def full_truck_fmu3(request, full_truck_fmu):
    """Path of the full truck's FMI 3.0 FMU."""
    return fmi3_beside(request, "--full-truck-fmu3", full_truck_fmu)


@pytest.fixture(scope="session", autouse=True)
def runner_library():
    """The compiled coupled run's library (damper_tools.runner), built by the packaging script's host
    build (package_fmu.cargo_build: the whole workspace, so that nothing already built for the FMUs
    and the damper program is compiled again): the sweeps step their HiL runs with it."""
    script("package_fmu").cargo_build(["linux64"])
    from damper_tools import runner
    return runner.library_path()


@pytest.fixture(scope="session")
def fmus(fmu, truck_fmu):
    """Keyword arguments naming both FMUs for the scripts' functions (truck_fmu=, damper_fmu=)."""
    return {"truck_fmu": truck_fmu, "damper_fmu": fmu}


def script(name):
    """The module of scripts/NAME.py (scripts/ is not a package)."""
    spec = importlib.util.spec_from_file_location(name, REPO / "scripts" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def windows_build_missing():
    """Why scripts/package_fmu.py cannot build the win64 binaries here (None when it can)."""
    return script("package_fmu").windows_missing()


@pytest.fixture(scope="session")
def seed_target_dir():
    """scripts/cargo_seed.py's seed_target_dir: a second cargo target directory started from
    target/release's compiled dependencies."""
    return script("cargo_seed").seed_target_dir


@pytest.fixture(scope="session")
def win64(fmus):
    """Both FMUs, which must carry win64 binaries; skips only where the Windows cross-build cannot
    run (scripts/setup.sh could not install Rust's Windows target), and says why."""
    for path in fmus.values():
        with zipfile.ZipFile(path) as z:
            if not any(name.startswith("binaries/win64/") for name in z.namelist()):
                reason = windows_build_missing()
                if reason:
                    pytest.skip(f"no win64 binary in {path.name}: {reason}")
                pytest.fail(f"{path} has no win64 binary, although this machine can build it")
    return fmus


@pytest.fixture(scope="session")
def model_description(fmu):
    return read_model_description(str(fmu), validate=True)


@pytest.fixture(scope="session")
def damper_unit(fmu):
    """The damper FMU extracted once: for the low-level API (fmu.Slave, several instances of it) and
    for fmpy.simulate_fmu on the extracted directory (the rig tests)."""
    return FmuUnit.load(fmu)


@pytest.fixture
def work_dir(request):
    """An empty directory for one test's files."""
    path = WORK / request.node.name.replace("[", "_").replace("]", "")
    shutil.rmtree(path, ignore_errors=True)
    path.mkdir(parents=True)
    return path


@pytest.fixture(scope="module")
def damper():
    """The `damper` program (skips when it has not been built)."""
    if not DAMPER.is_file():
        pytest.skip(f"{DAMPER} is missing: cargo build --release -p damper_cli")
    return DAMPER


@pytest.fixture(scope="module")
def damper_exe(damper):
    """The `damper` program's Windows build (python3 scripts/build_cli.py); skips, saying why, only
    where the Windows cross-build cannot run."""
    if not DAMPER_EXE.is_file():
        reason = windows_build_missing()
        if reason:
            pytest.skip(f"{DAMPER_EXE} is missing: {reason}")
        pytest.fail(f"{DAMPER_EXE} is missing, although this machine can build it: python3 scripts/build_cli.py")
    return DAMPER_EXE


@pytest.fixture(scope="module")
def dask_client():
    """A client of a LocalCluster(n_workers=2, threads_per_worker=1, processes=True), per test module."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        yield client


@pytest.fixture(scope="session")
def crates_compiled_in():
    """A function: the {(name, version)} of the registry crates compiled into a workspace crate's
    binary for an FMI platform, as `cargo tree` lists its normal dependencies."""
    targets = {"linux64": "x86_64-unknown-linux-gnu", "win64": "x86_64-pc-windows-gnu"}

    def crates(crate, platform):
        out = subprocess.run(["cargo", "tree", "--locked", "-p", crate, "-e", "normal", "--prefix", "none",
                              "--target", targets[platform]], cwd=REPO, check=True, capture_output=True, text=True)
        found = set()
        for line in out.stdout.splitlines():
            name, version, *rest = line.split()
            if not rest or rest == ["(*)"]:  # "(/path)" marks the workspace's own crates
                found.add((name, version.removeprefix("v")))
        return found

    return crates
