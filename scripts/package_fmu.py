#!/usr/bin/env python3
"""Package the damper as FMI 2.0 and FMI 3.0 Co-Simulation FMUs (standard library only).

    python3 scripts/package_fmu.py              # cargo build --release (Linux and Windows), then zip
    python3 scripts/package_fmu.py --no-build   # zip what target/ already holds
    python3 scripts/package_fmu.py --platforms linux64   # the Linux binaries only
    python3 scripts/package_fmu.py --fmi 2      # the FMI 2.0 FMU only

The FMI 2.0 FMU (target/fmu/SemiActiveDamper.fmu) holds

    modelDescription.xml
    binaries/linux64/SemiActiveDamper.so      (copy of target/release/libsemi_active_damper.so)
    binaries/win64/SemiActiveDamper.dll       (copy of target/x86_64-pc-windows-gnu/release/semi_active_damper.dll)
    documentation/index.html                  (generated here from modelDescription.xml)
    documentation/physics.md                  (copy of docs/physics.md: equations, parameter reasoning)
    documentation/licenses/                   (the project's licences and those of the code in the binaries)

The FMI 3.0 FMU (target/fmu/fmi3/SemiActiveDamper.fmu) holds the same, with the model description
that `fmi3-model-description` (crates/fmi_codegen) generates from modelDescription.xml, and the
binaries of the crate's feature `fmi3` (built into target/fmi3/, so that each standard's binary
exports its own functions alone) under binaries/x86_64-linux and binaries/x86_64-windows.

The Windows binary is cross-compiled with cargo's x86_64-pc-windows-gnu target and the MinGW-w64
linker (.cargo/config.toml); scripts/setup.sh installs both. By default (--platforms auto) it is
left out, with a printed reason, where they are missing; --platforms linux64,win64 insists on it.

Entries are written with forward slashes and a fixed time stamp, so that the same inputs give
the same bytes.
"""

import argparse
import html
import json
import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
CRATE = "semi_active_damper"
# FMI 2.0 platform folder -> (cargo target triple, None for the host's; the library's file name
# for a crate; the binary's suffix in the FMU).
PLATFORMS = {
    "linux64": (None, "lib{}.so", ".so"),
    "win64": ("x86_64-pc-windows-gnu", "{}.dll", ".dll"),
}
# The FMI 3.0 platform tuple of each FMI 2.0 platform folder.
FMI3_PLATFORMS = {"linux64": "x86_64-linux", "win64": "x86_64-windows"}
WINDOWS_LINKER = "x86_64-w64-mingw32-gcc"
ZIP_DATE = (1980, 1, 1, 0, 0, 0)
# Functions each standard's binary must define (a check that the right build was packaged).
REQUIRED_SYMBOLS = {
    2: ("fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SetReal", "fmi2FreeInstance"),
    3: ("fmi3InstantiateCoSimulation", "fmi3DoStep", "fmi3GetFloat64", "fmi3SetFloat64", "fmi3FreeInstance"),
}
FMI_VERSIONS = (2, 3)
# The model's physics document. Both FMUs ship it as documentation/physics.md, because the variable
# descriptions cite its sections ("see physics.md §x") and a user of the FMU has no repository.
PHYSICS_DOC = REPO / "docs" / "physics.md"
# Link to it, and to the licences, from index.html (relative: they resolve inside the unpacked FMU).
PHYSICS_LINK = ('<p>The equations of every component, the reasoning and source of every parameter value '
                'and the checks behind them are in <a href="physics.md">physics.md</a> '
                '(<code>documentation/physics.md</code> in this FMU); a reference "physics.md §x" in a '
                'variable description names one of its sections.</p>'
                '<p>Licence: MIT OR Apache-2.0. The licences of this FMU and of the code compiled into its '
                'binaries are in <a href="licenses/THIRD-PARTY.txt">licenses/</a>.</p>')



# Licences. The project's own, and those of the code compiled into the binaries: the crates' MIT and
# Apache licences ask that their notices travel with the binaries. Gathered here from cargo's own
# dependency tree and metadata (some forty lines) rather than with cargo-about, which CI would have to
# build from source for this one job.
PROJECT_LICENCES = ("LICENSE-MIT", "LICENSE-APACHE")
# the texts of the licences a crate may declare without shipping a licence file
SPDX_TEXTS = {"MIT": "LICENSE-MIT", "Apache-2.0": "LICENSE-APACHE"}
LICENCE_FILE = re.compile(r"(LICEN[CS]E|COPYING|COPYRIGHT|NOTICE|UNLICENSE)", re.IGNORECASE)
# cargo tree's target for each FMI platform folder (the host's toolchain builds linux64)
TREE_TARGETS = {"linux64": "x86_64-unknown-linux-gnu", "win64": "x86_64-pc-windows-gnu"}
# the FMI 2.0 and 3.0 headers' licence: the FMI layer transcribes their types (the program's importer
# binds them)
FMI_HEADERS_LICENCE = REPO / "crates" / "fmi_slave" / "FMI-HEADERS-LICENSE.txt"
# Debian's copyright file of the MinGW-w64 runtime that the win64 binaries' start-up code comes from
MINGW_COPYRIGHT = Path("/usr/share/doc/mingw-w64-x86-64-dev/copyright")

# Style of the FMUs' documentation/index.html.
CSS = """body { font-family: sans-serif; max-width: 75em; margin: 1em auto; padding: 0 1em; line-height: 1.4; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em 0; font-size: 0.9em; }
th, td { border: 1px solid #bbb; padding: 0.2em 0.4em; vertical-align: top; text-align: left; }
th { background: #eee; }
td.num { text-align: right; white-space: nowrap; }
pre { background: #f6f6f6; padding: 0.6em; overflow-x: auto; }
.tag { font-weight: bold; }
.tag-P { color: #1a6b1a; } .tag-S { color: #1a4d8f; } .tag-A { color: #8f5a1a; }"""

def target_dir(fmi_version=2):
    """Cargo's target directory (CARGO_TARGET_DIR if set); the FMI 3.0 binaries are built into its
    folder fmi3/, where they do not replace the FMI 2.0 ones (the same crates with another feature)."""
    base = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    return base / "fmi3" if fmi_version == 3 else base


def library_path(platform, crate, fmi_version=2):
    """Where cargo build --release puts `crate`'s library for `platform` and FMI version."""
    triple, name, _ = PLATFORMS[platform]
    return target_dir(fmi_version) / (triple or "") / "release" / name.format(crate)


def windows_missing():
    """What the Windows cross-build lacks here (None when it can run): the Rust standard library of
    its target (rustup target add) or the MinGW-w64 linker (Debian's gcc-mingw-w64-x86-64)."""
    triple = PLATFORMS["win64"][0]
    try:
        sysroot = subprocess.run(["rustc", "--print", "sysroot"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return "rustc not found"
    if not (Path(sysroot.strip()) / "lib" / "rustlib" / triple).is_dir():
        return f"Rust's {triple} target is not installed (rustup target add {triple})"
    if not (os.environ.get("CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER") or shutil.which(WINDOWS_LINKER)):
        return f"the MinGW-w64 linker {WINDOWS_LINKER} is not installed (apt-get install gcc-mingw-w64-x86-64)"
    return None


def platforms_arg(text, program, product="the FMU gets"):
    """The platforms of --platforms: 'auto' is linux64, and win64 where it can be built (the reason
    printed where not, as "{program}: {product} no win64 binary: …"); a list insists on every
    platform in it."""
    if text != "auto":
        chosen = [p.strip() for p in text.split(",") if p.strip()]
        unknown = [p for p in chosen if p not in PLATFORMS]
        if unknown or not chosen:
            sys.exit(f"{program}: --platforms {text}: choose from {', '.join(PLATFORMS)} (comma-separated) or auto")
        if "win64" in chosen and (reason := windows_missing()):
            sys.exit(f"{program}: cannot build win64: {reason}; bash scripts/setup.sh installs it")
        return chosen
    reason = windows_missing()
    if reason:
        print(f"{program}: {product} no win64 binary: {reason}; bash scripts/setup.sh installs it")
        return ["linux64"]
    return ["linux64", "win64"]


FMU_CRATES = ("semi_active_damper", "quarter_truck", "full_truck")


def selection(packages, triple, fmi_version):
    """cargo's package selection for `packages`: on the host (FMI 2.0, into target/release) the whole
    workspace, whatever is asked for. A package compiled with other features replaces its artifacts
    (the FMU crates' rlibs carry no hash in their file names at all), and a build of a few packages
    resolves fewer features of the shared dependencies (typenum, syn, serde_core, …) than the whole
    workspace's: so every `-p` build after `cargo test` recompiled what the next build needed again
    (the engine and the damper program: about two minutes of scripts/test.sh each time). Elsewhere
    (Windows, or FMI 3.0 in its own target directory) the packages alone: the FMU crates need no
    libclang there."""
    if triple is None and fmi_version == 2:
        return ["--workspace"]
    return [word for package in packages for word in ("-p", package)]


def cargo_build(platforms, packages=FMU_CRATES, environment=None, fmi_version=2):
    """Builds `packages` for each platform; by default the three FMUs' libraries (the damper's and the
    two trucks'), on the host with the rest of the workspace (`selection`), which needs libclang for
    the importer's bindings (scripts/setup.sh installs it). `environment(triple)`, if given, is the
    build's environment for a target triple (None: the host's). For FMI 3.0 each FMU crate gets its
    feature `fmi3`, in target_dir(3)."""
    for platform in platforms:
        triple = PLATFORMS[platform][0]
        command = ["cargo", "build", "--release"] + selection(packages, triple, fmi_version)
        command += ["--target", triple] if triple else []
        if fmi_version == 3:
            features = ",".join(f"{p}/fmi3" for p in packages if p in FMU_CRATES)
            command += ["--features", features, "--target-dir", str(target_dir(3))]
        print("+ " + " ".join(command), flush=True)
        subprocess.run(command, cwd=REPO, env=environment(triple) if environment else None, check=True)


def check_library(path, fmi_version=2):
    """Fails unless the shared library exists and names the functions of its FMI version (a byte
    search of its symbol strings; the library is not loaded)."""
    if not path.is_file():
        sys.exit(f"package_fmu: {path} not found (run python3 scripts/package_fmu.py without --no-build)")
    data = path.read_bytes()
    missing = [name for name in REQUIRED_SYMBOLS[fmi_version] if name.encode() + b"\0" not in data]
    if missing:
        sys.exit(f"package_fmu: {path} does not define {', '.join(missing)}")


def read_model(xml_path):
    """The parts of modelDescription.xml the documentation needs."""
    root = ET.parse(xml_path).getroot()
    cs = root.find("CoSimulation")
    experiment = root.find("DefaultExperiment")
    variables = []
    for sv in root.find("ModelVariables"):
        typ = next(iter(sv))
        variables.append({
            "name": sv.get("name"),
            "valueReference": sv.get("valueReference"),
            "causality": sv.get("causality", "local"),
            "variability": sv.get("variability", "continuous"),
            "type": typ.tag,
            "unit": typ.get("unit", ""),
            "start": typ.get("start", ""),
            "min": typ.get("min", ""),
            "max": typ.get("max", ""),
            "description": sv.get("description", ""),
        })
    return {
        "modelName": root.get("modelName"),
        "description": root.get("description", ""),
        "version": root.get("version", ""),
        "guid": root.get("guid"),
        "fmiVersion": root.get("fmiVersion"),
        "modelIdentifier": cs.get("modelIdentifier"),
        "cs_flags": {k: v for k, v in cs.attrib.items() if k != "modelIdentifier"},
        "defaultExperiment": dict(experiment.attrib) if experiment is not None else {},
        "variables": variables,
    }


def start_value(model, name):
    for v in model["variables"]:
        if v["name"] == name:
            return float(v["start"])
    raise KeyError(name)


def format_number(text):
    """Compact display of a number given as text in the XML."""
    if text == "":
        return ""
    try:
        x = float(text)
    except ValueError:
        return html.escape(text)
    if x != 0 and (abs(x) >= 1e5 or abs(x) < 1e-3):
        mantissa, exponent = f"{x:.6e}".split("e")
        return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"
    return f"{x:.6g}"


def tag_description(text):
    """Escapes a description and highlights the provenance tags [P], [S], [A]."""
    escaped = html.escape(text)
    return re.sub(r"\[([PSA])\]", r'<span class="tag tag-\1">[\1]</span>', escaped)


def variable_rows(model, causality):
    rows = []
    for v in model["variables"]:
        if v["causality"] != causality:
            continue
        rows.append(
            "<tr>"
            f"<td><code>{html.escape(v['name'])}</code></td>"
            f"<td>{v['valueReference']}</td>"
            f"<td>{v['type']}</td>"
            f"<td>{v['causality']}</td>"
            f"<td>{html.escape(v['unit'])}</td>"
            f"<td class=num>{format_number(v['start'])}</td>"
            f"<td class=num>{format_number(v['min'])}</td>"
            f"<td class=num>{format_number(v['max'])}</td>"
            f"<td>{tag_description(v['description'])}</td>"
            "</tr>"
        )
    return "\n".join(rows)


LINUX_TEXT = ": Linux x86-64 with glibc 2.34 or later"
WINDOWS_TEXT = ": 64-bit Windows 10 or later (cross-compiled with MinGW-w64; it needs no DLL that Windows itself lacks)"
PLATFORM_TEXT = {
    "linux64": "<code>linux64</code>" + LINUX_TEXT,
    "win64": "<code>win64</code>" + WINDOWS_TEXT,
    "x86_64-linux": "<code>x86_64-linux</code>" + LINUX_TEXT,
    "x86_64-windows": "<code>x86_64-windows</code>" + WINDOWS_TEXT,
}


def identity_html(model):
    """The FMU's identity in the documentation: FMI 2.0's GUID, FMI 3.0's instantiation token (the
    same string: the variable table's fingerprint)."""
    what = "GUID" if model["fmiVersion"] == "2.0" else "instantiation token"
    return f"{what} <code>{html.escape(model['guid'])}</code>"


def for_version(model, fmi_version):
    """`model` (read from the FMI 2.0 description) as the documentation of its FMI `fmi_version` FMU."""
    if fmi_version == 2:
        return {**model, "prefix": "fmi2", "derivatives": "; a master's fmi2SetRealInputDerivatives ramps the "
                "velocity and the demands (canInterpolateInputs)"}
    return {**model, "fmiVersion": "3.0", "prefix": "fmi3", "derivatives": " (FMI 3.0 has no input derivatives)",
            "platforms": [FMI3_PLATFORMS[p] for p in model["platforms"]]}


def platforms_html(model):
    """The paragraph naming the binaries this FMU carries."""
    return "<p>Binaries: " + "; ".join(PLATFORM_TEXT[p] for p in model["platforms"]) + ".</p>"


def documentation_html(model):
    """documentation/index.html: self-contained description of the model."""
    header = ("<tr><th>name</th><th>vr</th><th>type</th><th>causality</th><th>unit</th>"
              "<th>start</th><th>min</th><th>max</th><th>description</th></tr>")
    sections = []
    for causality, title in (("input", "Inputs"), ("output", "Outputs"), ("parameter", "Parameters")):
        sections.append(f"<h3>{title}</h3>\n<table>\n{header}\n{variable_rows(model, causality)}\n</table>")
    flags = ", ".join(f"{k}={v}" for k, v in model["cs_flags"].items())
    experiment = ", ".join(f"{k}={v}" for k, v in model["defaultExperiment"].items())
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{html.escape(model['modelName'])} — FMI {model['fmiVersion']} Co-Simulation FMU</title>
<style>
{CSS}
</style>
</head>
<body>
<h1>{html.escape(model['modelName'])}</h1>
<p>FMI {model['fmiVersion']} Co-Simulation FMU, version {html.escape(model['version'])},
model identifier <code>{html.escape(model['modelIdentifier'])}</code>,
{identity_html(model)}.</p>
<p>{html.escape(model['description'])}</p>
{platforms_html(model)}

<h2>What it is</h2>
<p>A continuously-variable semi-active damper for heavy trucks after Kitching, Cole and Cebon,
<i>The development of a semi-active truck damper</i>. A high-speed proportional spool valve sets the
pressure drop of a "uniflow" circuit: check valves route the oil one way through the valve in both
directions of motion, and a gas-charged reservoir takes the rod volume. A digital cascade controller
(2 kHz by default) closes an inner loop on spool position (PID plus a flow-force compensation current)
and an outer loop on damper force. The master gives the damper velocity and a force demand; the FMU
returns the force measured by the load cell and the internal signals of the valve and the chambers.
The plant is integrated inside every <code>{model['prefix']}DoStep</code> by a stiff Rosenbrock method of order 3
with step-size control inside each controller sample (tolerance <code>rtol</code>, steps of at most
<code>h_max</code>); the controller samples on the grid start time + k·<code>T_sample</code>, whatever
the communication steps are.</p>

<h2>Equations in brief</h2>
<pre>
Geometry      A_p = π D_piston²/4,  A_r = π D_rod²/4,  A_a = A_p − A_r
              V_A = A_a (L_half + L_dead − x_p) + V_hose   (annulus, rod side: p_ext)
              V_B = A_p (L_half + L_dead + x_p)            (full bore: p_comp)
Oil + air     β_e(p) = (1 + α₀ r) / (1/β_oil + α₀ r / (n (p + p_a))),  r = (p_a/(p + p_a))^(1/n)
Orifices      Q(A, Δp) = C_d A sqrt(2/ρ) Δp / (Δp² + p_transition²)^(1/4)
Valve ports   n_ports circular ports of radius r_port uncovered by the spool edge beyond x_lap
Chambers      dp_A/dt = β_e(p_A)/V_A (A_a dx_p/dt + Q_cv1 − Q_valve − Q_relief − Q_leak)
              dp_B/dt = β_e(p_B)/V_B (−A_p dx_p/dt − Q_cv1 + Q_cv2 + Q_leak)
Reservoir     p_r = (p_reservoir0 + p_a)(V_gas0/V_g)^n − p_a
Force         F_h = p_A A_a − p_B A_p  (+ friction);  mount in series: k1 δ + k3 δ³ = F_h,  F_damper = F_h
Spool         m ẍ_s = K_sol i_sol − k_spool x_s − c_spool ẋ_s − F_flow − F_stop
              F_flow = 2 C_d C_v cos θ_jet · A(x_s) · max(p_A − p_r, 0)   (closes the valve)
Coil          di_sol/dt = (i_cmd(t − tau_amp) − i_sol)/tau_coil,   i_cmd ∈ [0, I_max]
Spool loop    i_cmd = Kp_x e + Ki_x ∫e − Kd_x ẋ_s,filtered + i_flow-force-compensation
Force loop    force_controller 0: inverse-valve feedforward area × exp(−PI on the relative force error)
              force_controller 1: the paper's PID from relative force error to spool position
</pre>

<h2>Sign conventions</h2>
<ul>
<li><code>v_damper</code> &gt; 0: extension (rod moving out of the body); <code>x_damper</code> is its integral,
0 = mid-stroke.</li>
<li><code>F_damper</code>, <code>F_demand</code> &gt; 0: tension, i.e. a force resisting extension.
A dissipative demand has the sign of <code>v_damper</code>; the other sign cannot be delivered and is
clipped to 0 (<code>F_demand_clipped</code>).</li>
<li>Pressures are gauge pressures [Pa]. <code>x_spool</code> = 0 is the spring-centred spool; the ports open above
<code>x_lap</code>.</li>
<li><code>control_mode</code> 0: the force loop computes the spool demand (<code>x_spool_ref</code>);
1: <code>x_spool_demand</code> is the spool demand and <code>F_demand</code> is ignored.</li>
</ul>

<h2>Variables</h2>
{PHYSICS_LINK}
<p>Source tags in the descriptions: <span class="tag tag-P">[P]</span> stated in the paper,
<span class="tag tag-S">[S]</span> from another public source, <span class="tag tag-A">[A]</span> an engineering
assumption chosen so that the model is coherent and meets the paper's figures.</p>
{chr(10).join(sections)}

<h2>Capabilities</h2>
<p>{html.escape(flags)}.<br>Default experiment: {html.escape(experiment)}.</p>

<h2>Limits</h2>
<ul>
{limits_html(model)}
</ul>
</body>
</html>
"""


def limits_html(model):
    """The list items of documentation/index.html's "Limits", with figures from the start values."""
    p_r0 = start_value(model, "p_reservoir0")
    d_rod = start_value(model, "D_rod")
    d_piston = start_value(model, "D_piston")
    l_half = start_value(model, "L_half_stroke")
    l_dead = start_value(model, "L_dead")
    v_hose = start_value(model, "V_hose")
    a_rod = math.pi * d_rod ** 2 / 4
    a_piston = math.pi * d_piston ** 2 / 4
    gas_force = p_r0 * a_rod
    v_ext = (a_piston - a_rod) * (l_half + l_dead) + v_hose
    v_comp = v_ext + a_piston * (l_half + l_dead)
    return f"""<li>Gas force offset: at rest both chambers are at the reservoir pressure, so the damper pushes out with
−p_reservoir0·A_r = −{gas_force / 1e3:.2f} kN with the default parameters. <code>F_damper</code> includes it,
like the load cell of the rig.</li>
<li>Semi-active: only dissipative forces can be produced. With the valve wide open the force cannot go below
a velocity-dependent minimum (≈0.1 kN at 0.15 m/s, ≈5 kN at 1 m/s, see physics.md §5.3); the relief valve caps it
near 37 kN.</li>
<li>Velocity range: the input accepts |v_damper| ≤ 5 m/s; at high velocity and high force, flow forces make
the spool show small limit cycles (physics.md §10).</li>
<li>Stroke: end stops act only with the catalog effect <code>effect_end_stops</code> (off by default). Keep
|x_damper| below L_half_stroke = {l_half * 1e3:.0f} mm without it; beyond, the chamber volumes are floored and
the result is not physical (the FMU logs a warning).</li>
<li>Compression is slower than extension: the compressed oil volume at mid-stroke is
{v_comp * 1e6:.0f} cm³ against {v_ext * 1e6:.0f} cm³ in extension (ratio {v_comp / v_ext:.2f}).</li>
<li>The paper's 15 Hz peak of the Hardware-in-the-Loop force spectrum is not a property of the damper alone:
with the quarter truck of the paper it needs a rig's force path delayed 2–3 ms, and even then it is a broad
maximum, not a peak.</li>
<li>Parameters have variability "fixed": they can be set before <code>{model['prefix']}ExitInitializationMode</code>
only; later changes are refused with {model['prefix']}Error. Over a communication step the velocity moves along
the slope <code>a_damper</code> (0: held){model['derivatives']}.</li>
<li>Gas coming out of solution at low pressure and the oil's temperature are catalog effects
(<code>effect_gas_release</code>, <code>effect_oil_temperature</code>), off by default. Not modelled: check-valve
dynamics, solenoid hysteresis and spool stiction, pipe fluid inertia, load-cell filtering (physics.md §8 lists
their signatures).</li>"""


def write_zip(fmu_path, files, executable=lambda name: name.startswith("binaries/")):
    """Writes (archive name, bytes) pairs into a deflated zip with fixed time stamps; the entries
    `executable(name)` picks get mode 755, the others 644."""
    fmu_path.parent.mkdir(parents=True, exist_ok=True)
    tmp = fmu_path.with_suffix(".fmu.tmp")
    with zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name, data in files:
            assert "\\" not in name
            info = zipfile.ZipInfo(name, date_time=ZIP_DATE)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o755 if executable(name) else 0o644) << 16
            z.writestr(info, data)
    tmp.replace(fmu_path)


def cargo_json(args):
    return json.loads(subprocess.run(["cargo", *args], cwd=REPO, check=True, capture_output=True, text=True).stdout)


def linked_crates(crate, platforms):
    """(name, version) of every registry crate compiled into `crate`'s library for `platforms`: cargo
    tree's normal dependencies, with the features of that build. The workspace's own crates (path
    dependencies) are the project's; proc-macro crates run in the compiler and leave no code."""
    found = set()
    for platform in platforms:
        out = subprocess.run(["cargo", "tree", "--locked", "-p", crate, "-e", "normal", "--prefix", "none",
                              "--format", "{p}", "--target", TREE_TARGETS[platform]],
                             cwd=REPO, check=True, capture_output=True, text=True).stdout
        for line in out.splitlines():
            match = re.fullmatch(r"(\S+) v(\S+)(?: \(\*\))?", line.strip())
            if match:
                found.add((match[1], match[2]))
    return sorted(found)


def crate_licence_files(name, folder):
    """A crate's licence files: those at its top, and for a -sys crate, which may bundle a C library
    with a licence of its own (zstd-sys: zstd/LICENSE), those up to two folders down."""
    depth = 3 if name.endswith("-sys") else 1
    return sorted(f for f in folder.rglob("*") if f.is_file() and LICENCE_FILE.match(f.name)
                  and len(f.relative_to(folder).parts) <= depth)


def third_party_notice(crate, platforms, product="this FMU"):
    """THIRD-PARTY.txt: each crate compiled into `crate`'s binaries, its licence and the text of its
    licence files (or of its declared licences, for a crate published without one)."""
    metadata = cargo_json(["metadata", "--format-version", "1", "--locked"])
    packages = {(p["name"], p["version"]): p for p in metadata["packages"]}
    crates = linked_crates(crate, platforms)
    about = ("The binaries are built with Rust from this project's code (MIT OR Apache-2.0: LICENSE-MIT, "
             "LICENSE-APACHE), with the C types of the FMI 2.0 and FMI 3.0 standards' headers (2-Clause BSD: "
             "FMI-headers.txt), and contain code of the Rust standard library (MIT OR Apache-2.0; its notices: "
             "rust-standard-library.html)" + (" and of the crates below, each with the text of its licence files."
                                               if crates else ", and of no other crate."))
    if "win64" in platforms:
        about += (" The win64 binary also contains start-up code of the MinGW-w64 runtime (its licences: "
                  "mingw-w64-runtime.txt) and libgcc's unwinder (GPL-3.0 with the GCC Runtime Library Exception, "
                  "which asks for no notice).")
    lines = [f"Third-party code in the binaries of {product} ({', '.join(platforms)})", "", textwrap.fill(about, 78)]
    if crates:
        lines += ["", textwrap.fill("Crates: " + ", ".join(f"{n} {v}" for n, v in crates) + ".", 78)]
    for name, version in crates:
        meta = packages[(name, version)]
        folder = Path(meta["manifest_path"]).parent
        lines += ["", "=" * 78, f"{name} {version}: {meta['license']}, {meta.get('repository') or ''}".rstrip(", "),
                  "=" * 78]
        files = crate_licence_files(name, folder)
        for f in files:
            text = f.read_text(encoding="utf-8", errors="replace").rstrip()
            lines += ["", f"--- {f.relative_to(folder).as_posix()} ---", "", text]
        if not files:
            lines += declared_licence_texts(name, version, meta, folder)
    return "\n".join(lines) + "\n"


def declared_licence_texts(name, version, meta, folder):
    """For a crate published without a licence file: the texts of the licences its expression names
    (MIT and Apache-2.0, the project's own texts; MIT's copyright line names the crate's authors).
    Any other licence stops the packaging, naming the crate."""
    offered = [term.strip() for term in re.split(r" OR |/", meta["license"] or "")]
    known = [term for term in offered if term in SPDX_TEXTS]
    if not known:
        raise SystemExit(f"package_fmu: {name} {version} ({folder}) has no licence file, and its licence "
                         f"{meta['license'] or meta['license_file']!r} is not one whose text this script has")
    authors = ", ".join(meta.get("authors") or []) or f"the authors of {name}"
    lines = ["", f"(No licence file in the crate: the texts of the licences it declares, {meta['license']}.)"]
    for term in known:
        text = (REPO / SPDX_TEXTS[term]).read_text(encoding="utf-8").rstrip()
        if term == "MIT":
            text = re.sub(r"^Copyright \(c\) .*$", f"Copyright (c) {authors}", text, flags=re.M)
        lines += ["", f"--- {term} ---", "", text]
    return lines


def common_licences(platforms):
    """(file name, bytes) of the notices every binary of the project needs beside THIRD-PARTY.txt: the
    FMI headers' and, for the code the toolchain puts in, the Rust standard library's and for
    win64 the MinGW-w64 runtime's."""
    sysroot = subprocess.run(["rustc", "--print", "sysroot"], check=True, capture_output=True, text=True).stdout
    files = [("FMI-headers.txt", FMI_HEADERS_LICENCE.read_bytes()), ("rust-standard-library.html",
              (Path(sysroot.strip()) / "share" / "doc" / "rust" / "COPYRIGHT-library.html").read_bytes())]
    if "win64" in platforms:
        if not MINGW_COPYRIGHT.exists():
            raise SystemExit(f"package_fmu: {MINGW_COPYRIGHT} (the MinGW-w64 runtime's licences) is missing: "
                             "bash scripts/setup.sh installs it with the Windows linker")
        files.append(("mingw-w64-runtime.txt", MINGW_COPYRIGHT.read_bytes()))
    return files


def licence_files(crate, platforms):
    """The (archive name, bytes) pairs of documentation/licenses/."""
    files = [(name, (REPO / name).read_bytes()) for name in PROJECT_LICENCES]
    files.append(("THIRD-PARTY.txt", third_party_notice(crate, platforms).encode("utf-8")))
    files += common_licences(platforms)
    return [(f"documentation/licenses/{name}", data) for name, data in files]


def fmi3_model_description(xml_path):
    """The FMI 3.0 model description generated from the FMI 2.0 one at `xml_path` (cargo runs
    crates/fmi_codegen's program: the build's own parser and checks, one variable table)."""
    command = ["cargo", "run", "--quiet", "--release", "-p", "fmi_codegen", "--bin", "fmi3-model-description", "--",
               str(xml_path)]
    return subprocess.run(command, cwd=REPO, check=True, capture_output=True).stdout


def package(libraries, xml_path, fmu_path, documentation=None, crate=CRATE, fmi_version=2):
    """Zips the FMU of FMI `fmi_version`, with the binary of each platform in `libraries` ({FMI 2.0
    platform folder: path}) built from `crate`; `documentation(model)` writes its index.html
    (default: the damper's). Every FMU also carries docs/physics.md as documentation/physics.md, and
    the licences."""
    model = read_model(xml_path)
    model["platforms"] = list(libraries)
    model = for_version(model, fmi_version)
    folder = (lambda p: p) if fmi_version == 2 else FMI3_PLATFORMS.get
    binaries = [(f"binaries/{folder(platform)}/{model['modelIdentifier']}{PLATFORMS[platform][2]}", path.read_bytes())
                for platform, path in libraries.items()]
    description = xml_path.read_bytes() if fmi_version == 2 else fmi3_model_description(xml_path)
    files = [
        ("modelDescription.xml", description),
        *binaries,
        ("documentation/index.html", (documentation or documentation_html)(model).encode("utf-8")),
        ("documentation/physics.md", PHYSICS_DOC.read_bytes()),
        *licence_files(crate, list(libraries)),
    ]
    write_zip(fmu_path, files)
    return fmu_path


def fmi3_output(output):
    """Where the FMI 3.0 FMU of an FMI 2.0 FMU path goes: its folder's fmi3/, same file name."""
    return output.parent / "fmi3" / output.name


def add_arguments(parser, crate, output):
    """The options every packaging command takes."""
    parser.add_argument("--no-build", action="store_true", help="do not run cargo build --release")
    parser.add_argument("--platforms", default="auto",
                        help="binaries to package: auto (linux64, and win64 where it can be built) or a "
                             f"comma-separated list of {', '.join(PLATFORMS)} (default: auto)")
    parser.add_argument("--fmi", default="2,3",
                        help="FMI versions to package, comma-separated: 2 (the FMI 2.0 FMU), 3 (the FMI 3.0 "
                             f"FMU, written to {fmi3_output(output).relative_to(REPO)}) (default: 2,3)")
    parser.add_argument("--library", type=Path, default=None,
                        help=f"linux64 FMI 2.0 shared library to package (default: <target>/release/lib{crate}.so)")
    parser.add_argument("--output", type=Path, default=output, help=f"FMI 2.0 FMU to write (default: {output})")


def fmi_versions(args, program):
    """The FMI versions of --fmi."""
    try:
        versions = sorted({int(v) for v in args.fmi.split(",") if v.strip()})
    except ValueError:
        versions = []
    if not versions or any(v not in FMI_VERSIONS for v in versions):
        sys.exit(f"{program}: --fmi {args.fmi}: choose from 2 and 3, comma-separated")
    return versions


def libraries(args, crate, program, fmi_version=2):
    """Builds (unless --no-build) and checks the libraries to package: {platform: path}."""
    platforms = platforms_arg(args.platforms, program)
    if not args.no_build:
        cargo_build(platforms, fmi_version=fmi_version)
    use_given = fmi_version == 2 and args.library
    chosen = {p: (args.library if p == "linux64" and use_given else library_path(p, crate, fmi_version))
              for p in platforms}
    for path in chosen.values():
        check_library(path, fmi_version)
    return chosen


def package_versions(args, crate, xml_path, documentation, program):
    """Builds and packages the FMUs of every FMI version of --fmi; prints what it wrote."""
    for version in fmi_versions(args, program):
        output = args.output if version == 2 else fmi3_output(args.output)
        fmu = package(libraries(args, crate, program, version), xml_path, output, documentation, crate, version)
        print(f"{program}: wrote {fmu} (FMI {version}.0, {fmu.stat().st_size / 1e6:.1f} MB)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(parser, CRATE, REPO / "target" / "fmu" / "SemiActiveDamper.fmu")
    args = parser.parse_args(argv)
    package_versions(args, CRATE, REPO / "modelDescription.xml", documentation_html, "package_fmu")


if __name__ == "__main__":
    main()
