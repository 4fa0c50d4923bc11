"""The headline speed figures of `bash scripts/benchmark.sh`, written once to docs/benchmark.json and
checked wherever a document quotes them (tests/python/test_benchmark_figures.py; damper_tools.doc_figures).

    .venv/bin/python -m damper_tools.benchmark_figures out/benchmark/benchmark.md [--docs]

reads the benchmark's report (its own tables and lines) and prints the figures as JSON; with
--docs it writes them to docs/benchmark.json, after which every document that quotes a figure must
agree with it (the test names each quote that does not). A busy hour of a shared machine gives
about half a quiet hour's speeds: write the figures of a quiet run.
"""

import argparse
import json
import re
import sys
from pathlib import Path

from damper_tools import doc_figures

FIGURES = doc_figures.path("benchmark")
COMMAND = ("bash scripts/benchmark.sh, in a quiet hour; then .venv/bin/python -m damper_tools.benchmark_figures "
           "out/benchmark/benchmark.md --docs")

# figure: (pattern of the report with one group, what it is); the report is cargo bench's tables,
# the cross-check's table and the diagnosis's lines (scripts/benchmark.sh)
REPORT_PATTERNS: dict[str, tuple[str, str]] = {
    "realtime_default": (r"\| 3e-4 \| FMU default \| (\d+)x \|", "real-time factor at the default rtol 3e-4"),
    "p99_default_us": (r"\| 3e-4 \| FMU default \| \d+x \| [\d.]+ \| ([\d.]+) \|", "p99 fmi2DoStep at 3e-4 (µs)"),
    "rms_error_default_pct": (r"\| 3e-4 \| FMU default \|(?: [^|]+ \|){6} [\d.]+ \| ([\d.]+) % \|",
                              "RMS force error at 3e-4 (% of the force's RMS)"),
    "realtime_diagnosis": (r"\| 3e-5 \| diagnosis \| (\d+)x \|", "real-time factor at the diagnosis's rtol 3e-5"),
    "realtime_c_api": (r"Through the FMU's C API [^:]*: (\d+)x real time", "real-time factor through the C API"),
    "six_dampers_two_threads": (r"\| 3e-4 \| \d+x \| \d+x \| \d+x \| (\d+)x \|", "six dampers on two threads, 3e-4"),
    "python_slower": (r"\| FMU faster by \| \| (\d+)x \|", "the plain-Python cross-check against the FMU"),
    "python_rms_diff_n": (r"\| force difference FMU − Python \| \| RMS ([\d.]+) N",
                          "the cross-check's RMS force difference at the FMU's default rtol (N)"),
    "python_max_diff_n": (r"\| force difference FMU − Python \| \| RMS [^|]*, max ([\d.]+) N \|",
                          "the cross-check's largest force difference (N)"),
    "diagnose_60s_s": (r"- wall time ([\d.]+) s, verdict", "diagnosis of a 60 s, 1 kHz record (s)"),
    "diagnose_60s_k1_mount": (r"- wall time [\d.]+ s, verdict effect \(mount_compliance\), k1_mount=([\d.e+-]+)",
                              "the mount stiffness the diagnosis fits on that record (N/m)"),
}


# cargo bench's tables (benches/realtime.rs), by rtol: a row's pattern, its columns, and the columns the
# documents quote of each row they show (the 3e-4 and 3e-5 rows' others are the figures above)
TABLES: dict[str, tuple[str, tuple[str, ...], dict[str, tuple[str, ...]]]] = {
    "rtol": (r"\| {rtol} \| [^|]* \| (\d+)x \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| (\d+) \| ([\d.]+) \| "
             r"([\d.]+) % \| ([\d.]+) \|",
             ("realtime", "mean_us", "p99_us", "worst_us", "replayed_us", "faults", "err_n", "err_pct", "err_sigma"),
             {**{r: ("realtime", "mean_us", "p99_us", "worst_us", "replayed_us", "faults", "err_n")
                 for r in ("1e-2", "1e-3", "1e-4", "1e-5")},
              "3e-4": ("mean_us", "worst_us", "replayed_us", "faults", "err_n", "err_sigma"),
              "3e-5": ("mean_us", "p99_us", "worst_us", "replayed_us", "faults", "err_n", "err_pct")}),
    "six": (r"\| {rtol} \| (\d+)x \| (\d+)x \| (\d+)x \| (\d+)x \|",
            ("alone", "one_by_one", "one_thread", "two_threads"),
            {"3e-4": ("one_by_one", "one_thread"), "3e-5": ("one_by_one", "one_thread", "two_threads")}),
    "seeds": (r"\| {rtol} \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) % \| ([\d.]+) \|",
              ("least_n", "median_n", "largest_n", "largest_pct", "largest_sigma"),
              {"3e-4": ("least_n", "largest_n", "largest_pct"), "3e-5": ("least_n", "largest_n", "largest_sigma")}),
}
LINES: dict[str, tuple[str, tuple[str, ...]]] = {
    "converged_f_rms_kn": (r"converged run \(rtol 1e-9, h_max 5 us\): F_rms ([\d.]+) kN", ()),
    "c_api": (r"Through the FMU's C API [^:]*: \d+x real time, ([\d.]+) us per step against ([\d.]+) us",
              ("c_api_step_us", "direct_step_us")),
}


def parse_report(text: str) -> dict[str, float]:
    """The figures of a benchmark report; a figure the report lacks is an error naming it."""
    figures: dict[str, float] = {}
    for name, (pattern, what) in REPORT_PATTERNS.items():
        found = re.search(pattern, text)
        if found is None:
            raise ValueError(f"the benchmark report has no {what} ({name}: /{pattern}/)")
        figures[name] = float(found.group(1))
    for table, (row, columns, quoted) in TABLES.items():
        for rtol, wanted in quoted.items():
            found = re.search(row.format(rtol=re.escape(rtol)), text)
            if found is None:
                raise ValueError(f"the benchmark report has no {table} row at rtol {rtol}")
            values = dict(zip(columns, found.groups(), strict=True))
            figures.update({f"{table}_{rtol}_{c}": float(values[c]) for c in wanted})
    for name, (pattern, names) in LINES.items():
        found = re.search(pattern, text)
        if found is None:
            raise ValueError(f"the benchmark report has no {name} line (/{pattern}/)")
        figures.update({n: float(v) for n, v in zip(names or (name,), found.groups(), strict=True)})
    return figures


def read(path: Path = FIGURES) -> dict[str, float]:
    """The figures written to docs/benchmark.json (numbers only: its provenance is left out)."""
    return doc_figures.flatten(json.loads(path.read_text(encoding="utf-8")))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report", type=Path, help="out/benchmark/benchmark.md")
    parser.add_argument("--docs", action="store_true", help=f"write the figures to {FIGURES}")
    args = parser.parse_args(argv)
    text = args.report.read_text(encoding="utf-8")
    measured = text.splitlines()[0].removeprefix("# Benchmark, ")
    figures = parse_report(text)
    if args.docs:
        doc_figures.write("benchmark", figures, COMMAND, measured=measured)
    sys.stdout.write(json.dumps({"measured": measured, "command": COMMAND, **figures}, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
