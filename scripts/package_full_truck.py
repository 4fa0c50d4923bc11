#!/usr/bin/env python3
"""Package the three-axle full truck as FMI 2.0 and FMI 3.0 Co-Simulation FMUs (standard library only).

    python3 scripts/package_full_truck.py              # cargo build --release (Linux and Windows), then zip
    python3 scripts/package_full_truck.py --no-build   # zip what target/ already holds

The FMU (target/fmu/FullTruck.fmu) holds modelDescription.xml (crates/full_truck/), the binaries
(binaries/linux64/FullTruck.so, binaries/win64/FullTruck.dll), documentation/index.html (generated
here), documentation/physics.md and the licences, as scripts/package_truck.py packs the quarter
truck (whose helpers it uses), and target/fmu/fmi3/FullTruck.fmu the FMI 3.0 build.
"""

import argparse
import html

# Run as a script, Python puts scripts/ first on sys.path, so the siblings are found.
import package_fmu
import package_truck

REPO = package_fmu.REPO
CRATE = "full_truck"
XML = REPO / "crates" / "full_truck" / "modelDescription.xml"
OUTPUT = REPO / "target" / "fmu" / "FullTruck.fmu"

EQUATIONS = """\
Coordinates: body heave z, pitch θ (nose up), roll φ (left up) at its centre of mass; each axle's
bounce z_i and roll φ_i. Corner k: axle i, side σ = +1 left / −1 right; x_i = x_cg − x_axle,i.
at the damper:  z_b,k = z + x_i θ + σ s/2 φ,   z_a,k = z_i + σ s/2 φ_i       (s: suspension_track)
suspension:     F_s,k = k_s,i (z_b,k − z_a,k) + c_s (ż_b,k − ż_a,k) + F_k     (F_k: damper, tension +)
tyre:           F_t,k = k_t,i (z_r,k − z_i − σ t/2 φ_i) + c_t (…)            (t: tyre_track)
M z̈ = −Σ F_s,k      I_θ θ̈ = −Σ x_i F_s,k      I_φ φ̈ = −Σ σ s/2 F_s,k − Σ k_roll,i (φ − φ_i) + M g h φ
m_i z̈_i = Σ (F_s,k + F_t,k)      J_i φ̈_i = Σ σ (s/2 F_s,k + t/2 F_t,k) + k_roll,i (φ − φ_i)
F_k by damper_mode: 0 the corner's F_damper input, 1 the clipped demand, 2 passive, 3 tracking.
Integration: classical RK4, each communication step split into equal steps ≤ h_max."""


def documentation_html(model):
    page = package_truck.documentation_html(model)
    start, end = page.index("<pre>") + len("<pre>\n"), page.index("</pre>")
    page = page[:start] + html.escape(EQUATIONS, quote=False) + "\n" + page[end:]
    connect = ("Connect <code>v_damper</code> and <code>F_demand</code> to\nSemiActiveDamper.fmu's inputs and its",
               "Connect each corner's <code>v_damper</code> and <code>F_demand</code> to the inputs of its\n"
               "own SemiActiveDamper.fmu instance and that instance's")
    load = ("add the static wheel load (m_body + m_axle)·g to\n<code>F_tyre</code>",
            "add each corner's static load to\nits <code>F_tyre</code>")
    for old, new in (connect, load):
        if old not in page:
            raise SystemExit(f"package_full_truck: the quarter truck's page no longer says {old!r}")
        page = page.replace(old, new)
    return page


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    package_fmu.add_arguments(parser, CRATE, OUTPUT)
    args = parser.parse_args(argv)
    package_fmu.package_versions(args, CRATE, XML, documentation_html, "package_full_truck")


if __name__ == "__main__":
    main()
