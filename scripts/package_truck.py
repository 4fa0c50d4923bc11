#!/usr/bin/env python3
"""Package the quarter truck as FMI 2.0 and FMI 3.0 Co-Simulation FMUs (standard library only).

    python3 scripts/package_truck.py              # cargo build --release (Linux and Windows), then zip
    python3 scripts/package_truck.py --no-build   # zip what target/ already holds

The FMU (target/fmu/QuarterTruck.fmu) holds

    modelDescription.xml                  (crates/quarter_truck/modelDescription.xml)
    binaries/linux64/QuarterTruck.so      (copy of target/release/libquarter_truck.so)
    binaries/win64/QuarterTruck.dll       (copy of target/x86_64-pc-windows-gnu/release/quarter_truck.dll)
    documentation/index.html              (generated here from modelDescription.xml)
    documentation/physics.md              (copy of docs/physics.md, shared with the damper's FMU)
    documentation/licenses/               (as in the damper's FMU)

and target/fmu/fmi3/QuarterTruck.fmu the FMI 3.0 build, as scripts/package_fmu.py packs the damper's.
It takes the options of scripts/package_fmu.py (--platforms and --fmi among them) and reuses its zip
and documentation helpers (same fixed time stamps, so the same inputs give the same bytes).
"""

import argparse
import html

# Run as a script, Python puts scripts/ first on sys.path, so the sibling is found.
import package_fmu

REPO = package_fmu.REPO
CRATE = "quarter_truck"
XML = REPO / "crates" / "quarter_truck" / "modelDescription.xml"
OUTPUT = REPO / "target" / "fmu" / "QuarterTruck.fmu"


def documentation_html(model):
    header = ("<tr><th>name</th><th>vr</th><th>type</th><th>causality</th><th>unit</th>"
              "<th>start</th><th>min</th><th>max</th><th>description</th></tr>")
    sections = []
    for causality, title in (("input", "Inputs"), ("output", "Outputs"), ("parameter", "Parameters")):
        sections.append(f"<h3>{title}</h3>\n<table>\n{header}\n"
                        f"{package_fmu.variable_rows(model, causality)}\n</table>")
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(model['modelName'])}</title>
<style>
{package_fmu.CSS}
</style></head><body>
<h1>{html.escape(model['modelName'])} {html.escape(model['version'])}</h1>
<p>{html.escape(model['description'])}</p>
<p>FMI {html.escape(model['fmiVersion'])} Co-Simulation, model identifier
<code>{html.escape(model['modelIdentifier'])}</code>, {package_fmu.identity_html(model)}.</p>
{package_fmu.platforms_html(model)}
<h2>Equations</h2>
<pre>
M_s z̈_s = −F_s,        F_s = k_s (z_s − z_u) + c_s (ż_s − ż_u) + F        (F: damper force, tension +)
M_u z̈_u = F_s + F_t,   F_t = k_t (z_r − z_u) + c_t (ż_r − ż_u)             (tyre, compression +)
F by damper_mode:  0  the F_damper input (held over a communication step)
                   1  the clipped Modified Skyhook demand, evaluated continuously
                   2  c_passive (ż_s − ż_u)
Clipped MSD:  F_demand = C_m [α V_rel + (1 − α) V_body] if it has the sign of V_rel, else 0
              V_rel = ż_s − ż_u (extension +), V_body = ż_s
Road over a step from t_k:  z_r(t) = z_road + v_road (t − t_k)
Integration: classical RK4, each communication step split into equal steps ≤ h_max.
</pre>
<p>All displacements are from static equilibrium; add the static wheel load (m_body + m_axle)·g to
<code>F_tyre</code> for the total tyre force. Connect <code>v_damper</code> and <code>F_demand</code> to
SemiActiveDamper.fmu's inputs and its <code>F_damper</code> (with <code>tare_load_cell</code> = true) to
<code>F_damper</code>. Provenance tags: <span class="tag tag-P">[P]</span> paper,
<span class="tag tag-S">[S]</span> other public source, <span class="tag tag-A">[A]</span> assumption.</p>
{package_fmu.PHYSICS_LINK}
<h2>Variables</h2>
{chr(10).join(sections)}
</body></html>
"""


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    package_fmu.add_arguments(parser, CRATE, OUTPUT)
    args = parser.parse_args(argv)
    package_fmu.package_versions(args, CRATE, XML, documentation_html, "package_truck")


if __name__ == "__main__":
    main()
