//! Which physical effect is missing: every effect of the catalog (docs/effects.md) is tried in
//! turn. An effect the baseline lacks is switched on; one it has is refitted ("a parameter
//! moved"). Its one or two parameters are fitted on the training part, and the candidate is scored
//! on the held-out validation part. The verdict:
//!
//! - `none`: the baseline's validation residual is at the noise floor and no candidate improves it;
//! - `effect`: the best candidate explains at least [`MIN_EXPLAINED`] of the validation error above
//!   the noise floor with plausible parameters, and either clearly more than the best plausible
//!   runner-up or it alone brings the residual to the noise floor;
//! - `unexplained`: neither.
//!
//! The share explained is (b² − c²)/(b² − f²) with b, c, f the NRMSE of the baseline, of the
//! candidate and of the noise floor: a weak effect near the noise cannot halve the NRMSE, but can
//! explain all of the error the noise leaves room for.
//!
//! The noise floor is estimated from the residual itself: white sensor noise of variance σ² gives
//! second differences of variance 6σ², while a model error, being smooth at the sample rate, barely
//! shows in them.

use crate::fit::{minimize, standard_errors, Bound, Fit};
use crate::ladder::{climb, share, Ladder};
use crate::parameters::{effect_on, get_real, set_effect, set_real};
use semi_active_damper::effects::{EffectInfo, FittedParameter};
use semi_active_damper::physics::params::Parameters;

/// Least share of the validation error above the noise floor an effect must explain to be named.
pub const MIN_EXPLAINED: f64 = 0.5;
/// The best plausible runner-up must explain less than this fraction of what the best explains.
pub const MAX_RUNNER_UP_RATIO: f64 = 0.7;
/// A baseline within this factor of the noise floor has nothing to explain.
pub const FLOOR_FACTOR: f64 = 1.3;
/// Near the noise floor (a baseline within [`FLOOR_FACTOR`] of it) an effect is still named when
/// it cuts the validation mean-square error by at least this share of the noise variance. Over 20
/// records with nothing hidden (rig and HiL) no candidate cut more than 0.0014; a weak hidden piston
/// leakage on HiL data cuts 0.07–0.57 (`examples/ranking_accuracy.rs`).
pub const MIN_GAIN: f64 = 0.02;
/// Objective evaluations per fit.
pub const MAX_EVALS: usize = 25;

/// The catalog: every effect of the model (`semi_active_damper::effects`), in its order.
pub fn catalog() -> impl Iterator<Item = &'static EffectInfo> {
    semi_active_damper::effects::CATALOG.into_iter().map(|e| e.info())
}

fn bound(f: &FittedParameter) -> Bound {
    Bound { lo: f.search.0, hi: f.search.1, log: f.log }
}

/// Normalised RMS error: RMS(model − measured) / standard deviation of the measured signal.
pub fn nrmse(model: &[f64], measured: &[f64]) -> f64 {
    let n = measured.len().min(model.len()) as f64;
    let mean = measured.iter().sum::<f64>() / n;
    let var = measured.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / n;
    let mse = model.iter().zip(measured).map(|(m, y)| (m - y).powi(2)).sum::<f64>() / n;
    (mse / var).sqrt()
}

/// Standard deviation of white noise in `r`, from its second differences (see the module docs).
pub fn noise_sigma(r: &[f64]) -> f64 {
    let d2: Vec<f64> = r.windows(3).map(|w| w[0] - 2.0 * w[1] + w[2]).collect();
    (d2.iter().map(|d| d * d).sum::<f64>() / d2.len().max(1) as f64 / 6.0).sqrt()
}

/// The model as the diagnosis sees it: the force for the first `n` samples of the measurement.
pub type Simulator<'a> = dyn Fn(&Parameters, usize) -> Result<Vec<f64>, String> + Sync + 'a;

/// A scored candidate.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub effect: &'static str,
    /// "switched on" or "refitted".
    pub action: &'static str,
    pub params: Vec<(&'static str, f64, Option<f64>)>,
    pub nrmse_train: f64,
    pub nrmse_validation: f64,
    /// Relative cut of the validation NRMSE against the baseline.
    pub reduction: f64,
    /// Share of the baseline's validation error above the noise floor that this candidate explains.
    pub explained: f64,
    pub plausible: bool,
    /// Why not plausible, or empty.
    pub flags: Vec<String>,
    pub signature: &'static str,
    pub evaluations: usize,
}

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

/// Runs the diagnosis over `specs` (usually the whole [`catalog`]) with the model, data and
/// thread pool of `fit`, from the `baseline` parameters whose force over the measurement is `base`
/// (the comparison has it already).
pub fn diagnose(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    base: &[f64],
) -> Result<Diagnosis, String> {
    let (measured, split) = (fit.measured, fit.split);
    let nrmse_baseline = nrmse(&base[split..], &measured[split..]);
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

/// Told of each fitted candidate, with how many of the fits of this round are done and how many
/// the round has (a round: the ranking, then each step of the ladder). Calls come one at a time,
/// `done` counting up, so a progress display needs no locking of its own.
pub type Progress<'a> = dyn Fn(&Candidate, usize, usize) + Sync + 'a;

/// What fitting a candidate needs: the model, the measured force, the train/validation split, the
/// threads that fit candidates at once, and whom to tell of each fit.
pub struct FitSetup<'a> {
    pub simulate: &'a Simulator<'a>,
    pub measured: &'a [f64],
    pub split: usize,
    pub pool: &'a rayon::ThreadPool,
    pub progress: &'a Progress<'a>,
}

impl FitSetup<'_> {
    /// Fits every effect of `specs` on top of `params` (whose validation NRMSE is the first of
    /// `errors`, the noise floor the second), in parallel; best first. Each fit is a pure function
    /// of its inputs and the ranking is made in catalog order, so the result does not depend on
    /// the thread count.
    pub fn all(
        &self,
        specs: &[&'static EffectInfo],
        params: &Parameters,
        errors: (f64, f64),
    ) -> Result<Vec<Candidate>, String> {
        use rayon::prelude::*;
        // the costliest fits first (par_bridge hands the items out in this order), so that no
        // thread is left alone with a long one at the end
        let mut order: Vec<usize> = (0..specs.len()).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(model_runs(specs[i])));
        let done = std::sync::Mutex::new(0);
        let mut results: Vec<(usize, Result<Candidate, String>)> = self.pool.install(|| {
            order
                .into_iter()
                .par_bridge()
                .map(|i| {
                    let c = try_candidate(self.simulate, params, self.measured, self.split, errors, specs[i]);
                    if let Ok(c) = &c {
                        let mut done = done.lock().expect("no fit panicked");
                        *done += 1;
                        (self.progress)(c, *done, specs.len());
                    }
                    (i, c)
                })
                .collect()
        });
        results.sort_by_key(|r| r.0);
        let mut candidates = results.into_iter().map(|(_, c)| c).collect::<Result<Vec<_>, _>>()?;
        candidates.sort_by(|a, b| a.nrmse_validation.total_cmp(&b.nrmse_validation));
        Ok(candidates)
    }
}

/// Model runs a fit of `spec` takes, about: its grid, or the simplex's budget and the Hessian.
fn model_runs(spec: &EffectInfo) -> usize {
    match spec.fitted {
        [FittedParameter { search, grid: Some(step), .. }] => ((search.1 - search.0) / step).round() as usize + 1,
        p => MAX_EVALS * p.len() + 2 * p.len() * p.len(),
    }
}

/// Fits `spec` on top of `baseline` and scores it (`nrmse_baseline` is the error it starts from).
pub fn try_candidate(
    simulate: &Simulator<'_>,
    baseline: &Parameters,
    measured: &[f64],
    split: usize,
    (nrmse_baseline, nrmse_floor): (f64, f64),
    spec: &EffectInfo,
) -> Result<Candidate, String> {
    let mut start = *baseline;
    let action = if effect_on(baseline, spec.key)? { "refitted" } else { "switched on" };
    set_effect(&mut start, spec.key, true)?;
    let with = |x: &[f64]| -> Result<Parameters, String> {
        let mut p = start;
        for (s, &v) in spec.fitted.iter().zip(x) {
            set_real(&mut p, s.name, v)?;
        }
        Ok(p)
    };
    let train = &measured[..split];
    let sse = |x: &[f64]| -> f64 {
        match with(x).and_then(|p| simulate(&p, split)) {
            Ok(m) => m.iter().zip(train).map(|(m, y)| (m - y).powi(2)).sum(),
            Err(_) => f64::INFINITY,
        }
    };
    let x0: Vec<f64> = spec
        .fitted
        .iter()
        .map(|s| get_real(&start, s.name).map(|v| v.clamp(s.search.0.max(1e-300), s.search.1)))
        .collect::<Result<_, _>>()?;
    let bounds: Vec<Bound> = spec.fitted.iter().map(bound).collect();
    let (fit, errors) = match spec.fitted {
        [p @ FittedParameter { grid: Some(step), .. }] => {
            let bound = bound(p);
            // the whole grid: the answer is exact to half a step
            let n = ((bound.hi - bound.lo) / step).round() as usize;
            let best = (0..=n)
                .map(|k| bound.lo + k as f64 * step)
                .map(|x| (x, sse(&[x])))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("non-empty grid");
            (Fit { x: vec![best.0], value: best.1, evaluations: n + 1 }, vec![Some(0.5 * step)])
        }
        _ => {
            let fit = minimize(sse, &x0, &bounds, MAX_EVALS * spec.fitted.len());
            let errors = standard_errors(sse, (&fit.x, fit.value), split, 1e-2);
            (fit, errors)
        }
    };
    let fitted = with(&fit.x)?;
    let full = simulate(&fitted, measured.len())?;
    let nrmse_validation = nrmse(&full[split..], &measured[split..]);
    let nrmse_train = nrmse(&full[..split], train);
    let mut flags = Vec::new();
    for (s, &x) in spec.fitted.iter().zip(&fit.x) {
        if bound(s).at_bound(x) {
            flags.push(format!("{} = {x:.4e} at its search bound", s.name));
        } else if x < s.plausible.0 || x > s.plausible.1 {
            flags.push(format!(
                "{} = {x:.4e} outside the plausible {:.3e}–{:.3e}",
                s.name, s.plausible.0, s.plausible.1
            ));
        }
    }
    Ok(Candidate {
        effect: spec.key,
        action,
        params: spec.fitted.iter().zip(&fit.x).zip(errors).map(|((s, &x), e)| (s.name, x, e)).collect(),
        nrmse_train,
        nrmse_validation,
        reduction: 1.0 - nrmse_validation / nrmse_baseline,
        explained: share(nrmse_baseline, nrmse_validation, nrmse_floor),
        plausible: flags.is_empty(),
        flags,
        signature: spec.signature,
        evaluations: fit.evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_sigma_sees_white_noise_not_smooth_error() {
        let mut s = 1u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // uniform noise of width 1: σ = 1/√12; plus a smooth 2 Hz error sampled at 1 kHz
        let r: Vec<f64> =
            (0..20_000).map(|k| rnd() + 50.0 * (k as f64 * 2e-3 * std::f64::consts::PI * 2.0).sin()).collect();
        let sigma = noise_sigma(&r);
        assert!((sigma - 1.0 / 12f64.sqrt()).abs() < 0.02, "{sigma}");
    }

    #[test]
    fn catalog_names_are_fmu_parameters() {
        let mut p = semi_active_damper::variables::default_parameters();
        for e in catalog() {
            set_effect(&mut p, e.key, true).unwrap();
            for s in e.fitted {
                let v = get_real(&p, s.name).unwrap();
                set_real(&mut p, s.name, v).unwrap();
                assert!(s.plausible.0 >= s.search.0 && s.plausible.1 <= s.search.1, "{}", s.name);
            }
        }
    }
}
