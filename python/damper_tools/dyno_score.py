"""The real-damper loop scored on independent passive-damper records (damper_tools.dyno).

    .venv/bin/python -m damper_tools.dyno_score --sizes small car truck --seeds 1 2 3 --out out/dyno_score

For each damper (a size and a seed) it does what a user with a dyno does: writes the datasheet
description and the records (damper_tools.dyno: an independent model, logger-like measurement
chains), calibrates on the calibration records from the datasheet (`damper calibrate --damper`),
then diagnoses each other record with the calibrated parameters (`damper diagnose --damper
--params`): a record of the unchanged damper, and one each with the gas pre-charge changed, an
adjuster (bleed area) changed, the oil heated by 30-50 K (with a temperature column), the stroke
reaching the bump rubbers, which the datasheet does not describe, and the oil saturated with the
reservoir's gas, which it lets out below the pre-charge. Then it calibrates a campaign over
three settings of one bleed adjuster in one calibration (`--per-setting`, the records grouped by
`--setting` as a test log book names them): the adjuster's value per setting, the rest shared.

Scoring (the truth files are read only here, never by `damper`):
- calibration: each record's NRMSE after calibration against its noise floor; each fitted
  parameter's error against the truth, in relative terms and in its reported standard
  uncertainties (z);
- unchanged: nothing named (verdict `none`);
- a change: the verdict names the effect that carries it first (gas_charge, rebound_valve or
  compression_valve, oil_temperature, end_stops, gas_release), and its size parameter: its relative error and
  z against the truth, in the uncertainty the diagnosis reports with the calibration's carried in
  (`--calibration`) (for the heated oil the viscosity coefficient, which the truth did not
  change: the change's size is the measured temperature).

Writes OUT/dyno_score.md (tables) and OUT/dyno_score.json (every case); with --docs the headline
figures the documents quote to docs/dyno_score.json (damper_tools.doc_figures).
"""

import argparse
import json
import subprocess
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from damper_tools import DAMPER, REPO, doc_figures, dyno
from damper_tools.verdicts import right

SCENARIOS = ("unchanged", "gas", "valve", "heated", "end_stop", "gas_release")
# the effect that carries each change, and its size parameter (None: the change's parameter)
EXPECTED = {"gas": ("gas_charge", "p_reservoir0"), "heated": ("oil_temperature", "visc_temp_coeff"),
            "end_stop": ("end_stops", "k_end_stop"), "gas_release": ("gas_release", "gas_solubility")}


@dataclass
class Case:
    size: str
    seed: int
    scenario: str
    record: str
    change: dict[str, Any]
    verdict: str = ""
    effects: list[str] = field(default_factory=list)
    expected: str | None = None
    parameter: str | None = None
    fitted: float | None = None
    std_error: float | None = None
    truth: float | None = None
    nrmse_baseline: float = 0.0
    nrmse_after: float = 0.0
    floor: float = 0.0
    seconds: float = 0.0

    @property
    def named(self) -> bool:
        """Right (verdicts.right): nothing named for the unchanged damper, else the effect that
        carries the change named first."""
        if self.scenario == "unchanged":
            return right((), self.verdict, self.effects)
        if self.expected is None:
            return False
        return right((self.expected,), self.verdict, self.effects, first=True)

    @property
    def relative_error(self) -> float | None:
        if self.fitted is None or not self.truth:
            return None
        return (self.fitted - self.truth) / self.truth

    @property
    def z(self) -> float | None:
        if self.fitted is None or self.truth is None or not self.std_error:
            return None
        return (self.fitted - self.truth) / self.std_error


def run(damper: Path, args: list[str]) -> float:
    """Runs the `damper` program with `args`; returns the seconds it took."""
    t0 = time.perf_counter()
    done = subprocess.run([str(damper), *args, "-q"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"damper {' '.join(args)}: {done.stderr}")
    return time.perf_counter() - t0


def calibrate(damper: Path, records: list[Path], sheet: Path, out: Path, threads: int,
              extra: tuple[str, ...] = ()) -> dict[str, Any]:
    """`damper calibrate` on `records` (with `extra` arguments), each parameter scored against the
    truth of a record it applies to (a setting's own value against that setting's)."""
    seconds = run(damper, ["calibrate", *map(str, records), "--damper", str(sheet), "--out", str(out),
                   "--threads", str(threads), *extra])
    c = json.loads((out / "calibration.json").read_text())
    truths = {Path(r).name: json.loads(r.with_suffix(".json").read_text())["truth_parameters"] for r in records}
    setting_truth = {r["setting"]: truths[Path(r["path"]).name] for r in c["records"]}
    params = []
    for p in c["parameters"]:
        truth = setting_truth[p["setting"]] if p.get("setting") else truths[records[0].name]
        t, u = truth.get(p["name"]), p["std_uncertainty"]
        params.append({"name": p["name"], "setting": p.get("setting"), "value": p["value"], "std_uncertainty": u,
                       "truth": t, "status": p["status"], "relative_error": (p["value"] - t) / t if t else None,
                       "z": (p["value"] - t) / u if (u and t is not None) else None})
    fits = [{"record": Path(r["path"]).name, "after": r["nrmse_after"], "floor": r["noise_floor"]}
            for r in c["records"]]
    return {"seconds": seconds, "parameters": params, "records": fits}


def expected(scenario: str, change: dict[str, Any]) -> tuple[str | None, str | None]:
    if scenario == "valve":
        name = change["parameter"]
        return ("rebound_valve" if name.endswith("_reb") else "compression_valve"), name
    return EXPECTED.get(scenario, (None, None))


def diagnose(damper: Path, size: str, seed: int, scenario: str, record: Path, sheet: Path, params: Path,
             out: Path, threads: int) -> Case:
    truth_file = json.loads(record.with_suffix(".json").read_text())
    change = truth_file["change"]
    seconds = run(damper, ["diagnose", str(record), "--damper", str(sheet), "--params", str(params), "--out", str(out),
                   "--calibration", str(params.with_name("calibration.json")), "--threads", str(threads)])
    s = json.loads((out / "summary.json").read_text())
    case = Case(size, seed, scenario, record.name, change, verdict=s["verdict"], effects=s.get("effects") or [],
                nrmse_baseline=s["nrmse_baseline"], nrmse_after=s.get("nrmse_after_ladder") or s["nrmse_baseline"],
                floor=s["nrmse_noise_floor"], seconds=seconds)
    case.expected, case.parameter = expected(scenario, change)
    if case.parameter:
        case.truth = truth_file["truth_parameters"].get(case.parameter)
        for c in s["candidates"]:
            if c["effect"] == case.expected and case.parameter in c["params"]:
                case.fitted = c["params"][case.parameter]["value"]
                case.std_error = c["params"][case.parameter]["std_error"]
                break
    return case


def settings_arguments(records: list[Path]) -> tuple[str, ...]:
    """The calibration's --per-setting and --setting arguments for the settings scenario's records,
    from what a test log book says: which adjuster was turned and the setting of each record."""
    changes = [json.loads(r.with_suffix(".json").read_text())["change"] for r in records]
    by_setting: dict[str, list[str]] = {}
    for r, ch in zip(records, changes, strict=True):
        by_setting.setdefault(ch["setting"], []).append(str(r))
    return ("--per-setting", changes[0]["parameter"],
            *(a for label, paths in by_setting.items() for a in ("--setting", f"{label}={','.join(paths)}")))


def one_damper(damper: Path, size: str, seed: int, out: Path,
               threads: int) -> tuple[dict[str, Any], list[Case], dict[str, Any]]:
    records = out / "records"
    made = {sc: dyno.make_records(size, seed, sc, records) for sc in ("calibration", "settings", *SCENARIOS)}
    sheet = records / f"{size}_{seed}_datasheet.toml"
    cal_dir = out / "calibrate" / f"{size}_{seed}"
    cal = calibrate(damper, made["calibration"], sheet, cal_dir, threads)
    cases = [diagnose(damper, size, seed, sc, made[sc][0], sheet, cal_dir / "parameters.ssv",
                      out / "diagnose" / f"{size}_{seed}_{sc}", threads) for sc in SCENARIOS]
    settings = calibrate(damper, made["settings"], sheet, out / "calibrate" / f"{size}_{seed}_settings", threads,
                         settings_arguments(made["settings"]))
    return cal, cases, settings


def fmt(x: float | None, spec: str) -> str:
    return "–" if x is None else format(x, spec)


def settings_table(settings: dict[str, Any]) -> list[str]:
    """The several-settings calibrations: each setting's adjuster value against the truth."""
    lines = ["", "## Several settings of one adjuster in one calibration", "",
             "| damper | adjuster | setting: fitted / truth (rel. error, z) | shared: |z| > 2 | |z| > 3 | "
             "records: NRMSE after / floor | time |", "|---|---|---|---|---|---|---|"]
    for key, cal in settings.items():
        own = [p for p in cal["parameters"] if p["setting"]]
        shared = [p for p in cal["parameters"] if not p["setting"] and p["status"] == "fitted" and p["z"] is not None]
        cells = "; ".join(f"{p['setting']} {p['value']:.4g} / {p['truth']:.4g} "
                          f"({100 * p['relative_error']:+.1f} %, {fmt(p['z'], '+.1f')})" for p in own)
        ratios = ", ".join(f"{r['after'] / r['floor']:.2f}" for r in cal["records"])
        lines.append(f"| {key} | {own[0]['name']} | {cells} | {sum(abs(p['z']) > 2 for p in shared)} of "
                     f"{len(shared)} | {sum(abs(p['z']) > 3 for p in shared)} | {ratios} | {cal['seconds']:.1f} s |")
    own = [p for cal in settings.values() for p in cal["parameters"] if p["setting"]]
    lines += ["", f"Adjuster values: {sum(abs(p['relative_error']) <= 0.1 for p in own)} of {len(own)} within 10 %, "
                  f"{sum(p['z'] is not None and abs(p['z']) <= 3 for p in own)} of {len(own)} within 3 reported σ."]
    return lines


def report(calibrations: dict[str, Any], cases: list[Case], settings: dict[str, Any] | None = None) -> str:
    lines = ["# The real-damper loop on independent passive-damper records", "",
             "`.venv/bin/python -m damper_tools.dyno_score` (damper_tools.dyno's records; docs/real-dampers.md).", "",
             "## Calibration from the datasheet", "",
             "| damper | records: NRMSE after / noise floor | parameters: largest relative error | |z| > 2 | |z| > 3 | "
             "time |", "|---|---|---|---|---|---|"]
    for key, cal in calibrations.items():
        ratios = ", ".join(f"{r['after'] / r['floor']:.2f}" for r in cal["records"])
        fitted = [p for p in cal["parameters"] if p["status"] == "fitted" and p["z"] is not None]
        worst = max(fitted, key=lambda p: abs(p["relative_error"]))
        lines.append(f"| {key} | {ratios} | {worst['name']} {100 * worst['relative_error']:+.1f} % | "
                     f"{sum(abs(p['z']) > 2 for p in fitted)} of {len(fitted)} | "
                     f"{sum(abs(p['z']) > 3 for p in fitted)} | {cal['seconds']:.1f} s |")
    lines += ["", "## Diagnosis of each record with the calibrated parameters", "",
              "| damper | record | change | verdict | named | expected | size: fitted / truth | rel. error | z | "
              "NRMSE after / floor | time |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in cases:
        size = (f"{c.parameter} {fmt(c.fitted, '.4g')} / {fmt(c.truth, '.4g')}" if c.parameter else "–")
        rel = fmt(None if c.relative_error is None else 100 * c.relative_error, "+.1f")
        lines.append(f"| {c.size} {c.seed} | {c.scenario} | {c.change.get('what', '')} | {c.verdict} | "
                     f"{', '.join(c.effects) or '–'} | {c.expected or 'nothing'} | {size} | {rel} % | "
                     f"{fmt(c.z, '+.1f')} | {c.nrmse_after / c.floor:.2f} | {c.seconds:.1f} s |")
    lines += ["", "## Summary", ""]
    for sc in SCENARIOS:
        these = [c for c in cases if c.scenario == sc]
        ok = sum(c.named for c in these)
        line = f"- **{sc}**: {ok} of {len(these)} {'nothing named' if sc == 'unchanged' else 'named'}"
        sized = [c for c in these if c.named and c.relative_error is not None]
        if sized:
            within = sum(abs(c.relative_error) <= 0.1 for c in sized if c.relative_error is not None)
            line += (f"; size within 10 %: {within} of {len(sized)}, "
                     f"|z| ≤ 3: {sum(c.z is not None and abs(c.z) <= 3 for c in sized)} of {len(sized)}")
        lines.append(line)
    changed = [c for c in cases if c.scenario != "unchanged"]
    lines.append(f"- **all changes**: {sum(c.named for c in changed)} of {len(changed)} named")
    if settings:
        lines += settings_table(settings)
    return "\n".join(lines) + "\n"


def headline(calibrations: dict[str, Any], cases: list[Case], settings: dict[str, Any],
             wall_s: float) -> dict[str, float]:
    """The figures the documents quote (docs/dyno_score.json): per scenario the records named and, of
    the named changes, the sizes within 10 % and within 3 reported sigma; the settings campaigns' adjuster
    values; the calibrated records against their floors and the calibrated parameters against the truth
    (the damper with the most beyond 2 sigma; `k_open_comp` on the small dampers); the named changes
    beyond 3 sigma and the changes not named (<scenario>_<damper>_...); the program's and the wall time."""
    out: dict[str, float] = {}
    for sc in SCENARIOS:
        these = [c for c in cases if c.scenario == sc]
        out[f"{sc}_named"], out[f"{sc}_cases"] = sum(c.named for c in these), len(these)
        sized = [c for c in these if c.named and c.relative_error is not None]
        if sc != "unchanged":
            out[f"{sc}_sized"] = len(sized)
            out[f"{sc}_within_10pct"] = sum(abs(c.relative_error or 0) <= 0.1 for c in sized)
            out[f"{sc}_within_3sigma"] = sum(c.z is not None and abs(c.z) <= 3 for c in sized)
        for c in these:
            tag = f"{sc}_{c.size}_{c.seed}"
            if c.named and c.z is not None and abs(c.z) > 3:
                out[f"{tag}_z"], out[f"{tag}_rel_err_pct"] = c.z, 100 * (c.relative_error or 0)
            if sc != "unchanged" and not c.named:
                out[f"{tag}_floor_ratio"] = c.nrmse_after / c.floor
                if c.relative_error is not None:
                    out[f"{tag}_rel_err_pct"] = 100 * c.relative_error
    own = [p for cal in settings.values() for p in cal["parameters"] if p["setting"]]
    out["settings_values"] = len(own)
    out["settings_within_10pct"] = sum(abs(p["relative_error"]) <= 0.1 for p in own)
    out["settings_within_3sigma"] = sum(p["z"] is not None and abs(p["z"]) <= 3 for p in own)
    ratios = [r["after"] / r["floor"] for cal in calibrations.values() for r in cal["records"]]
    doc_figures.span(out, "calibration_floor_ratio", ratios)
    ratios = sorted(r["after"] / r["floor"] for cal in settings.values() for r in cal["records"])
    out["settings_floor_ratio_min"], out["settings_floor_ratio_max"] = ratios[0], ratios[-1]
    out["settings_floor_ratio_second"] = ratios[-2]
    fitted = {key: [p for p in cal["parameters"] if p["status"] == "fitted" and p["z"] is not None]
              for key, cal in calibrations.items()}
    every = [p for ps in fitted.values() for p in ps]
    out["calibrated_parameters"] = len(every)
    out["calibrated_within_3sigma"] = sum(abs(p["z"]) <= 3 for p in every)
    out["calibrated_within_2sigma"] = sum(abs(p["z"]) <= 2 for p in every)
    out["calibrated_beyond_2sigma"] = sum(abs(p["z"]) > 2 for p in every)
    worst = max(fitted, key=lambda k: sum(abs(p["z"]) > 2 for p in fitted[k]))
    out[f"calibration_{worst.replace(' ', '_')}_beyond_2sigma"] = sum(abs(p["z"]) > 2 for p in fitted[worst])
    out[f"calibration_{worst.replace(' ', '_')}_fitted"] = len(fitted[worst])
    small = [p for key, ps in fitted.items() if key.startswith("small") for p in ps if p["name"] == "k_open_comp"]
    if small:
        doc_figures.span(out, "small_k_open_comp_abs_err_pct", [100 * abs(p["relative_error"]) for p in small])
        out["small_k_open_comp_abs_z_max"] = max(abs(p["z"]) for p in small)
    program = (sum(c["seconds"] for c in calibrations.values()) + sum(c.seconds for c in cases)
               + sum(c["seconds"] for c in settings.values()))
    out["program_min"], out["wall_min"] = program / 60, wall_s / 60
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", nargs="+", default=list(dyno.SIZES), choices=dyno.SIZES)
    ap.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", type=Path, default=REPO / "out" / "dyno_score")
    ap.add_argument("--damper", type=Path, default=DAMPER, help="the damper program (default: the release build)")
    ap.add_argument("--docs", action="store_true", help="write the headline figures to docs/dyno_score.json "
                    "(every size, seeds 1 2 3 only)")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    a.out.mkdir(parents=True, exist_ok=True)
    calibrations: dict[str, Any] = {}
    settings: dict[str, Any] = {}
    cases: list[Case] = []
    for seed in a.seeds:
        for size in a.sizes:
            cal, these, settings[f"{size} {seed}"] = one_damper(a.damper, size, seed, a.out, a.threads)
            calibrations[f"{size} {seed}"] = cal
            cases += these
            print(f"{size} {seed}: " + ", ".join(f"{c.scenario} {'ok' if c.named else 'MISSED'}" for c in these),
                  flush=True)
    (a.out / "dyno_score.md").write_text(report(calibrations, cases, settings), encoding="utf-8")
    (a.out / "dyno_score.json").write_text(json.dumps(
        {"calibrations": calibrations, "settings": settings,
         "cases": [asdict(c) | {"named": c.named} for c in cases]}, indent=1), encoding="utf-8")
    if a.docs:
        if a.sizes != list(dyno.SIZES) or a.seeds != [1, 2, 3]:
            raise SystemExit("dyno_score: --docs needs every size and seeds 1 2 3 (the documents quote those)")
        doc_figures.write("dyno_score", headline(calibrations, cases, settings, time.perf_counter() - t0),
                          ".venv/bin/python -m damper_tools.dyno_score --seeds 1 2 3 --docs")
    print(report(calibrations, cases, settings))


if __name__ == "__main__":
    main()
