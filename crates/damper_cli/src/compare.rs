//! `damper compare`: the model driven by the measured inputs, overlaid on the measurement, and
//! where it fails. Writes `DIR/report.html` and `DIR/summary.json` and prints a summary.

use crate::analysis::{analyse, Analysis};
use crate::dsp::mean;
use crate::measurement::{Mapping, Measurement, DEFAULT_MAX_GAP};
use crate::model::{Backend, Drive, Model, Prediction};
use crate::parameters::{
    changed_parameters, effect, effect_on, effects, set_effect, set_parameter, set_real, EffectExt, Value,
};
use crate::summary::{self, Summary};
use crate::units::Column;
use semi_active_damper::variables::default_parameters;
use std::path::PathBuf;
use std::time::Instant;

/// Fewest samples in each of the train and validation parts.
pub const MIN_PART: usize = 100;

/// Options of `damper compare`.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    pub measurement: PathBuf,
    pub out: PathBuf,
    /// `KEY` or `KEY=VALUE` (the effect's first parameter).
    pub with: Vec<String>,
    pub without: Vec<String>,
    pub maps: Vec<Mapping>,
    /// `--set NAME=VALUE`, applied last.
    pub sets: Vec<(String, String)>,
    /// Share of the samples in the train part.
    pub split: f64,
    /// The measured force has its rest offset removed (the model's `tare_load_cell`).
    pub tare_load_cell: bool,
    /// Load-cell low-pass applied to the model's force [Hz].
    pub load_cell_lowpass_hz: Option<f64>,
    /// Run the model through this packaged FMU instead of in-process (`--fmu`).
    pub fmu: Option<PathBuf>,
    /// Print nothing.
    pub quiet: bool,
    /// Effects left out of a diagnosis's candidates (`--skip`).
    pub skip: Vec<String>,
    /// Most samples missing in one gap of the time column that are interpolated (`--max-gap`);
    /// a longer gap is an error.
    pub max_gap: usize,
}

impl CompareOptions {
    pub fn new(measurement: impl Into<PathBuf>, out: impl Into<PathBuf>) -> CompareOptions {
        CompareOptions {
            measurement: measurement.into(),
            out: out.into(),
            with: Vec::new(),
            without: Vec::new(),
            maps: Vec::new(),
            sets: Vec::new(),
            split: 0.7,
            tare_load_cell: false,
            load_cell_lowpass_hz: None,
            fmu: None,
            quiet: true,
            skip: Vec::new(),
            max_gap: DEFAULT_MAX_GAP,
        }
    }
}

/// The model a comparison uses and how it differs from the default.
#[derive(Clone, Debug)]
pub struct ModelSetup {
    pub model: Model,
    /// Where it runs: in-process or through the FMU of `--fmu`.
    pub backend: Backend,
    /// (effect key, on) for the whole catalog.
    pub effects: Vec<(&'static str, bool)>,
    /// Parameters that differ from the model's defaults.
    pub changed: Vec<(&'static str, Value)>,
}

/// Builds the model for a drive: defaults, control mode from the drive, tare, `--with`,
/// `--without`, then `--set`; the FMU of `--fmu` imported and checked against the parameters.
pub fn build_model(opts: &CompareOptions, drive: &Drive) -> Result<ModelSetup, String> {
    let mut p = default_parameters();
    p.control_mode = drive.control_mode();
    p.tare_load_cell = opts.tare_load_cell;
    for w in &opts.with {
        let (key, value) = match w.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (w.trim(), None),
        };
        let e = effect(key)?;
        if opts.without.iter().any(|o| effect(o).map(|x| x.key) == Ok(e.key)) {
            return Err(format!("effect {} is both in --with and --without", e.key));
        }
        set_effect(&mut p, e.key, true)?;
        if let Some(v) = value {
            set_parameter(&mut p, e.size_parameter(), v).map_err(|err| format!("--with {w}: {err}"))?;
        }
    }
    for w in &opts.without {
        set_effect(&mut p, w, false)?;
    }
    for (name, value) in &opts.sets {
        set_parameter(&mut p, name, value).map_err(|e| format!("--set {name}={value}: {e}"))?;
    }
    if p.control_mode != drive.control_mode() {
        return Err(format!(
            "--set control_mode={} contradicts the measurement: it has {} (control_mode {})",
            p.control_mode,
            if drive.control_mode() == 0 { "F_demand" } else { "only x_spool_demand" },
            drive.control_mode()
        ));
    }
    p.validate().map_err(|e| format!("model parameters: {e}"))?;
    if let Some(fc) = opts.load_cell_lowpass_hz {
        if !(fc > 0.0 && fc.is_finite()) {
            return Err(format!("--load-cell-lowpass {fc}: must be a positive frequency in Hz"));
        }
    }
    let backend = match &opts.fmu {
        Some(path) => Backend::fmu(path)?,
        None => Backend::InProcess,
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
pub fn split_index(m: &Measurement, fraction: f64) -> Result<usize, String> {
    if !(fraction > 0.0 && fraction < 1.0) {
        return Err(format!("--split {fraction}: must be between 0 and 1 (the train share)"));
    }
    let n = m.len();
    let split = (fraction * n as f64).round() as usize;
    if split < MIN_PART || n - split < MIN_PART {
        return Err(format!(
            "{}, line {}, {}: the record has only {n} samples ({:.3} s); --split {fraction} leaves {split} for training \
             and {} for validation, and each part needs at least {MIN_PART}",
            m.path,
            m.lines.last().copied().unwrap_or(0),
            m.describe_column(Column::Time),
            m.time[n - 1] - m.time[0],
            n - split
        ));
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
    /// Wall time of the model run [s].
    pub run_seconds: f64,
    pub warnings: Vec<String>,
}

/// Reads, runs and analyses (no files written).
pub fn compare(opts: &CompareOptions) -> Result<Comparison, String> {
    let m = Measurement::read(&opts.measurement, &opts.maps, opts.max_gap)?;
    let split = split_index(&m, opts.split)?;
    let drive = Drive::from_measurement(&m);
    let setup = build_model(opts, &drive)?;
    let t0 = Instant::now();
    let prediction = setup.backend.run(&setup.model, &drive).map_err(|e| format!("{}: {e}", m.path))?;
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

/// `damper compare`: compare, write the report and the summary, print the summary.
pub fn run(opts: &CompareOptions) -> Result<Comparison, String> {
    let c = compare(opts)?;
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: cannot create: {e}", opts.out.display()))?;
    let json_path = opts.out.join("summary.json");
    std::fs::write(&json_path, summary::to_json(&summary(&c))).map_err(|e| format!("{}: {e}", json_path.display()))?;
    let html_path = opts.out.join("report.html");
    std::fs::write(&html_path, crate::report::html(&c)).map_err(|e| format!("{}: {e}", html_path.display()))?;
    if !opts.quiet {
        print!("{}", terminal_summary(&c));
        println!("report:  {}", html_path.display());
        println!("summary: {}", json_path.display());
    }
    Ok(c)
}

fn metrics(m: &crate::dsp::Metrics) -> summary::Metrics {
    summary::Metrics {
        fit_percent: m.fit_percent,
        nrmse: m.nrmse,
        rmse: m.rmse,
        bias: m.bias,
        std_measured: m.std_measured,
        samples: m.samples,
    }
}

/// The model settings of the summary.
pub fn model_settings(setup: &ModelSetup) -> summary::ModelSettings {
    let p = &setup.model.params;
    summary::ModelSettings {
        control_mode: p.control_mode.into(),
        tare_load_cell: p.tare_load_cell,
        load_cell_lowpass_hz: setup.model.load_cell_lowpass_hz,
        backend: setup.backend.name().into(),
        fmu: setup.backend.fmu_path().map(|p| p.display().to_string()),
        effects: setup.effects.iter().map(|(k, on)| (k.to_string(), *on)).collect(),
        changed_parameters: setup.changed.iter().map(|(n, v)| (n.to_string(), (*v).into())).collect(),
    }
}

/// `summary.json`, with the diagnosis empty.
pub fn summary(c: &Comparison) -> Summary {
    let a = &c.analysis;
    let m = &c.measurement;
    let f = a.force();
    let w = &a.whiteness;
    Summary {
        tool: "damper compare".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        measurement: m.path.clone(),
        samples: m.len(),
        sample_interval_s: a.dt,
        duration_s: m.time[m.len() - 1] - m.time[0],
        control_mode: if c.drive.control_mode() == 0 { "force" } else { "spool_position" }.into(),
        velocity_from_displacement: m.velocity_from_displacement,
        model: model_settings(&c.setup),
        split: summary::Split {
            train_fraction: c.options.split,
            first_validation_sample: a.split,
            t_split: m.time[a.split],
        },
        residual_definition: "model - measured (as in docs/effects.md)".into(),
        nrmse_baseline: f.validation.nrmse,
        observations: crate::analysis::observations(a),
        noise_floor_estimate: a.noise_floor_estimate,
        signals: a
            .fits
            .iter()
            .map(|s| {
                let signal = summary::Signal {
                    unit: s.column.si_unit().into(),
                    train: metrics(&s.train),
                    validation: metrics(&s.validation),
                    lag_s: s.lag.seconds,
                    lag_refined_s: s.lag.refined_seconds,
                    lag_of_changes_s: s.lag.changes_seconds,
                };
                (s.column.name().to_string(), signal)
            })
            .collect(),
        regimes: a
            .regimes
            .iter()
            .map(|r| summary::Regime {
                group: r.group.into(),
                regime: r.name.clone(),
                samples: r.samples,
                time_share: r.time_share,
                rms_residual: r.rms,
                mean_residual: r.mean,
                error_share: r.error_share,
                concentration: r.concentration,
            })
            .collect(),
        frequency_bands: a
            .bands
            .iter()
            .map(|b| summary::Band {
                f_lo_hz: b.lo,
                f_hi_hz: b.hi,
                residual_share: b.residual_share,
                residual_rms: b.residual_rms,
                band_nrmse: b.band_nrmse,
            })
            .collect(),
        worst_windows: a
            .worst
            .iter()
            .map(|w| summary::Window {
                t_start: w.t_start,
                t_end: w.t_end,
                rms_residual: w.rms,
                mean_residual: w.mean,
                mean_abs_velocity: w.mean_abs_velocity,
                tags: w.tags.clone(),
            })
            .collect(),
        lag: summary::Lag {
            samples: f.lag.samples as i64,
            seconds: f.lag.seconds,
            refined_seconds: f.lag.refined_seconds,
            peak_correlation: f.lag.peak,
            search_range_s: f.lag.max_seconds,
            of_changes_s: f.lag.changes_seconds,
            definition: "argmax_k sum_t y(t+k) yhat(t): positive = the measured force comes later".into(),
        },
        whiteness: summary::Whiteness {
            part: "validation".into(),
            samples: w.samples,
            max_lag: w.max_lag,
            band: w.band,
            fraction_outside: w.fraction_outside,
            ljung_box_q: w.ljung_box_q,
            ljung_box_lags: w.ljung_box_lags,
            chi2_95: w.chi2_95,
            white: w.white,
        },
        input_cross_correlation: a
            .input_correlations
            .iter()
            .map(|x| {
                let xc = summary::CrossCorrelation {
                    max_abs: x.max_abs,
                    at_lag_s: x.at_lag_seconds,
                    band: x.band,
                    within_band: x.max_abs <= x.band,
                };
                (x.input.name().to_string(), xc)
            })
            .collect(),
        events: summary::Events {
            velocity_reversals: a.reversals.len(),
            demand_steps: a.demand_steps.len(),
            residual_jump_at_reversals: a.reversal_jump,
        },
        model_run_s: c.run_seconds,
        warnings: c.warnings.clone(),
        verdict: None,
        best_effect: None,
        candidates: None,
        diagnosis: None,
    }
}

/// The terminal summary.
pub fn terminal_summary(c: &Comparison) -> String {
    use std::fmt::Write;
    let a = &c.analysis;
    let m = &c.measurement;
    let mut s = String::new();
    let dur = m.time[m.len() - 1] - m.time[0];
    let _ = writeln!(
        s,
        "damper compare: {} — {} samples, {:.0} Hz, {:.2} s, {} control",
        m.path,
        m.len(),
        1.0 / a.dt,
        dur,
        if c.drive.control_mode() == 0 { "force" } else { "spool-position" }
    );
    let _ = writeln!(s, "model: {}", describe_model(&c.setup));
    let _ = writeln!(s, "model run: {:.2} s ({:.0}× real time)", c.run_seconds, dur / c.run_seconds.max(1e-9));
    let _ = writeln!(
        s,
        "{:<16}{:>10}{:>10}{:>12}{:>10}{:>12}",
        "signal", "train fit", "NRMSE", "valid. fit", "NRMSE", "lag [ms]"
    );
    for f in &a.fits {
        let _ = writeln!(
            s,
            "{:<16}{:>9.1}%{:>10.4}{:>11.1}%{:>10.4}{:>12.2}",
            f.column.name(),
            f.train.fit_percent,
            f.train.nrmse,
            f.validation.fit_percent,
            f.validation.nrmse,
            f.lag.refined_seconds * 1e3
        );
    }
    let f = a.force();
    let _ = writeln!(
        s,
        "F_damper validation NRMSE {:.4} (white-noise floor estimate {:.4}); lag {} samples ({:+.2} ms refined, \
         {:+.2} ms on the changes; + = measurement later)",
        f.validation.nrmse,
        a.noise_floor_estimate,
        f.lag.samples,
        f.lag.refined_seconds * 1e3,
        f.lag.changes_seconds * 1e3
    );
    if let Some(j) = a.reversal_jump {
        let _ = writeln!(
            s,
            "residual jump across velocity reversals: {j:+.0} N over {} reversals (a missing friction F·sign(v) gives −2F)",
            a.reversals.len()
        );
    }
    let w = &a.whiteness;
    let _ = writeln!(
        s,
        "residual whiteness (validation): {:.1} % of lags 1..{} outside ±1.96/√N, Ljung–Box Q({}) = {:.1} vs {:.1}: {}",
        100.0 * w.fraction_outside,
        w.max_lag,
        w.ljung_box_lags,
        w.ljung_box_q,
        w.chi2_95,
        if w.white { "white" } else { "not white" }
    );
    let _ = writeln!(s, "observations:");
    for o in crate::analysis::observations(a) {
        let _ = writeln!(s, "  - {o}");
    }
    let mut hot: Vec<_> = a.regimes.iter().filter(|r| r.samples > 0 && r.time_share >= 0.01).collect();
    hot.sort_by(|x, y| y.concentration.total_cmp(&x.concentration));
    let _ = writeln!(s, "where it fails (share of squared error / share of time):");
    for r in hot.iter().take(4) {
        let _ = writeln!(
            s,
            "  {:<11} {:<36} {:>5.1} % / {:>5.1} %  (×{:.2}), RMS {:.0} N, mean {:+.0} N",
            r.group,
            r.name,
            100.0 * r.error_share,
            100.0 * r.time_share,
            r.concentration,
            r.rms,
            r.mean
        );
    }
    if let Some(wst) = a.worst.first() {
        let _ = writeln!(
            s,
            "worst window: {:.3}–{:.3} s, RMS {:.0} N ({})",
            wst.t_start,
            wst.t_end,
            wst.rms,
            wst.tags.join(", ")
        );
    }
    for w in &c.warnings {
        let _ = writeln!(s, "note: {w}");
    }
    s
}

/// One line: effects off/on against the default, changed parameters, tare, filter and backend.
pub fn describe_model(setup: &ModelSetup) -> String {
    let defaults: Vec<(&str, bool)> = effects().map(|e| (e.key, e.default_on())).collect();
    let mut parts = Vec::new();
    for ((k, on), (_, d)) in setup.effects.iter().zip(&defaults) {
        if on != d {
            parts.push(format!("{}{}", if *on { "+" } else { "−" }, k));
        }
    }
    let on: Vec<&str> = setup.effects.iter().filter(|e| e.1).map(|e| e.0).collect();
    let mut s = if parts.is_empty() {
        format!("default effects ({})", on.join(", "))
    } else {
        format!("default {} → effects on: {}", parts.join(" "), on.join(", "))
    };
    let changed: Vec<String> = setup
        .changed
        .iter()
        .filter(|(n, _)| !n.starts_with("effect_") && *n != "control_mode" && *n != "tare_load_cell")
        .map(|(n, v)| format!("{n}={v}"))
        .collect();
    if !changed.is_empty() {
        s += &format!("; {}", changed.join(", "));
    }
    s += &format!("; tare_load_cell {}", setup.model.params.tare_load_cell);
    if let Some(fc) = setup.model.load_cell_lowpass_hz {
        s += &format!("; load-cell low-pass {fc} Hz");
    }
    s += &format!("; {}", setup.backend.describe());
    s
}

/// Sets a Real parameter, for callers outside (diagnose, tests).
pub fn with_real(setup: &ModelSetup, name: &str, value: f64) -> Result<Model, String> {
    let mut model = setup.model;
    set_real(&mut model.params, name, value)?;
    Ok(model)
}
