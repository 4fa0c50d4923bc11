"""Session fixtures of the Python suite.

The FMU under test is built (cargo build --release) and packaged once per session into
tests/python/work/, or taken from `--fmu PATH`. scripts/ is put on sys.path so that tests
import the same scenario and metric code as scripts/paper_tests.py (rig_tests) and the packager.
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


def pytest_addoption(parser):
    parser.addoption("--fmu", action="store", default=None,
                     help="test this FMU instead of building and packaging target/release's library")


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
