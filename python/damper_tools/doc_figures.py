"""The measured figures the documents quote, written once per measuring tool to docs/<tool>.json.

<tool> is the name of the command that measures them: `benchmark` (scripts/benchmark.sh, through
benchmark_figures), `paper_tests`, `valve_response`, `hil_scenarios`, `hil_rig`, `instances`,
`benefit_map`, `full_truck`, `blind_score`, `dyno_score`, `sweep` (damper-sweep) and `campaign`, each
written by its `--docs` option, and `ranking_accuracy` (the Rust example's output,
docs/ranking_accuracy.txt, read by `python -m damper_tools.doc_figures ranking_accuracy`). A file holds
"measured" (when and on what) and "command" (how to measure them again) beside the figures, numbers
in the unit their name ends in (_ms, _hz, _pct, _kn, _s, ...). A tool that measures in several runs
(blind_score: its chains; sweep: its worker counts) writes its run as a section, an object with its
own "measured" and "command", and keeps the other sections; a figure of a section is read as
"section.name".

tests/python/test_benchmark_figures.py checks every quote of a figure in every tracked document
against these files, to the digits quoted. The figures of a run that is not in the documents yet
make that test name them: update the quotes, or the run was not the one to publish.

    .venv/bin/python -m damper_tools.doc_figures ranking_accuracy   # docs/ranking_accuracy.txt -> .json
"""

import json
import math
import os
import platform
import re
import sys
from collections.abc import Mapping
from datetime import date
from pathlib import Path
from typing import Any

from damper_tools import REPO, jsonable

DOCS = REPO / "docs"


def path(tool: str) -> Path:
    return DOCS / f"{tool}.json"


def machine() -> str:
    """Today and this machine, as a figure's "measured"."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8").splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{date.today().isoformat()} on {os.cpu_count()} cores: {cpu}"


def write(tool: str, figures: Mapping[str, float], command: str, *, section: str | None = None,
          measured: str | None = None) -> Path:
    """Write one run's figures to docs/<tool>.json with their provenance (`measured`: default today
    and this machine): the file's own figures, or with `section` that section's; the file's other
    sections are kept."""
    entry: dict[str, Any] = {"measured": measured or machine(), "command": command}
    entry.update(jsonable({k: float(v) for k, v in figures.items()}))
    target = path(tool)
    old: dict[str, Any] = json.loads(target.read_text(encoding="utf-8")) if target.is_file() else {}
    if section is None:  # this run's figures replace the file's own; its sections (other runs) stay
        data = {**entry, **{k: v for k, v in old.items() if isinstance(v, Mapping) and k not in entry}}
    else:
        data = {**old, section: entry}
    target.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    return target


def flatten(data: Mapping[str, Any], prefix: str = "") -> dict[str, float]:
    """The numbers of a figures file, a section's as "section.name" (the provenance strings left out)."""
    out: dict[str, float] = {}
    for key, value in data.items():
        if isinstance(value, Mapping):
            out.update(flatten(value, f"{prefix}{key}."))
        elif isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value):
            out[prefix + key] = float(value)
    return out


def read(tool: str) -> dict[str, float]:
    """The figures of docs/<tool>.json."""
    return flatten(json.loads(path(tool).read_text(encoding="utf-8")))


def unproven(data: Mapping[str, Any], where: str = "") -> list[str]:
    """The parts of a figures file holding numbers without a "measured" and a "command" string."""
    missing = []
    numbers = any(isinstance(v, int | float) and not isinstance(v, bool) for v in data.values())
    if numbers and not all(isinstance(data.get(k), str) and data[k] for k in ("measured", "command")):
        missing.append(where or "the file")
    for key, value in data.items():
        if isinstance(value, Mapping):
            missing += unproven(value, f"{where}{key}.")
    return missing


def table_rows(text: str) -> list[list[list[str]]]:
    """The Markdown tables of `text`, each as its rows of cells (the header and the rule left out)."""
    tables: list[list[list[str]]] = []
    current: list[list[str]] = []
    for line in [*text.splitlines(), ""]:
        if line.startswith("|"):
            current.append([cell.strip() for cell in line.strip().strip("|").split("|")])
        elif current:
            tables.append(current[2:])
            current = []
    return tables


def numbers(cell: str) -> list[float]:
    """The numbers of a table cell, in order (∞ as infinity)."""
    return [math.inf if x == "∞" else float(x) for x in re.findall(r"[-+]?\d+(?:\.\d+)?|∞", cell)]


def span(out: dict[str, float], name: str, values: list[float]) -> None:
    """`name`_min and `name`_max of `values` into `out`."""
    out[f"{name}_min"], out[f"{name}_max"] = min(values), max(values)


# ----------------------------------------------------------------------- ranking accuracy (Rust example)

RANKING_TXT = DOCS / "ranking_accuracy.txt"
RANKING_COMMAND = ("cargo run --release -p damper_engine --features study --example ranking_accuracy"
                   " | tee docs/ranking_accuracy.txt; .venv/bin/python -m damper_tools.doc_figures ranking_accuracy")
_PCT = r"([\d.]+)"
# effect: (unit suffix, scale from SI) of its fitted parameter in docs/diagnose.md's table
SEED_TABLE_UNITS = {"amplifier_delay": ("_ms", 1e3), "check_valve_cracking": ("_bar", 1e-5)}


def ranking_accuracy(text: str) -> dict[str, float]:
    """The headline figures of the example's report (docs/ranking_accuracy.txt): each group's summary
    counts, the per-effect halving counts of the weakest effects, their baseline/floor ranges, the
    fitted values of seeds 1 and 2 (docs/diagnose.md's table), the pairs' counts and the run."""
    figures: dict[str, float] = {}

    def count(names: str, pattern: str, block: str) -> None:
        found = re.search(pattern, block)
        if found is None:
            raise ValueError(f"docs/ranking_accuracy.txt: no /{pattern}/ for {names}")
        for key, value in zip(names.split(","), found.groups(), strict=True):
            figures[key] = float(value)

    blocks = dict(re.findall(r"== (\w+): \d+ runs ==\n(.*?)(?=\n== |\Z)", text, re.S))
    rows = {group: re.findall(r"^(\w+) +(\d+) \w+ \(\w+\) +\d+ +[\d.]+ +[\d.]+ +[\d.]+ +([\d.]+) +(\d+)% +\w+ +"
                              r"\w+=([\d.e+-]+)/([\d.e+-]+)", blocks[group], re.M) for group in ("rig", "hil")}
    for group in ("rig", "hil"):
        block = blocks[group]
        count(f"{group}_ranked_first,{group}_runs", r"ranked first: (\d+) of (\d+)", block)
        count(f"{group}_named", r"verdict effect naming it: (\d+) of", block)
        count(f"{group}_fit20,{group}_median_err_pct,{group}_worst_err_pct",
              r"fitted within 20 %: (\d+) of \d+ \(median error ([\d.]+) %, worst ([\d.]+) %\)", block)
        count(f"{group}_halved,{group}_halving_runs", r"halving where baseline ≥ 2× floor: (\d+) of (\d+)", block)
        count(f"{group}_at_floor", r"at the floor: (\d+) of", block)
        for effect in ("flow_forces", "viscous_friction") if group == "rig" else ("flow_forces",):
            count(f"{group}_{effect}_halved,{group}_{effect}_halving_runs",
                  rf"\n  {effect} +\S+ +\S+ +\S+ +\S+ +(\d+)/(\d+)", block)
    leakage = [float(r[2]) for r in rows["hil"] if r[0] == "piston_leakage"]
    flow = [float(r[2]) for group in ("rig", "hil") for r in rows[group] if r[0] == "flow_forces"]
    figures.update(hil_piston_leakage_bf_min=min(leakage), hil_piston_leakage_bf_max=max(leakage),
                   flow_forces_bf_min=min(flow), flow_forces_bf_max=max(flow))
    for effect, seed, _, cut, fitted, truth in rows["rig"]:  # seeds 1 and 2 in docs/diagnose.md's units
        if seed in ("1", "2"):
            unit, scale = SEED_TABLE_UNITS.get(effect, ("", 1.0))
            figures[f"rig_{effect}_seed{seed}_fitted{unit}"] = scale * float(fitted)
            figures[f"rig_{effect}_seed{seed}_truth{unit}"] = scale * float(truth)
            figures[f"rig_{effect}_seed{seed}_cut_pct"] = float(cut)
    pairs = blocks["pairs"]
    count("pairs_both_found,pairs_runs", r"both found: (\d+) of (\d+)", pairs)
    count("pairs_effect", r"verdict effect: (\d+) of", pairs)
    count("pairs_fit20,pairs_sizes", r"fitted within 20 %: (\d+) of (\d+)", pairs)
    count("pairs_at_floor", r"at the floor \(ladder\): (\d+) of", pairs)
    ladders = re.findall(r"^(\w+\+\w+) +\d+ \w+ +([\w+]+) .*?(<-- FAIL)?$", pairs, re.M)
    figures["pairs_amplifier_delay_mount_passed"] = sum(
        1 for pair, _, fail in ladders if pair == "amplifier_delay+mount_compliance" and not fail)
    figures["pairs_third_effect_passed"] = sum(1 for _, ladder, fail in ladders if ladder.count("+") > 1 and not fail)
    count("none_total,none_runs", r"verdict none: (\d+) of (\d+)", blocks["none"])
    count("none_rig", r"rig: verdict none: (\d+) of", blocks["none"])
    count("none_hil", r"hil: verdict none: (\d+) of", blocks["none"])
    count("drift_unexplained,drift_runs", r"unexplained: (\d+) of (\d+)", blocks["drift"])
    count("total_runs,total_min", r"total: (\d+) runs in \d+ s \(([\d.]+) min\)", text)
    return figures


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if args != ["ranking_accuracy"]:
        sys.stderr.write(__doc__ or "")
        return 2
    text = RANKING_TXT.read_text(encoding="utf-8")
    write("ranking_accuracy", ranking_accuracy(text), RANKING_COMMAND,
          measured=f"{text.splitlines()[0]} (docs/ranking_accuracy.txt)")
    print(f"wrote {path('ranking_accuracy')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
