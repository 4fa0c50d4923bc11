"""The measured figures live in one generated place per measuring tool, docs/<tool>.json
(damper_tools.doc_figures: each tool's --docs writes its file; docs/benchmark.json is written by
damper_tools.benchmark_figures from a run of scripts/benchmark.sh). Every document that quotes a figure
agrees with its file to the digits it quotes; every quote pattern finds its quote (a pattern that
matches nothing checks nothing) and every figure of a file is quoted; the figures of a generated table
or report (docs/full-truck-table.md, docs/benefit-map-table.md, docs/ranking_accuracy.txt) are the ones
that table gives. A figure measured by hand sits in a section of its nearest tool's file with the
command that measured it. The benchmark's parser reads the benchmark's own report lines, and the tools
that take too long to run here write, from results shaped like their last runs', the figures their
files hold."""

import json
import re
import subprocess
from pathlib import Path

from damper_tools import benchmark_figures, benefit_map, doc_figures, full_truck, reference_figures

REPO = Path(__file__).resolve().parents[2]

# A number as the documents write it (a sign, the Unicode minus, an exponent), a range's dash, a range.
N = r"([−+-]?\d+(?:\.\d+)?(?:e[−+-]?\d+)?)"
TO = "–"
R = N + TO + N
W = r"(\d+|one|two|three|four|five|six|seven|eight|nine|ten|eleven|twelve)"  # a count, in digits or a word


def robust_row(tag: str, frame: str, controller: str) -> tuple[tuple[str, ...], list[str]]:
    """The figures and the pattern of a row of docs/hil.md's robustness table (the first row has the
    ranges of the mean errors and the seeds' count as well)."""
    first = tag == "tared_ff"
    spread = rf" \[{N}, {N}\]" if first else ""
    names = ["ext_mean_kn_mean", "ext_mean_kn_sd", *(["ext_mean_kn_min", "ext_mean_kn_max"] if first else []),
             "ext_above_pct_mean", "ext_above_pct_sd", "comp_mean_kn_mean", "comp_mean_kn_sd",
             *(["comp_mean_kn_min", "comp_mean_kn_max"] if first else []), "comp_below_pct_mean", "comp_below_pct_sd",
             "peak_hz_mean", "peak_hz_sd", "peak_hz_min", "peak_hz_max", "pattern"]
    pattern = (rf"\| {frame} \| {controller} \| {N} ± {N} kN{spread} \| {N} ± {N} % \| {N} ± {N} kN{spread} \| "
               rf"{N} ± {N} % \| {N} ± {N} Hz \[{N}, {N}\] \| {N} of " + (N if first else r"\d+"))
    return tuple(f"robust_{tag}_{n}" for n in names) + (("robust_seeds",) if first else ()), [pattern]


# tool: {figure, or a tuple of figures (one per group), each as "name", "-name" (the quote is its
# negative, "3 % worse" of a benefit of -3 %), "abs:name" (its magnitude, "6 % off"), "max:name" (the quote
# bounds it, "to within 2 Hz") or "a|b" (one quote of two figures, a range's ends that print alike): the
# ways the documents quote it, on text whose whitespace runs are single spaces}
QUOTES: dict[str, dict[str | tuple[str, ...], list[str]]] = {
    "benchmark": {
        "realtime_default": [r"(\d+)× real time at the default rtol", r"\*\*(\d+)× real time\*\* at the default",
                             r"\| \*\*FMU default\*\* \| \*\*(\d+)×\*\*", r"\((\d+)× in `cargo bench`"],
        "realtime_c_api": [r"(\d+)× through the FMU's C API",
                           r"\*\*Through the FMU's C API\*\* \([^)]*\): \*\*(\d+)×\*\*", r"(\d+)× through the C API"],
        "realtime_diagnosis": [r"(\d+)× at the diagnosis's rtol", r"\| \*\*diagnosis\*\* \| \*\*(\d+)×\*\*",
                               r"\(0\.\d+ %\) at (\d+)×", r"tolerance, at (\d+)×", r"(\d+)× at 3e-5 \("],
        "six_dampers_two_threads": [r"(\d+)× on two threads"],
        ("realtime_default",): [r"against a converged run and (\d+)× real time"],
        ("rtol_3e-5_err_pct", "realtime_diagnosis"): [rf"3e-5 gives {N} % at {N}×"],
        "python_slower": [r"(\d+)× slower than the FMU", r"The FMU runs (\d+)× faster through fmpy"],
        "diagnose_60s_reruns.wall_s_min|diagnose_60s_reruns.wall_s_max": [
            r"record diagnosed in ([\d.]+) s", r"A 60 s record at 1 kHz takes ([\d.]+) s on 2 cores"],
        ("diagnose_60s_reruns.wall_s_min", "diagnose_60s_s"): [rf"\*\*{R} s\*\* wall"],
        **{tuple(f"rtol_{rtol}_{c}" for c in ("realtime", "mean_us", "p99_us", "worst_us", "replayed_us", "faults",
                                              "err_n")): [
            rf"\| {rtol} \| \| {N}× \| {N} \| {N} \| {N} \| {N} \| {N} \| {N} \|"]
           for rtol in ("1e-2", "1e-3", "1e-4", "1e-5")},
        ("rtol_3e-4_mean_us", "rtol_3e-4_worst_us", "rtol_3e-4_replayed_us", "rtol_3e-4_faults", "rtol_3e-4_err_n"): [
            rf"\| \*\*FMU default\*\* \| \*\*\d+×\*\* \| {N} \| [\d.]+ \| {N} \| {N} \| {N} \| \*\*{N} \("],
        ("rtol_3e-5_mean_us", "rtol_3e-5_p99_us", "rtol_3e-5_worst_us", "rtol_3e-5_replayed_us", "rtol_3e-5_faults",
         "rtol_3e-5_err_n", "rtol_3e-5_err_pct"): [
            rf"\| \*\*diagnosis\*\* \| \*\*\d+×\*\* \| {N} \| {N} \| {N} \| {N} \| {N} \| \*\*{N} \({N} %\)\*\* \|"],
        ("rtol_3e-5_err_n", "rtol_3e-5_err_pct"): [rf"{N} N \({N} %\) at rtol 3e-5, the diagnosis's tolerance"],
        "rtol_3e-5_err_n": [r"\d+× at 3e-5 \(([\d.]+) N\)"],
        "rtol_3e-4_err_sigma": [r"the benchmark's input has ([\d.]+) load-cell noise sigmas RMS"],
        ("c_api_step_us", "direct_step_us"): [rf"{N} µs a step against {N} µs calling the damper directly"],
        ("six_3e-4_one_by_one", "six_3e-4_one_thread", "six_dampers_two_threads", "six_3e-5_one_by_one",
         "six_3e-5_one_thread", "six_3e-5_two_threads"): [
            rf"at 3e-4: {N}× one by one, {N}× in lockstep on one thread, {N}× on two threads "
            rf"\({N}×, {N}× and {N}× at 3e-5\)"],
        ("seeds_3e-4_least_n", "seeds_3e-4_largest_n", "seeds_3e-4_largest_pct", "seeds_3e-5_least_n",
         "seeds_3e-5_largest_n", "accuracy_1e-2.least_n", "accuracy_1e-2.largest_n"): [
            rf"{R} N at 3e-4 \(at most {N} %\), {R} N at 3e-5\. At 1e-2 \(one step per sample\) the controller's "
            rf"decisions at force reversals amplify last-bit differences: {R} N"],
        ("seeds_3e-4_least_n", "seeds_3e-4_largest_n", "seeds_3e-4_largest_pct"): [
            rf"\({R} N, at most {N} %, on twelve such inputs\)"],
        ("rtol_3e-5_err_n", "rtol_3e-5_err_pct", "seeds_3e-5_least_n", "seeds_3e-5_largest_n"): [
            rf"gives {N} N \({N} %\) at \d+×, and {R} N on the twelve inputs"],
        "seeds_3e-4_largest_pct": [r"at most (\d\.\d+) % on twelve random inputs",
                                   r"\(at most (\d\.\d+) % over twelve random inputs\)"],
        ("seeds_3e-5_least_n", "seeds_3e-5_largest_n", "seeds_3e-5_largest_sigma"): [
            rf"rtol 3e-5 \({R} N, under {N} load-cell σ\)"],
        ("rtol_3e-4_mean_us", "p99_default_us", "rtol_3e-4_worst_us", "rtol_3e-4_replayed_us", "rtol_3e-4_err_n"): [
            rf"mean `fmi2DoStep` {N} µs, p99 {N} µs, worst {N} µs as run \([^)]*replayed, is {N} µs\), RMS force error "
            rf"against a converged run \(rtol 1e-9, steps ≤ 5 µs\) {N} N ="],
        "converged_f_rms_kn": [r"steps ≤ 5 µs; RMS force ([\d.]+) kN\)"],
        ("quick_mode.realtime_min", "quick_mode.realtime_max"): [rf"`quick` gives {R}× at 3e-4"],
        tuple(f"profile.{n}_pct" for n in ("do_step", "linearised", "evaluation", "inverse_valve", "port_area",
                                          "force_loop", "exp", "mount")): [
            rf"the adjugate and the solves {N} %, the linearised evaluation {N} %, the plain evaluation {N} %, "
            rf"the inverse valve law {N} %, the port area {N} %, the force loop {N} % and its `exp` {N} %, "
            rf"the mount {N} %"],
        ("diagnose_60s_k1_mount", "diagnose_60s_fit.k1_mount_std_error", "diagnose_60s_fit.k1_mount_truth"): [
            rf"k1 fitted {N} ± {N} against the truth's {N}", rf"k1 = {N} ± {N} N/m \(hidden {N}\)"],
        "python_rms_diff_n": [r"the forces are ([\d.]+) N RMS apart at its default tolerance"],
        "python_max_diff_n": [r"default tolerance \(largest ([\d.]+) N\)"],
        "rms_error_default_pct": [r"\((\d\.\d+) % RMS force error", r"RMS force error of (\d\.\d+) %",
                                  r"cargo bench: (\d\.\d+) % RMS force error",
                                  r"= \*\*(\d\.\d+) %\*\*", r"at (\d\.\d+) % RMS force error",
                                  r"\| \*\*FMU default\*\* \|(?: [^|]+ \|){6} \*\*[\d.]+ \((\d\.\d+) %\)\*\* \|"],
        "p99_default_us": [r"p99 `fmi2DoStep` ([\d.]+) µs", r"p99 ([\d.]+) µs, worst",
                           r"p99 ≤ 10 µs at the default: ([\d.]+) µs",
                           r"\| \*\*FMU default\*\* \| \*\*\d+×\*\* \| [\d.]+ \| ([\d.]+) \|"],
    },
    "paper_tests": {
        "spool_dead_min_ms|spool_dead_max_ms": [
            r"\| Valve dead time, Fig\. 4 \| [^|]+ \| ([\d.]+) ms \|", r"\| ([\d.]+) ms \(five steps\) \|",
            r"dead time \(spool moved 2 % of the step\) ([\d.]+) ms", r"\(dead time ([\d.]+) ms, t90"],
        "spool_t50_min_ms|spool_t50_max_ms": [r"\| t50 ([\d.]+) ms, t90 [\d.]+–", r"ms, t50 ([\d.]+) ms, t90 [\d.]+–",
                                              r"monotone steps: t50 ([\d.]+) ms"],
        ("spool_t90_min_ms", "spool_t90_max_ms"): [rf"t50 [\d.]+ ms, t90 {R} ms"],
        "spool_t90_min_ms": [r"\(dead time [\d.]+ ms, t90 ([\d.]+) ms\)"],
        "spool_overshoot_max_pct": [r"\| largest ([\d.]+) % \|", r"overshoot at most ([\d.]+) %"],
        ("spool_t90_min_ms", "spool_t90_max_ms", "spool_overshoot_max_pct"): [
            rf"steps without significant overshoot \(paper Fig\. 4\): t90 {R} ms, largest overshoot {N} %"],
        ("extension_step1_t90_ms", "extension_step1_t100_ms", "extension_step1_overshoot_pct"): [
            rf"\| t90 {N} ms, t100 {N} ms, overshoot {N} % \| yes \|"],
        ("extension_step1_t90_ms", "extension_step1_t100_ms", "extension_step1_t10_ms", "extension_step1_t50_ms",
         "extension_step1_overshoot_pct"): [
            rf"2 → 12 kN at 0\.15 m/s, Fig\. 6 \| [^|]+ \| t90 {N} ms, t100 {N} ms \(t10 {N} ms, t50 {N} ms\), "
            rf"overshoot {N} %"],
        ("extension_step2_t90_ms", "extension_step2_t100_ms", "extension_step2_t10_ms", "extension_step2_t50_ms",
         "extension_step2_overshoot_pct"): [
            rf"12 → 22 kN at 0\.15 m/s, Fig\. 6 \| [^|]+ \| t90 {N} ms, t100 {N} ms \(t10 {N} ms, t50 {N} ms\), "
            rf"overshoot {N} %"],
        ("extension_step1_t90_ms", "extension_step2_t90_ms", "extension_step1_t100_ms", "extension_step2_t100_ms",
         "extension_step1_overshoot_pct", "extension_step2_overshoot_pct", "compression_step1_t90_ms",
         "compression_step2_t90_ms", "t90_ratio_step1", "t90_ratio_step2"): [
            rf"extension t90 {N} ms and {N} ms \(t100 {N} and {N} ms\), overshoot {N} % and {N} %; compression "
            rf"t90 {N} and {N} ms, {N} and {N} times the extension's"],
        ("compression_step1_t90_ms", "compression_step2_t90_ms", "t90_ratio_step1", "t90_ratio_step2"): [
            rf"\| t90 {N} ms / {N} ms; t90 ratio compression/extension {N}, {N} \|"],
        ("t90_ratio_step1", "t90_ratio_step2"): [rf"\| t90 ratio {N} and {N} \|"],
        "extension_step1_t90_ms": [r"\(t90 (\d+) ms, rig-validation\.md\)"],
        ("extension_step1_overshoot_pct", "extension_step2_overshoot_pct"): [
            rf"goes with the {R} % overshoot of the Fig\. 6 steps", rf"\(Fig\. 6: {R} %\)"],
        ("extension_step1_overshoot_pct", "extension_step2_overshoot_pct", "compression_step1_overshoot_pct",
         "compression_step2_overshoot_pct"): [rf"overshoot by {R} % in extension and {R} % in compression"],
        ("extension_step1_overshoot_pct", "compression_step1_overshoot_pct"): [rf"instead of {N} % and {N} %"],
        "compressed_volume_ratio": [r"\| ([\d.]+) \(from the parameters\) \|"],
    },
    "valve_response": {
        **{tuple(f"valve_{tag}_{m}" for m in ("gain_mm_a", "f3db_hz", "f90_hz", "delay_ms", "loop_f3db_hz",
                                              "loop_f90_hz", "loop_delay_ms")): [
            rf"\| {label} \| {N} mm/A \| {N} Hz \| {N} Hz \| {N} ms \| {N} Hz \| {N} Hz \| {N} ms \|"]
           for tag, label in (("10_small", r"1\.0 mm ± 0\.1 mm"), ("10_large", r"1\.0 mm ± 0\.8 mm"),
                              ("25_small", r"2\.5 mm ± 0\.1 mm"), ("25_large", r"2\.5 mm ± 1\.9 mm"),
                              ("35_small", r"3\.5 mm ± 0\.1 mm"), ("35_large", r"3\.5 mm ± 0\.9 mm"),
                              ("25_rest", r"2\.5 mm ± 0\.1 mm, at rest \(no flow\)"))},
        ("valve_mid_f3db_hz_min", "valve_mid_f3db_hz_max", "valve_mid_f90_hz_min", "valve_mid_f90_hz_max",
         "valve_mid_delay_ms_min", "valve_mid_delay_ms_max"): [
            rf"−3 dB {R} Hz, −90° {R} Hz, {R} ms \(spool mass–spring\)"],
        ("valve_mid_f3db_hz_min", "valve_mid_f3db_hz_max", "valve_mid_f90_hz_min", "valve_mid_f90_hz_max"): [
            rf"current → spool: −3 dB at {R} Hz, −90° at {R} Hz\."],
        ("valve_mid_f90_hz_min", "valve_mid_f90_hz_max"): [rf"−90° at {R} Hz, against the natural frequency"],
        ("valve_mid_f3db_hz_min", "valve_mid_f3db_hz_max"): [rf"−3 dB at {R} Hz, against 0\.87"],
        ("valve_small_gain_mm_a_min|valve_small_gain_mm_a_max", "valve_mid_gain_mm_a_min|valve_mid_gain_mm_a_max"): [
            rf"the gain at 4 Hz is {N} mm/A and falls to the mechanical {N} mm/A"],
        ("valve_small_f3db_hz_min", "valve_small_f3db_hz_max"): [rf'"−3 dB at {R} Hz" there'],
        ("valve_small_f90_hz_min", "valve_small_f90_hz_max"): [rf"\({R} Hz\) is the mechanical one"],
        ("loop_f3db_hz_min", "loop_f3db_hz_max", "loop_f90_hz_min", "loop_f90_hz_max", "loop_delay_ms_min",
         "loop_delay_ms_max"): [rf"−3 dB at {R} Hz, −90° at {R} Hz, equivalent delay {R} ms\.",
                                rf"\| −3 dB {R} Hz, −90° {R} Hz, delay {R} ms; no peak \|"],
        ("loop_f3db_hz_min", "loop_f3db_hz_max", "loop_delay_ms_min", "loop_delay_ms_max"): [
            rf"closed spool loop: −3 dB at {R} Hz, equivalent delay {R} ms\."],
        "loop_gain_max": [r"no resonance peak in the closed loop, largest gain ([\d.]+)\)"],
        ("i_sol_large_a_min", "i_sol_large_a_max"): [rf"the current stays within {R} A"],
        ("valve_coherence_mid_min", "valve_coherence_10_small", "valve_coherence_10_large"): [
            rf"at least {N} at 2\.5 and 3\.5 mm; at 1 mm, where the flow force acts, it is {N} \(small\) and {N} "
            r"\(large amplitude\)"],
        # the table's rows; the 0.15 m/s row is quoted in the README as well (one key: a second entry
        # with the same key would replace the first, and the table's row would go unchecked)
        **{(f"force_{v}_ext_f3db_hz", f"force_{v}_comp_f3db_hz", f"force_{v}_ext_f90_hz", f"force_{v}_comp_f90_hz"): [
            rf"\| 0\.{v[1:]} m/s \| {N} / {N} Hz \| {N} / {N} Hz \|",
            *([rf"\| −3 dB {N} / {N} Hz, −90° {N} / {N} Hz \(0\.05–0\.25 m/s"] if v == "015" else [])]
           for v in ("005", "015", "025")},
        ("force_015_ext_f90_hz", "force_015_comp_f90_hz"): [rf"−90° at {N} Hz in extension and {N} Hz in compression"],
        ("force_015_comp_f90_hz", "force_015_ext_f90_hz"): [rf"The −90° frequency is {N} against {N} Hz at 0\.15 m/s"],
        "force_015_ext_f90_hz": [r"A −90° frequency of (\d+) Hz is a quarter period"],
        "max:force_amplitude_max_diff_hz": [r"±1 kN gives the same to within (\d+) Hz"],
        ("force_gain_low_min", "force_gain_low_max", "force_fast_peak_8_40hz_min",
         "force_fast_peak_8_40hz_max"): [rf"The gain is {R} at 4 Hz and peaks at {R} between 8 and 40 Hz"],
        ("force_coherence_min", "force_coherence_max", "force_coherence_005_comp_large"): [
            rf"the coherence across realizations is {R}, and {N} in compression at 0\.05 m/s"],
        ("flow_turbulent_points", "flow_max_dev_pct"): [
            rf"all {N} points lie on the law at the measured spool position "
                                                        rf"to within {N} %",
                                                        rf"\| {N} turbulent points on [^|]* within {N} %"],
        ("flow_spool_at_widest_fastest_mm_min", "flow_spool_at_widest_fastest_mm_max"): [
            rf"pushes the spool back to {R} mm"],
        "force_velocity_smallest_01_kn": [rf"{N} kN at 0\.1 m/s for 0\.8 mm"],
        tuple(f"limit_cycles.{n}" for n in ("force_pp_1ms_kn", "force_pp_1ms_pct", "spool_pp_1ms_mm",
                                            "force_pp_06ms_kn", "force_pp_06ms_pct", "force_pp_minus1ms_kn",
                                            "force_pp_minus1ms_pct")): [
            rf"at \+1 m/s the force varies by {N} kN peak to peak \({N} %\) and the spool by {N} mm; at \+0\.6 m/s by "
            rf"{N} kN \({N} %\); at −1 m/s by {N} kN \({N} %\)"],
    },
    "hil_scenarios": {
        ("minor_peak_above_3_hz|minor_peak_band_hz|minor_ideal_peak_band_hz", "others_peak_above_3_hz_min",
         "others_peak_above_3_hz_max", "others_peak_band_hz_min", "others_peak_band_hz_max"): [
            rf"the largest value above 3 Hz and in 5–30 Hz is at {N} Hz, the same as the ideal semi-active force; the "
            rf"other eight cases: {R} Hz above 3 Hz, {R} Hz in 5–30 Hz"],
        "minor_peak_band_hz": [r"a plateau above 3 Hz whose largest value is at (\d+) Hz on the minor road"],
        ("minor_ext_mean_error_kn", "minor_ext_above_pct"): [
            rf"\| Extending: [^|]* \| often \| [^|]* \| {N} kN, {N} %"],
        ("minor_comp_mean_error_kn", "minor_comp_below_pct"): [
            rf"\| Contracting: [^|]* \| often \| [^|]* \| {N} kN, {N} %"],
        "minor_mean_error_kn": [r"\| ([+−-][\d.]+) kN \(both halves of the pattern add to it\)"],
        ("minor_f_rms_kn", "minor_f_demand_rms_kn", "minor_error_rms_kn"): [
            rf"\| RMS force / demand, RMS error \| [^|]* \| [^|]* \| {N} / {N} kN, {N} kN \|"],
        ("minor_ext_mean_error_kn", "minor_ext_above_pct", "minor_comp_mean_error_kn", "minor_comp_below_pct",
         "minor_f_rms_kn", "minor_f_demand_rms_kn"): [
            rf"docs/hil\.md: {N} kN / {N} % and {N} kN / {N} %, force RMS {N} kN against {N} kN"],
        ("minor_f_rms_kn", "minor_f_demand_rms_kn"): [rf"\(RMS {N} kN against {N} kN on the minor road\)"],
        ("ext_mean_error_kn_min", "ext_mean_error_kn_max", "ext_above_pct_min", "ext_above_pct_max",
         "comp_mean_error_kn_max", "comp_mean_error_kn_min", "comp_below_pct_min", "comp_below_pct_max"): [
            rf"\(extension {N} to {N} kN, {R} % of the time above; compression {N} to {N} kN, {R} % below\)"],
        "best_passive_kns_m_min|best_passive_kns_m_max": [
            r"the rule falls back to the lowest-DLC setting, (\d+) kNs/m"],
        **{(f"{tag}_best_passive_kns_m", *(f"{tag}_{n}_{m}" for n, m in (
                ("passive", "a_body_rms"), ("passive", "dlc"), ("passive", "x_rms_mm"), ("passive", "x_peak_mm"),
                ("ideal", "a_body_rms"), ("ideal", "ride_change_pct"), ("ideal", "dlc"), ("ideal", "x_rms_mm"),
                ("ideal", "x_peak_mm"), ("fmu", "a_body_rms"), ("fmu", "ride_change_pct"), ("fmu", "dlc"),
                ("fmu", "x_rms_mm"), ("fmu", "x_peak_mm")))): [
            rf"\| {label}, \d+ m/s \| best passive, {N} kNs/m \| {N} \| {N} \| {N} / {N} \| \| \| ideal semi-active \| "
            rf"\*\*{N}\*\* \({N} %\) \| {N} \| {N} / {N} \| \| \| damper FMU \| {N} \({N} %\) \| {N} \| {N} / {N} \|"]
           for tag, label in (("minor_14", r"minor road \(128e-6 m³\)"), ("major_20",
           r"major road \(class B, 64e-6 m³\)"),
                              ("motorway_25", r"motorway \(class A, 16e-6 m³\)"))},
        ("ideal_benefit_pct_min", "ideal_benefit_pct_max"): [rf"rides about 7 % better \({R} %\)"],
        ("fmu_ride_change_pct_min", "fmu_ride_change_pct_max", "-fmu_dlc_change_pct_max", "-fmu_dlc_change_pct_min"): [
            rf"rides {R} % worse than the best passive damper, with a DLC {R} % lower"],
        ("fmu_v_max_min", "fmu_v_max_max"): [rf"largest \|v_damper\| is {R} m/s"],
        ("crg_best_passive_kns_m", "crg_passive_a_body_rms", "crg_passive_dlc", "crg_ideal_a_body_rms", "crg_ideal_dlc",
         "crg_fmu_a_body_rms", "crg_fmu_dlc", "crg_fmu_v_max", "crg_fmu_f_max_kn"): [
            rf"the best passive damper \({N} kNs/m, the lowest RMS a_body with DLC ≤ the ideal's\) gives RMS "
            rf"a_body {N} "
            rf"m/s², DLC {N}\. The ideal semi-active gives {N} m/s², {N}, and the damper FMU {N} m/s², {N} "
            rf"\(\|v_damper\| up to {N} m/s, \|F\| up to {N} kN\)"],
    },
    "hil_rig": {
        **{tuple(f"{tag}_{m}" for m in ("peak_hz", "prominence", "ext_mean_kn", "ext_above_pct", "comp_mean_kn",
                                        "comp_below_pct")): [
            rf"\| {label} \| (?:\*\*)?{N} Hz(?:\*\*)? \| {N} \| {N} kN, {N} % \| {N} kN, {N} % \|"]
           for tag, label in (("none", "no rig"), ("act0_100", "actuator 0 ms, 100 Hz"),
                              ("act2_inf", "actuator 2 ms, ∞"),
                              ("lc1", "load-cell delay 1 ms"), ("lc2", r"\*\*load-cell delay 2 ms\*\*"),
                              ("lc3", r"\*\*load-cell delay 3 ms\*\*"), ("lc4", "load-cell delay 4 ms"),
                              ("lc6", "load-cell delay 6 ms"))},
        ("none_peak_hz", "act2_inf_peak_hz|act0_100_peak_hz", "lag4_peak_hz_min", "lag4_peak_hz_max"): [
            rf"Without a rig the peak is {N} Hz\. With a 2 ms delay, or a 100 Hz actuator, it is {N} Hz; with "
            rf"4–8 ms it "
            rf"is {R} Hz"],
        ("actuator_lag_ext_above_pct_min", "actuator_lag_ext_above_pct_max"): [
            rf"the force is above the demand only {R} % of the time"],
        ("actuator_lag_comp_below_pct_min", "actuator_lag_comp_below_pct_max"): [
            rf"Compression stays below the demand, {R} % of the time"],
        ("lc2_ext_mean_kn", "lc2_comp_mean_kn"): [rf"asymmetry grows with the delay \({N}/{N} kN at 2 ms\)"],
        ("lc2_prominence", "lc3_prominence", "none_prominence"): [
            rf"but only {R}× the band's median; the no-rig spectrum is a plateau with {N}\."],
        "lc6_peak_hz": [r"appears only with 6 ms or more of latency\. It then sits at (\d+) Hz",
                        r"[Aa] clear peak needs ≥ 6 ms and then sits at (\d+) Hz"],
        "lc2_peak_hz|lc3_peak_hz": [r"with 2–3 ms of force-path delay moves it to (\d+) Hz",
                                    r"moves the largest value to (\d+) Hz with 2–3 ms"],
        **dict(robust_row(*row) for row in (("tared_ff", "tared", r"feedforward \+ PI \(default\)"),
                                            ("tared_pid", "tared", "paper PID"),
                                            ("raw_ff", "raw", r"feedforward \+ PI"), ("raw_pid", "raw", "paper PID"))),
        **{tuple(f"robust_{tag}_{m}" for m in (
                "ext_mean_kn_mean", "ext_mean_kn_sd", "ext_above_pct_mean", "ext_above_pct_sd", "comp_mean_kn_mean",
                "comp_mean_kn_sd", "comp_below_pct_mean", "comp_below_pct_sd", "peak_hz_mean", "peak_hz_sd",
                "peak_hz_min", "peak_hz_max", "prominence_mean", "prominence_sd", "pattern", "paper_like")): [
            rf"\| load-cell delay {tag[2:]} ms \| {N} ± {N} kN \| {N} ± {N} % \| {N} ± {N} kN \| {N} ± {N} % \| "
            rf"{N} ± {N} Hz \[{N}, {N}\] \| {N} ± {N} \| {N} of \d+ \| {N} of \d+ \|"] for tag in ("lc2", "lc3")},
        ("robust_tared_ff_ext_mean_kn_sd", "robust_tared_ff_comp_mean_kn_sd"): [
            rf"on every seed, with a small spread \(±{R} kN\)"],
        "robust_raw_frame_comp_shift_kn": [r"It adds about ([\d.]+) kN of magnitude in compression"],
        ("robust_tared_pid_error_rms_kn", "robust_tared_ff_error_rms_kn"): [
            rf"with an RMS error of {N} kN against {N} kN"],
        ("robust_tared_ff_peak_hz_min", "robust_tared_ff_peak_hz_max"): [rf"It moves {R} Hz between seeds",
                                                                         rf"largest 5–30 Hz value {R} Hz over"],
        ("robust_lc2_ext_mean_kn_mean", "robust_lc3_ext_mean_kn_mean", "robust_lc2_comp_mean_kn_mean",
         "robust_lc3_comp_mean_kn_mean", "robust_lc_peak_hz_min", "robust_lc_peak_hz_max", "robust_lc3_peak_hz_mean",
         "robust_lc3_peak_hz_sd", "robust_lc3_paper_like", "robust_seeds", "robust_lc_prominence_min",
         "robust_lc_prominence_max"): [
            rf"grows \({N}…{N} kN, {N}…{N} kN\), and the spectrum's largest value in 5–30 Hz moves to {R} Hz "
            rf"\({N} ± {N} Hz at 3 ms, in 15 ± 2 Hz on {N} of {N} seeds\)\. It stays a broad maximum \({R}× the "
            r"band's median\)"],
        ("robust_lc_peak_hz_min", "robust_lc_peak_hz_max", "robust_lc_prominence_min", "robust_lc_prominence_max"): [
            rf"\({R} Hz over five road seeds\), keeping the sign pattern on every seed; it still does not stand out "
            rf"\({R}× the band's median\)"],
        ("robust_tared_ff_peak_hz_min", "robust_tared_ff_peak_hz_max", "robust_seeds", "robust_lc_peak_hz_min",
         "robust_lc_peak_hz_max", "robust_seeds", "robust_lc3_peak_hz_mean", "robust_lc3_peak_hz_sd"): [
            rf"value {R} Hz over {N} seeds\); rig with a 2–3 ms force-path delay: {R} Hz over {N} seeds "
            rf"\({N} ± {N} Hz at 3 ms\)"],
        ("robust_tared_ff_ext_mean_kn_mean", "robust_tared_ff_ext_mean_kn_sd", "robust_tared_ff_ext_above_pct_mean",
         "robust_tared_ff_comp_mean_kn_mean", "robust_tared_ff_comp_mean_kn_sd", "robust_tared_ff_comp_below_pct_mean",
         "robust_tared_ff_pattern", "robust_seeds",
         "robust_raw_ff_pattern|robust_tared_pid_pattern|robust_raw_pid_pattern",
         "robust_seeds"): [
            rf"tared, feedforward \+ PI: {N} ± {N} kN {N} %, {N} ± {N} kN {N} % \({N} of {N} seeds\); raw load "
            rf"cell or the "
            rf"paper's PID: {N} of {N}"],
    },
    "benefit_map": {
        ("best_linear_kns_m_min", "best_linear_kns_m_max"): [rf"is within 0\.2 % of the linear {R} kNs/m"],
        "ideal_paper_benefit_pct_min|ideal_paper_benefit_pct_max": [
            r"the ideal damper rides about (\d+) % better at a DLC no worse in every case"],
        ("ideal_paper_benefit_pct_min", "ideal_paper_benefit_pct_max"): [
            rf"the ideal damper's with the paper's law: {R} % over the nine cases"],
        ("fitted_ext_delay_ms_min", "fitted_ext_delay_ms_max", "fitted_comp_delay_ms_min", "fitted_comp_delay_ms_max",
         "fitted_comp_bw_hz_min", "fitted_comp_bw_hz_max"): [
            rf"Its fitted tracking is a delay of {R} ms in extension \(including the 1 ms coupling step\) and "
            rf"{R} ms with a {R} Hz lag in compression"],
        ("longest_delay_ms_min", "longest_delay_ms_max"): [rf"the benefit is gone at {R} ms of pure delay",
                                                           rf"gone at {R} ms of force delay"],
        ("ideal_best_law_cm_min|ideal_best_law_cm_max", "ideal_best_law_alpha_min|ideal_best_law_alpha_max",
         "ideal_best_law_benefit_pct_min", "ideal_best_law_benefit_pct_max"): [
            rf"The ideal damper's best law \(Cm {N} kNs/m, α {N}\) rides {R} % better"],
        ("fmu_best_law_cm_min|fmu_best_law_cm_max", "fmu_best_law_alpha_min|fmu_best_law_alpha_max",
         "fmu_best_law_benefit_pct_min", "fmu_best_law_benefit_pct_max"): [
            rf"the best law \(Cm {N}, α {N}\) gives {R} %"],
        ("fmu_gains_cm_min", "fmu_gains_cm_max", "fmu_gains_alpha_min", "fmu_gains_alpha_max",
         "fmu_gains_benefit_pct_min", "fmu_gains_benefit_pct_max", "fmu_gains_wk_pct_min", "fmu_gains_wk_pct_max"): [
            rf"with Cm {R}, α {R} it rides {R} % better than the best passive damper of either kind "
            rf"at a DLC no worse in all nine cases \(Wk-weighted {R} %\)"],
        ("fmu_gains_cm_min", "fmu_gains_cm_max", "fmu_gains_alpha_min", "fmu_gains_alpha_max",
         "fmu_gains_benefit_pct_min", "fmu_gains_benefit_pct_max"): [
            rf"with Cm {R} kNs/m, α {R} and no force-loop integral \+{R} %"],
        ("common_setting_benefit_pct_min", "common_setting_benefit_pct_mean"): [
            rf"\(Cm 48, α 0\.2, Kp_F 1, Ki_F 0\) gives at least {N} % \({N} % on average\)"],
        ("ki_f0_rig_steps.extension_overshoot_pct", "ki_f0_rig_steps.compression_overshoot_pct"): [
            rf"Ki_F 0 overshoots {N} % in extension and {N} % in compression"],
        ("ki_f0_rig_steps.extension_t100_later_ms", "ki_f0_rig_steps.compression_t100_later_ms"): [
            rf"reaches the demand {N} and {N} ms later \(`sweep\.run_rig`\)"],
        ("-least_dlc_ideal_dlc_change_pct_max", "-least_dlc_ideal_dlc_change_pct_min",
         "-least_dlc_fmu_dlc_change_pct_max", "-least_dlc_fmu_dlc_change_pct_min",
         "-least_dlc_stress_change_pct_max", "-least_dlc_stress_change_pct_min", "passive_dlc_min",
         "passive_dlc_max"): [
            rf"ideally {R} % below the passive damper's DLC and with the FMU {R} % \(the second table\)\. "
            rf"The fourth-power road stress moves far less \({R} %\): at DLC {R} it is"],
        "crg_best_linear_kns_m": [r"loses to the best passive damper \((\d+) kNs/m\) ideally too"],
        ("best_linear_kns_m_min", "coupling_step.gains_benefit_1ms_pct", "coupling_step.gains_benefit_05ms_pct",
         "coupling_step.gains_benefit_025ms_pct", "-coupling_step.paper_benefit_1ms_pct",
         "-coupling_step.paper_benefit_05ms_pct", "-coupling_step.paper_benefit_025ms_pct"): [
            rf"against the {N} kNs/m passive damper, Cm 48/α 0\.2/Ki_F 0 rides {N} % better at 1 ms, {N} % at 0\.5 ms "
            rf"and {N} % at 0\.25 ms; the paper's law {N}, {N} and {N} % worse"],
        "fmu_gains_on_edge": [rf"the best FMU settings of {W} cases sit on an edge"],
        ("ideal_paper_benefit_pct_min|ideal_paper_benefit_pct_max", "longest_delay_ms_min", "longest_delay_ms_max",
         "fitted_delay_ms_min", "fitted_delay_ms_max", "-fmu_paper_benefit_pct_max", "-fmu_paper_benefit_pct_min"): [
            rf"the paper's law ideal \+{N} %, gone at {R} ms of force delay; the FMU lags {R} ms and rides "
            rf"{R} % worse"],
    },
    "full_truck": {
        ("-fmu_paper_benefit_pct_max", "-fmu_paper_benefit_pct_min", "ideal_paper_benefit_pct_min",
         "ideal_paper_benefit_pct_max"): [
            rf"FMU rides {R} % worse at the seat than the best passive damper, where the ideal damper with the "
            rf"same law rides {R} % better"],
        ("fmu_search_random_benefit_pct_min", "fmu_search_random_benefit_pct_max", "fmu_search_crg_benefit_pct",
         "ideal_search_benefit_pct_min", "ideal_search_benefit_pct_max", "fmu_best_qt_benefit_pct_min",
         "fmu_best_qt_benefit_pct_max", "fmu_best_qt_random_dlc_change_pct_min",
         "fmu_best_qt_random_dlc_change_pct_max"): [
            rf"{R} % on the random roads and {N} % on the Belgian block; the ideal damper gets {R} %\. The "
            rf"quarter truck's single best setting \(Cm 48, α 0\.2\) rides {R} % better but costs {R} % DLC"],
        ("-fmu_paper_benefit_pct_max", "-fmu_paper_benefit_pct_min", "fmu_search_random_benefit_pct_min",
         "fmu_search_random_benefit_pct_max", "fmu_search_crg_benefit_pct"): [
            rf"the FMU with the paper's law {R} % worse, retuned \+{R} % on random roads, \+{N} % on the "
            r"Belgian block"],
    },
    "blind_score": {
        ("transducer.cases", "transducer.single_passed", "transducer.single_cases", "transducer.pair_passed",
         "transducer.pair_cases", "transducer.clean_passed", "transducer.clean_cases",
         "transducer.foreign_does_not_fit",
         "transducer.foreign_cases", "lvdt_clean.clean_passed", "lvdt_clean.clean_cases", "lvdt_pair.pair_passed",
         "lvdt_pair.pair_cases"): [
            rf"On {N} records made independently of its numerics \(\[docs/blind-score\.md\]\([^)]*\)\) it names {N} of "
            rf"{N} hidden single effects and both of {N} of {N} overlapping pairs, nothing on {N} of {N} clean "
            rf"records, "
            rf"`does_not_fit` for {N} of {N} foreign dampers; on velocities a logger made from its LVDT, "
            rf"nothing on {N} of "
            rf"{N} clean records, both of an overlapping pair on {N} of {N}\."],
        ("transducer.cases", "transducer.wall_s", "lvdt_clean.cases", "lvdt_pair.cases"): [
            rf"`\.venv/bin/damper-blind-score --jobs 2 --threads 1` \({N} cases, {N} s on 2 cores\), "
            rf"`\.venv/bin/damper-blind-score --chain lvdt --only clean --jobs 2 --threads 1` \({N} cases\) and "
            rf"`\.venv/bin/damper-blind-score --chain lvdt --only pair --seeds 7 --jobs 2 --threads 1` \({N} cases\)"],
        ("transducer.single_passed", "transducer.single_cases", "transducer.single_end_stops_passed",
         "transducer.single_end_stops_cases", "transducer.single_end_stops_partial",
         "transducer.single_end_stops_partial_floor_ratio_min", "transducer.single_end_stops_partial_floor_ratio_max",
         "transducer.single_end_stops_unexplained"
         ): [rf"\| {N} of {N} \| end stops {N} of {N}: named but `partial` on {W} records \(the ladder leaves "
             rf"{R}× a floor made tiny by stop forces of tens of kN\), `unexplained` on {W} HiL record at 500 Hz "
             rf"\(the stop's fit stalls\) \|"],
        ("transducer.pair_passed", "transducer.pair_cases"): [rf"\| pair \(3 pairs, rig, seeds 1–3\) \| {N} of {N} \|"],
        ("transducer.clean_passed", "transducer.clean_cases"): [
            rf"\| clean \(rig and HiL, seeds 1–20\) \| {N} of {N} `none`"],
        ("transducer.foreign_passed", "transducer.foreign_cases"): [
            rf"\| foreign \(MR, passive; seeds 1–4\) \| {N} of {N} \| – all `does_not_fit`"],
        ("lvdt_clean.clean_passed", "lvdt_clean.clean_cases", "lvdt_clean.clean_unexplained",
         "lvdt_clean.clean_failed_floor_ratio_min|lvdt_clean.clean_failed_floor_ratio_max"): [
            rf"\| clean, LVDT chain \(rig, seeds 1–20\) \| {N} of {N} `none` \| {W} record, seed 18 \(500 Hz\): "
            rf"`unexplained`, "
            rf"{N}× the floor"],
        "lvdt_clean.clean_passed": [r"brings them back to (\d+) of 20\."],
        ("lvdt_pair.pair_passed", "lvdt_pair.pair_cases", "lvdt_pair.pair_failures_missing_check_valve_cracking|"
         "lvdt_pair.pair_failures", "lvdt_pair.pair_seal_friction+amplifier_delay_passed",
         "lvdt_pair.pair_seal_friction+amplifier_delay_cases"): [
            rf"\| pairs, LVDT chain \(3 pairs, rig, seeds 1–7\) \| {N} of {N} \| check-valve cracking missed in "
            rf"all {N} "
            rf"failures \(seal friction \+ amplifier delay {N} of {N}\)"],
        ("lvdt_pair_true_model.floor_ratio_min", "lvdt_pair_true_model.floor_ratio_max"): [
            rf"the true model leaves {R}× it"],
        ("sampled_filter.substep_fed_rms_sigma_min", "sampled_filter.substep_fed_rms_sigma_max"): [
            rf"difference is {R} σ RMS \(rig and HiL records at 500 Hz, seed 1\)"],
        **{tuple(f"sampled_filter.{m}_{rate}_{u}" for m in ("rms", "max") for u in ("n", "sigma")): [
            rf"\| {rate} Hz \| {N} N = {N} σ \| {N} N = {N} σ \|"] for rate in (500, 1000, 2000)},
        ("sampled_filter.rms_500_sigma", "sampled_filter.max_500_sigma", "sampled_filter.substep_fed_rms_sigma_min",
         "sampled_filter.substep_fed_rms_sigma_max"): [
            rf"differed from the continuous filter by {N}σ RMS and {N}σ at demand steps at 500 Hz; fed every 0\.5 ms "
            rf"substep, {R}σ"],
        ("sampled_filter.rms_500_sigma", "sampled_filter.max_500_sigma"): [
            rf"samples 2 ms apart it differed from the continuous filter by {N}σ RMS and {N}σ at demand steps"],
    },
    "dyno_score": {
        ("program_min", "wall_min"): [
            rf"About {N} minutes of the program's time on 2 cores \({N} minutes of wall time"],
        ("unchanged_named", "unchanged_cases"): [rf"\| unchanged \| {N} of {N} `none` \|"],
        **{(f"{sc}_named", f"{sc}_cases", f"{sc}_within_10pct", f"{sc}_sized", f"{sc}_within_3sigma", f"{sc}_sized"): [
            rf"\| {label} \| {N} of {N} \| {N} of {N} \| {N} of {N} \|"]
           for sc, label in (("gas", "gas pre-charge"), ("valve", "valve adjuster"), ("heated", "oil heated"),
                             ("end_stop", "end stop"), ("gas_release", "gas out of solution"))},
        ("settings_within_10pct", "settings_values", "settings_within_3sigma", "settings_values"): [
            rf"\| three settings in one calibration \(the adjuster's value per setting\) \| – \| {N} of {N} \| "
            rf"{N} of {N} \|"],
        ("calibration_floor_ratio_min", "calibration_floor_ratio_max", "settings_floor_ratio_min",
         "settings_floor_ratio_second", "settings_floor_ratio_max", "calibrated_within_3sigma", "calibrated_parameters",
         "calibrated_within_2sigma"): [
            rf"Calibration brings every record to {R}× its floor \(the settings campaigns to {R}×, but for "
            rf"one record at {N}×\), and {N} of the {N} calibrated parameters lie within 3 of their reported "
            rf"uncertainties of the truth \({N} within 2\)"],
        ("calibration_floor_ratio_min", "calibration_floor_ratio_max"): [rf"every record ends at {R}× its noise floor"],
        ("calibrated_beyond_2sigma", "calibrated_parameters", "calibration_truck_3_beyond_2sigma",
         "calibration_truck_3_fitted"): [
            rf"{N} of {N} parameters lie beyond 2σ where a Gaussian would put 6, most of them truck 3's \({N} of {N},"],
        ("abs:heated_truck_3_z", "abs:heated_truck_3_rel_err_pct"): [
            rf"truck 3's heated record lands {N}σ\s?\({N} %\) from the truth"],
        ("small_k_open_comp_abs_err_pct_min", "small_k_open_comp_abs_err_pct_max", "small_k_open_comp_abs_z_max"): [
            rf"barely reached\) is {R} % off, within {N}σ"],
        ("abs:end_stop_truck_2_rel_err_pct", "end_stop_truck_2_floor_ratio"): [
            rf"ends `partial` \(the stop named, k {N} % off, {N}× the floor left"],
    },
    "sweep": {
        ("hil_200_workers_1.wall_s", "hil_200_workers_2.wall_s"): [
            rf"The 200-point sweep takes about {N} s on 1 worker and {N} s on 2;"],
        "hil_200_workers_2.wall_s": [rf"# 200 HiL runs of 15 s(?: on a LocalCluster)?: {N} s on 2 workers"],
        ("hil_200_workers_2.cpu_s_of_runs", "hil_200_workers_1.cpu_s_of_runs"): [
            rf"the runs' own times add up to {N} s on two workers against {N} s on one"],
        **{(f"hil_200_workers_{w}.wall_s", f"hil_200_workers_{w}.cpu_s_of_runs"): [rf"\| {w} \| {N} s \| {N} s \|"]
           for w in (1, 2)},
        ("hil_200_workers_1.points|hil_200_workers_2.points",): [
            rf"`damper-sweep sweeps/hil_200\.toml --workers N --docs` \({N} points, cluster start"],
        ("montecarlo_10k_workers_2.wall_s", "montecarlo_10k_workers_2.cpu_s_of_runs"): [
            rf"\| `--workers 2` \(a LocalCluster\) \| {N} s \| {N} s \|"],
        ("montecarlo_10k_workers_2_scheduler.wall_s", "montecarlo_10k_workers_2_scheduler.cpu_s_of_runs"): [
            rf"started by hand \| {N} s \| {N} s \|"],
        ("montecarlo_10k_workers_2.points|montecarlo_10k_workers_2_scheduler.points",): [
            rf"the Monte-Carlo of the assumed damper parameters with {N} draws"],
        ("hil_200_interrupted.points_kept", "hil_200_interrupted.points_run_on_resume"): [
            rf"stopped it with exit status 130 and {N} points kept \(dask logs the cancelled tasks\); the same command "
            rf"then ran the other {N},"],
    },
    "coupled_benchmark": {
        **{(f"{name}_ms", f"{name}_over_damper"): [rf"\| {row} \| {N} ms \| {N} \|"]
           for name, row in (("runner_own_road", "compiled runner, the truck's own road"),
                             ("runner_fed_road", "compiled runner, the road fed as a series"),
                             ("ecos", r"ecos 0\.7\.2, `step_until` \(nothing recorded\)"),
                             ("libcosim", r"libcosim 0\.0\.6, `simulate_until`, seven variables observed"),
                             ("fmpy_loop", r"the fmpy loop \(`cosim\.py`\)"))},
        "damper_own_ms": [rf"\| the damper FMU alone, its own time \| {N} ms \| 1 \|"],
        ("load_before", "load_after"): [rf"load average {N} before, {N} after"],
        ("runner_runs_per_s", "fmpy_runs_per_s", "sweep_speedup"): [
            rf"runs at {N} points per second per worker in one process, against {N} through the fmpy loop with "
            rf"the same metrics \({N}×\)"],
        "hil_200_speedup": [rf'`master = "fmpy"`\) the sweep takes {N}× as long'],
        ("hil_200_runner_workers_2_s", "hil_200_fmpy_workers_2_s", "hil_200_speedup"): [
            rf"the whole 200-point sweep on 2 workers took {N} s against {N} s through the fmpy loop in the same "
            rf"benchmark run \({N}×"],
        ("point_total_ms", "point_run_ms", "point_fit_ms"): [
            rf"every metric\) costs {N} ms of a worker: {N} ms the coupled run, {N} ms the tracking fit"],
        ("point_total_ms", "point_run_ms", "point_fit_ms", "point_rest_ms"): [
            rf"A point costs {N} ms: {N} ms the coupled run, {N} ms the tracking fit, {N} ms the rest"],
        "point_rest_ms": [rf"sums of squared errors in `crates/cosim_runner/src/tracking_fit\.rs`\), {N} ms the other"],
        ("coarse_point_total_ms", "coarse_metric_rel_change_max"): [
            rf"a point costs {N} ms and no metric moves by more than {N} of itself"],
        ("coarse_points_fit_changed", "coarse_points"): [
            rf"the fitted delays and bandwidths of {N} of {N} points changed"],
        "runner_own_road_over_damper": [rf"\*\*Against the damper's own time\.\*\* The coupled run costs {N}× the"],
        "runner_extra_us_per_step": [rf"about as much as the damper \({N} µs a step over the damper's",
                                     rf"the truck FMU itself, its road made at initialisation among it \({N} µs a "
                                     r"step: four RK4 substeps"],
    },
    "campaign": {
        ("effect_right", "effect_records"): [
            rf"\| 16 with one hidden effect \(8 effects × 2 seeds\) \| {N} of {N} named"],
        ("clean_right", "clean_records"): [rf"\| 6 clean \| {N} of {N} `none` \|"],
        ("right", "judged", "wall_s", "record_s_min", "record_s_max"): [
            rf"\| all 22 \| \*\*{N} of {N}\*\* \| {N} s \({R} s per record\) \|"],
        ("judged", "right"): [rf"{N} generated records get {N} verdicts right"],
    },
    "instances": {
        ("per_pair_s_min", "per_pair_s_max", "per_pair_step_us_min", "per_pair_step_us_max", "realtime_per_pair_min",
         "realtime_per_pair_max"): [
            rf"about {R} s per pair for 5 s at 1 ms, {R} µs per pair and step, {R}× real time per pair"],
    },
    "crosscheck": {
        tuple(f"runs_2026_11_27.{n}" for n in (
            "python_s_per_s_min", "python_s_per_s_max", "fmu_3e-4_s_per_s", "fmu_3e-4_dostep_s_per_s",
            "fmu_1e-6_s_per_s", "fmu_1e-6_dostep_s_per_s", "fmu_1e-7_s_per_s", "fmu_1e-7_dostep_s_per_s", "ratio_3e-4",
            "ratio_1e-6", "ratio_1e-7", "rms_force_kn", "rms_diff_3e-4_n", "rms_diff_3e-4_pct", "max_diff_3e-4_n",
            "rms_diff_1e-6_n", "rms_diff_1e-6_pct", "max_diff_1e-6_n", "rms_diff_1e-7_n", "max_diff_1e-7_n")): [
            rf"\| wall time per simulated second \| {R} s \| {N} s through fmpy \({N} s in `fmi2DoStep`\) \| "
            rf"{N} s \({N} s in `fmi2DoStep`\) \| {N} s \({N} s\) \| \| FMU faster than Python \| \| {N}× \| {N}× \| "
            rf"{N}× \| \| force difference FMU − Python, RMS force {N} kN \| \| RMS {N} N \({N} %\), max {N} N \| "
            rf"RMS {N} N \({N} %\), max {N} N \| RMS {N} N, max {N} N \|"],
        "runs_2026_11_27.rms_diff_1e-7_n": [r"agrees with it to ([\d.]+) N RMS at rtol 1e-7"],
    },
    "call_sequences": {
        tuple(f"long_run_seed1.{n}" for n in ("calls", "ok_steps", "wall_s", "longest_call_ms", "panics", "hangs",
                                              "non_finite_after_ok", "non_conforming")): [
            rf"\| long run, seed 1 \(2 shared cores\) \| 10⁶ \| {N} \({N} OK steps\) \| {N} s, longest call {N} ms \| "
            rf"{N} \| {N} \| {N} \| {N} \|"],
        tuple(f"fmi3_seed1.{n}" for n in ("calls", "ok_steps", "discards", "wall_s", "longest_call_ms", "panics",
                                          "hangs", "non_finite_after_ok", "non_conforming")): [
            rf"\| FMI 3\.0, `CALL_SEQUENCES=100000 … call_sequences::fmi3`, seed 1 \(2 shared cores\) \| 10⁵ \| "
            rf"{N} \({N} OK steps, {N} Discard\) \| {N} s, longest call {N} ms \| {N} \| {N} \| {N} \| {N} \|"],
    },
    "ranking_accuracy": {
        ("rig_runs", "rig_ranked_first", "rig_named", "rig_fit20", "rig_median_err_pct", "rig_worst_err_pct",
         "rig_at_floor", "rig_halved", "rig_halving_runs", "rig_flow_forces_halved", "rig_flow_forces_halving_runs",
         "rig_viscous_friction_halved", "rig_viscous_friction_halving_runs"): [
            rf"\| one effect, rig inputs \| {N} \| {N} \| {N} \| {N} \(median error {N} %, worst {N} %\) \| {N} \| "
            rf"{N} of {N} \(flow forces {N} of {N}, viscous friction {N} of {N}\) \|"],
        ("hil_runs", "hil_ranked_first", "hil_named", "hil_fit20", "hil_median_err_pct", "hil_worst_err_pct",
         "hil_at_floor", "hil_halved", "hil_halving_runs", "hil_flow_forces_halved", "hil_flow_forces_halving_runs"): [
            rf"\| one effect, HiL inputs \| {N} \| {N} \| {N} \| {N} \(median {N} %, worst {N} %\) \| {N} \| "
            rf"{N} of {N} \(flow forces {N} of {N}\) \|"],
        "hil_worst_err_pct": [r"piston leakage's \(([\d.]+) % at seed 2"],
        ("hil_piston_leakage_bf_min", "hil_piston_leakage_bf_max"): [rf"HiL inputs \(baselines {R}× the floor"],
        ("flow_forces_bf_min", "flow_forces_bf_max"): [rf"and flow forces \({R}× the floor\)"],
        ("none_total", "none_runs", "none_rig", "none_hil", "drift_unexplained", "drift_runs"): [
            rf"verdict `none` in {N} of {N} \({N} rig, {N} HiL\)\. \*\*Load-cell drift\*\* \(\+600 N over the "
            rf"record, outside the catalog\): `unexplained` in {N} of {N}"],
        ("pairs_effect", "pairs_runs", "pairs_both_found", "pairs_at_floor", "pairs_fit20", "pairs_sizes",
         "pairs_amplifier_delay_mount_passed"): [
            rf"verdict `effect` in {N} of {N}, both found in {N} of \d+, the ladder at the floor in {N} of \d+, "
            rf"{N} of {N} size parameters within 20 %\. Amplifier delay \+ mount compliance passes in {N} of"],
        "pairs_third_effect_passed": [r"In (\d+) passing runs the ladder adds"],
        "total_runs": [
            r"runs the diagnosis on (\d+) generated records", r"ranking_accuracy`, (\d+) diagnoses, [\d.]+ min;"],
        "total_min": [
            r"ranking_accuracy` \(([\d.]+) min on 2 cores", r"ranking_accuracy`, \d+ diagnoses, ([\d.]+) min;"],
        **{tuple(f"rig_{effect}_seed{seed}_{what}{unit if what != 'cut_pct' else ''}"
                 for seed in (1, 2) for what in ("fitted", "truth", "cut_pct")): [
            rf"\| {label} \| {N} / {N}{quantity}, {N} %[^|]* \| {N} / {N}{quantity}, {N} %[^|]* \|"]
           for effect, label, unit, quantity in (
               ("seal_friction", r"seal friction, F_coulomb", "", " N"),
               ("piston_leakage", r"piston leakage, G_leak", "", ""),
               ("amplifier_delay", r"amplifier delay, tau_amp", "_ms", r" ms \(b\)"),
               ("compressibility", r"air content, air_fraction", "", ""),
               ("mount_compliance", r"mount stiffness, k1_mount", "", " N/m"),
               ("check_valve_cracking", r"check-valve cracking, p_cv_crack", "_bar", " bar"),
               ("flow_forces", r"flow forces, Cv_valve", "", ""),
               ("viscous_friction", r"viscous friction, c_viscous \(the worked example\)", "", " N·s/m"))},
    },    # the slow Python reference's printed output (damper_tools.reference_figures): docs/physics.md §6, hil.md
    "reference": {
        ("spool_dead_time_ms", "spool_t90_ms", "spool_overshoot_max_pct"): [
            rf"found a dead time of {N} ms and t90 {N} ms in every step, with at most {N} % overshoot"],
        **{tuple(f"ffc_{kind}_{x}_{m}_um" for x in ("16", "25") for m in ("rms", "max")): [
            rf"\| {label} \| {N} / {N} µm \| {N} / {N} µm \|"]
           for kind, label in (("none", r"none \(flow_force_compensation 0\)"),
                               ("fixed", r"fixed gain at 50 bar \(flow_force_compensation 1\)"),
                               ("scheduled", r"scheduled, Q·sqrt\(Δp̂\) \(flow_force_compensation 2\)"))},
        "ffc_flow_force_max_n": [rf"Flow forces reach {N} N there"],
        ("steps_extension_2_12_t90_ms|steps_extension_12_22_t90_ms", "steps_compression_2_12_t90_ms",
         "steps_compression_12_22_t90_ms"): [
            rf"The reference found t90 {N} ms in extension and {N} / {N} ms in compression"],
        ("valve_air_2_5_ext_t50_ms", "valve_air_2_5_ext_t90_ms", "valve_air_0_ext_t50_ms", "valve_air_0_ext_t90_ms",
         "valve_rigid_mount_ext_t50_ms", "valve_rigid_mount_ext_t90_ms", "valve_air_2_5_comp_t50_ms",
         "valve_air_2_5_comp_t90_ms", "valve_air_0_comp_t50_ms", "valve_air_0_comp_t90_ms"): [
            rf"extension {N} / {N} ms with 2\.5 % air, {N} / {N} ms without air, {N} / {N} ms with a rigid mount; "
            rf"compression {N} / {N} ms with 2\.5 % air, {N} / {N} ms without\."],
        ("viscous_body_hz", "viscous_body_zeta", "viscous_wheel_hz", "viscous_wheel_zeta"): [
            rf"c = α C_m = 19\.2 kN·s/m, {N} Hz \(ζ {N}\) and {N} Hz \(ζ {N}\)"],
        ("maxwell_2_mn_wheel_hz", "maxwell_5_mn_wheel_hz"): [rf"with k = 2 MN/m gives {N} Hz, with 5 MN/m {N} Hz"],
        ("msd_lag0_force_peak_hz", "msd_lag10_force_peak_hz", "msd_lag10_tyre_peak_hz"): [
            rf"peaks at {N} Hz with an ideal force actuator but at {N} Hz \(tyre force {N} Hz\)"],
        ("hil_force_peak_hz", "hil_5ms_force_peak_hz"): [
            rf"peaks at {N} Hz with no extra latency and at {N} Hz with 5 ms of extra latency"],
        tuple(f"msd_{road}_{m}" for m in ("dlc", "f_rms_kn", "f_max_kn", "v_max")
              for road in ("a", "b", "minor", "c")): [
            rf"16 / 64 / 128 / 256 e-6 m³: DLC {N} / {N} / {N} / {N}, damper force RMS {N} / {N} / {N} / {N} kN, "
            rf"largest force {N} / {N} / {N} / {N} kN, largest relative velocity {N} / {N} / {N} / {N} m/s"],
        ("hil_extension_above_pct", "hil_extension_mean_kn", "hil_compression_below_pct", "hil_compression_mean_kn",
         "hil_f_rms_kn", "hil_f_demand_rms_kn", "hil_error_rms_kn", "hil_v_max", "hil_f_max_kn", "hil_force_peak_hz",
         "hil_5ms_force_peak_hz", "hil_5ms_error_rms_kn"): [
            rf"in extension the force exceeds the demand \*\*{N} %\*\* of the time \(mean \*\*{N} kN\*\*\); in "
            rf"compression it falls short \*\*{N} %\*\* of the time \(mean \*\*{N} kN\*\*\), the paper's T11 pattern\. "
            rf"Force RMS {N} kN against a demand of {N} kN, tracking error RMS {N} kN, "
            rf"largest relative velocity {N} m/s, largest force {N} kN, force-spectrum peak \*\*{N} Hz\*\*\. "
            rf"With 5 ms extra latency: peak \*\*{N} Hz\*\*, error RMS {N} kN\."],
        "hil_force_peak_hz": [rf"\| 15 Hz \(wheel hop\) \| {N} Hz \|"],
        ("hil_extension_mean_kn", "hil_extension_above_pct"): [
            rf"\| Extending: force above the demand \| often \| {N} kN, {N} % \|"],
        ("hil_compression_mean_kn", "hil_compression_below_pct"): [
            rf"\| Contracting: force below the demand \| often \| {N} kN, {N} % \|"],
        ("hil_f_rms_kn", "hil_f_demand_rms_kn", "hil_error_rms_kn"): [
            rf"\| RMS force / demand, RMS error \| — \| {N} / {N} kN, {N} kN \|"],
    },
}
# The figures files whose figures a generated table or report of the docs gives as well: the file and
# the function that reads them from it.
GENERATED = {"ranking_accuracy": (doc_figures.RANKING_TXT, doc_figures.ranking_accuracy),
             "benefit_map": (benefit_map.DOCS_TABLE, benefit_map.headline),
             "full_truck": (full_truck.DOCS_TABLE, full_truck.headline)}


def documents() -> list[Path]:
    """The tracked documents (the journal is history, not reference) and the model descriptions."""
    names = subprocess.run(["git", "ls-files", "*.md", "modelDescription.xml", "crates/*/modelDescription.xml"],
                           cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    return [REPO / n for n in names if n != "JOURNAL.md"]


WORDS = {w: k for k, w in enumerate("zero one two three four five six seven eight nine ten eleven twelve".split())}


def agrees(quoted: str, value: float) -> bool:
    """`quoted` is `value` to the digits it has (either way at an exact half); a number word exactly."""
    if quoted.lower() in WORDS:
        return WORDS[quoted.lower()] == value
    number = quoted.replace("−", "-")
    mantissa, _, exponent = number.lower().partition("e")
    quantum = 10.0 ** (int(exponent or 0) - len(mantissa.partition(".")[2]))
    return abs(value - float(number)) <= quantum / 2 * (1 + 1e-9)


def names(key: str | tuple[str, ...]) -> tuple[str, ...]:
    return (key,) if isinstance(key, str) else key


def value(name: str, figures: dict[str, float]) -> float:
    if name.startswith("abs:"):
        return abs(figures[name[4:]])
    return -figures[name[1:]] if name.startswith("-") else figures[name]


def bare(name: str) -> str:
    """The figure a quote's name stands for."""
    return name.removeprefix("max:").removeprefix("abs:").lstrip("-")


def disagreements(text: str, sources: dict[str, dict[str, float]], where: str,
                  quotes: dict[str, dict[str | tuple[str, ...], list[str]]] = QUOTES
                  ) -> tuple[list[str], set[tuple[str, str]], set[str]]:
    """(each quote in one document's `text` that disagrees with its source, the (tool, figure)s
    quoted, the patterns that found a quote)."""
    flat = re.sub(r"\s+", " ", text)
    wrong, quoted, found = [], set(), set()
    for tool, table in quotes.items():
        figures = sources[tool]
        for key, patterns in table.items():
            for pattern in patterns:
                for match in re.finditer(pattern, flat):
                    found.add(pattern)
                    assert len(match.groups()) == len(names(key)), (pattern, key)
                    for group, group_names in zip(match.groups(), names(key), strict=True):
                        for name in group_names.split("|"):
                            quoted.add((tool, bare(name)))
                            if name.startswith("max:"):  # an upper bound: "to within 2 Hz"
                                if value(name[4:], figures) > float(group.replace("−", "-")):
                                    wrong.append(f"{where}: '{match.group(0)}' bounds {name[4:]} by {group}, "
                                                 f"docs/{tool}.json {value(name[4:], figures):g}")
                            elif not agrees(group, value(name, figures)):
                                wrong.append(f"{where}: '{match.group(0)}' says {group} for {name}, "
                                             f"docs/{tool}.json {value(name, figures):g}")
    return wrong, quoted, found


def sources() -> dict[str, dict[str, float]]:
    return {tool: doc_figures.read(tool) for tool in QUOTES}


def test_every_quote_of_a_measured_figure_agrees_with_its_figures_file():
    figures = sources()
    wrong, quoted, found = [], set(), set()
    for path in documents():
        w, q, f = disagreements(path.read_text(encoding="utf-8"), figures, str(path.relative_to(REPO)))
        wrong += w
        quoted |= q
        found |= f
    assert not wrong, "\n".join(wrong)
    patterns = {p for table in QUOTES.values() for ps in table.values() for p in ps}
    assert patterns <= found, "these quote patterns match nothing:\n" + "\n".join(sorted(patterns - found))
    # every figure is quoted somewhere and every quoted figure is in its file
    every = {(tool, name) for tool, f in figures.items() for name in f}
    assert quoted == every, (f"not quoted: {sorted(every - quoted)}", f"not in a file: {sorted(quoted - every)}")


def test_every_figures_file_says_how_it_was_measured():
    files = {p.stem for p in (REPO / "docs").glob("*.json")} - {"summary.schema"}
    assert files == set(QUOTES), "a docs/*.json with no quotes checked, or quotes of no file"
    for tool in QUOTES:
        data = json.loads(doc_figures.path(tool).read_text(encoding="utf-8"))
        missing = doc_figures.unproven(data)
        assert missing == [], f"docs/{tool}.json: no measured or command in {missing}"


def test_the_figures_of_a_generated_table_are_the_tables():
    for tool, (table, read) in GENERATED.items():
        derived, stored = read(table.read_text(encoding="utf-8")), doc_figures.read(tool)
        assert {name: stored.get(name) for name in derived} == derived, (
            f"docs/{tool}.json and {table.name} are not of the same run")


def test_a_quote_that_disagrees_is_named():
    figures = sources()
    b = figures["benchmark"]
    doc = f"It runs {b['realtime_default'] + 1:.0f}× real time at the default rtol 3e-4, p99 `fmi2DoStep` 9.9 µs."
    wrong, quoted, _ = disagreements(doc, figures, "doc.md")
    assert quoted == {("benchmark", "realtime_default"), ("benchmark", "p99_default_us")}
    assert len(wrong) == 2 and all(w.startswith("doc.md: ") for w in wrong), wrong


def test_digits_and_signs_of_a_quote():
    assert agrees("12", 11.5) and agrees("11", 11.5) and not agrees("12", 11.4)
    assert agrees("−0.30", -0.304) and not agrees("−0.30", 0.30) and agrees("+7", 6.6)
    assert agrees("4.02e-13", 4.0213e-13) and not agrees("4.02e-13", 4.0313e-13)
    assert agrees("six", 6) and not agrees("Six", 6.2)
    figures = {"t": {"a": 2.0, "b": -3.04}}
    quotes: dict[str, dict[str | tuple[str, ...], list[str]]] = {"t": {("a|b",): [rf"x {N}"], "-b": [rf"y {N}"],
                                                                       "max:a": [rf"within {N}"]}}
    wrong, quoted, _ = disagreements("x 2 y 3.0 within 3", figures, "d.md", quotes)
    assert quoted == {("t", "a"), ("t", "b")} and len(wrong) == 1 and "for b" in wrong[0], wrong
    wrong, _, _ = disagreements("within 1", figures, "d.md", quotes)
    assert len(wrong) == 1 and "bounds a by 1" in wrong[0], wrong


def test_a_figures_file_keeps_the_other_runs_sections(tmp_path, monkeypatch):
    monkeypatch.setattr(doc_figures, "DOCS", tmp_path)
    doc_figures.write("t", {"x": 1}, "cmd a", section="one")
    doc_figures.write("t", {"y": 2}, "cmd b")
    doc_figures.write("t", {"z": 3}, "cmd c", section="two")
    doc_figures.write("t", {"w": 4}, "cmd d")
    assert doc_figures.read("t") == {"w": 4.0, "one.x": 1.0, "two.z": 3.0}
    data = json.loads((tmp_path / "t.json").read_text())
    assert data["command"] == "cmd d" and data["one"]["command"] == "cmd a" and doc_figures.unproven(data) == []
    assert doc_figures.unproven({"x": 1.0}) == ["the file"]


# The tools that cannot be run here (tens of minutes each) write the figures of the documents: their
# headline functions, fed results shaped like the published runs', give the names of their files.

def section_names(tool: str, section: str | None = None) -> set[str]:
    figures = doc_figures.read(tool)
    if section is None:
        return {k for k in figures if "." not in k}
    return {k.removeprefix(section + ".") for k in figures if k.startswith(section + ".")}


def test_the_hil_rig_writes_the_quoted_figures():
    from damper_tools import hil_rig

    def metrics() -> dict[str, float]:
        return {"peak_Hz": 12.0, "prominence": 2.0, "ext_mean_error": 300.0, "ext_above": 0.6,
                "comp_mean_error": -300.0, "comp_below": 0.6}

    points = [hil_rig.SweepPoint(lat, fa, {"unstable": "F_demand"} if fa < 40 else metrics())
              for lat in hil_rig.SWEEP_LATENCIES for fa in hil_rig.SWEEP_BANDWIDTHS]
    force_path = [(d, metrics()) for d in hil_rig.SWEEP_LOAD_CELL_DELAYS]
    stats = {k: (1.0, 0.1, 0.5, 1.5) for k in ("peak_Hz", "prominence", "ext_mean_error", "ext_above",
                                              "comp_mean_error", "comp_below", "error_rms")}
    rows = [{"rig": label, "tare_load_cell": tare, "force_controller": fc, "seeds": [1, 2, 3, 4, 5], "pattern_count": 5,
             "paper_like_count": 3, "stats": stats} for label, _, tare, fc in hil_rig.robustness_cases()]
    assert set(hil_rig.headline(metrics(), points, force_path, rows)) == section_names("hil_rig")


def test_the_blind_score_writes_the_quoted_figures():
    from damper_tools import blind_score

    def case(cat: str, hidden: tuple[str, ...], passed: bool, verdict: str = "effect") -> dict[str, object]:
        named = [e for e in hidden if passed or e != "check_valve_cracking"]
        return {"category": cat, "hidden": list(hidden), "passed": passed, "verdict": verdict, "effects": named,
                "nrmse_baseline": 0.02, "nrmse_after": 0.01, "nrmse_floor": 0.005}

    effects = ["end_stops", *(f"e{k}" for k in range(10))]
    def passes(e: str, k: int) -> bool:  # end stops 2 of 6, every other effect 6 of 6
        return k < {"end_stops": 2}.get(e, 6)

    single = [case("single", (e,), passes(e, k), "effect" if passes(e, k) else
                   ("unexplained" if e == "end_stops" and k == 5 else "partial")) for e in effects for k in range(6)]
    transducer = (single + [case("pair", pair, True) for pair in blind_score.PAIRS for _ in range(3)]
                  + [case("clean", (), True, "none") for _ in range(40)]
                  + [case("foreign", (), True, "does_not_fit") for _ in range(8)])
    assert set(blind_score.headline(transducer, 477.0)) == section_names("blind_score", "transducer")
    clean = [case("clean", (), k > 0, "none" if k else "unexplained") for k in range(20)]
    assert set(blind_score.headline(clean, None)) == section_names("blind_score", "lvdt_clean")
    pairs = [case("pair", pair, pair == blind_score.PAIRS[2] or k < 3 + (pair == blind_score.PAIRS[0]))
             for pair in blind_score.PAIRS for k in range(7)]
    assert set(blind_score.headline(pairs, None)) == section_names("blind_score", "lvdt_pair")


def test_the_dyno_score_writes_the_quoted_figures():
    from damper_tools import dyno_score

    dampers = [(size, seed) for seed in (1, 2, 3) for size in ("small", "car", "truck")]

    def parameter(name: str, z: float, setting: str | None = None) -> dict[str, object]:
        return {"name": name, "setting": setting, "status": "fitted", "z": z, "relative_error": 0.01 * z}

    calibrations = {f"{size} {seed}": {"seconds": 60.0, "records": [{"after": 1.2, "floor": 1.0}] * 3,
                                       "parameters": [parameter("k_open_comp" if k == 0 else f"p{k}",
                                                                2.5 if (size, seed, k) == ("truck", 3, 1) else 1.0)
                                                      for k in range(14)]} for size, seed in dampers}
    settings = {f"{size} {seed}": {"seconds": 60.0, "records": [{"after": 1.2, "floor": 1.0}] * 3,
                                   "parameters": [parameter("A_bleed", 1.0, f"s{k}") for k in range(3)]}
                for size, seed in dampers}
    cases = []
    for size, seed in dampers:
        for sc in dyno_score.SCENARIOS:
            expected, parameter_name = dyno_score.EXPECTED.get(sc, ("rebound_valve", "G_bleed_reb"))
            missed = (sc, size, seed) == ("end_stop", "truck", 2)
            c = dyno_score.Case(size, seed, sc, "r.csv", {}, verdict="none" if sc == "unchanged" else
                                ("partial" if missed else "effect"), effects=[] if sc == "unchanged" else [expected],
                                nrmse_after=0.02, floor=0.01)
            if sc != "unchanged":
                c.expected, c.parameter, c.truth, c.std_error = expected, parameter_name, 1.0, 0.01
                c.fitted = 1.05 if (sc, size, seed) == ("heated", "truck", 3) else 1.001
            cases.append(c)
    assert set(dyno_score.headline(calibrations, cases, settings, 2100.0)) == section_names("dyno_score")


def test_the_campaign_and_the_benefit_maps_common_setting_write_the_quoted_figures():
    from damper_tools import campaign

    rows = [{"expected": "seal_friction" if k < 16 else "none", "right": True, "seconds": 7.0 + k % 12}
            for k in range(22)]
    assert set(campaign.headline(rows, 147.0)) == section_names("campaign")
    results = {"controller": [{"road": road, **benefit_map.COMMON_SETTING, "benefit": 0.08}
                              for road in ("minor", "major", "motorway", "belgian_block")]}
    assert set(benefit_map.common_setting(results)) | set(benefit_map.headline(benefit_map.DOCS_TABLE.read_text(
        encoding="utf-8"))) == section_names("benefit_map")


# lines as benches/realtime.rs, damper_tools.crosscheck and scripts/benchmark.sh print them
REPORT = """# Benchmark, 2026-12-01 on 2 cores: Some CPU
scenario: 10 s, v_rms 0.250 m/s, 1 ms steps; converged run (rtol 1e-9, h_max 5 us): F_rms 14.08 kN
| 1e-2 |  | 1050x | 0.95 | 3.4 | 33.0 | 8.7 | 1 | 48.6 | 0.345 % | 2.43 |
| 3e-3 |  | 1070x | 0.93 | 2.9 | 30.1 | 6.1 | 0 | 39.0 | 0.277 % | 1.95 |
| 1e-3 |  | 1080x | 0.93 | 2.6 | 27.5 | 5.6 | 0 | 30.1 | 0.214 % | 1.51 |
| 3e-4 | FMU default | 998x | 1.00 | 3.4 | 40.1 | 7.2 | 0 | 17.2 | 0.122 % | 0.86 |
| 1e-4 |  | 930x | 1.08 | 3.9 | 35.1 | 8.5 | 0 | 6.6 | 0.047 % | 0.33 |
| 5e-5 |  | 800x | 1.25 | 4.4 | 40.0 | 8.8 | 0 | 2.0 | 0.014 % | 0.10 |
| 3e-5 | diagnosis | 640x | 1.56 | 5.0 | 51.0 | 9.1 | 0 | 0.7 | 0.005 % | 0.04 |
| 1e-5 |  | 460x | 2.17 | 6.1 | 104.0 | 9.5 | 0 | 0.2 | 0.001 % | 0.01 |
Through the FMU's C API (in process; fmi2SetReal twice, fmi2DoStep, fmi2GetReal per step) at rtol 3e-4: 990x real \
time, 1.01 us per step against 0.97 us calling the damper directly; the same forces bit for bit: yes
| 3e-4 | 170x | 172x | 175x | 350x |
| 3e-5 | 110x | 111x | 112x | 148x |
| 3e-4 | 16.20 | 18.00 | 22.50 | 0.153 % | 1.13 |
| 3e-5 | 0.55 | 0.80 | 1.16 | 0.008 % | 0.06 |
| FMU faster by | | 760x |
| force difference FMU − Python | | RMS 1.29 N (0.011 % of the RMS force), max 14.1 N |
- wall time 1.5 s, verdict effect (mount_compliance), k1_mount=3.2519e+07
"""


def test_the_parser_reads_the_benchmarks_own_report():
    figures = benchmark_figures.parse_report(REPORT)
    assert {k: figures[k] for k in ("realtime_default", "p99_default_us", "rms_error_default_pct", "realtime_diagnosis",
                                    "realtime_c_api", "six_dampers_two_threads", "python_slower", "python_rms_diff_n",
                                    "python_max_diff_n", "diagnose_60s_s", "diagnose_60s_k1_mount")} == {
        "realtime_default": 998, "p99_default_us": 3.4, "rms_error_default_pct": 0.122, "realtime_diagnosis": 640,
        "realtime_c_api": 990, "six_dampers_two_threads": 350, "python_slower": 760, "python_rms_diff_n": 1.29,
        "python_max_diff_n": 14.1, "diagnose_60s_s": 1.5, "diagnose_60s_k1_mount": 3.2519e7}
    assert figures["rtol_1e-2_faults"] == 1 and figures["rtol_1e-5_worst_us"] == 104.0
    assert figures["rtol_3e-4_err_sigma"] == 0.86 and figures["rtol_3e-5_err_pct"] == 0.005
    assert figures["six_3e-5_two_threads"] == 148 and figures["seeds_3e-4_largest_pct"] == 0.153
    assert figures["c_api_step_us"] == 1.01 and figures["direct_step_us"] == 0.97
    assert figures["converged_f_rms_kn"] == 14.08
    # the rows the documents do not show are not read (3e-3, 5e-5)
    assert not any("3e-3" in k or "5e-5" in k for k in figures)
    # the file holds what the parser writes, and the sections of the hand measurements beside it
    assert set(figures) == {k for k in benchmark_figures.read() if "." not in k}


def test_a_report_without_a_figure_is_refused_by_name():
    try:
        benchmark_figures.parse_report(REPORT.replace("FMU faster by", "FMU quicker by"))
    except ValueError as e:
        assert "python_slower" in str(e)
    else:
        raise AssertionError("a report without the cross-check's ratio was accepted")


REFERENCE_OUTPUT = REPO / "tests" / "python" / "resources" / "slow_reference_output.txt"


def test_the_references_figures_are_what_its_recorded_output_gives():
    """docs/reference.json holds what damper_tools.reference_figures reads from the reference's output
    kept in the repository (the reference itself is not: its output is the record)."""
    figures = reference_figures.parse_output(REFERENCE_OUTPUT.read_text(encoding="utf-8"))
    assert figures == doc_figures.read("reference")
    # spot checks against the printed lines: a step's t90, a ratio turned into a percentage, the largest
    # overshoot of the five spool steps
    assert figures["steps_compression_12_22_t90_ms"] == 40.5
    assert figures["hil_extension_above_pct"] == 73.0 and figures["hil_compression_mean_kn"] == -0.63
    assert figures["spool_overshoot_max_pct"] == 1.7


def test_a_reference_output_without_a_line_or_with_two_values_is_refused_by_name():
    text = REFERENCE_OUTPUT.read_text(encoding="utf-8")
    for changed, name in ((text.replace("viscous c= 19.2", "viscous c= 19.3"), "viscous_wheel_hz"),
                          (text.replace("2.5->1.8 mm: dead time(2%)  4.0", "2.5->1.8 mm: dead time(2%)  4.5"),
                           "spool_dead_time_ms")):
        try:
            reference_figures.parse_output(changed)
        except ValueError as e:
            assert name in str(e)
        else:
            raise AssertionError(f"an output without a single {name} was accepted")
