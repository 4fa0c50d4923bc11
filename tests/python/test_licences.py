"""Each FMU, FMI 2.0 and FMI 3.0, carries the licences of the code in its binaries
(documentation/licenses/): the project's own, the FMI headers' (the FMI layer transcribes their
types), the Rust standard library's notices, the MinGW-w64 runtime's where there is a win64 binary,
and THIRD-PARTY.txt with every crate
compiled in and the text of its licence files.

The crates expected are asked of `cargo tree` here, per platform, and each crate's section must hold
a text of one of the licences its expression offers."""

import re
import zipfile

import pytest

from damper_tools import REPO

CRATES = {"fmu": "semi_active_damper", "truck_fmu": "quarter_truck", "full_truck_fmu": "full_truck",
          "fmu3": "semi_active_damper", "truck_fmu3": "quarter_truck", "full_truck_fmu3": "full_truck"}
# FMI 3.0's platform tuples, by the FMI 2.0 folder names the crates are asked of cargo tree by
PLATFORM = {"x86_64-linux": "linux64", "x86_64-windows": "win64", "linux64": "linux64", "win64": "win64"}
# a phrase that each licence's text carries
LICENCE_TEXTS = {
    "MIT": "Permission is hereby granted, free of charge",
    "Apache-2.0": "Apache License",
    "Zlib": "This software is provided 'as-is'",
}
# a crate's section of THIRD-PARTY.txt: its name, version, licence expression and text
SECTION = re.compile(r"^={78}\n(\S+) (\S+): ([^\n,]+)(?:, \S+)?\n={78}\n(.*?)(?=^={78}\n|\Z)", re.M | re.S)


@pytest.mark.parametrize("which", CRATES)
def test_the_fmu_carries_the_licences_of_what_its_binaries_contain(request, which, crates_compiled_in):
    with zipfile.ZipFile(request.getfixturevalue(which)) as fmu:
        platforms = sorted({PLATFORM[n.split("/")[1]] for n in fmu.namelist() if n.startswith("binaries/")})
        licences = {n.removeprefix("documentation/licenses/"): fmu.read(n) for n in fmu.namelist()
                    if n.startswith("documentation/licenses/")}
        index = fmu.read("documentation/index.html").decode("utf-8")
    assert 'href="licenses/THIRD-PARTY.txt"' in index  # from documentation/index.html

    expected_files = {"LICENSE-MIT", "LICENSE-APACHE", "THIRD-PARTY.txt", "FMI-headers.txt",
                      "rust-standard-library.html"}
    if "win64" in platforms:
        expected_files.add("mingw-w64-runtime.txt")
    assert set(licences) == expected_files
    for name in ["LICENSE-MIT", "LICENSE-APACHE"]:
        assert licences[name] == (REPO / name).read_bytes()
    assert b"Rust Standard Library" in licences["rust-standard-library.html"]
    assert b'Modelica Association Project "FMI"' in licences["FMI-headers.txt"]

    sections = third_party_sections(licences["THIRD-PARTY.txt"].decode("utf-8"))
    assert set(sections) == set().union(*(crates_compiled_in(CRATES[which], p) for p in platforms))
    # the damper's linear algebra: an empty list from cargo tree would make the check above hollow
    assert CRATES[which] != "semi_active_damper" or any(name == "nalgebra" for name, _ in sections)


def third_party_sections(notice):
    """{(name, version): (licence expression, text)} of a THIRD-PARTY.txt, after checking that each
    crate's text holds one of the licences its expression names (or, for licences not listed here,
    some licence text)."""
    sections = {(name, version): (expression, text) for name, version, expression, text in SECTION.findall(notice)}
    for crate, (expression, text) in sections.items():
        known = set(re.findall(r"[\w.+-]+", expression)) & set(LICENCE_TEXTS)
        if known:
            assert any(LICENCE_TEXTS[term] in text for term in known), (crate, expression)
        else:  # BSD-3-Clause, ISC, bzip2, Unicode-3.0: a text at all
            assert len(text.strip()) > 300, (crate, expression)
    return sections

