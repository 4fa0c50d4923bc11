//! Which physical effect is missing: every effect of the catalog (docs/effects.md) is tried in
//! turn. An effect the baseline lacks is switched on; one it has is refitted ("a parameter
//! moved"). Its parameters are fitted on the training part, and the candidate is scored on the
//! held-out validation part. Then the ladder adds effects one at a time ([`crate::ladder`]) and
//! [`crate::verdict`] judges the outcome.
//!
//! The floor the verdict judges by has two parts, both reported: the sensor noise, estimated from
//! the residual so that the model's error cannot inflate it ([`noise_floor`]), and the model's own
//! numerical error, measured on each record as the difference between the baseline run and the
//! same run at a hundredth of its tolerance ([`Floor`]).

use crate::candidate::{Candidate, FitSetup};
use crate::dsp::{noise_floor, nrmse, std, NoiseEstimate};
use crate::ladder::{climb, Ladder};
use crate::verdict::{judge, Judged};
use semi_active_damper::effects::EffectInfo;
use semi_active_damper::physics::params::Parameters;

/// The floor of the validation NRMSE below which nothing can be explained.
#[derive(Clone, Copy, Debug)]
pub struct Floor {
    /// The sensor noise's share: σ_noise / std(measured) on the validation part.
    pub nrmse_noise: f64,
    /// The model's numerical error: RMS(F(rtol) − F(rtol·[`NUMERICS_CHECK_FACTOR`](crate::criteria::NUMERICS_CHECK_FACTOR)))
    /// / std(measured) on the validation part.
    pub nrmse_numerics: f64,
    /// √(noise² + numerics²): what the verdict judges by.
    pub nrmse: f64,
    /// The noise estimate (N), three ways.
    pub noise: NoiseEstimate,
    /// The tolerance the model ran at, and the one of the check.
    pub rtol: f64,
    pub rtol_check: f64,
}

/// The outcome of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// `effect`, `partial`, `none`, `does_not_fit` or `unexplained` ([`crate::verdict`]).
    pub verdict: &'static str,
    pub best_effect: Option<&'static str>,
    pub nrmse_baseline: f64,
    /// The floor the verdict judges by ([`Floor::nrmse`]).
    pub nrmse_noise_floor: f64,
    pub floor: Floor,
    pub candidates: Vec<Candidate>,
    pub explanation: String,
    /// Step 4: the effects added one at a time.
    pub ladder: Ladder,
    /// The answer: the effects the model lacks, in the ladder's order (verdict `effect`), or
    /// those that explain part of the error (verdict `partial`); else none.
    pub effects: Vec<&'static str>,
}

/// The force of the model at its tolerance and at the check's tighter one, over the measurement.
pub struct Numerics<'a> {
    pub base: &'a [f64],
    pub base_check: &'a [f64],
    pub rtol: f64,
    pub rtol_check: f64,
}

/// The floor of a baseline residual `measured − numerics.base` on the validation part from `split`.
pub fn floor(measured: &[f64], numerics: &Numerics<'_>, split: usize) -> Floor {
    let residual: Vec<f64> = numerics.base[split..].iter().zip(&measured[split..]).map(|(m, y)| m - y).collect();
    let noise = noise_floor(&residual);
    let val_std = std(&measured[split..]);
    let nrmse_noise = noise.sigma / val_std;
    let diff: Vec<f64> = numerics.base[split..].iter().zip(&numerics.base_check[split..]).map(|(a, b)| a - b).collect();
    let nrmse_numerics = crate::dsp::rms(&diff) / val_std;
    Floor {
        nrmse_noise,
        nrmse_numerics,
        nrmse: nrmse_noise.hypot(nrmse_numerics),
        noise,
        rtol: numerics.rtol,
        rtol_check: numerics.rtol_check,
    }
}

/// Runs the diagnosis over `specs` (usually the whole [`catalog`](crate::candidate::catalog)) with
/// the model, data and thread pool of `fit`, from the `baseline` parameters whose force over the
/// measurement is `numerics.base` (the comparison has it already).
pub fn diagnose(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    numerics: &Numerics<'_>,
) -> Result<Diagnosis, String> {
    let (measured, split) = (fit.measured, fit.split);
    let nrmse_baseline = nrmse(&measured[split..], &numerics.base[split..]);
    let floor = floor(measured, numerics, split);
    if !nrmse_baseline.is_finite() || !floor.nrmse.is_finite() {
        return Err(format!(
            "nothing to diagnose: the validation NRMSE is {nrmse_baseline} and the noise floor {} (is the measured force constant?)",
            floor.nrmse
        ));
    }
    let errors = (nrmse_baseline, floor.nrmse);
    let candidates = fit.all(specs, baseline, errors)?;
    let ladder = climb(fit, specs, baseline, &candidates, errors)?;
    let Judged { verdict, best_effect, explanation, ladder, effects } =
        judge(nrmse_baseline, &floor, &candidates, ladder)?;
    Ok(Diagnosis {
        verdict,
        best_effect,
        nrmse_baseline,
        nrmse_noise_floor: floor.nrmse,
        floor,
        candidates,
        explanation,
        ladder,
        effects,
    })
}
