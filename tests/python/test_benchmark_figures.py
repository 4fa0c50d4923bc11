"""The headline speed figures live in one place, docs/benchmark.json (written by
`damper_tools.benchmark_figures` from a run of scripts/benchmark.sh); every document that quotes one
agrees with it to the digits it quotes, and the parser reads the benchmark's own report lines."""

import re
import subprocess
from pathlib import Path

from damper_tools import benchmark_figures

REPO = Path(__file__).resolve().parents[2]

# figure: the ways the documents quote it (on text whose whitespace runs are single spaces), each
# with one group, the number
QUOTES: dict[str, list[str]] = {
    "realtime_default": [r"(\d+)× real time at the default rtol", r"\*\*(\d+)× real time\*\* at the default",
                         r"\| \*\*FMU default\*\* \| \*\*(\d+)×\*\*", r"\((\d+)× in `cargo bench`"],
    "realtime_c_api": [r"(\d+)× through the FMU's C API", r"\*\*Through the FMU's C API\*\* \([^)]*\): \*\*(\d+)×\*\*",
                       r"(\d+)× through the C API"],
    "realtime_diagnosis": [r"(\d+)× at the diagnosis's rtol", r"\| \*\*diagnosis\*\* \| \*\*(\d+)×\*\*",
                           r"\(0\.\d+ %\) at (\d+)×", r"tolerance, at (\d+)×", r"(\d+)× at 3e-5 \("],
    "six_dampers_two_threads": [r"(\d+)× on two threads"],
    "python_slower": [r"(\d+)× slower than the FMU"],
    "diagnose_60s_s": [r"record diagnosed in ([\d.]+) s"],
    "rms_error_default_pct": [r"\((\d\.\d+) % RMS force error", r"RMS force error of (\d\.\d+) %",
                              r"= \*\*(\d\.\d+) %\*\*", r"at (\d\.\d+) % RMS force error",
                              r"\| \*\*FMU default\*\* \|(?: [^|]+ \|){6} \*\*[\d.]+ \((\d\.\d+) %\)\*\* \|"],
    "p99_default_us": [r"p99 `fmi2DoStep` ([\d.]+) µs", r"p99 ([\d.]+) µs, worst",
                       r"p99 ≤ 10 µs at the default: ([\d.]+) µs",
                       r"\| \*\*FMU default\*\* \| \*\*\d+×\*\* \| [\d.]+ \| ([\d.]+) \|"],
}


def documents() -> list[Path]:
    """The tracked documents (the journal is history, not reference) and the model description."""
    names = subprocess.run(["git", "ls-files", "*.md", "modelDescription.xml", "crates/*/modelDescription.xml"],
                           cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    return [REPO / n for n in names if n != "JOURNAL.md"]


def disagreements(text: str, figures: dict[str, float], where: str) -> tuple[list[str], set[str]]:
    """(each quote that disagrees with `figures`, the figures quoted) in one document's `text`."""
    flat = re.sub(r"\s+", " ", text)
    wrong, quoted = [], set()
    for name, patterns in QUOTES.items():
        for pattern in patterns:
            for found in re.finditer(pattern, flat):
                quoted.add(name)
                number = found.group(1)
                digits = len(number.split(".")[1]) if "." in number else 0
                if round(figures[name], digits) != float(number):
                    wrong.append(f"{where}: '{found.group(0)}' says {number}, docs/benchmark.json {figures[name]:g}")
    return wrong, quoted


def test_every_quote_of_a_headline_figure_agrees_with_docs_benchmark_json():
    figures = benchmark_figures.read()
    wrong, quoted = [], set()
    for path in documents():
        w, q = disagreements(path.read_text(encoding="utf-8"), figures, str(path.relative_to(REPO)))
        wrong += w
        quoted |= q
    assert not wrong, "\n".join(wrong)
    # every figure is quoted somewhere: a pattern that matches nothing any more checks nothing
    assert quoted == set(QUOTES) == set(figures), (set(QUOTES) - quoted, set(figures) ^ set(QUOTES))


def test_a_quote_that_disagrees_is_named():
    figures = benchmark_figures.read()
    doc = f"It runs {figures['realtime_default'] + 1:.0f}× real time at the default rtol 3e-4, p99 `fmi2DoStep` 9.9 µs."
    wrong, quoted = disagreements(doc, figures, "doc.md")
    assert quoted == {"realtime_default", "p99_default_us"}
    assert len(wrong) == 2 and all(w.startswith("doc.md: ") for w in wrong), wrong


# lines as benches/realtime.rs, damper_tools.crosscheck and scripts/benchmark.sh print them
REPORT = """# Benchmark, 2026-12-01 on 2 cores: Some CPU
| 3e-4 | FMU default | 998x | 1.00 | 3.4 | 40.1 | 7.2 | 0 | 17.2 | 0.122 % | 0.86 |
| 3e-5 | diagnosis | 640x | 1.56 | 5.0 | 51.0 | 9.1 | 0 | 0.7 | 0.005 % | 0.04 |
Through the FMU's C API (in process; two fmi2SetReal a step) at rtol 3e-4: 990x real time, 1.01 us per step
| 3e-4 | 170x | 172x | 175x | 350x |
| FMU faster by | | 760x |
- wall time 1.5 s, verdict effect (mount_compliance), k1_mount=1e8
"""


def test_the_parser_reads_the_benchmarks_own_report():
    figures = benchmark_figures.parse_report(REPORT)
    assert figures == {"realtime_default": 998, "p99_default_us": 3.4, "rms_error_default_pct": 0.122,
                       "realtime_diagnosis": 640, "realtime_c_api": 990, "six_dampers_two_threads": 350,
                       "python_slower": 760, "diagnose_60s_s": 1.5}


def test_a_report_without_a_figure_is_refused_by_name():
    try:
        benchmark_figures.parse_report(REPORT.replace("FMU faster by", "FMU quicker by"))
    except ValueError as e:
        assert "python_slower" in str(e)
    else:
        raise AssertionError("a report without the cross-check's ratio was accepted")
