//! How well `damper diagnose` ranks, names and fits a missing effect, measured over many seeds
//! (the CI tests in `tests/diagnose.rs` use two).
//!
//! ```sh
//! cargo run --release -p damper_engine --features study --example ranking_accuracy -- \
//!     [--seeds N] [--out FILE.json] [--only rig|hil|pairs|none|drift[,...]] [--hil-seconds S]
//! ```
//!
//! Groups (data from `damper_engine::generate`, written to a scratch directory, diagnosed with
//! `diagnose_measurement`, load-cell low-pass 400 Hz, 2 threads, one diagnosis after another):
//!
//! - `rig`: every catalog effect hidden alone (at a random plausible value, absent from the model or
//!   moved away from its default), rig inputs in force control, 5 s, seeds 1..=N (default 10);
//! - `hil`: the same with HiL inputs (quarter truck on a minor road, 14 m/s), `--hil-seconds`
//!   (default 10 s, the generator's default: the first second is the road's fade-in), compared with
//!   `tare_load_cell` on since the HiL load cell is tared;
//! - `pairs`: six pairs of a force-path and a valve/hydraulic effect hidden at once, rig, seeds
//!   1..=N/2;
//! - `none`: nothing hidden, rig and HiL, seeds 1..=N;
//! - `drift`: an effect outside the catalog, a load-cell drift of +600 N linear over the record
//!   (as in `an_effect_outside_the_catalog_is_unexplained`), rig, seeds 1..=N.
//!
//! Per run: the verdict, the best effect, the ladder's effects, the rank of each true effect among
//! the candidates, the validation NRMSE of the baseline, of the true effect's candidate (pairs: of
//! the ladder) and the estimated noise floor, the reduction, whether the residual reached the floor
//! (≤ 1.3× floor), the fitted size parameter against the truth, and the wall time.

use damper_engine::comparison::CompareOptions;
use damper_engine::diagnose_measurement::diagnose_measurement;
use damper_engine::generate::{self, GenerateOptions, Generated, InputStyle};
use damper_engine::missing_effect::Diagnosis;
use damper_engine::parameters::{effect, get_real};
use damper_engine::summary::to_json;
use damper_engine::verdict::Verdict;
use indexmap::IndexMap;
use serde::Serialize;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Threads per diagnosis (the machine has two cores).
const THREADS: usize = 2;
/// "At the noise floor": within this factor of the floor estimated from the residual.
const AT_FLOOR: f64 = 1.3;
/// The issue's floors: the NRMSE cut by at least half (where the baseline is ≥ 2× the floor) and
/// the parameter within 20 % of the truth.
const MIN_CUT: f64 = 0.5;
const ROOM_FOR_HALVING: f64 = 2.0;
const PARAM_TOLERANCE: f64 = 0.2;
/// Record lengths (s).
const RIG_SECONDS: f64 = 5.0;
const DEFAULT_HIL_SECONDS: f64 = 10.0;
/// The out-of-catalog load-cell drift over the record (N).
const DRIFT_N: f64 = 600.0;
/// Pairs hidden at once: a force-path effect with a valve/hydraulic one.
const PAIRS: [(&str, &str); 6] = [
    ("seal_friction", "amplifier_delay"),
    ("piston_leakage", "compressibility"),
    ("check_valve_cracking", "flow_forces"),
    ("viscous_friction", "mount_compliance"),
    ("seal_friction", "compressibility"),
    ("amplifier_delay", "mount_compliance"),
];
const GROUPS: [&str; 5] = ["rig", "hil", "pairs", "none", "drift"];

/// How well `damper diagnose` ranks, names and fits a missing effect, over many seeds
#[derive(clap::Parser)]
struct Options {
    /// Seeds 1..=N per effect and group (pairs: 1..=N/2)
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..))]
    seeds: u64,
    /// Write every run's record to this JSON file
    #[arg(long, value_name = "FILE.json")]
    out: Option<PathBuf>,
    /// Run only these groups [default: all]
    #[arg(long, value_name = "GROUP,...", value_delimiter = ',', value_parser = clap::builder::PossibleValuesParser::new(GROUPS))]
    only: Vec<String>,
    /// Length of the HiL records (s)
    #[arg(long, value_name = "S", default_value_t = DEFAULT_HIL_SECONDS)]
    hil_seconds: f64,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Kind {
    Single,
    Pair,
    Nothing,
    Drift,
}

#[derive(Clone, Debug)]
struct Case {
    group: &'static str,
    kind: Kind,
    input: InputStyle,
    hidden: Vec<&'static str>,
    seed: u64,
    duration: f64,
}

impl Case {
    fn input_name(&self) -> &'static str {
        match self.input {
            InputStyle::Rig => "rig",
            InputStyle::Hil => "hil",
        }
    }
    fn label(&self) -> String {
        match self.kind {
            Kind::Drift => "load-cell drift".into(),
            Kind::Nothing => "nothing".into(),
            _ => self.hidden.join("+"),
        }
    }
}

/// A hidden effect's size parameter: fitted against the truth.
#[derive(Clone, Debug)]
struct FitCheck {
    effect: &'static str,
    param: &'static str,
    truth: f64,
    fitted: Option<f64>,
    /// Where the fitted value comes from: "candidate", "ladder", "ladder refit", or
    /// "candidate (not kept)" for a pair's effect the ladder did not keep.
    source: &'static str,
}

impl FitCheck {
    fn error(&self) -> Option<f64> {
        self.fitted.map(|f| (f - self.truth).abs() / self.truth.abs())
    }
    fn ok(&self) -> bool {
        self.error().is_some_and(|e| e <= PARAM_TOLERANCE) && !self.source.contains("not kept")
    }
}

/// One diagnosed record.
struct Record {
    case: Case,
    error: Option<String>,
    /// None when the run failed.
    verdict: Option<Verdict>,
    best_effect: Option<String>,
    effects: Vec<String>,
    /// The ladder's kept effects, whatever the verdict.
    ladder_effects: Vec<String>,
    explanation: String,
    /// (effect, validation NRMSE, plausible, explained share), best first.
    candidates: Vec<(String, f64, bool, f64)>,
    /// Rank (1-based) of each hidden effect among the candidates.
    ranks: Vec<Option<usize>>,
    nrmse_baseline: f64,
    nrmse_floor: f64,
    /// Singles: the true effect's candidate; pairs: the ladder's end; otherwise the ladder's end.
    nrmse_after: f64,
    nrmse_ladder: f64,
    /// None when the run failed.
    ladder: Option<Vec<RungRecord>>,
    expected_floor: f64,
    oracle_nrmse: f64,
    truth_tared: bool,
    fits: Vec<FitCheck>,
    seconds_generate: f64,
    seconds_diagnose: f64,
}

impl Record {
    /// The verdict's name, or `error` for a failed run.
    fn verdict_name(&self) -> &'static str {
        self.verdict.map_or("error", Verdict::as_str)
    }
    fn reduction(&self) -> f64 {
        1.0 - self.nrmse_after / self.nrmse_baseline
    }
    fn at_floor(&self) -> bool {
        self.nrmse_after <= AT_FLOOR * self.nrmse_floor
    }
    fn room_for_halving(&self) -> bool {
        self.nrmse_baseline >= ROOM_FOR_HALVING * self.nrmse_floor
    }
    fn halved(&self) -> bool {
        self.reduction() >= MIN_CUT
    }
    fn ranked_first(&self) -> bool {
        self.ranks.contains(&Some(1))
    }
    fn names_it(&self) -> bool {
        self.verdict == Some(Verdict::Effect) && self.best_effect.as_deref() == self.case.hidden.first().copied()
    }
    fn all_found(&self) -> bool {
        self.case.hidden.iter().all(|h| self.effects.iter().any(|e| e == h))
    }
    fn ok(&self) -> bool {
        if self.error.is_some() {
            return false;
        }
        match self.case.kind {
            Kind::Single => {
                self.ranks[0] == Some(1)
                    && self.names_it()
                    && self.at_floor()
                    && (!self.room_for_halving() || self.halved())
                    && self.fits.iter().all(FitCheck::ok)
            }
            Kind::Pair => {
                self.verdict == Some(Verdict::Effect)
                    && self.all_found()
                    && self.at_floor()
                    && (!self.room_for_halving() || self.halved())
                    && self.fits.iter().all(FitCheck::ok)
            }
            Kind::Nothing => self.verdict == Some(Verdict::NothingMissing),
            Kind::Drift => self.verdict == Some(Verdict::Unexplained),
        }
    }

    fn json(&self) -> RecordJson<'_> {
        let c = &self.case;
        RecordJson {
            group: c.group,
            input: c.input_name(),
            hidden: &c.hidden,
            out_of_catalog: (c.kind == Kind::Drift).then(|| format!("load-cell drift +{DRIFT_N} N linear")),
            seed: c.seed,
            duration_s: c.duration,
            error: self.error.as_deref(),
            verdict: self.verdict_name(),
            best_effect: self.best_effect.as_deref(),
            effects: &self.effects,
            ladder_effects: &self.ladder_effects,
            ranks: &self.ranks,
            nrmse_baseline: self.nrmse_baseline,
            nrmse_after: self.nrmse_after,
            nrmse_after_ladder: self.nrmse_ladder,
            nrmse_noise_floor: self.nrmse_floor,
            expected_floor_sensor: self.expected_floor,
            oracle_nrmse: self.oracle_nrmse,
            baseline_over_floor: self.nrmse_baseline / self.nrmse_floor,
            reduction: self.reduction(),
            at_floor: self.at_floor(),
            room_for_halving: self.room_for_halving(),
            halved: self.halved(),
            fits: self
                .fits
                .iter()
                .map(|f| FitJson {
                    effect: f.effect,
                    param: f.param,
                    truth: f.truth,
                    fitted: f.fitted,
                    relative_error: f.error(),
                    source: f.source,
                    within_tolerance: f.ok(),
                })
                .collect(),
            ok: self.ok(),
            truth_tare_load_cell: self.truth_tared,
            candidates: self
                .candidates
                .iter()
                .map(|(e, n, p, x)| CandidateJson { effect: e, nrmse_validation: *n, plausible: *p, explained: *x })
                .collect(),
            ladder: self.ladder.as_deref(),
            explanation: &self.explanation,
            seconds_generate: self.seconds_generate,
            seconds_diagnose: self.seconds_diagnose,
        }
    }
}

/// A record in the `--out` file (numbers that are not finite are written as null).
#[derive(Serialize)]
struct RecordJson<'a> {
    group: &'a str,
    input: &'a str,
    hidden: &'a [&'static str],
    out_of_catalog: Option<String>,
    seed: u64,
    duration_s: f64,
    error: Option<&'a str>,
    verdict: &'a str,
    best_effect: Option<&'a str>,
    effects: &'a [String],
    ladder_effects: &'a [String],
    ranks: &'a [Option<usize>],
    nrmse_baseline: f64,
    nrmse_after: f64,
    nrmse_after_ladder: f64,
    nrmse_noise_floor: f64,
    expected_floor_sensor: f64,
    oracle_nrmse: f64,
    baseline_over_floor: f64,
    reduction: f64,
    at_floor: bool,
    room_for_halving: bool,
    halved: bool,
    fits: Vec<FitJson<'a>>,
    ok: bool,
    truth_tare_load_cell: bool,
    candidates: Vec<CandidateJson<'a>>,
    ladder: Option<&'a [RungRecord]>,
    explanation: &'a str,
    seconds_generate: f64,
    seconds_diagnose: f64,
}

#[derive(Serialize)]
struct FitJson<'a> {
    effect: &'a str,
    param: &'a str,
    truth: f64,
    fitted: Option<f64>,
    relative_error: Option<f64>,
    source: &'a str,
    within_tolerance: bool,
}

#[derive(Serialize)]
struct CandidateJson<'a> {
    effect: &'a str,
    nrmse_validation: f64,
    plausible: bool,
    explained: f64,
}

/// A ladder rung as recorded: the fitted values without their errors.
#[derive(Serialize)]
struct RungRecord {
    added: &'static str,
    refit: bool,
    params: IndexMap<&'static str, f64>,
    nrmse_validation: f64,
    explained: f64,
    kept: bool,
}

/// The `--out` file.
#[derive(Serialize)]
struct Out<'a> {
    config: Config,
    summary: IndexMap<&'static str, Vec<String>>,
    total_seconds: f64,
    records: Vec<RecordJson<'a>>,
}

#[derive(Serialize)]
struct Config {
    seeds: u64,
    pair_seeds: u64,
    rig_seconds: f64,
    hil_seconds: f64,
    load_cell_lowpass_hz: f64,
    threads: usize,
    at_floor_factor: f64,
    min_cut: f64,
    param_tolerance: f64,
    drift_n: f64,
}

/// Adds `DRIFT_N` · k/n to the F_damper column of `csv`, written to `out`.
fn add_drift(csv: &Path, out: &Path) -> Result<(), String> {
    let text = std::fs::read_to_string(csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    let mut lines = text.lines();
    let header = lines.next().ok_or("empty CSV")?;
    let col = header.split(',').position(|c| c == "F_damper").ok_or("no F_damper column")?;
    let rows: Vec<&str> = lines.collect();
    let n = rows.len();
    let mut s = format!("{header}\n");
    for (k, row) in rows.iter().enumerate() {
        let mut cells: Vec<String> = row.split(',').map(String::from).collect();
        let f: f64 = cells[col].parse().map_err(|_| format!("bad F_damper cell on row {k}"))?;
        cells[col] = format!("{}", f + DRIFT_N * k as f64 / n as f64);
        s.push_str(&cells.join(","));
        s.push('\n');
    }
    std::fs::write(out, s).map_err(|e| format!("{}: {e}", out.display()))
}

fn ladder(d: &Diagnosis) -> Vec<RungRecord> {
    d.ladder
        .rungs
        .iter()
        .map(|r| RungRecord {
            added: r.added,
            refit: r.refit,
            params: r.params.iter().map(|(n, v, _)| (*n, *v)).collect(),
            nrmse_validation: r.nrmse_validation,
            explained: r.explained,
            kept: r.kept,
        })
        .collect()
}

/// The fitted size parameter of `key`: from its candidate (single), or from the ladder (pairs:
/// the last kept rung that fitted it, a kept refit overriding the first fit).
fn fit_check(
    d: &Diagnosis,
    g: &Generated,
    key: &'static str,
    from_ladder: bool,
) -> Result<FitCheck, damper_engine::Error> {
    let e = effect(key)?;
    let param = e.fitted[0].name;
    let truth = get_real(&g.params, param)?;
    let from_candidate = || {
        d.candidates.iter().find(|c| c.effect == key).and_then(|c| c.params.iter().find(|p| p.0 == param).map(|p| p.1))
    };
    let (fitted, source) = if from_ladder {
        match d.ladder.rungs.iter().rev().find(|r| r.added == key && r.kept) {
            Some(r) => {
                (r.params.iter().find(|p| p.0 == param).map(|p| p.1), if r.refit { "ladder refit" } else { "ladder" })
            }
            None => (from_candidate(), "candidate (not kept)"),
        }
    } else {
        (from_candidate(), "candidate")
    };
    Ok(FitCheck { effect: e.key, param, truth, fitted, source })
}

fn run_case(c: &Case, dir: &Path) -> Result<Record, String> {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let csv = dir.join("m.csv");
    let mut o = GenerateOptions::new(&csv, dir.join("m_truth.json"));
    o.duration = c.duration;
    o.seed = c.seed;
    o.input = c.input;
    o.effects = c.hidden.iter().map(|h| h.to_string()).collect();
    let t0 = Instant::now();
    let g = generate::write(&o).map_err(|e| e.to_string())?;
    let measurement = if c.kind == Kind::Drift {
        let drifted = dir.join("drifted.csv");
        add_drift(&csv, &drifted)?;
        drifted
    } else {
        csv
    };
    let seconds_generate = t0.elapsed().as_secs_f64();
    let mut co = CompareOptions::new(&measurement);
    co.load_cell_lowpass_hz = Some(400.0);
    // the HiL load cell is tared (README, `--tare-load-cell`); the rig's is raw
    co.tare_load_cell = c.input == InputStyle::Hil;
    let t1 = Instant::now();
    let r = diagnose_measurement(&co, THREADS, &|_, _, _| {}).map_err(|e| e.to_string())?;
    let seconds_diagnose = t1.elapsed().as_secs_f64();
    let d = &r.diagnosis;
    let ranks: Vec<Option<usize>> =
        c.hidden.iter().map(|h| d.candidates.iter().position(|x| x.effect == *h).map(|i| i + 1)).collect();
    let fits = c
        .hidden
        .iter()
        .map(|h| fit_check(d, &g, h, c.kind == Kind::Pair))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| e.to_string())?;
    let nrmse_after = match c.kind {
        Kind::Single => d.candidates.iter().find(|x| x.effect == c.hidden[0]).map_or(f64::NAN, |x| x.nrmse_validation),
        _ => d.ladder.nrmse_validation,
    };
    let _ = std::fs::remove_dir_all(dir);
    Ok(Record {
        case: c.clone(),
        error: None,
        verdict: Some(d.verdict),
        best_effect: d.best_effect.map(String::from),
        effects: d.effects.iter().map(|e| e.to_string()).collect(),
        ladder_effects: d.ladder.effects.iter().map(|e| e.to_string()).collect(),
        explanation: d.explanation.clone(),
        candidates: d
            .candidates
            .iter()
            .map(|x| (x.effect.to_string(), x.nrmse_validation, x.plausible, x.explained))
            .collect(),
        ranks,
        nrmse_baseline: d.nrmse_baseline,
        nrmse_floor: d.nrmse_noise_floor,
        nrmse_after,
        nrmse_ladder: d.ladder.nrmse_validation,
        ladder: Some(ladder(d)),
        expected_floor: g.expected_floor,
        oracle_nrmse: g.oracle_nrmse,
        truth_tared: g.params.tare_load_cell,
        fits,
        seconds_generate,
        seconds_diagnose,
    })
}

fn failed(c: &Case, e: String) -> Record {
    Record {
        case: c.clone(),
        error: Some(e),
        verdict: None,
        best_effect: None,
        effects: Vec::new(),
        ladder_effects: Vec::new(),
        explanation: String::new(),
        candidates: Vec::new(),
        ranks: vec![None; c.hidden.len()],
        nrmse_baseline: f64::NAN,
        nrmse_floor: f64::NAN,
        nrmse_after: f64::NAN,
        nrmse_ladder: f64::NAN,
        ladder: None,
        expected_floor: f64::NAN,
        oracle_nrmse: f64::NAN,
        truth_tared: false,
        fits: Vec::new(),
        seconds_generate: 0.0,
        seconds_diagnose: 0.0,
    }
}

fn rank_text(r: &[Option<usize>]) -> String {
    r.iter().map(|x| x.map_or("-".to_string(), |k| k.to_string())).collect::<Vec<_>>().join(",")
}

fn fit_text(f: &FitCheck) -> String {
    let err = f.error().map_or("   -".to_string(), |e| format!("{:>5.1}%", 100.0 * e));
    let mark = if f.ok() { "" } else { "!" };
    let fitted = f.fitted.map_or("-".to_string(), |x| format!("{x:.4e}"));
    format!("{}={fitted}/{:.4e} {err}{mark}", f.param, f.truth)
}

fn header(kind: Kind) -> String {
    match kind {
        Kind::Single => format!(
            "{:<21} {:>4} {:<34} {:>4} {:>8} {:>8} {:>8} {:>5} {:>6} {:>5}  {:<44} {:>6}",
            "effect",
            "seed",
            "verdict (best)",
            "rank",
            "baseline",
            "true",
            "floor",
            "b/f",
            "cut",
            "floor",
            "fitted/truth err",
            "time"
        ),
        Kind::Pair => format!(
            "{:<38} {:>4} {:<11} {:<52} {:>5} {:>8} {:>8} {:>8} {:>6} {:>5}  {:<80} {:>6}",
            "pair",
            "seed",
            "verdict",
            "effects (ladder)",
            "ranks",
            "baseline",
            "ladder",
            "floor",
            "cut",
            "floor",
            "fitted/truth err",
            "time"
        ),
        Kind::Nothing | Kind::Drift => format!(
            "{:<16} {:<5} {:>4} {:<34} {:>8} {:>8} {:>5}  {:<26} {:>6}",
            "hidden", "input", "seed", "verdict (best)", "baseline", "floor", "b/f", "best candidate (NRMSE)", "time"
        ),
    }
}

fn row(r: &Record) -> String {
    let c = &r.case;
    let time = format!("{:.1}s", r.seconds_generate + r.seconds_diagnose);
    if let Some(e) = &r.error {
        return format!("{:<21} {:>4} ERROR {e}", c.label(), c.seed);
    }
    let verdict =
        format!("{}{}", r.verdict_name(), r.best_effect.as_ref().map_or(String::new(), |b| format!(" ({b})")));
    let yes = |b: bool| if b { "yes" } else { "NO" };
    let mark = if r.ok() { "" } else { "  <-- FAIL" };
    match c.kind {
        Kind::Single => format!(
            "{:<21} {:>4} {:<34} {:>4} {:>8.4} {:>8.4} {:>8.4} {:>5.1} {:>5.0}% {:>5}  {:<44} {:>6}{mark}",
            c.label(),
            c.seed,
            verdict,
            rank_text(&r.ranks),
            r.nrmse_baseline,
            r.nrmse_after,
            r.nrmse_floor,
            r.nrmse_baseline / r.nrmse_floor,
            100.0 * r.reduction(),
            yes(r.at_floor()),
            r.fits.iter().map(fit_text).collect::<Vec<_>>().join("; "),
            time
        ),
        Kind::Pair => format!(
            "{:<38} {:>4} {:<11} {:<52} {:>5} {:>8.4} {:>8.4} {:>8.4} {:>5.0}% {:>5}  {:<80} {:>6}{mark}",
            c.label(),
            c.seed,
            r.verdict_name(),
            match (r.effects.is_empty(), r.ladder_effects.is_empty()) {
                (true, false) => format!("(ladder kept {})", r.ladder_effects.join("+")),
                _ => r.effects.join("+"),
            },
            rank_text(&r.ranks),
            r.nrmse_baseline,
            r.nrmse_after,
            r.nrmse_floor,
            100.0 * r.reduction(),
            yes(r.at_floor()),
            r.fits.iter().map(fit_text).collect::<Vec<_>>().join("; "),
            time
        ),
        Kind::Nothing | Kind::Drift => {
            let best = r.candidates.first().map_or("-".to_string(), |(e, n, _, _)| format!("{e} ({n:.4})"));
            format!(
                "{:<16} {:<5} {:>4} {:<34} {:>8.4} {:>8.4} {:>5.2}  {:<26} {:>6}{mark}",
                c.label(),
                c.input_name(),
                c.seed,
                verdict,
                r.nrmse_baseline,
                r.nrmse_floor,
                r.nrmse_baseline / r.nrmse_floor,
                best,
                time
            )
        }
    }
}

fn median(mut x: Vec<f64>) -> f64 {
    damper_engine::dsp::median(&mut x)
}

fn count(rs: &[&Record], f: impl Fn(&Record) -> bool) -> usize {
    rs.iter().filter(|r| f(r)).count()
}

/// "fitted within 20 %: k of n (median error x %, worst y %)" over `fits`.
fn fit_line(fits: &[&FitCheck]) -> String {
    let errors: Vec<f64> = fits.iter().map(|f| f.error().unwrap_or(f64::INFINITY)).collect();
    let worst = errors.iter().copied().fold(0.0, f64::max);
    format!(
        "fitted within 20 %: {} of {} (median error {:.2} %, worst {:.2} %)",
        fits.iter().filter(|f| f.ok()).count(),
        fits.len(),
        100.0 * median(errors.clone()),
        100.0 * worst
    )
}

fn summary(group: &str, kind: Kind, records: &[&Record]) -> Vec<String> {
    let n = records.len();
    let mut s = Vec::new();
    let fits: Vec<&FitCheck> = records.iter().flat_map(|r| r.fits.iter()).collect();
    let room: Vec<&Record> = records.iter().copied().filter(|r| r.error.is_none() && r.room_for_halving()).collect();
    let errors = count(records, |r| r.error.is_some());
    match kind {
        Kind::Single => {
            s.push(format!("ranked first: {} of {n}", count(records, |r| r.ranks[0] == Some(1))));
            s.push(format!("verdict effect naming it: {} of {n}", count(records, Record::names_it)));
            s.push(format!(
                "ladder effects exactly [it]: {} of {n}",
                count(records, |r| r.effects.len() == 1 && r.all_found())
            ));
            s.push(fit_line(&fits));
            s.push(format!("halving where baseline ≥ 2× floor: {} of {}", count(&room, Record::halved), room.len()));
            s.push(format!("at the floor: {} of {n}", count(records, |r| r.error.is_none() && r.at_floor())));
            s.push(format!("all checks passed: {} of {n}", count(records, Record::ok)));
            // per effect, to see patterns
            let mut keys: Vec<&str> = Vec::new();
            for r in records {
                if !keys.contains(&r.case.hidden[0]) {
                    keys.push(r.case.hidden[0]);
                }
            }
            s.push(format!(
                "  {:<21} {:>6} {:>6} {:>6} {:>6} {:>8} {:>11} {:>14}",
                "per effect", "first", "named", "fit20", "floor", "halved", "median b/f", "median err %"
            ));
            for k in keys {
                let rs: Vec<&Record> = records.iter().copied().filter(|r| r.case.hidden[0] == k).collect();
                let m = rs.len();
                let room_k: Vec<&Record> =
                    rs.iter().copied().filter(|r| r.error.is_none() && r.room_for_halving()).collect();
                s.push(format!(
                    "  {:<21} {:>6} {:>6} {:>6} {:>6} {:>8} {:>11.2} {:>14.2}",
                    k,
                    format!("{}/{m}", count(&rs, |r| r.ranks[0] == Some(1))),
                    format!("{}/{m}", count(&rs, Record::names_it)),
                    format!("{}/{m}", count(&rs, |r| r.fits.iter().all(FitCheck::ok) && r.error.is_none())),
                    format!("{}/{m}", count(&rs, |r| r.error.is_none() && r.at_floor())),
                    format!("{}/{}", count(&room_k, Record::halved), room_k.len()),
                    median(rs.iter().map(|r| r.nrmse_baseline / r.nrmse_floor).collect()),
                    100.0
                        * median(
                            rs.iter().flat_map(|r| r.fits.iter().map(|f| f.error().unwrap_or(f64::INFINITY))).collect()
                        ),
                ));
            }
        }
        Kind::Pair => {
            s.push(format!("both found: {} of {n}", count(records, |r| r.error.is_none() && r.all_found())));
            s.push(format!(
                "exactly the two (ladder effects = the pair): {} of {n}",
                count(records, |r| r.error.is_none() && r.all_found() && r.effects.len() == 2)
            ));
            s.push(format!("verdict effect: {} of {n}", count(records, |r| r.verdict == Some(Verdict::Effect))));
            s.push(format!("one of the two ranked first: {} of {n}", count(records, Record::ranked_first)));
            s.push(fit_line(&fits));
            s.push(format!(
                "halving (ladder) where baseline ≥ 2× floor: {} of {}",
                count(&room, Record::halved),
                room.len()
            ));
            s.push(format!("at the floor (ladder): {} of {n}", count(records, |r| r.error.is_none() && r.at_floor())));
            s.push(format!("all checks passed: {} of {n}", count(records, Record::ok)));
        }
        Kind::Nothing => {
            s.push(format!("verdict none: {} of {n}", count(records, |r| r.verdict == Some(Verdict::NothingMissing))));
            for input in ["rig", "hil"] {
                let rs: Vec<&Record> = records.iter().copied().filter(|r| r.case.input_name() == input).collect();
                s.push(format!(
                    "  {input}: verdict none: {} of {}",
                    count(&rs, |r| r.verdict == Some(Verdict::NothingMissing)),
                    rs.len()
                ));
            }
        }
        Kind::Drift => {
            s.push(format!("unexplained: {} of {n}", count(records, |r| r.verdict == Some(Verdict::Unexplained))));
        }
    }
    if errors > 0 {
        s.push(format!("errors: {errors} of {n}"));
    }
    let secs: f64 = records.iter().map(|r| r.seconds_generate + r.seconds_diagnose).sum();
    s.push(format!("{group}: {n} runs in {secs:.0} s ({:.1} s per run)", secs / n.max(1) as f64));
    s
}

fn cases(group: &'static str, o: &Options) -> (Kind, Vec<Case>) {
    let seeds = 1..=o.seeds;
    let keys: Vec<&'static str> = semi_active_damper::effects::CATALOG.iter().map(|e| e.info().key).collect();
    let case =
        |kind, input, hidden: Vec<&'static str>, seed, duration| Case { group, kind, input, hidden, seed, duration };
    match group {
        "rig" | "hil" => {
            let (input, duration) =
                if group == "rig" { (InputStyle::Rig, RIG_SECONDS) } else { (InputStyle::Hil, o.hil_seconds) };
            let v = keys
                .iter()
                .flat_map(|k| seeds.clone().map(move |s| (*k, s)))
                .map(|(k, s)| case(Kind::Single, input, vec![k], s, duration))
                .collect();
            (Kind::Single, v)
        }
        "pairs" => {
            let v = PAIRS
                .iter()
                .flat_map(|&(a, b)| (1..=(o.seeds / 2).max(1)).map(move |s| (a, b, s)))
                .map(|(a, b, s)| case(Kind::Pair, InputStyle::Rig, vec![a, b], s, RIG_SECONDS))
                .collect();
            (Kind::Pair, v)
        }
        "none" => {
            let mut v: Vec<Case> =
                seeds.clone().map(|s| case(Kind::Nothing, InputStyle::Rig, vec![], s, RIG_SECONDS)).collect();
            v.extend(seeds.map(|s| case(Kind::Nothing, InputStyle::Hil, vec![], s, o.hil_seconds)));
            (Kind::Nothing, v)
        }
        _ => (Kind::Drift, seeds.map(|s| case(Kind::Drift, InputStyle::Rig, vec![], s, RIG_SECONDS)).collect()),
    }
}

fn main() {
    let o = <Options as clap::Parser>::parse();
    let scratch = std::env::temp_dir().join(format!("damper_ranking_accuracy_{}", std::process::id()));
    let start = Instant::now();
    let groups: Vec<&'static str> =
        GROUPS.iter().copied().filter(|g| o.only.is_empty() || o.only.iter().any(|x| x == g)).collect();
    println!(
        "ranking accuracy: seeds 1..={} (pairs 1..={}), rig {RIG_SECONDS} s, HiL {} s (tared), load-cell low-pass 400 Hz, {THREADS} threads per diagnosis",
        o.seeds,
        (o.seeds / 2).max(1),
        o.hil_seconds
    );
    let mut all: Vec<Record> = Vec::new();
    let mut summaries = IndexMap::new();
    for group in groups {
        let (kind, cs) = cases(group, &o);
        println!("\n== {group}: {} runs ==", cs.len());
        println!("{}", header(kind));
        let first = all.len();
        for c in &cs {
            let r = run_case(c, &scratch).unwrap_or_else(|e| failed(c, e));
            println!("{}", row(&r));
            let _ = std::io::stdout().flush();
            all.push(r);
        }
        let rs: Vec<&Record> = all[first..].iter().collect();
        let lines = summary(group, kind, &rs);
        println!("-- {group} summary --");
        for l in &lines {
            println!("{l}");
        }
        summaries.insert(group, lines);
    }
    let total = start.elapsed().as_secs_f64();
    println!("\ntotal: {} runs in {total:.0} s ({:.1} min)", all.len(), total / 60.0);
    let _ = std::fs::remove_dir_all(&scratch);
    if let Some(path) = &o.out {
        let out = Out {
            config: Config {
                seeds: o.seeds,
                pair_seeds: (o.seeds / 2).max(1),
                rig_seconds: RIG_SECONDS,
                hil_seconds: o.hil_seconds,
                load_cell_lowpass_hz: 400.0,
                threads: THREADS,
                at_floor_factor: AT_FLOOR,
                min_cut: MIN_CUT,
                param_tolerance: PARAM_TOLERANCE,
                drift_n: DRIFT_N,
            },
            summary: summaries,
            total_seconds: total,
            records: all.iter().map(Record::json).collect(),
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            let _ = std::fs::create_dir_all(dir);
        }
        match std::fs::write(path, to_json(&out)) {
            Ok(()) => println!("records: {}", path.display()),
            Err(e) => {
                eprintln!("{}: {e}", path.display());
                std::process::exit(1);
            }
        }
    }
}
