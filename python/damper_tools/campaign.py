"""Campaign diagnosis: `damper diagnose` on every record of a folder, one Dask task per record, one
table at the end.

    .venv/bin/damper-campaign diagnose RECORDS_DIR --out out/campaign [--truth TRUTH_DIR]
    .venv/bin/damper-campaign generate --out out/campaign_demo      # records with known effects

Each task gets the record's bytes and runs the `damper` program (shipped to the workers by a worker
plugin, like the sweep's FMUs: a worker needs no shared file system and no Rust) as

    damper -q --threads T diagnose RECORD --out DIR --load-cell-lowpass 400 [--tare-load-cell] [EXTRA...]

and returns summary.json and report.html, which the client writes to OUT/reports/<record>/. A record
that fails (unreadable, refused by the program, a crash) is a row with its error, never the end of
the campaign. The table, one row per record (record, status, verdict, effects named, fitted values
with their standard errors, NRMSE before/after the named effects and the floor, seconds, error), is
written as
OUT/campaign.csv, OUT/campaign.md and OUT/index.html (each record linked to its report). A record
whose row is in OUT/rows/ with the same bytes is not diagnosed again (resume).

With truth files (`damper generate --truth`, one <record>.json per record) each row also gets the
expected effects, their hidden values and whether the verdict is right (damper_tools.verdicts, the
rule damper-blind-score applies too): a hidden effect must be named with the verdict `effect`; a
clean record must get `none` with nothing named.

Nothing here prints; damper-campaign is the command.
"""

import argparse
import csv
import hashlib
import html
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

from distributed.diagnostics.plugin import WorkerPlugin

from damper_tools import DAMPER, REPO
from damper_tools.sweep import dask_client
from damper_tools.verdicts import right

PLUGIN_NAME = "damper-campaign-program"
OUT = REPO / "out" / "campaign"
COLUMNS = ("record", "status", "verdict", "effects", "best_effect", "fitted", "nrmse_baseline", "nrmse_after",
           "nrmse_floor", "reduction", "expected", "hidden", "right", "seconds", "error", "report")
# The effects damper generate hides in the demonstration set (the catalog of docs/effects.md).
DEMO_EFFECTS = ("seal_friction", "piston_leakage", "viscous_friction", "amplifier_delay", "check_valve_cracking",
                "compressibility", "mount_compliance", "flow_forces")


@dataclass
class Options:
    """How every record of the campaign is diagnosed."""
    load_cell_lowpass: float | None = 400.0
    tare_load_cell: bool = False
    threads: int = 1
    extra: list[str] = field(default_factory=list)
    timeout_s: float = 900.0

    def arguments(self) -> list[str]:
        args = ["--load-cell-lowpass", f"{self.load_cell_lowpass:g}"] if self.load_cell_lowpass else []
        return args + (["--tare-load-cell"] if self.tare_load_cell else []) + list(self.extra)


# --------------------------------------------------------------------------- one record

def diagnose_bytes(name: str, data: bytes, options: Options, damper: str | Path | None = None) -> dict[str, Any]:
    """Diagnoses one record given as bytes (on a worker the program comes from the worker plugin).
    Returns {record, status ('ok' or 'error'), error, exit_code, seconds, summary (dict or None),
    report_html (str or None), stderr}."""
    damper = Path(damper) if damper else worker_program()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="campaign_") as tmp:
        record = Path(tmp) / name
        record.write_bytes(data)
        out = Path(tmp) / "report"
        command = [str(damper), "-q", "--threads", str(options.threads), "diagnose", str(record), "--out", str(out),
                   *options.arguments()]
        try:
            proc = subprocess.run(command, capture_output=True, text=True, timeout=options.timeout_s)
            code, stderr = proc.returncode, (proc.stderr or proc.stdout or "").strip()
        except subprocess.TimeoutExpired:
            code, stderr = -1, f"timed out after {options.timeout_s:g} s"
        summary_path, report_path = out / "summary.json", out / "report.html"
        summary = json.loads(summary_path.read_text(encoding="utf-8")) if summary_path.is_file() else None
        report = report_path.read_text(encoding="utf-8") if report_path.is_file() else None
    ok = code == 0 and summary is not None
    error = "" if ok else (stderr.replace(str(record), name).splitlines() or [f"exit status {code}"])[-1][:400]
    return {"record": name, "status": "ok" if ok else "error", "error": error, "exit_code": code,
            "seconds": time.perf_counter() - start, "summary": summary, "report_html": report, "stderr": stderr[-2000:]}


def fitted_values(summary: dict[str, Any]) -> dict[str, dict[str, float | None]]:
    """The parameters of the named effects at their fitted values: the kept rungs of the ladder
    (a later rung's value of the same parameter wins)."""
    out: dict[str, dict[str, float | None]] = {}
    for rung in summary.get("ladder") or []:
        if rung.get("added") != "baseline" and rung.get("kept"):
            out.update(rung.get("params") or {})
    return out


def _fmt_fitted(fitted: dict[str, dict[str, float | None]]) -> str:
    parts = []
    for name, v in fitted.items():
        value, se = v.get("value"), v.get("std_error")
        if value is None:
            continue
        parts.append(f"{name}={value:.4g}" + (f"±{se:.2g}" if se is not None else ""))
    return "; ".join(parts)


def expected_effects(truth: dict[str, Any]) -> list[str]:
    """The hidden effects of a `damper generate` truth file."""
    return [e["key"] for e in truth.get("effects") or []]


def hidden_values(truth: dict[str, Any]) -> str:
    """The hidden effects' parameter values of a truth file, as the fitted column writes them."""
    return "; ".join(f"{k}={v:.4g}" for e in truth.get("effects") or [] for k, v in (e.get("params") or {}).items())


def judge(expected: list[str] | None, verdict: str | None, named: list[str]) -> bool | None:
    """Right or not (verdicts.right); None when there is no truth."""
    return None if expected is None else right(expected, verdict, named)


def row_of(result: dict[str, Any], truth: dict[str, Any] | None = None) -> dict[str, Any]:
    """The table's row of one diagnose result."""
    s = result.get("summary") or {}
    named = list(s.get("effects") or [])
    fitted = fitted_values(s) if s else {}
    base, after = s.get("nrmse_baseline"), s.get("nrmse_after_ladder")
    expected = expected_effects(truth) if truth is not None else None
    stem = Path(result["record"]).stem
    return {"record": result["record"], "status": result["status"], "verdict": s.get("verdict"),
            "effects": ";".join(named), "best_effect": s.get("best_effect"), "fitted": _fmt_fitted(fitted),
            "fitted_json": json.dumps(fitted), "nrmse_baseline": base, "nrmse_after": after,
            "nrmse_floor": s.get("nrmse_noise_floor"),
            "reduction": (1.0 - after / base) if base and after is not None else None,
            "expected": None if expected is None else (";".join(expected) or "none"),
            "hidden": None if truth is None else hidden_values(truth),
            "right": judge(expected, s.get("verdict") if s else "error", named) if result["status"] == "ok"
            else (None if expected is None else False),
            "seconds": round(result["seconds"], 2), "error": result["error"],
            "report": f"reports/{stem}/report.html" if result.get("report_html") else "",
            "sha256": result.get("sha256", "")}


# --------------------------------------------------------------------------- the program on the workers

class ShipProgram(WorkerPlugin):
    """Worker plugin carrying the `damper` program's bytes: written once, executable, under each
    worker's local directory (also on a worker started or restarted later)."""

    name = PLUGIN_NAME

    def __init__(self, program: str | Path) -> None:
        self.blob = Path(program).read_bytes()
        self.path: Path | None = None

    def setup(self, worker: Any) -> None:
        folder = Path(worker.local_directory) / "programs" / hashlib.sha256(self.blob).hexdigest()[:16]
        path = folder / "damper"
        if not path.is_file():
            folder.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=folder)
            with os.fdopen(fd, "wb") as f:
                f.write(self.blob)
            os.chmod(tmp, 0o755)
            os.replace(tmp, path)
        self.path = path


def worker_program() -> Path:
    from distributed import get_worker

    path = cast(ShipProgram, get_worker().plugins[PLUGIN_NAME]).path
    assert path is not None, "ShipProgram.setup has run on every worker"
    return path


# --------------------------------------------------------------------------- the campaign

def find_records(folder: str | Path) -> list[Path]:
    """The *.csv files of a folder and its subfolders, sorted."""
    return sorted(p for p in Path(folder).rglob("*.csv") if p.is_file())


def _row_file(out: Path, record: str) -> Path:
    return out / "rows" / f"{Path(record).stem}.json"


def _write(out: Path, result: dict[str, Any], row: dict[str, Any]) -> None:
    stem = Path(result["record"]).stem
    rep = out / "reports" / stem
    if result.get("summary") is not None or result.get("report_html"):
        rep.mkdir(parents=True, exist_ok=True)
        if result.get("summary") is not None:
            (rep / "summary.json").write_text(json.dumps(result["summary"], indent=1), encoding="utf-8")
        if result.get("report_html"):
            (rep / "report.html").write_text(result["report_html"], encoding="utf-8")
    path = _row_file(out, result["record"])
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(row), encoding="utf-8")


@dataclass
class Outcome:
    rows: list[dict[str, Any]]
    ran: int
    skipped: int
    wall_s: float


def run_campaign(records: Sequence[Path], out: str | Path, options: Options | None = None, client: Any = None,
                 damper: str | Path = DAMPER, truth_dir: str | Path | None = None,
                 on_row: Callable[[dict[str, Any]], object] | None = None, retries: int = 2) -> Outcome:
    """Diagnoses every record (serially here when client is None, else one Dask task each); writes
    the reports and one row file per record as they arrive; returns the rows in record order."""
    options = options or Options()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    names = [p.name for p in records]
    if len(set(Path(n).stem for n in names)) != len(names):
        raise ValueError("two records share a name; give the campaign one folder of uniquely named records")
    rows: dict[str, dict[str, Any]] = {}

    def truth_of(name: str) -> dict[str, Any] | None:
        if truth_dir is None:
            return None
        path = Path(truth_dir) / f"{Path(name).stem}.json"
        return json.loads(path.read_text(encoding="utf-8")) if path.is_file() else None

    todo = []
    for p in records:
        digest = hashlib.sha256(p.read_bytes()).hexdigest()
        row_path, summary_path = _row_file(out, p.name), out / "reports" / p.stem / "summary.json"
        if row_path.is_file() and summary_path.is_file():
            old = json.loads(row_path.read_text(encoding="utf-8"))
            if old.get("sha256") == digest and old["status"] == "ok":
                # diagnosed before: the row again from its summary (and today's truth files)
                result = {"record": p.name, "status": "ok", "error": "", "seconds": old["seconds"], "sha256": digest,
                          "summary": json.loads(summary_path.read_text(encoding="utf-8")),
                          "report_html": old.get("report")}
                rows[p.name] = row_of(result, truth_of(p.name))
                if on_row:
                    on_row(rows[p.name])
                continue
        todo.append((p, digest))
    skipped = len(rows)

    def accept(result: dict[str, Any], digest: str) -> None:
        result["sha256"] = digest
        row = row_of(result, truth_of(result["record"]))
        _write(out, result, row)
        rows[result["record"]] = row
        if on_row:
            on_row(row)

    if client is None:
        for p, digest in todo:
            accept(diagnose_bytes(p.name, p.read_bytes(), options, damper), digest)
    elif todo:
        from distributed import as_completed

        client.register_plugin(ShipProgram(damper), name=PLUGIN_NAME)
        digests = {}
        futures = []
        for p, digest in todo:
            fut = client.submit(diagnose_bytes, p.name, p.read_bytes(), options, key=f"diagnose-{digest[:20]}-{p.stem}",
                                retries=retries, pure=False)
            digests[fut.key] = digest
            futures.append(fut)
        for fut in as_completed(futures):
            accept(fut.result(), digests[fut.key])
            fut.release()
    ordered = [rows[n] for n in names]
    return Outcome(ordered, ran=len(todo), skipped=skipped, wall_s=time.perf_counter() - start)


# --------------------------------------------------------------------------- the table

def _cell(v: Any, column: str = "") -> str:
    if column == "seconds" and isinstance(v, float):
        return f"{v:.1f}"
    if v is None:
        return "–"
    if isinstance(v, bool):
        return "yes" if v else "NO"
    if isinstance(v, float):
        return "–" if math.isnan(v) else f"{v:.4f}"
    return str(v)


def write_csv(path: Path, rows: Sequence[dict[str, Any]]) -> Path:
    with path.open("w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=[*COLUMNS, "fitted_json"], extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in [*COLUMNS, "fitted_json"]})
    return path


def score(rows: Sequence[dict[str, Any]]) -> tuple[int, int]:
    """(right, judged): rows with a truth and whether their verdict is right."""
    judged = [r for r in rows if r.get("right") is not None]
    return sum(1 for r in judged if r["right"]), len(judged)


def markdown(rows: Sequence[dict[str, Any]]) -> str:
    cols = [c for c in COLUMNS if c != "report" and (c not in ("expected", "hidden", "right") or
                                                      any(r.get(c) is not None for r in rows))]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        lines.append("| " + " | ".join(_cell(r.get(c), c).replace("|", "/") for c in cols) + " |")
    right, judged = score(rows)
    failed = sum(1 for r in rows if r["status"] != "ok")
    tail = f"; right verdicts: {right} of {judged}" if judged else ""
    lines += ["", f"{len(rows)} records, {failed} failed{tail}"]
    return "\n".join(lines) + "\n"


def headline(rows: Sequence[dict[str, Any]], wall_s: float) -> dict[str, float]:
    """The figures the documents quote (docs/campaign.json): right verdicts of the records with a
    hidden effect, of the clean ones and of all, the wall time and the range of one record's."""
    out: dict[str, float] = {}
    out["right"], out["judged"] = score(rows)
    for name, sel in (("effect", [r for r in rows if r.get("expected") not in (None, "none")]),
                      ("clean", [r for r in rows if r.get("expected") == "none"])):
        out[f"{name}_right"], out[f"{name}_records"] = score(sel)
    seconds = [r["seconds"] for r in rows]
    out |= {"wall_s": wall_s, "record_s_min": min(seconds), "record_s_max": max(seconds)}
    return out


def write_index(path: Path, rows: Sequence[dict[str, Any]], title: str, note: str = "") -> Path:
    esc = html.escape
    cols = [c for c in COLUMNS if c != "report" and (c not in ("expected", "hidden", "right") or
                                                      any(r.get(c) is not None for r in rows))]
    right, judged = score(rows)
    failed = sum(1 for r in rows if r["status"] != "ok")
    out = [f"<!doctype html><html><head><meta charset='utf-8'><title>{esc(title)}</title><style>"
           "body{font-family:sans-serif;margin:1em}table{border-collapse:collapse;font-size:12px}"
           "td,th{border:1px solid #ccc;padding:2px 6px}tr.error{background:#fdd}tr.wrong{background:#fec}"
           "</style></head><body>", f"<h1>{esc(title)}</h1>",
           f"<p>{len(rows)} records, {failed} failed" + (f"; right verdicts: {right} of {judged}" if judged else "")
           + f". {esc(note)} Table: <a href='campaign.csv'>campaign.csv</a>, "
           "<a href='campaign.md'>campaign.md</a>.</p>",
           "<table><tr>" + "".join(f"<th>{esc(c)}</th>" for c in cols) + "<th>report</th></tr>"]
    for r in rows:
        cls = "error" if r["status"] != "ok" else ("wrong" if r.get("right") is False else "")
        cells = "".join(f"<td>{esc(_cell(r.get(c), c))}</td>" for c in cols)
        link = f"<a href='{esc(r['report'])}'>report</a>" if r.get("report") else "–"
        out.append(f"<tr class='{cls}'>{cells}<td>{link}</td></tr>")
    out.append("</table></body></html>")
    path.write_text("\n".join(out), encoding="utf-8")
    return path


def write_tables(out: Path, rows: Sequence[dict[str, Any]], title: str = "Campaign diagnosis", note: str = "") -> None:
    write_csv(out / "campaign.csv", rows)
    (out / "campaign.md").write_text(markdown(rows), encoding="utf-8")
    write_index(out / "index.html", rows, title, note)


# --------------------------------------------------------------------------- a demonstration set

@dataclass
class GenCase:
    name: str
    effects: tuple[str, ...]
    seed: int


def demo_cases(per_effect: int = 2, clean: int = 6, effects: Sequence[str] = DEMO_EFFECTS) -> list[GenCase]:
    """per_effect records for each effect hidden alone, then `clean` records with nothing hidden."""
    cases = [GenCase(f"{e}_s{s}", (e,), 100 + 10 * k + s) for k, e in enumerate(effects)
             for s in range(1, per_effect + 1)]
    cases += [GenCase(f"clean_s{s}", (), 500 + s) for s in range(1, clean + 1)]
    return cases


def generate(case: GenCase, records: Path, truths: Path, duration: float, damper: str | Path = DAMPER,
             extra: Sequence[str] = ()) -> Path:
    """`damper generate` of one case: records/<name>.csv, truths/<name>.json."""
    records.mkdir(parents=True, exist_ok=True)
    truths.mkdir(parents=True, exist_ok=True)
    rec, truth = records / f"{case.name}.csv", truths / f"{case.name}.json"
    command = [str(damper), "-q", "generate", "--out", str(rec), "--truth", str(truth), "--seed", str(case.seed),
               "--duration", f"{duration:g}", *[a for e in case.effects for a in ("--effect", e)], *extra]
    subprocess.run(command, check=True, capture_output=True, text=True)
    return rec


# --------------------------------------------------------------------------- the command

def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--damper", type=Path, default=DAMPER, help="the damper program (target/release/damper)")
    sub = parser.add_subparsers(dest="command", required=True)
    d = sub.add_parser("diagnose", help="diagnose every *.csv of a folder, one table")
    d.add_argument("records", type=Path, help="folder of records (*.csv, also in subfolders)")
    d.add_argument("--out", type=Path, default=OUT)
    d.add_argument("--truth", type=Path, default=None, help="folder of <record>.json truth files (damper generate)")
    d.add_argument("--load-cell-lowpass", type=float, default=400.0, help="Hz; 0: none")
    d.add_argument("--tare-load-cell", action="store_true")
    d.add_argument("--threads", type=int, default=1, help="threads of each diagnose (one task per worker core)")
    d.add_argument("--extra", action="append", default=[], help="one more argument for diagnose; repeatable")
    d.add_argument("--docs", action="store_true", help="write the headline figures to docs/campaign.json (the "
                   "demonstration set of `campaign generate`, with --truth)")
    g = sub.add_parser("generate", help="records with known hidden effects (damper generate, here: a few "
                       "hundredths of a second each), for a demonstration")
    g.add_argument("--out", type=Path, required=True, help="writes OUT/records/*.csv and OUT/truth/*.json")
    g.add_argument("--per-effect", type=int, default=2)
    g.add_argument("--clean", type=int, default=6)
    g.add_argument("--duration", type=float, default=4.0, help="s per record")
    where = d.add_mutually_exclusive_group()
    where.add_argument("--scheduler", default=None, help="address of a running scheduler")
    where.add_argument("--workers", type=int, default=None, help="LocalCluster workers (default: one per core)")
    where.add_argument("--serial", action="store_true", help="no Dask: one record after the other here")
    args = parser.parse_args(argv)
    if not args.damper.is_file():
        print(f"campaign: {args.damper}: no such program (cargo build --release -p damper_cli)", file=sys.stderr)
        return 2

    start = time.perf_counter()
    if args.command == "generate":
        cases = demo_cases(args.per_effect, args.clean)
        for c in cases:
            generate(c, args.out / "records", args.out / "truth", args.duration, args.damper)
        print(f"campaign: wrote {len(cases)} records to {args.out / 'records'} and their truth to "
              f"{args.out / 'truth'} in {time.perf_counter() - start:.1f} s")
        return 0

    records = find_records(args.records)
    if not records:
        print(f"campaign: no *.csv in {args.records}", file=sys.stderr)
        return 2
    from tqdm import tqdm

    options = Options(load_cell_lowpass=args.load_cell_lowpass or None, tare_load_cell=args.tare_load_cell,
                      threads=args.threads, extra=list(args.extra))
    bar = tqdm(total=len(records), unit="record", desc="diagnose")
    try:
        with dask_client(args.scheduler, args.workers, args.serial) as client:
            workers = f"{len(client.nthreads())} workers" if client else "serially"
            outcome = run_campaign(records, args.out, options, client, args.damper, args.truth,
                                   on_row=lambda _r: bar.update(1))
    except KeyboardInterrupt:
        print(f"campaign: interrupted; finished records are kept in {args.out / 'rows'}: run the same command "
              "again to resume", file=sys.stderr)
        return 130
    finally:
        bar.close()
    note = (f"{outcome.ran} diagnosed now, {outcome.skipped} from earlier runs; {workers}, "
            f"{outcome.wall_s:.0f} s.")
    write_tables(args.out, outcome.rows, f"Campaign diagnosis of {args.records}", note)
    if args.docs:
        from damper_tools import doc_figures

        if outcome.skipped or args.truth is None:
            raise SystemExit("campaign: --docs needs a fresh run (nothing resumed) with --truth")
        doc_figures.write("campaign", headline(outcome.rows, outcome.wall_s),
                          f"damper-campaign diagnose {args.records} --truth {args.truth} --docs ({workers})")
    print(markdown(outcome.rows))
    print(f"campaign: {note} Wrote {args.out / 'index.html'}, campaign.csv, campaign.md")
    return 0
