"""The headline speed figures of `bash scripts/benchmark.sh`, written once to docs/benchmark.json and
checked wherever a document quotes them (tests/python/test_docs.py).

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

from damper_tools import REPO

FIGURES = REPO / "docs" / "benchmark.json"

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
    "diagnose_60s_s": (r"- wall time ([\d.]+) s, verdict", "diagnosis of a 60 s, 1 kHz record (s)"),
}


def parse_report(text: str) -> dict[str, float]:
    """The figures of a benchmark report; a figure the report lacks is an error naming it."""
    figures: dict[str, float] = {}
    for name, (pattern, what) in REPORT_PATTERNS.items():
        found = re.search(pattern, text)
        if found is None:
            raise ValueError(f"the benchmark report has no {what} ({name}: /{pattern}/)")
        figures[name] = float(found.group(1))
    return figures


def read(path: Path = FIGURES) -> dict[str, float]:
    """The figures written to docs/benchmark.json (numbers only: its notes are left out)."""
    data = json.loads(path.read_text(encoding="utf-8"))
    return {k: float(v) for k, v in data.items() if isinstance(v, int | float)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report", type=Path, help="out/benchmark/benchmark.md")
    parser.add_argument("--docs", action="store_true", help=f"write the figures to {FIGURES}")
    args = parser.parse_args(argv)
    text = args.report.read_text(encoding="utf-8")
    figures: dict[str, object] = {"measured": text.splitlines()[0].removeprefix("# Benchmark, ")}
    figures.update(parse_report(text))
    out = json.dumps(figures, indent=2) + "\n"
    if args.docs:
        FIGURES.write_text(out, encoding="utf-8")
    sys.stdout.write(out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
