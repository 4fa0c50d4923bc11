//! A comparison: the measurement read, the model driven by its inputs, and the analysis of where
//! it fails (what `damper compare` shows; nothing written or printed here).

use crate::analysis::{analyse, Analysis};
use crate::dsp::mean;
use crate::error::{Error, Place};
use crate::fmu_model::FmuModel;
use crate::measurement::{Mapping, Measurement, DEFAULT_MAX_GAP};
use crate::model::{Backend, Drive, InProcess, Model, Prediction};
use crate::parameters::{changed_parameters, effect, effect_on, effects, set_effect, set_parameter, EffectExt, Value};
use crate::units::Column;
use semi_active_damper::physics::params::Parameters;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

/// Fewest samples in each of the train and validation parts.
pub const MIN_PART: usize = 100;

/// What to compare and with which model (`damper compare`'s options but where the results go).
#[derive(Clone, Debug)]
pub struct CompareOptions {
    pub measurement: PathBuf,
    /// `KEY` or `KEY=VALUE` (the effect's first parameter).
    pub with: Vec<String>,
    pub without: Vec<String>,
    pub maps: Vec<Mapping>,
    /// `--damper FILE.toml`: the damper's description (its datasheet), applied to the defaults
    /// first.
    pub damper_file: Option<PathBuf>,
    /// `--params FILE.ssv`: an SSP parameter set applied after the description, before `--with`,
    /// `--without` and `--set`.
    pub params_file: Option<PathBuf>,
    /// `--set NAME=VALUE`, applied last.
    pub sets: Vec<(String, String)>,
    /// Share of the samples in the train part.
    pub split: f64,
    /// The measured force has its rest offset removed (the model's `tare_load_cell`).
    pub tare_load_cell: bool,
    /// Load-cell low-pass applied to the model's force (Hz).
    pub load_cell_lowpass_hz: Option<f64>,
    /// Run the model through this packaged FMU instead of in-process (`--fmu`).
    pub fmu: Option<PathBuf>,
    /// Effects left out of a diagnosis's candidates (`--skip`).
    pub skip: Vec<String>,
    /// Most samples missing in one gap of the time column that are interpolated (`--max-gap`);
    /// a longer gap is an error.
    pub max_gap: usize,
    /// The model's `rtol` at most this, unless `--set rtol=…` (diagnose and calibrate: [`ANALYSIS_RTOL`]).
    pub rtol_at_most: Option<f64>,
    /// Columns negated as they are read (`--flip`): a logger's other sign convention.
    pub flips: Vec<Column>,
    /// The time column wins over a sample rate the logger states in a comment (`--trust-time-column`).
    pub trust_time_column: bool,
    /// Drive the model with a velocity made again from the displacement where the logger's was
    /// made from it ([`Measurement::with_velocity_made_again`]): the diagnosis's choice.
    pub velocity_made_again: bool,
    /// The calibration whose parameter set the model runs with (`--calibration`), and the setting
    /// of its parameter set: a diagnosis carries its uncertainty into what it fits.
    pub calibration: Option<(PathBuf, Option<String>)>,
}

/// The tolerance `diagnose` and `calibrate` run the model at, unless the user sets one: the
/// FMU's default (3e-4) leaves a numerical error at fast transients that a diagnosis can fit (at
/// 1e-3 it was about 0.3 load-cell noise sigmas, and a candidate fitted it and was named); 3e-5
/// leaves 1.5 N RMS against a converged run, 0.08 of the rig's 20 N sigma (`cargo bench --bench
/// realtime`, docs/performance.md).
pub const ANALYSIS_RTOL: f64 = 3e-5;

impl CompareOptions {
    pub fn new(measurement: impl Into<PathBuf>) -> CompareOptions {
        CompareOptions {
            measurement: measurement.into(),
            with: Vec::new(),
            without: Vec::new(),
            maps: Vec::new(),
            damper_file: None,
            params_file: None,
            sets: Vec::new(),
            split: 0.7,
            tare_load_cell: false,
            load_cell_lowpass_hz: None,
            fmu: None,
            skip: Vec::new(),
            max_gap: DEFAULT_MAX_GAP,
            rtol_at_most: None,
            flips: Vec::new(),
            trust_time_column: false,
            velocity_made_again: false,
            calibration: None,
        }
    }
}

/// The model a comparison uses and how it differs from the default.
#[derive(Clone, Debug)]
pub struct ModelSetup {
    pub model: Model,
    /// Where it runs: in-process or through the FMU of `--fmu`.
    pub backend: Arc<dyn Backend>,
    /// (effect key, on) for the whole catalog.
    pub effects: Vec<(&'static str, bool)>,
    /// Parameters that differ from the model's defaults.
    pub changed: Vec<(&'static str, Value)>,
}

/// Builds the model for a drive: defaults, `--damper`, control mode from the drive, the starting
/// stroke from a measured displacement, tare, `--params`, `--with`, `--without`, then `--set`;
/// the FMU of `--fmu` imported and checked against the parameters.
pub fn build_model(opts: &CompareOptions, drive: &Drive) -> Result<ModelSetup, Error> {
    let mut p = Parameters::default();
    if let Some(file) = &opts.damper_file {
        let description = crate::description::Description::read(file)?;
        description.apply(&mut p)?;
        if description.kind == crate::description::Kind::Passive && drive.control_mode() != 2 {
            return Err(Error::PassiveWithDemand {
                path: file.clone(),
                demand: if drive.control_mode() == 0 { "F_demand" } else { "x_spool_demand" },
            });
        }
    }
    p.control_mode = drive.control_mode();
    p.tare_load_cell = opts.tare_load_cell;
    if let Some(x) = drive.x_damper_start {
        p.x_damper_start = x;
    }
    if let Some(file) = &opts.params_file {
        crate::ssv::apply(&mut p, file)?;
    }
    for w in &opts.with {
        let (key, value) = match w.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (w.trim(), None),
        };
        let e = effect(key)?;
        if opts.without.iter().any(|o| effect(o).ok().map(|x| x.key) == Some(e.key)) {
            return Err(Error::WithAndWithout { effect: e.key });
        }
        set_effect(&mut p, e.key, true)?;
        if let Some(v) = value {
            set_parameter(&mut p, e.size_parameter(), v).map_err(|err| err.context(format!("--with {w}")))?;
        }
    }
    for w in &opts.without {
        set_effect(&mut p, w, false)?;
    }
    for (name, value) in &opts.sets {
        set_parameter(&mut p, name, value).map_err(|e| e.context(format!("--set {name}={value}")))?;
    }
    if let Some(rtol) = opts.rtol_at_most.filter(|_| !opts.sets.iter().any(|(name, _)| name == "rtol")) {
        p.rtol = p.rtol.min(rtol);
    }
    if p.control_mode != drive.control_mode() {
        return Err(Error::ControlMode {
            set: p.control_mode,
            has: match drive.control_mode() {
                0 => "F_demand",
                1 => "only x_spool_demand",
                _ => "no demand",
            },
            mode: drive.control_mode(),
        });
    }
    p.validate().map_err(Error::ModelParameters)?;
    if let Some(fc) = opts.load_cell_lowpass_hz {
        if !(fc > 0.0 && fc.is_finite()) {
            return Err(Error::BadOption {
                option: format!("--load-cell-lowpass {fc}"),
                problem: "must be a positive frequency in Hz".into(),
            });
        }
    }
    let backend: Arc<dyn Backend> = match &opts.fmu {
        Some(path) => Arc::new(FmuModel::open(path)?),
        None => Arc::new(InProcess),
    };
    let effects = effects().map(|e| (e.key, effect_on(&p, e.key).unwrap_or(false))).collect();
    Ok(ModelSetup {
        model: Model { params: p, load_cell_lowpass_hz: opts.load_cell_lowpass_hz },
        backend,
        effects,
        changed: changed_parameters(&p),
    })
}

/// The split index, or an error naming the file, the last line and the time column.
pub fn split_index(m: &Measurement, fraction: f64) -> Result<usize, Error> {
    if !(fraction > 0.0 && fraction < 1.0) {
        return Err(Error::BadOption {
            option: format!("--split {fraction}"),
            problem: "must be between 0 and 1 (the train share)".into(),
        });
    }
    let n = m.len();
    let split = (fraction * n as f64).round() as usize;
    if split < MIN_PART || n - split < MIN_PART {
        return Err(Error::InFile {
            at: Place::field(&m.path, m.lines.last().copied().unwrap_or(0), m.describe_column(Column::Time)),
            problem: format!(
                "the record has only {n} samples ({:.3} s); --split {fraction} leaves {split} for training \
                 and {} for validation, and each part needs at least {MIN_PART}",
                m.time[n - 1] - m.time[0],
                n - split
            ),
        });
    }
    Ok(split)
}

/// A finished comparison.
#[derive(Clone, Debug)]
pub struct Comparison {
    pub options: CompareOptions,
    pub measurement: Measurement,
    pub drive: Drive,
    pub setup: ModelSetup,
    pub prediction: Prediction,
    pub analysis: Analysis,
    /// Wall time of the model run (s).
    pub run_seconds: f64,
    pub warnings: Vec<String>,
}

/// Reads, runs and analyses (no files written).
pub fn compare(opts: &CompareOptions) -> Result<Comparison, Error> {
    let m = read_checked(opts, &opts.measurement)?;
    let split = split_index(&m, opts.split)?;
    crate::record_checks::check(&m, split)?;
    let drive = Drive::from_measurement(&m);
    let setup = build_model(opts, &drive)?;
    let t0 = Instant::now();
    let prediction = setup.backend.run(&setup.model, &drive).map_err(|e| e.context(&m.path))?;
    let run_seconds = t0.elapsed().as_secs_f64();
    let analysis = analyse(&m, &drive, &prediction, split);
    let mut warnings = m.notes.clone();
    if !m.ignored.is_empty() {
        warnings.push(format!("columns not used: {}", m.ignored.join(", ")));
    }
    if let Some(w) = tare_hint(&m, &prediction, opts.tare_load_cell) {
        warnings.push(w);
    }
    Ok(Comparison { options: opts.clone(), measurement: m, drive, setup, prediction, analysis, run_seconds, warnings })
}

/// Reads a record with the options' columns, flips and gaps, and checks its traps
/// ([`crate::record_traps`]): the samples a clipped force leaves out are marked in `excluded`, the
/// warnings added to its notes.
pub fn read_checked(opts: &CompareOptions, path: &std::path::Path) -> Result<Measurement, Error> {
    let mut m = Measurement::read_flipped(path, &opts.maps, opts.max_gap, &opts.flips)?;
    if opts.velocity_made_again {
        m = m.with_velocity_made_again();
    }
    let findings = crate::record_traps::check(&m, opts.trust_time_column)?;
    m.excluded = findings.excluded;
    m.notes.extend(findings.warnings);
    Ok(m)
}

/// If the record starts at rest and the measured and modelled forces there differ by the gas
/// force, the tare option is probably the wrong way round.
fn tare_hint(m: &Measurement, p: &Prediction, tare: bool) -> Option<String> {
    let v = m.get(Column::VDamper)?;
    let y = m.get(Column::FDamper)?;
    let k = v.iter().take_while(|x| x.abs() < 2e-3).count().min(200);
    if k < 10 {
        return None;
    }
    let (measured, model) = (mean(&y[..k]), mean(&p.f_damper[..k]));
    if (measured - model).abs() < 300.0 {
        return None;
    }
    Some(if tare {
        format!(
            "at rest (first {k} samples) the measured force is {measured:.0} N, the tared model's {model:.0} N: \
             if the measured force keeps the rest offset (the reservoir gas force), drop --tare-load-cell"
        )
    } else {
        format!(
            "at rest (first {k} samples) the measured force is {measured:.0} N, the model's {model:.0} N \
             (the reservoir gas force): if the load cell was zeroed at rest, add --tare-load-cell"
        )
    })
}
