//! `summary.json` of `damper compare` and `damper diagnose` as typed structs; the file's layout is
//! the field order here, its schema `docs/summary.schema.json`. Numbers are SI unless the name
//! says otherwise (`_s` seconds, `_hz` hertz); forces and their errors are in N. A number that is
//! not finite (a metric of a constant channel, a regime without samples) is written as `null`
//! and read back as NaN.

use crate::parameters::Value;
use crate::verdict::Verdict;
use indexmap::IndexMap;
use serde::{Deserialize, Deserializer, Serialize};

/// Reads `null` as NaN: serde_json writes a non-finite f64 as `null`, but reads `null` into an f64
/// only through this.
pub fn nan_if_null<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Pretty JSON (two-space indentation) with a final newline, as written to the files.
pub fn to_json<T: Serialize>(value: &T) -> String {
    let mut s = serde_json::to_string_pretty(value).expect("plain structs with string keys serialize");
    s.push('\n');
    s
}

/// A model parameter's value, with its own JSON type.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ParameterValue {
    Boolean(bool),
    Integer(i64),
    Real(f64),
}

impl From<Value> for ParameterValue {
    fn from(v: Value) -> ParameterValue {
        match v {
            Value::Real(x) => ParameterValue::Real(x),
            Value::Integer(i) => ParameterValue::Integer(i.into()),
            Value::Boolean(b) => ParameterValue::Boolean(b),
        }
    }
}

/// The summary: the comparison, and with `damper diagnose` the diagnosis.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Summary {
    /// `damper compare` (also for diagnose: the comparison is compare's).
    pub tool: String,
    /// The damper_cli version.
    pub version: String,
    /// The measurement file as given on the command line.
    pub measurement: String,
    /// Samples in the record.
    pub samples: usize,
    /// Sample interval (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub sample_interval_s: f64,
    /// Last sample time minus first (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub duration_s: f64,
    /// `force` (the record has F_demand) or `spool_position` (only x_spool_demand).
    pub control_mode: String,
    /// The velocity was differentiated from the measured displacement x_damper.
    pub velocity_from_displacement: bool,
    pub model: ModelSettings,
    pub split: Split,
    /// The residual's sign convention.
    pub residual_definition: String,
    /// Validation NRMSE of F_damper with the model as run (1); diagnose: of its baseline.
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_baseline: f64,
    /// What the analysis concludes, one sentence each.
    pub observations: Vec<String>,
    /// Validation NRMSE that white sensor noise alone would give, estimated from the second
    /// differences of the residual (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub noise_floor_estimate: f64,
    /// Per measured output, F_damper first.
    pub signals: IndexMap<String, Signal>,
    /// The F_damper residual by operating regime (whole record).
    pub regimes: Vec<Regime>,
    /// The F_damper residual by frequency band (validation part).
    pub frequency_bands: Vec<Band>,
    /// What the F_damper residual follows (whole record).
    pub residual_signature: ResidualSignature,
    /// The windows with the largest F_damper residual, worst first.
    pub worst_windows: Vec<Window>,
    /// Lag between the measured and the modelled F_damper.
    pub lag: Lag,
    pub whiteness: Whiteness,
    /// Cross-correlation of the F_damper residual with each input.
    pub input_cross_correlation: IndexMap<String, CrossCorrelation>,
    pub events: Events,
    /// Wall time of the model run (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub model_run_s: f64,
    /// Notes on the data and the settings.
    pub warnings: Vec<String>,
    /// Diagnose: what it concludes ([`Verdict`]); compare: null.
    pub verdict: Option<Verdict>,
    /// Diagnose: the best plausible candidate, if any; compare: null.
    pub best_effect: Option<String>,
    /// Diagnose: every candidate effect, best first; compare: null.
    pub candidates: Option<Vec<Candidate>>,
    /// Diagnose only: the rest of the diagnosis (absent from compare's summary).
    #[serde(flatten)]
    pub diagnosis: Option<Diagnosis>,
}

/// The model as run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ModelSettings {
    /// The model's control_mode parameter: 0 force, 1 spool position.
    pub control_mode: i64,
    /// The model's force has its rest offset removed.
    pub tare_load_cell: bool,
    /// Load-cell low-pass applied to the model's force (Hz); null: none.
    pub load_cell_lowpass_hz: Option<f64>,
    /// `in_process` or `fmu`.
    pub backend: String,
    /// The FMU file with the `fmu` backend; otherwise null.
    pub fmu: Option<String>,
    /// Every effect of the catalog: on or off.
    pub effects: IndexMap<String, bool>,
    /// The parameters that differ from the model's defaults (SI units).
    pub changed_parameters: IndexMap<String, ParameterValue>,
}

/// The train/validation split.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Split {
    /// Share of the samples in the train part (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub train_fraction: f64,
    /// Index of the first validation sample.
    pub first_validation_sample: usize,
    /// Time of the first validation sample (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub t_split: f64,
}

/// Fit of one measured output.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Signal {
    /// The SI unit of its errors.
    pub unit: String,
    pub train: Metrics,
    pub validation: Metrics,
    /// Lag of the measured signal against the model's, whole samples (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub lag_s: f64,
    /// The same, refined between samples (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub lag_refined_s: f64,
    /// The same on the sample-to-sample changes (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub lag_of_changes_s: f64,
}

/// Model against measurement on one part of the record; errors in the signal's unit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Metrics {
    /// 100 (1 − NRMSE) (%).
    #[serde(deserialize_with = "nan_if_null")]
    pub fit_percent: f64,
    /// RMS error over the measured signal's standard deviation (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse: f64,
    /// RMS error.
    #[serde(deserialize_with = "nan_if_null")]
    pub rmse: f64,
    /// Mean error, model − measured.
    #[serde(deserialize_with = "nan_if_null")]
    pub bias: f64,
    /// Standard deviation of the measured signal.
    #[serde(deserialize_with = "nan_if_null")]
    pub std_measured: f64,
    pub samples: usize,
}

/// The F_damper residual in one operating regime.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Regime {
    /// What the regimes split by (velocity, direction, demand, ...).
    pub group: String,
    pub regime: String,
    pub samples: usize,
    /// Share of the record's time in the regime (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub time_share: f64,
    /// RMS residual (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_residual: f64,
    /// Mean residual (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_residual: f64,
    /// Share of the squared residual in the regime (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub error_share: f64,
    /// error_share / time_share (1): above 1 the error concentrates there.
    #[serde(deserialize_with = "nan_if_null")]
    pub concentration: f64,
}

/// What the F_damper residual follows ([`crate::residual_signature`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ResidualSignature {
    /// Stroke, velocity, force, force rate, time (and oil temperature when measured), ranked by
    /// the share of the residual's variance above the noise that a function of each explains.
    pub follows: Vec<Follows>,
    /// The frequency band with the most residual power above the noise; null when none is above it.
    pub dominant_band: Option<DominantBand>,
    /// The same in one sentence.
    pub text: String,
}

/// One quantity of [`ResidualSignature::follows`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Follows {
    /// `stroke`, `velocity`, `force`, `force_rate`, `temperature` or `time`.
    pub quantity: String,
    /// Share of the residual's variance above the noise (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub share: f64,
}

/// [`ResidualSignature::dominant_band`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DominantBand {
    #[serde(deserialize_with = "nan_if_null")]
    pub f_lo_hz: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub f_hi_hz: f64,
    /// Share of the residual's power above the noise in the band (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub share: f64,
}

/// The F_damper residual in one frequency band.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Band {
    /// Lower band edge (Hz).
    #[serde(deserialize_with = "nan_if_null")]
    pub f_lo_hz: f64,
    /// Upper band edge (Hz).
    #[serde(deserialize_with = "nan_if_null")]
    pub f_hi_hz: f64,
    /// Share of the residual's power in the band (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub residual_share: f64,
    /// RMS of the residual in the band (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub residual_rms: f64,
    /// sqrt(residual power / measured power) in the band (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub band_nrmse: f64,
}

/// A window of large F_damper residual.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Window {
    /// Start (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub t_start: f64,
    /// End (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub t_end: f64,
    /// RMS residual (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_residual: f64,
    /// Mean residual (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_residual: f64,
    /// Mean |v_damper| (m/s).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_abs_velocity: f64,
    /// What happens in the window (reversal, demand step, ...).
    pub tags: Vec<String>,
}

/// Lag between the measured and the modelled F_damper.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Lag {
    /// Whole samples; positive: the measured force comes later.
    pub samples: i64,
    /// The same (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub seconds: f64,
    /// Refined between samples (parabola through the peak) (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub refined_seconds: f64,
    /// Normalised cross-correlation at the peak (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub peak_correlation: f64,
    /// Lags searched: ± this (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub search_range_s: f64,
    /// The same estimate on the sample-to-sample changes of both forces (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub of_changes_s: f64,
    /// False where the correlation peaks at the search's edge: the lags in seconds are then NaN.
    pub found: bool,
    pub definition: String,
}

/// Whiteness of the F_damper residual.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Whiteness {
    /// The part of the record tested (`validation`).
    pub part: String,
    pub samples: usize,
    /// Autocorrelation lags tested: 1..=max_lag.
    pub max_lag: usize,
    /// The 95 % band of a white residual's autocorrelation, ±1.96/√N (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub band: f64,
    /// Share of the lags outside the band (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub fraction_outside: f64,
    /// Ljung–Box statistic (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub ljung_box_q: f64,
    /// Lags in the Ljung–Box statistic.
    pub ljung_box_lags: usize,
    /// 95 % quantile of χ² with ljung_box_lags degrees of freedom (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub chi2_95: f64,
    /// ljung_box_q below chi2_95.
    pub white: bool,
}

/// Cross-correlation of the F_damper residual (validation part) with an input.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CrossCorrelation {
    /// Largest |correlation| over the lags (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub max_abs: f64,
    /// Its lag; positive: the residual after the input (s).
    #[serde(deserialize_with = "nan_if_null")]
    pub at_lag_s: f64,
    /// The 95 % band of an uncorrelated residual, ±1.96/√N (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub band: f64,
    /// max_abs ≤ band.
    pub within_band: bool,
}

/// Events in the record.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Events {
    pub velocity_reversals: usize,
    pub demand_steps: usize,
    /// Mean jump of the F_damper residual across the velocity reversals (N); null: too few.
    pub residual_jump_at_reversals: Option<f64>,
}

/// A fitted parameter (SI units).
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct Fitted {
    #[serde(deserialize_with = "nan_if_null")]
    pub value: f64,
    /// One standard error (Gauss–Newton, with the calibration's part where given); null: not
    /// determined.
    pub std_error: Option<f64>,
    /// The part of `std_error` inherited from the calibration (`--calibration`); null: none given.
    #[serde(default)]
    pub std_error_calibration: Option<f64>,
}

/// The parameters fitted with an effect, by name.
pub fn fitted(params: &[(&str, f64, Option<f64>)]) -> IndexMap<String, Fitted> {
    fitted_with(params, &[])
}

/// [`fitted`] with the part of each uncertainty inherited from the calibration (empty: none).
pub fn fitted_with(params: &[(&str, f64, Option<f64>)], inherited: &[Option<f64>]) -> IndexMap<String, Fitted> {
    params
        .iter()
        .enumerate()
        .map(|(i, (n, v, e))| {
            let std_error_calibration = inherited.get(i).copied().flatten();
            (n.to_string(), Fitted { value: *v, std_error: *e, std_error_calibration })
        })
        .collect()
}

/// A candidate effect, fitted on top of the baseline.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Candidate {
    pub effect: String,
    /// `switched on`, or `refitted` where the baseline has the effect.
    pub action: String,
    /// Train NRMSE of F_damper with the candidate (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_train: f64,
    /// Validation NRMSE of F_damper with the candidate (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_validation: f64,
    /// 1 − nrmse_validation / nrmse_baseline (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub reduction: f64,
    /// Share of the validation error above the noise floor it explains, (b² − c²)/(b² − f²) (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub explained: f64,
    pub params: IndexMap<String, Fitted>,
    pub plausible: bool,
    /// Why it is not plausible.
    pub flags: Vec<String>,
    /// The effect's signature in the residual.
    pub signature: String,
    /// Model runs the fit took.
    pub model_runs: usize,
}

/// The part of the summary only `damper diagnose` writes.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Diagnosis {
    /// The effects named, in the ladder's order.
    pub effects: Vec<String>,
    /// Validation NRMSE of F_damper at the ladder's end (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_after_ladder: f64,
    /// The model with the named effects against the baseline; absent when none is named.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub after: Option<After>,
    /// Validation NRMSE of the floor the verdict judges by, √(noise² + numerics²) (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_noise_floor: f64,
    /// The floor's parts and how they were estimated.
    pub floor: Floor,
    /// Why the verdict.
    pub explanation: String,
    /// The validation NRMSE as effects are added one at a time, baseline first.
    pub ladder: Vec<Rung>,
    /// The baseline's error in each part of the record against that part's floor.
    pub parts: Vec<RecordPart>,
}

/// One part of the record ([`crate::record_parts`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RecordPart {
    /// `train`, `validation` or `block k of 5`.
    pub part: String,
    #[serde(deserialize_with = "nan_if_null")]
    pub t_start: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub t_end: f64,
    /// RMS of the baseline's residual over the part (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_residual: f64,
    /// The part's floor (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_floor: f64,
    /// `rms_residual / rms_floor` (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub ratio: f64,
}

/// The floor of the validation NRMSE: sensor noise and the model's numerical error.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Floor {
    /// The sensor noise's share, σ_noise / std(F_damper) (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_noise: f64,
    /// The model's numerical error: the baseline at `rtol` against the same run at `rtol_check` (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_numerics: f64,
    /// The noise estimate used (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub noise_sigma: f64,
    /// Its two robust parts (N): median over windows of the mean-square second difference, and
    /// from the median absolute second difference.
    #[serde(deserialize_with = "nan_if_null")]
    pub noise_sigma_window: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub noise_sigma_mad: f64,
    /// The plain second-difference estimate over all samples (N): what a model error would
    /// inflate.
    #[serde(deserialize_with = "nan_if_null")]
    pub noise_sigma_all: f64,
    /// How the noise is estimated.
    pub noise_method: String,
    /// Relative tolerance of the model's runs (1).
    pub rtol: f64,
    /// Relative tolerance of the numerical check (1).
    pub rtol_check: f64,
    /// The velocity noise of the sensitivity test (m/s, RMS): the velocity's resolution estimated
    /// from the record, or the coloured noise of a velocity made from the displacement.
    pub delta_v: f64,
    /// The force's shift under it that leaves a sample out of the fits and scores (N).
    pub sensitive_threshold: f64,
    /// Validation samples left out.
    pub left_out_validation: usize,
    /// The velocity's noise carried through the model into its force, as an NRMSE on the
    /// validation part (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_inputs: f64,
    /// The part of it the noise estimate cannot see, in the floor (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_inputs_unseen: f64,
}

/// A rung of the ladder.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Rung {
    /// The effect added or refitted, `baseline` for the first rung.
    pub added: String,
    /// The effect was in the model already and was refitted.
    pub refit: bool,
    /// Its parameters on this rung.
    pub params: IndexMap<String, Fitted>,
    /// Validation NRMSE of F_damper (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub nrmse_validation: f64,
    /// Share of the error left above the floor it explains (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub explained: f64,
    /// The rung was kept (it helped enough).
    pub kept: bool,
}

/// Before and after adding the named effects.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct After {
    /// The effects added, in the ladder's order.
    pub effects: Vec<String>,
    /// Validation NRMSE of each measured output (1).
    pub validation_nrmse: IndexMap<String, BeforeAfter>,
    /// The residual is white after.
    pub white_after: bool,
    /// Ljung–Box statistic of the F_damper residual (1).
    pub ljung_box_q: BeforeAfter,
    /// RMS F_damper residual per regime (regimes with samples).
    pub regimes: Vec<RegimeChange>,
}

/// A number before and after.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct BeforeAfter {
    #[serde(deserialize_with = "nan_if_null")]
    pub before: f64,
    #[serde(deserialize_with = "nan_if_null")]
    pub after: f64,
}

/// A regime's F_damper residual before and after.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RegimeChange {
    pub group: String,
    pub regime: String,
    /// Share of the record's time in the regime (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub time_share: f64,
    /// RMS residual before (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_before: f64,
    /// RMS residual after (N).
    #[serde(deserialize_with = "nan_if_null")]
    pub rms_after: f64,
}
