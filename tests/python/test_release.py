"""The release archive (scripts/release.py): the three FMUs (FMI 2.0 and 3.0) and the `damper` program
for Linux and Windows in one zip, as a user unpacks it. The program from the archive diagnoses the example record
through the FMU from the archive; the program's THIRD-PARTY.txt lists every crate compiled into it;
the same inputs give the same archive, byte for byte."""

import posixpath
import subprocess
import sys
import zipfile

import pytest

from damper_tools import REPO
from test_licences import third_party_sections
from test_readme import LINK, relative_files

RELEASE = REPO / "scripts" / "release.py"


@pytest.fixture(scope="module")
def archive(damper_exe, win64, tmp_path_factory):
    """The archive of what target/ holds (test.sh builds it all before pytest)."""
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, str(RELEASE), "--no-build", "--out-dir", str(out)], check=True)
    (path,) = out.glob("semi-active-damper-*.zip")
    return path


def unpack(archive, into):
    """Unpacks as unzip does, with the archive's file modes (Python's zipfile drops them)."""
    with zipfile.ZipFile(archive) as z:
        for info in z.infolist():
            z.extract(info, into)
            (into / info.filename).chmod(info.external_attr >> 16 & 0o777)
    (folder,) = into.iterdir()
    return folder


def test_the_archive_holds_the_fmus_and_both_programs(archive):
    folder = archive.stem + "/"  # semi-active-damper-<version>/
    with zipfile.ZipFile(archive) as z:
        modes = {info.filename.removeprefix(folder): info.external_attr >> 16 for info in z.infolist()}
    assert set(modes) == {
        "README.txt", "LICENSE-MIT", "LICENSE-APACHE", "fmu/SemiActiveDamper.fmu", "fmu/QuarterTruck.fmu",
        "fmu/FullTruck.fmu", "fmu/fmi3/SemiActiveDamper.fmu", "fmu/fmi3/QuarterTruck.fmu", "fmu/fmi3/FullTruck.fmu",
        "bin/linux64/damper", "bin/win64/damper.exe", "bin/THIRD-PARTY.txt",
        "bin/FMI-headers.txt", "bin/rust-standard-library.html",
        "bin/mingw-w64-runtime.txt", "examples/rig_valve_test.csv",
        "docs/cli.md", "docs/physics.md"}
    assert {name for name, mode in modes.items() if mode & 0o111} == {"bin/linux64/damper", "bin/win64/damper.exe"}


def test_the_archive_s_documents_link_only_to_what_it_holds(archive):
    with zipfile.ZipFile(archive) as z:
        names = set(z.namelist())
        for name in [n for n in names if n.endswith(".md")]:
            local = {posixpath.normpath(posixpath.join(posixpath.dirname(name), t))
                     for t in relative_files(LINK.findall(z.read(name).decode("utf-8")))}
            assert local <= names, name


def test_the_program_in_the_archive_runs_the_fmu_in_the_archive(archive, tmp_path):
    folder = unpack(archive, tmp_path)
    version = folder.name.removeprefix("semi-active-damper-")
    program = folder / "bin" / "linux64" / "damper"
    assert subprocess.run([program, "--version"], capture_output=True, text=True, check=True).stdout.split() == \
        ["damper", version]
    # the README.txt's command, through the FMU of the archive
    result = subprocess.run([program, "compare", "examples/rig_valve_test.csv", "--out", "comparison",
                             "--fmu", "fmu/SemiActiveDamper.fmu", "--load-cell-lowpass", "400"],
                            cwd=folder, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "SemiActiveDamper.fmu" in result.stdout
    assert (folder / "comparison" / "report.html").stat().st_size > 0
    assert "bin/linux64/damper diagnose examples/rig_valve_test.csv" in (folder / "README.txt").read_text()


def test_the_program_s_licences_cover_every_crate_compiled_in(archive, crates_compiled_in):
    with zipfile.ZipFile(archive) as z:
        (name,) = [n for n in z.namelist() if n.endswith("bin/THIRD-PARTY.txt")]
        sections = third_party_sections(z.read(name).decode("utf-8"))
    expected = crates_compiled_in("damper_cli", "linux64") | crates_compiled_in("damper_cli", "win64")
    assert set(sections) == expected
    assert any(crate == "clap" for crate, _ in sections)


def test_the_same_inputs_give_the_same_archive(archive, tmp_path):
    subprocess.run([sys.executable, str(RELEASE), "--no-build", "--out-dir", str(tmp_path)], check=True)
    assert (tmp_path / archive.name).read_bytes() == archive.read_bytes()
