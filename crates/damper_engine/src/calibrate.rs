//! Calibration: the nominal parameters a user cannot know (valve geometry, oil volumes and air,
//! mount stiffness, gas pre-charge, solenoid) fitted on one or more calibration records, their
//! force residuals stacked, by bounded Levenberg–Marquardt ([`crate::lm`]); and which of them the
//! data can pin.
//!
//! ```text
//! minimise  Σ_records Σ_k (F_model,k(θ) − F_measured,k)²     (N²), k over the samples kept: not
//!           left out by the record's checks, nor hanging on the velocity below what the record
//!           resolves (crate::sensitivity)
//! θ         each parameter on a log scale in [start/3, 3·start] ∩ the model's range
//! pinned    relative standard uncertainty ≤ 25 %, |correlation| ≤ 0.99 with every other fitted
//!           parameter, JᵀJ not singular; otherwise the worst offender is held at its given value
//!           and the fit is redone without it, until every fitted parameter is pinned
//! ```
//! Records taken at several settings of an adjustable damper are calibrated together
//! ([`crate::settings`]): the parameters the adjuster moves once per setting, the rest once.
//! The model runs at `rtol` = 3e-5 (unless `--set rtol=…`): at the default 3e-4 the numerical error
//! is of the order of the sensor noise (0.86 σ RMS on `cargo bench`'s input), and it would also blur
//! the finite differences.

use crate::comparison::{build_model, CompareOptions, ANALYSIS_RTOL};
use crate::dsp::{noise_sigma, nrmse, std};
use crate::error::{Error, Place};
use crate::lm::{self, Bound, Solution};
use crate::model::{thread_pool, Backend, Drive, Model};
use crate::parameters::{changed_parameters, get_real, lookup, Param, Value};
use crate::sensitivity::ShiftedRuns;
use crate::settings::{apply, Entry, Settings};
use crate::units::Column;
use semi_active_damper::physics::params::Parameters;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// The parameters fitted by default: those force records identify (each moves the force of a rig
/// record by more than the sensor noise when moved by 20 %).
pub const DEFAULT_FIT: [&str; 11] = [
    "r_port",
    "x_lap",
    "Cd_valve",
    "V_hose",
    "air_fraction",
    "k1_mount",
    "p_cv_crack",
    "V_gas0",
    "p_reservoir0",
    "K_sol",
    "tau_coil",
];

/// The parameters fitted by default on a passive damper's records (the valve held shut): the gas,
/// the air, the mount, the seals and each passive valve the description has (its parts switched
/// off are left out).
pub const PASSIVE_FIT: [&str; 14] = [
    "p_reservoir0",
    "air_fraction",
    "k1_mount",
    "F_coulomb",
    "G_bleed_reb",
    "A_bleed_reb",
    "p_open_reb",
    "k_open_reb",
    "A_open_reb",
    "G_bleed_comp",
    "A_bleed_comp",
    "p_open_comp",
    "k_open_comp",
    "A_open_comp",
];

/// The parameters the steady stage fits (the force–velocity law's), of those fitted.
const STEADY_FIT: [&str; 12] = [
    "p_reservoir0",
    "F_coulomb",
    "G_bleed_reb",
    "A_bleed_reb",
    "p_open_reb",
    "k_open_reb",
    "A_open_reb",
    "G_bleed_comp",
    "A_bleed_comp",
    "p_open_comp",
    "k_open_comp",
    "A_open_comp",
];

/// The controller's gains, added by `--fit-controller` (they are the user's own settings, known
/// unless the controller is a black box).
pub const CONTROLLER_GAINS: [&str; 5] = ["Kp_F", "Ki_F", "Kp_x", "Ki_x", "Kd_x"];

/// Largest relative standard uncertainty of a parameter called identified.
pub const MAX_RELATIVE_UNCERTAINTY: f64 = 0.25;
/// Largest |correlation| of a parameter with another fitted one.
pub const MAX_CORRELATION: f64 = 0.99;

/// What `damper calibrate` does.
#[derive(Clone, Debug)]
pub struct CalibrateOptions {
    /// The calibration records.
    pub records: Vec<PathBuf>,
    /// The model and reading options shared by every record (its `measurement` is ignored).
    pub compare: CompareOptions,
    /// Parameters to fit (`--fit`); empty: [`DEFAULT_FIT`].
    pub fit: Vec<String>,
    /// Add [`CONTROLLER_GAINS`].
    pub fit_controller: bool,
    pub max_relative_uncertainty: f64,
    pub max_correlation: f64,
    /// Threads for the Jacobian's columns (the result does not depend on it).
    pub threads: usize,
    /// Parameters fitted once per setting (`--per-setting`): what an adjuster moves.
    pub per_setting: Vec<String>,
    /// The records of each named setting (`--setting LABEL=A.csv,B.csv`); a record named in none
    /// is a setting of its own.
    pub settings: Vec<(String, Vec<PathBuf>)>,
}

impl CalibrateOptions {
    pub fn new(records: Vec<PathBuf>) -> CalibrateOptions {
        CalibrateOptions {
            records,
            compare: CompareOptions::new(""),
            fit: Vec::new(),
            fit_controller: false,
            max_relative_uncertainty: MAX_RELATIVE_UNCERTAINTY,
            max_correlation: MAX_CORRELATION,
            threads: crate::model::default_threads(),
            per_setting: Vec::new(),
            settings: Vec::new(),
        }
    }

    /// The parameters fitted once per setting, checked: Real parameters, each once.
    pub fn per_setting_names(&self) -> Result<Vec<&'static str>, Error> {
        let mut names: Vec<&'static str> = Vec::new();
        for n in &self.per_setting {
            let name = match lookup(n).map_err(|e| e.context(format!("--per-setting {n}")))? {
                Param::Real(v) => v.name(),
                _ => return Err(only_real(format!("--per-setting {n}"))),
            };
            if !names.contains(&name) {
                names.push(name);
            }
        }
        Ok(names)
    }

    /// The names to fit, checked: Real parameters of the model, each once ([`DEFAULT_FIT`] unless
    /// `--fit` names them).
    pub fn names(&self) -> Result<Vec<&'static str>, Error> {
        self.names_for(None)
    }

    /// [`CalibrateOptions::names`] for the records' model `p`: a passive damper's default is
    /// [`PASSIVE_FIT`], of the parts it has.
    pub fn names_for(&self, p: Option<&Parameters>) -> Result<Vec<&'static str>, Error> {
        let mut names: Vec<&'static str> = Vec::new();
        let passive: Vec<&str> = match p {
            Some(p) if crate::steady::is_passive(p) => {
                PASSIVE_FIT.iter().copied().filter(|n| part_present(p, n)).collect()
            }
            _ => DEFAULT_FIT.to_vec(),
        };
        let given: Vec<&str> =
            if self.fit.is_empty() { passive } else { self.fit.iter().map(String::as_str).collect() };
        let extra = if self.fit_controller { CONTROLLER_GAINS.as_slice() } else { &[] };
        for n in given.iter().chain(extra) {
            let name = match lookup(n).map_err(|e| e.context(format!("--fit {n}")))? {
                Param::Real(v) => v.name(),
                _ => return Err(only_real(format!("--fit {n}"))),
            };
            if !names.contains(&name) {
                names.push(name);
            }
        }
        Ok(names)
    }
}

/// `option: only Real parameters can be fitted`.
fn only_real(option: String) -> Error {
    Error::BadOption { option, problem: "only Real parameters can be fitted".into() }
}

/// Whether the part a parameter belongs to is in the model: a valve's parameters need the valve,
/// the seal friction its switch.
fn part_present(p: &Parameters, name: &str) -> bool {
    if name.ends_with("_reb") {
        p.effect_rebound_valve
    } else if name.ends_with("_comp") {
        p.effect_compression_valve
    } else if name == "F_coulomb" {
        p.effect_seal_friction
    } else if name == "k1_mount" {
        p.effect_mount_compliance
    } else if name == "air_fraction" {
        p.effect_compressibility
    } else {
        true
    }
}

/// What the steady stage did (a passive damper's calibration).
#[derive(Clone, Debug)]
pub struct SteadyStage {
    /// Quasi-steady samples of all records, and starts tried.
    pub points: usize,
    pub starts: usize,
    /// RMS force residual of the steady law before and after (N).
    pub rms_before: f64,
    pub rms_after: f64,
    /// (name as reported, the description's value, the steady stage's), each fitted.
    pub fitted: Vec<(String, f64, f64)>,
}

/// Whether a parameter was fitted.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    Fitted,
    /// Held at its start value; why.
    Held(String),
}

/// One parameter of the calibration.
#[derive(Clone, Debug)]
pub struct Calibrated {
    pub name: &'static str,
    /// The setting whose own value this is (`--per-setting`); None: shared by every record.
    pub setting: Option<String>,
    /// Its unit in the model ("1": dimensionless).
    pub unit: &'static str,
    pub start: f64,
    pub value: f64,
    /// Standard uncertainty (unit of the parameter); None when held.
    pub std_error: Option<f64>,
    /// Its strongest correlation with another fitted parameter (as reported).
    pub correlation: Option<(String, f64)>,
    /// The search box.
    pub scale: Bound,
    pub status: Status,
}

impl Calibrated {
    /// The name as reported: `A_bleed_reb[6 clicks]` for a setting's own value.
    pub fn display_name(&self) -> String {
        match &self.setting {
            Some(label) => format!("{}[{label}]", self.name),
            None => self.name.to_string(),
        }
    }

    /// Standard uncertainty over |value|.
    pub fn relative(&self) -> Option<f64> {
        self.std_error.map(|s| s / self.value.abs().max(1e-300))
    }

    /// The fitted value lies on its search box's edge.
    pub fn at_bound(&self) -> bool {
        self.status == Status::Fitted && self.scale.near_bound(self.value, lm::AT_BOUND)
    }
}

/// A record's force error before and after.
#[derive(Clone, Debug)]
pub struct RecordFit {
    pub path: String,
    /// The label of the setting it was taken at.
    pub setting: String,
    pub samples: usize,
    pub nrmse_before: f64,
    pub nrmse_after: f64,
    /// White-noise floor of the residual (NRMSE), from its second differences.
    pub noise_floor: f64,
}

/// One fit of the rounds.
#[derive(Clone, Debug)]
pub struct Round {
    /// The parameters fitted, as reported.
    pub fitted: Vec<String>,
    pub iterations: usize,
    pub model_runs: usize,
    pub converged: bool,
    /// RMS force residual (N).
    pub rms_residual: f64,
    /// The parameter held after this round and why, if any.
    pub held: Option<(String, String)>,
}

/// A finished calibration.
#[derive(Clone, Debug)]
pub struct Calibration {
    pub parameters: Vec<Calibrated>,
    pub records: Vec<RecordFit>,
    pub rounds: Vec<Round>,
    /// Parameters of `--params` and `--set` not fitted (written to the parameter set too).
    pub given: Vec<(&'static str, Value)>,
    /// rtol of the model runs.
    pub rtol: f64,
    pub model_runs: usize,
    pub seconds: f64,
    pub threads: usize,
    /// The steady stage, where it ran (a passive damper with quasi-steady samples).
    pub steady: Option<SteadyStage>,
    /// The settings the records were taken at (one unless `--setting`, `--per-setting`).
    pub settings: Vec<String>,
    /// The covariance of the fitted parameters (the last fit's), for what a diagnosis with these
    /// values inherits from their uncertainty ([`crate::propagation`]).
    pub covariance: Option<Covariance>,
}

/// The covariance of a calibration's fitted parameters (the sandwich of [`crate::lm`]).
#[derive(Clone, Debug)]
pub struct Covariance {
    /// Indices into [`Calibration::parameters`] of the rows and columns.
    pub parameters: Vec<usize>,
    /// Row by row, in the parameters' units.
    pub matrix: Vec<Vec<f64>>,
}

struct Record {
    path: String,
    /// Index of its setting ([`Settings::labels`]).
    setting: usize,
    measured: Vec<f64>,
    /// Per sample: scored (not left out by the record's checks, e.g. a clipped force).
    kept: Vec<bool>,
    drive: Drive,
    model: Model,
    backend: Arc<dyn Backend>,
    /// The velocity's noise where it was made from the displacement or smoothed.
    velocity_noise: Option<crate::velocity_noise::VelocityNoise>,
}

fn read_records(o: &CalibrateOptions, settings: &Settings) -> Result<Vec<Record>, Error> {
    if o.records.is_empty() {
        return Err(Error::NoRecords);
    }
    o.records
        .iter()
        .zip(&settings.of_record)
        .map(|(path, &setting)| {
            let c =
                CompareOptions { measurement: path.clone(), rtol_at_most: Some(ANALYSIS_RTOL), ..o.compare.clone() };
            let m = crate::comparison::read_checked(&c, path)?;
            // calibration fits the whole record: no validation part of its own
            crate::record_checks::check(&m, 0)?;
            let measured = m
                .get(Column::FDamper)
                .ok_or_else(|| Error::InFile { at: Place::file(&m.path), problem: "no F_damper column".into() })?
                .to_vec();
            let drive = Drive::from_measurement(&m);
            let setup = build_model(&c, &drive)?;
            let kept = m.excluded.iter().map(|e| !e).collect();
            Ok(Record {
                path: m.path.clone(),
                setting,
                measured,
                kept,
                drive,
                model: setup.model,
                backend: setup.backend,
                velocity_noise: m.velocity_noise,
            })
        })
        .collect()
}

/// The fit's entries: the shared parameters once, those of `--per-setting` once per setting
/// (each a setting's own only when there are several settings).
fn fit_entries(o: &CalibrateOptions, settings: &Settings, p: &Parameters) -> Result<Vec<Entry>, Error> {
    let per_setting = o.per_setting_names()?;
    if !per_setting.is_empty() && settings.labels.len() < 2 {
        return Err(Error::BadOption {
            option: format!("--per-setting {}", per_setting.join(",")),
            problem: "the records are all of one setting; give records of several (--setting LABEL=FILE,…)".into(),
        });
    }
    let shared: Vec<&'static str> = o.names_for(Some(p))?.into_iter().filter(|n| !per_setting.contains(n)).collect();
    Ok(settings.entries(&shared, &per_setting))
}

/// The search box of a parameter around its start value.
fn search_box(name: &str, start: f64, p: &Parameters) -> Result<Bound, Error> {
    let v = match lookup(name)? {
        Param::Real(v) => v,
        _ => return Err(Error::NotOfKind { name: name.to_string(), kind: "Real parameter", is: None }),
    };
    let (min, max) = (v.min().unwrap_or(f64::NEG_INFINITY), v.max().unwrap_or(f64::INFINITY));
    // relations validate() checks, kept inside the box
    let max = match name {
        "p_cv_crack" => max.min(0.95 * p.p_cv_full),
        "x_lap" => max.min(p.x_spool_max - 0.6e-3),
        _ => max,
    };
    if start > 0.0 {
        let (lo, hi) = ((start / 3.0).max(min), (start * 3.0).min(max));
        if lo > 0.0 && lo < hi {
            return Ok(Bound { lo, hi, log: true });
        }
    }
    let span = if start != 0.0 { 2.0 * start.abs() } else { 1.0 };
    let (lo, hi) = ((start - span).max(min), (start + span).min(max));
    if lo < hi {
        Ok(Bound { lo, hi, log: false })
    } else {
        Err(Error::NoRoomToSearch { name: name.to_string(), start, min, max })
    }
}

/// Runs every record with the entries `entries` = `x` that apply to its setting on top of its own
/// model.
fn forces(records: &[Record], entries: &[Entry], x: &[f64]) -> Result<Vec<Vec<f64>>, Error> {
    records
        .iter()
        .map(|r| {
            let mut model = r.model;
            apply(&mut model.params, entries, x, r.setting)?;
            model.params.validate()?;
            Ok(r.backend.run_first(&model, &r.drive, r.drive.len(), false).map_err(|e| e.context(&r.path))?.f_damper)
        })
        .collect()
}

/// Leaves out of each record's fitted samples those whose force hangs on the velocity below what
/// the record resolves ([`crate::sensitivity`], as the diagnosis does), given each record's model at
/// its start and its force `base` there; returns the draws of the residuals' change that the
/// velocity's noise makes over the samples kept, the records in turn (path k of each record makes
/// draw k; a record with fewer paths repeats its own, one with none adds zeros), whose spread the
/// calibrated parameters inherit ([`lm::covariance`]): a smoothed or filtered velocity rounds the
/// motion alike at every corner, and the fit absorbs what that does to the force without a trace
/// in its residuals. No draws where every record's noise is white ([`ShiftedRuns::input_error`]).
fn inform(records: &mut [Record], base: &[Vec<f64>], pool: &rayon::ThreadPool) -> Result<Vec<Vec<f64>>, Error> {
    use rayon::prelude::*;
    let runs: Vec<ShiftedRuns> = pool.install(|| {
        records
            .par_iter()
            .map(|r| {
                let run = |v_damper: Vec<f64>| {
                    let drive = Drive { v_damper, ..r.drive.clone() };
                    let run = r.backend.run_first(&r.model, &drive, drive.len(), false);
                    Ok(run.map_err(|e| e.context(&r.path))?.f_damper)
                };
                ShiftedRuns::new(r.velocity_noise.as_ref(), &r.drive.v_damper, run)
            })
            .collect::<Result<Vec<_>, Error>>()
    })?;
    let mut draws: Vec<Vec<Vec<f64>>> = Vec::with_capacity(records.len());
    for ((r, runs), base) in records.iter_mut().zip(&runs).zip(base) {
        let residual: Vec<f64> = base.iter().zip(&r.measured).map(|(m, y)| m - y).collect();
        let informative = runs.informative(base, noise_sigma(&residual));
        for (kept, informs) in r.kept.iter_mut().zip(&informative.keep) {
            *kept &= informs;
        }
        draws.push(runs.input_error(base, |i| r.kept[i]));
    }
    let n = draws.iter().map(Vec::len).max().unwrap_or(0);
    Ok((0..n)
        .map(|k| {
            records
                .iter()
                .zip(&draws)
                .flat_map(|(r, own)| match own.len() {
                    // white noise paths: no input error
                    0 => vec![0.0; r.kept.iter().filter(|k| **k).count()],
                    len => own[k % len].clone(),
                })
                .collect()
        })
        .collect())
}

/// Why the fit cannot pin a parameter (the worst one), if any: (index, reason).
fn worst(s: &Solution, names: &[String], o: &CalibrateOptions) -> Option<(usize, String)> {
    if s.covariance.is_none() {
        let i = *s.singular.first().unwrap_or(&0);
        let with: Vec<&str> = s.singular.iter().skip(1).map(|&k| names[k].as_str()).collect();
        return Some((
            i,
            if with.is_empty() {
                format!("JᵀJ singular (condition {:.1e}): the records do not move the force with it", s.condition)
            } else {
                format!("JᵀJ singular (condition {:.1e}): not separable from {}", s.condition, with.join(", "))
            },
        ));
    }
    let rel = |i: usize| s.std_error(i).unwrap_or(f64::INFINITY) / s.x[i].abs().max(1e-300);
    let (i, r) = (0..names.len()).map(|i| (i, rel(i))).max_by(|a, b| a.1.total_cmp(&b.1))?;
    if r > o.max_relative_uncertainty {
        return Some((
            i,
            format!("relative uncertainty {:.0} % above {:.0} %", 100.0 * r, 100.0 * o.max_relative_uncertainty),
        ));
    }
    let mut pairs: Vec<(usize, usize, f64)> = Vec::new();
    for i in 0..names.len() {
        if let Some((j, c)) = s.strongest_correlation(i) {
            if c.abs() > o.max_correlation && i < j {
                pairs.push((i, j, c));
            }
        }
    }
    let (i, j, c) = pairs.into_iter().max_by(|a, b| a.2.abs().total_cmp(&b.2.abs()))?;
    let (drop, keep) = if rel(i) >= rel(j) { (i, j) } else { (j, i) };
    Some((drop, format!("correlation {c:+.3} with {} (beyond ±{})", names[keep], o.max_correlation)))
}

/// Calibrates: fits, holds what the records cannot pin, refits; `progress` is told of each round.
pub fn calibrate(o: &CalibrateOptions, progress: &(dyn Fn(&Round) + Sync)) -> Result<Calibration, Error> {
    let t0 = Instant::now();
    let settings = Settings::group(&o.records, &o.settings)?;
    let mut records = read_records(o, &settings)?;
    let entries = fit_entries(o, &settings, &records[0].model.params)?;
    let names: Vec<String> = entries.iter().map(|e| settings.display(e)).collect();
    let pool = thread_pool(o.threads)?;
    // a parameter the records cannot pin is held at the value the user gave (the description,
    // --params, --set), not where the steady stage left it: the steady law alone may move it far
    // (a blow-off never reached, a bleed traded for a blow-off) within its wide box
    let given_values = entry_values(&entries, &records)?;
    let steady = steady_stage(&mut records, &entries, &settings, &pool)?;
    // every record's model starts where the steady stage left its setting
    let starts = entry_values(&entries, &records)?;
    let base = records[0].model.params;
    let scales: Vec<Bound> =
        entries.iter().zip(&starts).map(|(e, &s)| search_box(e.name, s, &base)).collect::<Result<_, _>>()?;
    let before = forces(&records, &[], &[])?;
    let inputs = inform(&mut records, &before, &pool)?;
    let problem = Problem {
        records: &records,
        entries: &entries,
        names: &names,
        measured: records.iter().flat_map(|r| r.measured.iter().copied()).collect(),
        kept: records.iter().flat_map(|r| r.kept.iter().copied()).collect(),
        scales: &scales,
        pool: &pool,
        inputs: &inputs,
    };
    let mut fit = problem.fit_rounds(&starts, &given_values, o, progress)?;
    let parameters = calibrated_parameters(&fit, &entries, &names, &settings, &starts, &scales);
    let covariance = covariance(&fit.last);
    let after = forces(&records, &entries, &fit.x)?;
    fit.model_runs += 1;
    Ok(Calibration {
        parameters,
        records: record_fits(&records, &settings, &before, &after),
        rounds: fit.rounds,
        given: given_parameters(&base, &entries),
        rtol: base.rtol,
        model_runs: fit.model_runs,
        seconds: t0.elapsed().as_secs_f64(),
        threads: o.threads,
        steady,
        settings: settings.labels,
        covariance,
    })
}

/// Each entry's value in the model of the first record it applies to.
fn entry_values(entries: &[Entry], records: &[Record]) -> Result<Vec<f64>, Error> {
    entries
        .iter()
        .map(|e| {
            let r = records.iter().find(|r| e.applies_to(r.setting)).expect("every setting has a record");
            get_real(&r.model.params, e.name)
        })
        .collect()
}

/// What the fits minimise: the records' stacked force residuals over the samples kept, as a
/// function of the entries' values.
struct Problem<'a> {
    records: &'a [Record],
    entries: &'a [Entry],
    /// The entries' names as reported.
    names: &'a [String],
    /// Every record's measured force, stacked (N).
    measured: Vec<f64>,
    /// Per stacked sample: scored.
    kept: Vec<bool>,
    /// Each entry's search box.
    scales: &'a [Bound],
    pool: &'a rayon::ThreadPool,
    /// The records' model inputs for [`lm::solve`] ([`inform`]).
    inputs: &'a [Vec<f64>],
}

/// Where the rounds of fits ended.
struct FitRounds {
    /// Every entry's value: fitted, or held at its given value.
    x: Vec<f64>,
    /// Per entry: why it is held, or `None` where it was fitted.
    held: Vec<Option<String>>,
    rounds: Vec<Round>,
    /// The last fit (the one that held nothing): its entries and its solution.
    last: Option<(Vec<usize>, Solution)>,
    model_runs: usize,
}

impl Problem<'_> {
    /// The stacked residuals (model − measured, N) over the samples kept, with the entries
    /// `active` at `y` and every other at its value in `x_held`.
    fn residuals(&self, active: &[usize], x_held: &[f64], y: &[f64]) -> Result<Vec<f64>, Error> {
        let mut all_x = x_held.to_vec();
        for (k, &i) in active.iter().enumerate() {
            all_x[i] = y[k];
        }
        let f = forces(self.records, self.entries, &all_x)?;
        Ok(f.iter()
            .flatten()
            .zip(&self.measured)
            .zip(&self.kept)
            .filter(|(_, k)| **k)
            .map(|((m, y), _)| m - y)
            .collect())
    }

    /// Fits every entry not yet held, from `starts`; holds the worst one the data cannot pin at
    /// its `given_values` and fits again, until every fitted entry is pinned.
    fn fit_rounds(
        &self,
        starts: &[f64],
        given_values: &[f64],
        o: &CalibrateOptions,
        progress: &(dyn Fn(&Round) + Sync),
    ) -> Result<FitRounds, Error> {
        let n_entries = self.entries.len();
        let mut x = starts.to_vec();
        // the values of held entries (the others are overwritten by each fit)
        let mut x_held = starts.to_vec();
        let mut held: Vec<Option<String>> = vec![None; n_entries];
        let mut rounds: Vec<Round> = Vec::new();
        let mut last: Option<(Vec<usize>, Solution)> = None;
        let mut model_runs = 1;
        while held.iter().any(Option::is_none) {
            let active: Vec<usize> = (0..n_entries).filter(|&i| held[i].is_none()).collect();
            let active_names: Vec<String> = active.iter().map(|&i| self.names[i].clone()).collect();
            let residuals = |y: &[f64]| self.residuals(&active, &x_held, y);
            let x0: Vec<f64> = active.iter().map(|&i| x[i]).collect();
            let sc: Vec<Bound> = active.iter().map(|&i| self.scales[i]).collect();
            let s = lm::solve(&residuals, &x0, &sc, self.pool, lm::Options::default(), self.inputs)?;
            model_runs += s.model_runs;
            for (k, &i) in active.iter().enumerate() {
                x[i] = s.x[k];
            }
            let bad = worst(&s, &active_names, o);
            let mut round = Round {
                fitted: active_names,
                iterations: s.iterations,
                model_runs: s.model_runs,
                converged: s.converged,
                rms_residual: (s.cost / s.residuals as f64).sqrt(),
                held: None,
            };
            match bad {
                Some((k, why)) => {
                    let i = active[k];
                    x[i] = given_values[i];
                    x_held[i] = given_values[i];
                    held[i] = Some(why.clone());
                    round.held = Some((self.names[i].clone(), why));
                    progress(&round);
                    rounds.push(round);
                }
                None => {
                    progress(&round);
                    rounds.push(round);
                    last = Some((active, s));
                    break;
                }
            }
        }
        Ok(FitRounds { x, held, rounds, last, model_runs })
    }
}

/// Each entry as calibrated: its value, its uncertainty and strongest correlation from the last
/// fit (none where held), its box and status.
fn calibrated_parameters(
    fit: &FitRounds,
    entries: &[Entry],
    names: &[String],
    settings: &Settings,
    starts: &[f64],
    scales: &[Bound],
) -> Vec<Calibrated> {
    entries
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let unit = match lookup(e.name) {
                Ok(Param::Real(v)) => v.unit(),
                _ => "1",
            };
            let (std_error, correlation) = match &fit.last {
                Some((active, s)) if fit.held[i].is_none() => {
                    let k = active.iter().position(|&a| a == i).expect("active");
                    (s.std_error(k), s.strongest_correlation(k).map(|(j, c)| (names[active[j]].clone(), c)))
                }
                _ => (None, None),
            };
            Calibrated {
                name: e.name,
                setting: e.setting.map(|s| settings.labels[s].clone()),
                unit,
                start: starts[i],
                value: fit.x[i],
                std_error,
                correlation,
                scale: scales[i],
                status: fit.held[i].clone().map_or(Status::Fitted, Status::Held),
            }
        })
        .collect()
}

/// The last fit's covariance of its parameters, where it has one.
fn covariance(last: &Option<(Vec<usize>, Solution)>) -> Option<Covariance> {
    last.as_ref().and_then(|(active, s)| {
        let c = s.covariance.as_ref()?;
        Some(Covariance {
            parameters: active.clone(),
            matrix: (0..active.len()).map(|i| (0..active.len()).map(|j| c[(i, j)]).collect()).collect(),
        })
    })
}

/// Each record's force error before and after (`before`, `after`: the model's forces, N), and
/// the white-noise floor of its residual after.
fn record_fits(records: &[Record], settings: &Settings, before: &[Vec<f64>], after: &[Vec<f64>]) -> Vec<RecordFit> {
    records
        .iter()
        .zip(before.iter().zip(after))
        .map(|(r, (b, a))| {
            let residual: Vec<f64> = a.iter().zip(&r.measured).map(|(m, y)| m - y).collect();
            RecordFit {
                path: r.path.clone(),
                setting: settings.labels[r.setting].clone(),
                samples: r.measured.len(),
                nrmse_before: nrmse(&r.measured, b),
                nrmse_after: nrmse(&r.measured, a),
                noise_floor: noise_sigma(&residual) / std(&r.measured),
            }
        })
        .collect()
}

/// The parameters of `--params` and `--set` not fitted, for the parameter set; not the run's
/// own settings (control mode, tare, tolerance), which the parameter set does not carry.
fn given_parameters(base: &Parameters, entries: &[Entry]) -> Vec<(&'static str, Value)> {
    let skip = ["control_mode", "tare_load_cell", "rtol"];
    changed_parameters(base)
        .into_iter()
        .filter(|(n, _)| !entries.iter().any(|e| e.name == *n) && !skip.contains(n))
        .collect()
}

/// The steady stage of a passive damper's calibration: the force–velocity law of the entries to
/// fit that shape it ([`STEADY_FIT`]) fitted on the quasi-steady samples of every record (each at
/// its setting), from several starts ([`crate::steady::fit_steady`]); the records' models then
/// start the dynamic fit there. None for another damper or too few quasi-steady samples (the
/// dynamic fit then starts from the description).
fn steady_stage(
    records: &mut [Record],
    entries: &[Entry],
    settings: &Settings,
    pool: &rayon::ThreadPool,
) -> Result<Option<SteadyStage>, Error> {
    let base = records[0].model.params;
    if !crate::steady::is_passive(&base) {
        return Ok(None);
    }
    let fitted: Vec<Entry> = entries.iter().copied().filter(|e| STEADY_FIT.contains(&e.name)).collect();
    let points: Vec<_> = records
        .iter()
        .flat_map(|r| crate::steady::steady_points(&r.drive, r.model.params.x_damper_start, &r.measured, r.setting))
        .collect();
    if fitted.is_empty() || points.len() < 4 * fitted.len() {
        return Ok(None);
    }
    let fit = crate::steady::fit_steady(&base, &fitted, &points, pool)?;
    let values: Vec<f64> = fit.fitted.iter().map(|f| f.2).collect();
    for r in records.iter_mut() {
        apply(&mut r.model.params, &fitted, &values, r.setting)?;
    }
    Ok(Some(SteadyStage {
        points: fit.points,
        starts: fit.starts,
        rms_before: fit.rms_before,
        rms_after: fit.rms_after,
        fitted: fit.fitted.iter().map(|(e, from, to)| (settings.display(e), *from, *to)).collect(),
    }))
}
