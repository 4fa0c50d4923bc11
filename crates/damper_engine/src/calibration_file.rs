//! What `damper calibrate` writes: `calibration.json` (typed here, serde) and the parameter set of
//! `parameters.ssv` ([`crate::ssv`]). SI units unless a name says otherwise.

use crate::calibrate::{Calibration, Status};
use crate::parameters::{lookup, Param, Value};
use crate::ssv::Written;
use crate::summary::ParameterValue;
use serde::{Deserialize, Serialize};

/// `calibration.json`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CalibrationFile {
    /// `damper calibrate` and its version.
    pub generator: String,
    /// The calibration records.
    pub records: Vec<RecordEntry>,
    /// The settings the records were taken at (`--setting`; one per record unless grouped).
    pub settings: Vec<String>,
    /// Every parameter of the fit, in the order fitted.
    pub parameters: Vec<ParameterEntry>,
    /// Parameters of `--params` and `--set` that were not fitted (also in parameters.ssv).
    pub given: Vec<GivenEntry>,
    /// The fits in turn: each holds the worst parameter it could not pin, the last holds none.
    pub rounds: Vec<RoundEntry>,
    /// The covariance of the fitted parameters; null when the last fit has none.
    #[serde(default)]
    pub covariance: Option<CovarianceEntry>,
    /// Largest relative standard uncertainty of a parameter called identified (1).
    pub max_relative_uncertainty: f64,
    /// Largest |correlation| with another fitted parameter (1).
    pub max_correlation: f64,
    /// The model's relative tolerance during the calibration (1).
    pub rtol: f64,
    pub model_runs: usize,
    /// Wall time (s).
    pub seconds: f64,
    pub threads: usize,
}

/// A record's force error before and after.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RecordEntry {
    pub path: String,
    /// The label of its setting.
    pub setting: String,
    pub samples: usize,
    /// F_damper NRMSE over the whole record with the start values (1).
    pub nrmse_before: f64,
    /// The same with the calibrated values (1).
    pub nrmse_after: f64,
    /// White-noise floor of the calibrated residual, as an NRMSE (1).
    pub noise_floor: f64,
}

/// A parameter of the fit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ParameterEntry {
    pub name: String,
    /// The setting whose own value this is (`--per-setting`); null: shared by every record.
    pub setting: Option<String>,
    /// The model's unit ("1": dimensionless).
    pub unit: String,
    pub start: f64,
    /// The calibrated value (the start value when held).
    pub value: f64,
    /// Standard uncertainty (the parameter's unit); null when held.
    pub std_uncertainty: Option<f64>,
    /// std_uncertainty / |value| (1); null when held.
    pub relative_uncertainty: Option<f64>,
    /// The fitted parameter it correlates with most, and the coefficient.
    pub strongest_correlation: Option<(String, f64)>,
    /// "fitted" or "held".
    pub status: String,
    /// Why held, or a note (at its search bound); empty otherwise.
    pub note: String,
    /// The search box [lo, hi] and its scale.
    pub search: [f64; 2],
    pub log_scale: bool,
}

/// The covariance of the fitted parameters: `damper diagnose --calibration` carries it into the
/// uncertainty of what it fits.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CovarianceEntry {
    /// The rows' and columns' parameters (FMU name, and setting for a setting's own value).
    pub parameters: Vec<CovarianceParameter>,
    /// Row by row, in the parameters' units.
    pub matrix: Vec<Vec<f64>>,
}

/// A row of [`CovarianceEntry`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CovarianceParameter {
    pub name: String,
    pub setting: Option<String>,
}

/// A parameter given, not fitted.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GivenEntry {
    pub name: String,
    pub value: ParameterValue,
}

/// One fit of the rounds.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RoundEntry {
    pub fitted: Vec<String>,
    pub iterations: usize,
    pub model_runs: usize,
    pub converged: bool,
    /// RMS force residual over all records (N).
    pub rms_residual: f64,
    /// The parameter held after this fit and why.
    pub held: Option<(String, String)>,
}

fn parameter_value(v: Value) -> ParameterValue {
    match v {
        Value::Real(x) => ParameterValue::Real(x),
        Value::Integer(i) => ParameterValue::Integer(i64::from(i)),
        Value::Boolean(b) => ParameterValue::Boolean(b),
    }
}

/// The note of a parameter: why held, or at its search bound.
pub fn note(p: &crate::calibrate::Calibrated) -> String {
    match &p.status {
        Status::Held(why) => why.clone(),
        Status::Fitted if p.at_bound() => {
            format!("at its search bound [{:.4e}, {:.4e}]: the uncertainty is not meaningful", p.scale.lo, p.scale.hi)
        }
        Status::Fitted => String::new(),
    }
}

/// `calibration.json`'s content.
pub fn file(c: &Calibration, max_relative_uncertainty: f64, max_correlation: f64) -> CalibrationFile {
    CalibrationFile {
        generator: format!("damper calibrate {}", env!("CARGO_PKG_VERSION")),
        records: c
            .records
            .iter()
            .map(|r| RecordEntry {
                path: r.path.clone(),
                setting: r.setting.clone(),
                samples: r.samples,
                nrmse_before: r.nrmse_before,
                nrmse_after: r.nrmse_after,
                noise_floor: r.noise_floor,
            })
            .collect(),
        settings: c.settings.clone(),
        parameters: c
            .parameters
            .iter()
            .map(|p| ParameterEntry {
                name: p.name.into(),
                setting: p.setting.clone(),
                unit: p.unit.into(),
                start: p.start,
                value: p.value,
                std_uncertainty: p.std_error,
                relative_uncertainty: p.relative(),
                strongest_correlation: p.correlation.clone(),
                status: if p.status == Status::Fitted { "fitted" } else { "held" }.into(),
                note: note(p),
                search: [p.scale.lo, p.scale.hi],
                log_scale: p.scale.log,
            })
            .collect(),
        given: c.given.iter().map(|(n, v)| GivenEntry { name: n.to_string(), value: parameter_value(*v) }).collect(),
        rounds: c
            .rounds
            .iter()
            .map(|r| RoundEntry {
                fitted: r.fitted.clone(),
                iterations: r.iterations,
                model_runs: r.model_runs,
                converged: r.converged,
                rms_residual: r.rms_residual,
                held: r.held.clone(),
            })
            .collect(),
        covariance: c.covariance.as_ref().map(|cov| CovarianceEntry {
            parameters: cov
                .parameters
                .iter()
                .map(|&i| CovarianceParameter {
                    name: c.parameters[i].name.to_string(),
                    setting: c.parameters[i].setting.clone(),
                })
                .collect(),
            matrix: cov.matrix.clone(),
        }),
        max_relative_uncertainty,
        max_correlation,
        rtol: c.rtol,
        model_runs: c.model_runs,
        seconds: c.seconds,
        threads: c.threads,
    }
}

/// The settings that need a parameter set of their own: those with values of their own
/// (`--per-setting`); empty when one set serves every record.
pub fn own_settings(c: &Calibration) -> Vec<&str> {
    c.settings
        .iter()
        .map(String::as_str)
        .filter(|s| c.parameters.iter().any(|p| p.setting.as_deref() == Some(s)))
        .collect()
}

/// The parameter set of `parameters.ssv` (or of one setting's, `setting`): the calibrated
/// parameters (fitted or held) shared by every record and the setting's own, then the given ones.
pub fn parameter_set(c: &Calibration, setting: Option<&str>) -> Vec<Written> {
    let mut out: Vec<Written> = c
        .parameters
        .iter()
        .filter(|p| p.setting.is_none() || p.setting.as_deref() == setting)
        .map(|p| Written {
            name: p.name.into(),
            value: Value::Real(p.value),
            unit: p.unit.into(),
            uncertainty: p.std_error,
            status: match &p.status {
                Status::Fitted => "calibrated".into(),
                Status::Held(why) => format!("held at its given value ({why})"),
            },
            start: Some(p.start),
        })
        .collect();
    for (name, value) in &c.given {
        let unit = match lookup(name) {
            Ok(Param::Real(v)) => v.unit().to_string(),
            _ => String::new(),
        };
        out.push(Written {
            name: name.to_string(),
            value: *value,
            unit,
            uncertainty: None,
            status: "given (--params or --set)".into(),
            start: None,
        });
    }
    out
}
