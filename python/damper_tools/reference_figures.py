"""The figures the docs quote from the team's slow Python reference (an independent implementation of
the same physics, kept outside this repository: docs/physics.md, "reference" numbers), read from its
printed output into docs/reference.json and checked wherever a document quotes them
(tests/python/test_benchmark_figures.py; damper_tools.doc_figures). Where the reference is kept, run
its script with its output into a file, then

    .venv/bin/python -m damper_tools.reference_figures slow_reference_output.txt [--docs]

prints the figures as JSON; with --docs it writes them to docs/reference.json. The output the file
holds now is kept in tests/python/resources/slow_reference_output.txt, from which a test reads the
same figures again.
"""

import argparse
import json
import re
import sys
from pathlib import Path

from damper_tools import doc_figures

COMMAND = ("the team's reference script (not in this repository) printing to slow_reference_output.txt, kept "
           "as tests/python/resources/slow_reference_output.txt; then "
           ".venv/bin/python -m damper_tools.reference_figures slow_reference_output.txt --docs")
MEASURED = "the slow Python reference's printed output (fixed-step linearly-implicit Euler, 20 µs)"

F = r"([-+]?\d+(?:\.\d+)?)"

# figure names: (a pattern of the output with one group per name); every match must agree when a
# pattern matches several lines (the five spool steps), else the output is refused
LINES: dict[tuple[str, ...], str] = {
    # 2 (a): spool loop, force loop open, five demand steps from 2.5 mm
    ("spool_dead_time_ms", "spool_t90_ms"): rf"dead time\(2%\) +{F} ms, t50 +[\d.]+ ms, t90 +{F} ms",
    # 2 (b): flow-force compensation, spool error RMS and max at x_dem 1.6 and 2.5 mm
    **{(f"ffc_{kind}_{x}_rms_um", f"ffc_{kind}_{x}_max_um"):
       rf"{label} +x_dem {xd} mm: spool error rms +{F} um, max +{F} um"
       for kind, label in (("none", r"no compensation"), ("fixed", r"I_fc = K_fc\*Q \(paper, fixed gain @50 bar\)"),
                           ("scheduled", r"I_fc ~ Q\*sqrt\(dp_est\) \(default\)"))
       for x, xd in (("16", r"1\.6"), ("25", r"2\.5"))},
    # 3: closed-loop force steps at 0.15 m/s, the baseline controller
    **{(f"steps_{d}_{a}_{b}_t90_ms",): rf"\[baseline\] {d} +{a}->{b} kN *: t10 +[\d.]+ ms, t50 +[\d.]+ ms, t90 +{F} ms"
       for d in ("extension", "compression") for a, b in (("2", "12"), ("12", "22"))},
    # 3a: open-loop valve steps, t50 and t90
    **{(f"valve_{key}_{d}_t50_ms", f"valve_{key}_{d}_t90_ms"):
       rf"{label} +{d} *: F +[\d.]+ -> +[\d.]+ kN, t10 +[\d.]+ ms, t50 +{F} ms, t90 +{F} ms"
       for key, label, directions in (("air_2_5", r"baseline 2\.5 % air", ("ext", "comp")),
                                      ("air_0", r"0 % air", ("ext", "comp")),
                                      ("rigid_mount", r"2\.5 % air, rigid mount", ("ext",)))
       for d in directions},
    # 4: quarter truck, damped natural frequencies
    ("viscous_body_hz", "viscous_body_zeta", "viscous_wheel_hz", "viscous_wheel_zeta"):
        rf"viscous c= 19\.2 kNs/m: {F} Hz \(zeta {F}\), {F} Hz \(zeta {F}\)",
    **{(f"maxwell_{k}_mn_wheel_hz",): rf"Maxwell c=19\.2 kNs/m, k_series= +{k} MN/m: [\d.]+ Hz \(zeta [\d.]+\), {F} Hz"
       for k in ("2", "5")},
    # 5: clipped MSD on random roads, the force ideal (lag 0) or lagged by 10 ms
    ("msd_lag0_force_peak_hz",): rf"force lag +0 ms: damper-force PSD peak {F} Hz",
    ("msd_lag10_force_peak_hz", "msd_lag10_tyre_peak_hz"):
        rf"force lag +10 ms: damper-force PSD peak {F} Hz, tyre-force PSD peak {F} Hz",
    **{(f"msd_{road}_dlc", f"msd_{road}_f_rms_kn", f"msd_{road}_f_max_kn", f"msd_{road}_v_max"):
       rf"Gd\(n0\)= +{g}e-6 m3, force lag +0 ms: .*?DLC {F}, F_rms {F} kN, \|F\|max {F} kN, "
       rf"v_rel rms [\d.]+ m/s max {F}"
       for road, g in (("a", "16"), ("b", "64"), ("minor", "128"), ("c", "256"))},
    # 6: the closed-loop HiL co-simulation, no extra latency and 5 ms
    ("hil_force_peak_hz", "hil_f_rms_kn", "hil_f_demand_rms_kn", "hil_error_rms_kn", "hil_extension_mean_kn",
     "hil_extension_above_pct", "hil_compression_mean_kn", "hil_compression_below_pct", "hil_v_max", "hil_f_max_kn"):
        rf"latency 0 ms: damper-force PSD peak {F} Hz; F_rms {F} kN \(demand {F}\), tracking err rms {F} kN; "
        rf"extension: mean\(F-Fd\) {F} kN, frac F>Fd {F}; compression: mean\(\|F\|-\|Fd\|\) {F} kN, "
        rf"frac \|F\|<\|Fd\| {F}; \|v\|max {F} m/s, \|F\|max {F} kN",
    ("hil_5ms_force_peak_hz", "hil_5ms_error_rms_kn"):
        rf"latency 5 ms: damper-force PSD peak {F} Hz; F_rms [\d.]+ kN \(demand [\d.]+\), tracking err rms {F} kN",
}
# the output's fractions, quoted as percentages
PERCENT = ("hil_extension_above_pct", "hil_compression_below_pct")
# figures that are the largest of several lines': the overshoot of the five spool steps (%), the
# flow force in the compensation runs (N)
LARGEST: dict[str, str] = {
    "spool_overshoot_max_pct": rf"overshoot +{F} %, final",
    "ffc_flow_force_max_n": rf"spool error rms .* F_flow max +{F} N",
}


def parse_output(text: str) -> dict[str, float]:
    """The figures of the reference's output; a figure it lacks, or one it gives two values of, is an
    error naming it."""
    figures: dict[str, float] = {}
    for names, pattern in LINES.items():
        found = [m.groups() for m in re.finditer(pattern, text)]
        if not found:
            raise ValueError(f"the reference's output has no line of {', '.join(names)} (/{pattern}/)")
        if len(set(found)) > 1:
            raise ValueError(f"the reference's output gives {', '.join(names)} differently: {sorted(set(found))}")
        figures.update({n: float(v) for n, v in zip(names, found[0], strict=True)})
    for name in PERCENT:
        figures[name] = round(100.0 * figures[name], 6)
    for name, pattern in LARGEST.items():
        values = [float(v) for v in re.findall(pattern, text)]
        if not values:
            raise ValueError(f"the reference's output has no line of {name} (/{pattern}/)")
        figures[name] = max(values)
    return figures


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("output", type=Path, help="the reference's printed output")
    parser.add_argument("--docs", action="store_true", help=f"write the figures to {doc_figures.path('reference')}")
    args = parser.parse_args(argv)
    figures = parse_output(args.output.read_text(encoding="utf-8"))
    if args.docs:
        doc_figures.write("reference", figures, COMMAND, measured=MEASURED)
    sys.stdout.write(json.dumps({"measured": MEASURED, "command": COMMAND, **figures}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
