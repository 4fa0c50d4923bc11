//! Which physical effect is missing: every effect of the catalog (docs/effects.md) is tried in
//! turn. An effect the baseline lacks is switched on; one it has is refitted ("a parameter
//! moved"). Its one or two parameters are fitted on the training part, and the candidate is scored
//! on the held-out validation part. The verdict:
//!
//! - `none`: the baseline's validation residual is at the noise floor and no candidate improves it;
//! - `effect`: the best candidate explains at least [`MIN_EXPLAINED`] of the validation error
//!   above the noise floor with plausible parameters, and either clearly more than the best
//!   plausible runner-up or it alone brings the residual to the noise floor;
//! - `unexplained`: neither.
//!
//! The share explained ([`share`](crate::criteria::share)) is (b² − c²)/(b² − f²) with b, c, f
//! the NRMSE of the baseline, of the candidate and of the noise floor: a weak effect near the
//! noise cannot halve the NRMSE, but can explain all of the error the noise leaves room for.
//!
//! The noise floor is white sensor noise, estimated from the residual ([`noise_sigma`]).

use crate::candidate::{Candidate, FitSetup};
use crate::criteria::{FLOOR_FACTOR, MAX_RUNNER_UP_RATIO, MIN_EXPLAINED, MIN_GAIN};
use crate::dsp::{noise_sigma, nrmse};
use crate::ladder::{climb, Ladder};
use semi_active_damper::effects::EffectInfo;
use semi_active_damper::physics::params::Parameters;

/// The outcome of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    pub verdict: &'static str,
    pub best_effect: Option<&'static str>,
    pub nrmse_baseline: f64,
    /// NRMSE the sensor noise alone would give on the validation part.
    pub nrmse_noise_floor: f64,
    pub candidates: Vec<Candidate>,
    pub explanation: String,
    /// Step 4: the effects added one at a time.
    pub ladder: Ladder,
    /// The answer: the effects the model lacks (the ladder's kept effects when the verdict is
    /// `effect`, else none).
    pub effects: Vec<&'static str>,
}

/// Runs the diagnosis over `specs` (usually the whole [`catalog`](crate::candidate::catalog)) with the model, data and
/// thread pool of `fit`, from the `baseline` parameters whose force over the measurement is `base`
/// (the comparison has it already).
pub fn diagnose(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    base: &[f64],
) -> Result<Diagnosis, String> {
    let (measured, split) = (fit.measured, fit.split);
    let nrmse_baseline = nrmse(&measured[split..], &base[split..]);
    let residual: Vec<f64> = base.iter().zip(measured).map(|(m, y)| m - y).collect();
    let sigma = noise_sigma(&residual[split..]);
    let val = &measured[split..];
    let val_std = (val.iter().map(|y| y * y).sum::<f64>() / val.len() as f64
        - (val.iter().sum::<f64>() / val.len() as f64).powi(2))
    .sqrt();
    let nrmse_noise_floor = sigma / val_std;

    let candidates = fit.all(specs, baseline, (nrmse_baseline, nrmse_noise_floor))?;

    let at_floor = nrmse_baseline <= FLOOR_FACTOR * nrmse_noise_floor;
    let best = candidates.first();
    // a rival that needs implausible parameters is no competing explanation
    let rivals = || candidates.iter().skip(1).filter(|c| c.plausible);
    let runner_up = rivals().map(|c| c.explained).fold(0.0, f64::max);
    // nor is one that leaves error above the noise floor where the best leaves none
    let floor = |c: &Candidate| c.nrmse_validation <= FLOOR_FACTOR * nrmse_noise_floor;
    let only_best_at_floor = best.is_some_and(floor) && !rivals().any(floor);
    // the cut of the mean-square error as a share of the noise variance, for weak effects
    let gain = |c: &Candidate| (nrmse_baseline.powi(2) - c.nrmse_validation.powi(2)) / nrmse_noise_floor.powi(2);
    let weak = best.filter(|b| {
        at_floor && b.plausible && gain(b) >= MIN_GAIN && rivals().all(|c| gain(c) < MAX_RUNNER_UP_RATIO * gain(b))
    });
    let (verdict, best_effect, explanation) = match best {
        Some(b)
            if !at_floor
                && b.explained >= MIN_EXPLAINED
                && b.plausible
                && (runner_up < MAX_RUNNER_UP_RATIO * b.explained || only_best_at_floor) =>
        {
            (
            "effect",
            Some(b.effect),
            format!(
                "{} {} explains {:.0} % of the error above the noise floor and cuts the validation NRMSE by {:.0} % ({:.4} → {:.4}; noise floor {:.4}). Its signature: {}.",
                b.effect,
                b.action,
                100.0 * b.explained,
                100.0 * b.reduction,
                nrmse_baseline,
                b.nrmse_validation,
                nrmse_noise_floor,
                b.signature
            ),
        )
        }
        _ if weak.is_some() => {
            let b = weak.expect("checked");
            (
                "effect",
                Some(b.effect),
                format!(
                    "a weak effect near the noise floor: the baseline's validation NRMSE {nrmse_baseline:.4} is only {:.2}× the floor {nrmse_noise_floor:.4}, but {} {} cuts its mean-square error by {:.0} % of the noise variance (NRMSE {:.4}), clearly more than any other candidate, with plausible parameters. Its signature: {}.",
                    nrmse_baseline / nrmse_noise_floor,
                    b.effect,
                    b.action,
                    100.0 * gain(b),
                    b.nrmse_validation,
                    b.signature
                ),
            )
        }
        _ if at_floor => (
            "none",
            None,
            format!(
                "the baseline's validation NRMSE {nrmse_baseline:.4} is at the noise floor {nrmse_noise_floor:.4}: nothing is missing that these data show"
            ),
        ),
        _ => (
            "unexplained",
            None,
            format!(
                "no candidate explains the residual confidently (best: {} explains {:.0} % of the error above the noise floor, best plausible runner-up {:.0} %); baseline NRMSE {nrmse_baseline:.4} against a noise floor of {nrmse_noise_floor:.4}",
                best.map_or("none", |b| b.effect),
                100.0 * best.map_or(0.0, |b| b.explained),
                100.0 * runner_up
            ),
        ),
    };
    let mut ladder = climb(fit, specs, baseline, &candidates, (nrmse_baseline, nrmse_noise_floor))?;
    if let Some(b) = weak {
        ladder.add(b)?;
    }
    let (verdict, best_effect, explanation) = match (verdict, ladder.effects.as_slice()) {
        ("unexplained", [first, _, ..]) if ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_noise_floor => (
            "effect",
            Some(*first),
            format!(
                "no single candidate explains the residual, but {} together bring the validation NRMSE from {nrmse_baseline:.4} to {:.4}, the noise floor {nrmse_noise_floor:.4} (see the ladder)",
                ladder.effects.join(" + "),
                ladder.nrmse_validation
            ),
        ),
        ("effect", [_, _, ..]) => (
            verdict,
            best_effect,
            format!("{explanation} With {} together the validation NRMSE is {:.4}.", ladder.effects.join(" + "), ladder.nrmse_validation),
        ),
        _ => (verdict, best_effect, explanation),
    };
    let effects = if verdict == "effect" { ladder.effects.clone() } else { Vec::new() };
    Ok(Diagnosis { verdict, best_effect, nrmse_baseline, nrmse_noise_floor, candidates, explanation, ladder, effects })
}
