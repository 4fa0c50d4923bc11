"""Blind score of `damper diagnose` on records it did not make (damper_tools.independent, .foreign).

    .venv/bin/damper-blind-score --quick            # 7 cases, about 1-2 min on 2 cores
    .venv/bin/damper-blind-score --jobs 1 --out out/blind

Builds a case set (every catalog effect alone on rig and HiL inputs at several seeds, pairs of
effects, clean records, foreign dampers), writes each record and its truth, runs
`damper diagnose REC --out DIR --load-cell-lowpass 400 [--tare-load-cell]` on it (the truth is never
passed), reads DIR/summary.json and scores:

- single effect: the verdict is `effect` and the effect is in `effects`;
- pair: both effects are in `effects` (verdict `effect`);
- clean: the verdict is `none` (nothing named; `partial`, `unexplained`, `does_not_fit` fail);
- foreign: fails only when the verdict is `effect` while the validation NRMSE after the named
  effects is above 2x the noise floor (an effect "explained" that does not explain the record).

The first three are damper_tools.verdicts.right, which the campaign's table applies too. Verdicts
other than `effect` and `none` (`partial`, `does_not_fit`, `unexplained`) count as not `effect`. Writes
OUT/blind_score.md (the table) and OUT/blind_score.json (every case: truth, verdict, effects,
NRMSE baseline / after / floor, times); with --docs the headline figures the documents quote to
docs/blind_score.json, in the section of the run's chain and --only (damper_tools.doc_figures).
"""

import argparse
import json
import platform
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict
from datetime import date
from pathlib import Path
from typing import Any

from damper_tools import DAMPER, DAMPER_FMU, REPO, TRUCK_FMU
from damper_tools import independent as ind
from damper_tools.verdicts import Verdict, right

PAIRS = (("seal_friction", "check_valve_cracking"), ("piston_leakage", "check_valve_cracking"),
         ("seal_friction", "amplifier_delay"))
FOREIGN_FACTOR = 2.0  # a foreign damper's named effect must bring the NRMSE within this times the floor


def category(case: ind.Case) -> str:
    if case.kind.startswith("foreign"):
        return "foreign"
    return {0: "clean", 1: "single", 2: "pair"}[min(len(case.effects), 2)]


def cases(quick: bool = False, seeds: int = 3, clean_seeds: int = 20, foreign_seeds: int = 4,
          motion: str = "continuous", chain: str = "transducer") -> list[ind.Case]:
    """The case set. Sample rates cycle through 500, 1000 and 2000 Hz, formats through ms/mm/s/kN and SI.
    With the LVDT chain (the velocity differentiated by the logger), rig records only."""
    def case(kind: str, seed: int, effects: Sequence[str] = (), k: int = 0) -> ind.Case:
        rate = ind.RATES[(seed + k) % len(ind.RATES)]
        fmt = "ms" if (seed + k) % 2 else "si"
        return ind.Case(kind, seed, tuple(effects), rate, fmt=fmt, motion=motion, chain=chain)

    if chain != "transducer":
        return [c for c in cases(quick, seeds, clean_seeds, 0, motion) if c.kind == "rig"
                for c in [ind.Case(c.kind, c.seed, c.effects, c.rate, fmt=c.fmt, motion=motion, chain=chain)]]

    if quick:
        return [case("rig", 1), case("hil", 1), case("rig", 1, ("seal_friction",)),
                case("hil", 2, ("amplifier_delay",)), case("rig", 2, PAIRS[1]),
                case("foreign_mr", 1), case("foreign_passive", 1)]
    cat = {key: e for key, e in ind.catalog().items() if e.hideable}
    out: list[ind.Case] = []
    for k, key in enumerate(cat):
        for seed in range(1, seeds + 1):
            out += [case("rig", seed, (key,), k), case("hil", seed, (key,), k)]
    for pair in PAIRS:
        out += [case("rig", seed, pair) for seed in range(1, seeds + 1)]
    for seed in range(1, clean_seeds + 1):
        out += [case("rig", seed), case("hil", seed)]
    for seed in range(1, foreign_seeds + 1):
        out += [case("foreign_mr", seed), case("foreign_passive", seed)]
    return out


def diagnose(damper: Path, record: Path, out: Path, tared: bool,
             threads: int) -> tuple[dict[str, Any] | None, str, float]:
    command = [str(damper), "--threads", str(threads), "-q", "diagnose", str(record), "--out", str(out),
               "--load-cell-lowpass", "400"] + (["--tare-load-cell"] if tared else [])
    start = time.perf_counter()
    proc = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    summary_path = out / "summary.json"
    if proc.returncode != 0 or not summary_path.is_file():
        return None, (proc.stderr or proc.stdout).strip()[-500:], seconds
    return json.loads(summary_path.read_text(encoding="utf-8")), "", seconds


def score(case: ind.Case, summary: dict[str, Any] | None) -> tuple[bool, str]:
    """(passed, why) for one case from its summary.json."""
    if summary is None:
        return False, "diagnose failed"
    verdict = summary.get("verdict")
    named = summary.get("effects") or []
    cat = category(case)
    if cat in ("single", "pair"):
        missing = [e for e in case.effects if e not in named]
        ok = right(case.effects, verdict, named)
        return ok, "" if ok else (f"verdict {verdict}" if verdict != Verdict.EFFECT else f"missed {', '.join(missing)}")
    if cat == "clean":
        ok = right((), verdict, named)
        return ok, "" if ok else f"verdict {verdict}" + (f" ({', '.join(named)})" if named else "")
    after, floor = summary.get("nrmse_after_ladder"), summary.get("nrmse_noise_floor")
    if verdict == Verdict.EFFECT and after is not None and floor and after > FOREIGN_FACTOR * floor:
        return False, f"effect named with NRMSE {after / floor:.1f}x the floor"
    return True, ""


def run_case(case: ind.Case, out: Path, damper: Path, threads: int, damper_fmu: Path,
             truck_fmu: Path) -> dict[str, Any]:
    record, truth_path = out / "records" / f"{case.name}.csv", out / "truth" / f"{case.name}.json"
    start = time.perf_counter()
    truth = ind.make(case, record, truth_path, damper_fmu, truck_fmu)
    gen_s = time.perf_counter() - start
    summary, error, diag_s = diagnose(damper, record, out / "diagnose" / case.name, case.tared, threads)
    passed, why = score(case, summary)
    row = {"case": case.name, "category": category(case), "kind": case.kind, "seed": case.seed,
           "rate_hz": case.rate, "format": case.fmt, "motion": case.motion, "hidden": list(case.effects),
           "hidden_values": {k: v["value"] for k, v in truth["hidden_effects"].items()},
           "truth": str(truth_path.relative_to(out)), "passed": passed, "why": why, "error": error,
           "generate_s": round(gen_s, 2), "diagnose_s": round(diag_s, 2)}
    if summary is not None:
        row.update(verdict=summary.get("verdict"), effects=summary.get("effects") or [],
                   nrmse_baseline=summary.get("nrmse_baseline"), nrmse_after=summary.get("nrmse_after_ladder"),
                   nrmse_floor=summary.get("nrmse_noise_floor"))
    return row


def _num(x: float | None) -> str:
    return "–" if x is None else f"{x:.4f}"


def table(rows: list[dict[str, Any]]) -> str:
    lines = ["| case | truth | verdict | effects named | NRMSE baseline | after | floor | pass | diagnose [s] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        truth = ", ".join(f"{k}={v:.3g}" for k, v in r["hidden_values"].items()) or (
            r["kind"] if r["category"] == "foreign" else "nothing hidden")
        named = ", ".join(r.get("effects", [])) or "–"
        lines.append(f"| {r['case']} | {truth} | {r.get('verdict', 'error')} | {named} "
                     f"| {_num(r.get('nrmse_baseline'))} | {_num(r.get('nrmse_after'))} | {_num(r.get('nrmse_floor'))} "
                     f"| {'yes' if r['passed'] else 'NO ' + r['why']} | {r['diagnose_s']:.1f} |")
    lines += ["", "| category | passed |", "|---|---|"]
    for cat in ("single", "pair", "clean", "foreign"):
        sel = [r for r in rows if r["category"] == cat]
        if sel:
            lines.append(f"| {cat} | {sum(r['passed'] for r in sel)} of {len(sel)} |")
    return "\n".join(lines) + "\n"


def headline(rows: list[dict[str, Any]], wall_s: float | None) -> dict[str, float]:
    """The figures the documents quote of one run (docs/blind_score.json, a section per chain and
    --only): each category's passed and cases; the foreign dampers' `does_not_fit`; the failures as
    docs/blind-score.md tells them (each single effect that failed: its passed and cases, its failures
    by verdict, how far above the floor its `partial`s ended; the clean failures by verdict and their
    baseline against the floor; the pairs' failures, the effect most of them missed, the pairs that
    all passed); the wall time of the whole set."""
    out: dict[str, float] = {"cases": len(rows)} | ({} if wall_s is None else {"wall_s": wall_s})
    by = {cat: [r for r in rows if r["category"] == cat] for cat in ("single", "pair", "clean", "foreign")}
    for cat, sel in by.items():
        if sel:
            out[f"{cat}_passed"], out[f"{cat}_cases"] = sum(r["passed"] for r in sel), len(sel)
    if by["foreign"]:
        out["foreign_does_not_fit"] = sum(r.get("verdict") == Verdict.DOES_NOT_FIT for r in by["foreign"])

    def ratio(r: dict[str, Any], key: str) -> float:
        return float(r[key] / r["nrmse_floor"])

    for effect in sorted({r["hidden"][0] for r in by["single"] if not r["passed"]}):
        these = [r for r in by["single"] if r["hidden"][0] == effect]
        out[f"single_{effect}_passed"], out[f"single_{effect}_cases"] = sum(r["passed"] for r in these), len(these)
        for verdict in sorted({r.get("verdict", "error") for r in these if not r["passed"]}):
            failed = [r for r in these if not r["passed"] and r.get("verdict", "error") == verdict]
            out[f"single_{effect}_{verdict}"] = len(failed)
            if verdict == Verdict.PARTIAL:
                ratios = [ratio(r, "nrmse_after") for r in failed]
                out[f"single_{effect}_partial_floor_ratio_min"] = min(ratios)
                out[f"single_{effect}_partial_floor_ratio_max"] = max(ratios)
    clean_failed = [r for r in by["clean"] if not r["passed"]]
    for verdict in sorted({r.get("verdict", "error") for r in clean_failed}):
        out[f"clean_{verdict}"] = sum(r.get("verdict", "error") == verdict for r in clean_failed)
    if clean_failed and all(r.get("nrmse_floor") for r in clean_failed):
        ratios = [ratio(r, "nrmse_baseline") for r in clean_failed]
        out["clean_failed_floor_ratio_min"], out["clean_failed_floor_ratio_max"] = min(ratios), max(ratios)
    pair_failed = [r for r in by["pair"] if not r["passed"]]
    if pair_failed:
        out["pair_failures"] = len(pair_failed)
        missed = Counter(e for r in pair_failed for e in r["hidden"] if e not in r.get("effects", []))
        effect, count = missed.most_common(1)[0]
        out[f"pair_failures_missing_{effect}"] = count
        for pair in PAIRS:
            these = [r for r in by["pair"] if tuple(r["hidden"]) == pair]
            if these and all(r["passed"] for r in these):
                out[f"pair_{'+'.join(pair)}_passed"], out[f"pair_{'+'.join(pair)}_cases"] = len(these), len(these)
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--damper", type=Path, default=DAMPER,
                        help="the damper program (default target/release/damper)")
    parser.add_argument("--damper-fmu", type=Path, default=DAMPER_FMU)
    parser.add_argument("--truck-fmu", type=Path, default=TRUCK_FMU)
    parser.add_argument("--out", type=Path, default=REPO / "out" / "blind")
    parser.add_argument("--quick", action="store_true", help="7 cases: clean rig and HiL, one effect on each, "
                        "an overlapping pair, both foreign dampers")
    parser.add_argument("--seeds", type=int, default=3, help="seeds per single effect and pair")
    parser.add_argument("--clean-seeds", type=int, default=20)
    parser.add_argument("--foreign-seeds", type=int, default=4)
    parser.add_argument("--motion", choices=ind.MOTIONS, default="continuous",
                        help="how the truth moves between samples (see damper_tools.independent)")
    parser.add_argument("--chain", choices=ind.CHAINS, default="transducer",
                        help="lvdt: rig records whose velocity the logger differentiates from the displacement")
    parser.add_argument("--only", choices=("single", "pair", "clean", "foreign"), default=None)
    parser.add_argument("--jobs", type=int, default=1, help="cases at once (each diagnose uses --threads)")
    parser.add_argument("--threads", type=int, default=2, help="threads of each diagnose")
    parser.add_argument("--docs", action="store_true", help="write the headline figures to docs/blind_score.json, "
                        "as the section of this chain and --only")
    args = parser.parse_args(argv)

    todo = cases(args.quick, args.seeds, args.clean_seeds, args.foreign_seeds, args.motion, args.chain)
    if args.only:
        todo = [c for c in todo if category(c) == args.only]
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(run_case, c, args.out, args.damper, args.threads, args.damper_fmu, args.truck_fmu)
                   for c in todo]
        rows = []
        for f in futures:
            rows.append(f.result())
            r = rows[-1]
            print(f"{r['case']:55s} {r.get('verdict', 'error'):12s} {','.join(r.get('effects', [])) or '-':40s} "
                  f"{'pass' if r['passed'] else 'FAIL ' + r['why']}", flush=True)
    wall = time.perf_counter() - start
    md = table(rows)
    head = (f"Blind score, {date.today().isoformat()}, {platform.node()} ({platform.machine()}), "
            f"{len(rows)} cases, motion {args.motion}, chain {args.chain}, jobs {args.jobs} x threads {args.threads}, "
            f"wall time {wall:.0f} s\n\n")
    (args.out / "blind_score.md").write_text(head + md, encoding="utf-8")
    (args.out / "blind_score.json").write_text(json.dumps(
        {"date": date.today().isoformat(), "wall_s": round(wall, 1), "args": {k: str(v) for k, v in vars(args).items()},
         "cases": rows, "case_specs": [asdict(c) for c in todo]}, indent=1) + "\n", encoding="utf-8")
    if args.docs:
        from damper_tools import doc_figures

        if args.quick:
            raise SystemExit("blind_score: --docs needs the whole set, not --quick")
        section = args.chain + (f"_{args.only}" if args.only else "")
        command = "damper-blind-score " + " ".join(a for a in (argv if argv is not None else sys.argv[1:]))
        doc_figures.write("blind_score", headline(rows, None if args.only or args.chain != "transducer" else wall),
                          command, section=section)
    print("\n" + head + md)
    print(f"wrote {args.out / 'blind_score.md'} and {args.out / 'blind_score.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
