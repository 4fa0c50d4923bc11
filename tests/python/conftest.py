"""Session fixtures of the Python suite.

The FMUs under test are built (cargo build --release of the two FMU packages) and packaged
once per session into tests/python/work/, or taken from `--fmu PATH` (the damper) and
`--truck-fmu PATH` (the quarter truck). scripts/ is put on sys.path so that tests import the same
scenario and metric code as the scripts (rig_tests, roads, cosim, ssp, hil_scenarios, full_truck)
and the packagers.
"""

import shutil
import sys
from pathlib import Path

import pytest
from fmpy import extract, read_model_description

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
WORK = HERE / "work"
sys.path.insert(0, str(REPO / "scripts"))

import package_fmu  # noqa: E402
import package_truck  # noqa: E402


def pytest_addoption(parser):
    parser.addoption("--fmu", action="store", default=None,
                     help="test this FMU instead of building and packaging target/release's library")
    parser.addoption("--truck-fmu", action="store", default=None,
                     help="use this quarter-truck FMU instead of packaging target/release/libquarter_truck.so")


@pytest.fixture(scope="session")
def fmu(request):
    """Path of the packaged FMU."""
    given = request.config.getoption("--fmu")
    if given:
        path = Path(given).resolve()
        if not path.is_file():
            pytest.exit(f"--fmu {given}: no such file", returncode=4)
        return path
    WORK.mkdir(exist_ok=True)
    package_fmu.cargo_build()
    library = package_fmu.target_dir() / "release" / package_fmu.LIBRARY_NAME
    package_fmu.check_library(library)
    return package_fmu.package(library, REPO / "modelDescription.xml", WORK / "SemiActiveDamper.fmu")


@pytest.fixture(scope="session")
def truck_fmu(request, fmu):
    """Path of the packaged quarter-truck FMU (built by the same cargo build as the damper)."""
    given = request.config.getoption("--truck-fmu")
    if given:
        path = Path(given).resolve()
        if not path.is_file():
            pytest.exit(f"--truck-fmu {given}: no such file", returncode=4)
        return path
    WORK.mkdir(exist_ok=True)
    library = package_fmu.target_dir() / "release" / package_truck.LIBRARY_NAME
    if not library.is_file():
        package_fmu.cargo_build()
    package_fmu.check_library(library)
    return package_truck.package(library, package_truck.XML, WORK / "QuarterTruck.fmu")


@pytest.fixture(scope="session")
def fmus(fmu, truck_fmu):
    """Keyword arguments naming both FMUs for the scripts' functions (truck_fmu=, damper_fmu=)."""
    return {"truck_fmu": truck_fmu, "damper_fmu": fmu}


@pytest.fixture(scope="session")
def model_description(fmu):
    return read_model_description(str(fmu), validate=True)


@pytest.fixture(scope="session")
def unzipdir(fmu):
    """The FMU extracted once, for the low-level API (several instances from one directory)."""
    target = WORK / "extracted"
    shutil.rmtree(target, ignore_errors=True)
    target.mkdir(parents=True)
    extract(str(fmu), unzipdir=str(target))
    return target


@pytest.fixture
def work_dir(request):
    """An empty directory for one test's files."""
    path = WORK / request.node.name.replace("[", "_").replace("]", "")
    shutil.rmtree(path, ignore_errors=True)
    path.mkdir(parents=True)
    return path
