//! One candidate of the diagnosis: an effect of the catalog (docs/effects.md) switched on, or
//! refitted where the model has it, its one or two parameters fitted on the training part and the
//! candidate scored on the held-out validation part; and the fitting of a whole round of
//! candidates in parallel.

use crate::bounds::Bound;
use crate::criteria::{share, MOVED_SIGMAS};
use crate::dsp::nrmse_kept;
use crate::error::Error;
use crate::lm;
use crate::parameters::{effect_on, real, set_effect, set_real};
use crate::sensitivity::Informative;
use semi_active_damper::effects::{Candidacy, EffectInfo, FittedParameter, Start};
use semi_active_damper::physics::params::Parameters;

/// Levenberg–Marquardt settings of a candidate's fit: it stops when an accepted step lowers the
/// sum of squares by less than 1e-4 of it (the fitted value then moves by far less than its
/// uncertainty), after at most 12 iterations.
pub const FIT_OPTIONS: lm::Options = lm::Options { max_iterations: 12, step: 3e-3, tolerance: 1e-4 };
/// A fit runs the model over at most this much of the train part (s), from its start; the
/// candidate is then scored on the whole validation part. One or two parameters are pinned by far
/// fewer samples, and the model's run time grows with the length: a 60 s record's diagnosis took
/// 55 s with the whole train part (42 s) at rtol 1e-4.
pub const MAX_FIT_SECONDS: f64 = 20.0;
/// A fitted value within this fraction of its box's (searched) range of a bound is "at its search
/// bound": the data do not pin it inside the box.
pub const AT_BOUND: f64 = 0.01;

/// The flag of a refit that stayed within its uncertainty of the model's value.
pub const NOTHING_MOVED: &str = "nothing moved";
/// The flag of an effect switched on whose size is within its uncertainty of zero.
pub const INDISTINGUISHABLE: &str = "is indistinguishable from off";

/// The catalog: every effect of the model (`semi_active_damper::effects`), in its order.
pub fn catalog() -> impl Iterator<Item = &'static EffectInfo> {
    semi_active_damper::effects::CATALOG.into_iter().map(|e| e.info())
}

/// The effects a diagnosis tries on a model `baseline` and a record with or without a temperature
/// column ([`Candidacy`]): every effect that may be missing, the damper's own passive valves where
/// it has them, the temperature's effect where the record measures it, the controlled valve's
/// effects where the valve is controlled.
pub fn candidates(baseline: &Parameters, has_temperature: bool) -> impl Iterator<Item = &'static EffectInfo> + '_ {
    catalog().filter(move |e| match e.candidacy {
        Candidacy::Always => true,
        Candidacy::WhenOn => effect_on(baseline, e.key).unwrap_or(false),
        Candidacy::WithTemperature => has_temperature,
        Candidacy::Controlled => baseline.control_mode != 2,
    })
}

fn bound(f: &FittedParameter) -> Bound {
    Bound { lo: f.search.0, hi: f.search.1, log: f.log }
}

/// The model as the diagnosis sees it: the force for the first `n` samples of the measurement.
pub type Simulator<'a> = dyn Fn(&Parameters, usize) -> Result<Vec<f64>, Error> + Sync + 'a;

/// A scored candidate.
#[derive(Clone, Debug)]
pub struct Candidate {
    pub effect: &'static str,
    /// "switched on" or "refitted".
    pub action: &'static str,
    pub params: Vec<(&'static str, f64, Option<f64>)>,
    /// Of each parameter's standard uncertainty (the third of `params`), the part inherited from
    /// the calibration ([`crate::propagation`]); empty unless the diagnosis was given one.
    pub inherited: Vec<Option<f64>>,
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

/// Told of each fitted candidate, with how many of the fits of this round are done and how many
/// the round has (a round: the ranking, then each step of the ladder). Calls come one at a time,
/// `done` counting up, so a progress display needs no locking of its own.
pub type Progress<'a> = dyn Fn(&Candidate, usize, usize) + Sync + 'a;

/// What fitting a candidate needs: the model, the measured force, the train/validation split, the
/// threads that fit candidates at once, and whom to tell of each fit.
pub struct FitSetup<'a> {
    pub simulate: &'a Simulator<'a>,
    pub measured: &'a [f64],
    /// The samples that inform the fits and the scores.
    pub informative: &'a Informative,
    pub split: usize,
    /// Samples a fit runs and scores, from the start: the train part, at most
    /// [`MAX_FIT_SECONDS`] of it (see there).
    pub train: usize,
    /// The largest |stroke| of the model over those samples (m), where a fit of a position
    /// starts ([`Start::OfLargestStroke`]).
    pub largest_stroke: f64,
    /// Draws of the model's force change that the noise of the measured velocity makes, each over
    /// the samples a fit's residuals hold (the informative ones of the first [`train`](Self::train));
    /// may be empty: the fitted parameters' uncertainty carries their spread ([`crate::lm`]).
    pub input_error: &'a [Vec<f64>],
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
    ) -> Result<Vec<Candidate>, Error> {
        use rayon::prelude::*;
        // the costliest fits first (par_bridge hands the items out in this order), so that no
        // thread is left alone with a long one at the end
        let mut order: Vec<usize> = (0..specs.len()).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(model_runs(specs[i])));
        let done = std::sync::Mutex::new(0);
        let mut results: Vec<(usize, Result<Candidate, Error>)> = self.pool.install(|| {
            order
                .into_iter()
                .par_bridge()
                .map(|i| {
                    let c = try_candidate(self.simulate, params, self.data(), errors, specs[i]);
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

impl FitSetup<'_> {
    /// [`fit_effects`] with this setup's model and data.
    pub fn joint(&self, params: &Parameters, keys: &[&str], fitted: &[FittedParameter]) -> Result<JointFit, Error> {
        fit_effects(self.simulate, params, self.data(), keys, fitted)
    }

    fn data(&self) -> Data<'_> {
        Data {
            measured: self.measured,
            keep: &self.informative.keep,
            train: self.train,
            split: self.split,
            largest_stroke: self.largest_stroke,
            input_error: self.input_error,
            pool: self.pool,
        }
    }
}

/// Model runs a fit of `spec` takes, about: [`grid_minimum`]'s coarse points and the ones around
/// the best, or a few Levenberg–Marquardt iterations of a Jacobian and a trial step.
fn model_runs(spec: &EffectInfo) -> usize {
    match spec.fitted {
        [FittedParameter { search, grid: Some(step), .. }] => {
            ((search.1 - search.0) / step).round() as usize / GRID_COARSE + 2 * GRID_COARSE
        }
        p => 5 * (p.len() + 1),
    }
}

/// A fit of some effects' parameters on top of a model, scored on the validation part.
#[derive(Clone, Debug)]
pub struct JointFit {
    /// (name, fitted value, standard uncertainty) of each parameter fitted.
    pub params: Vec<(&'static str, f64, Option<f64>)>,
    /// The model with the effects on at the fitted values.
    pub model: Parameters,
    pub nrmse_train: f64,
    pub nrmse_validation: f64,
    /// Why not plausible, or empty.
    pub flags: Vec<String>,
    pub evaluations: usize,
}

/// The measured force, the samples kept, the samples a fit runs (from the start), the first
/// sample of the validation part, and the threads a fit's Jacobian columns run on.
#[derive(Clone, Copy)]
pub struct Data<'a> {
    pub measured: &'a [f64],
    pub keep: &'a [bool],
    pub train: usize,
    pub split: usize,
    /// See [`FitSetup::largest_stroke`].
    pub largest_stroke: f64,
    /// See [`FitSetup::input_error`].
    pub input_error: &'a [Vec<f64>],
    pub pool: &'a rayon::ThreadPool,
}

/// Switches the effects `keys` on in `baseline` and fits `fitted` (their parameters, starting at
/// the model's values) on the training part of `measured`, then runs the whole record. A
/// quantised parameter (a delay in controller samples) is searched over its whole grid; the
/// others by bounded Levenberg–Marquardt ([`crate::lm`]), whose covariance at the optimum (the
/// sandwich for coloured residuals, with the inputs' noise carried in) gives their uncertainties.
/// It replaced a Nelder–Mead simplex of 25 runs per parameter plus a Hessian for the
/// uncertainties: the same optimum in about a third of the model runs (docs/performance.md).
pub fn fit_effects(
    simulate: &Simulator<'_>,
    baseline: &Parameters,
    Data { measured, keep, train: train_len, split, largest_stroke, input_error, pool }: Data<'_>,
    keys: &[&str],
    fitted: &[FittedParameter],
) -> Result<JointFit, Error> {
    let mut start = *baseline;
    for key in keys {
        set_effect(&mut start, key, true)?;
    }
    let with = |x: &[f64]| -> Result<Parameters, Error> {
        let mut p = start;
        for (s, &v) in fitted.iter().zip(x) {
            set_real(&mut p, s.name, v)?;
        }
        Ok(p)
    };
    let train = &measured[..train_len];
    let residuals = |x: &[f64]| -> Result<Vec<f64>, Error> {
        let m = simulate(&with(x)?, train_len)?;
        Ok(m.iter().zip(train).zip(keep).filter(|(_, k)| **k).map(|((m, y), _)| m - y).collect())
    };
    let switched_on = keys.iter().map(|k| effect_on(baseline, k).map(|on| !on)).collect::<Result<Vec<_>, _>>()?;
    let x0: Vec<f64> = fitted
        .iter()
        .map(|s| {
            let value = match s.start {
                Start::OfLargestStroke(share) if switched_on.iter().any(|&on| on) => Ok(share * largest_stroke),
                _ => real(&start, s.name),
            };
            value.map(|v| v.clamp(s.search.0.max(1e-300), s.search.1))
        })
        .collect::<Result<_, _>>()?;
    let bounds: Vec<Bound> = fitted.iter().map(bound).collect();
    let mut flags = Vec::new();
    let grid = fitted.iter().position(|f| f.grid.is_some());
    let (x, errors, evaluations) = match grid {
        None => match lm::solve(&residuals, &x0, &bounds, pool, FIT_OPTIONS, input_error) {
            Ok(solution) => {
                let errors = (0..fitted.len()).map(|i| solution.std_error(i)).collect();
                (solution.x, errors, solution.model_runs)
            }
            // the model failed at the start or next to it: the candidate stays where it started
            Err(e) => {
                flags.push(format!("the fit failed: {e}"));
                (x0.clone(), vec![None; fitted.len()], 0)
            }
        },
        Some(g) => match fit_on_grid(&residuals, &x0, &bounds, fitted, g, pool, input_error) {
            (Some((x, errors)), runs) => (x, errors, runs),
            (None, runs) => {
                flags.push("the fit failed at every grid point".to_string());
                (x0.clone(), vec![None; fitted.len()], runs)
            }
        },
    };
    let model = with(&x)?;
    let full = simulate(&model, measured.len())?;
    flags.extend(range_flags(fitted, &x));
    flags.extend(nothing_found_flags(baseline, keys, fitted, (&x, &x0), &errors)?);
    Ok(JointFit {
        params: fitted.iter().zip(&x).zip(errors).map(|((s, &x), e)| (s.name, x, e)).collect(),
        model,
        nrmse_train: nrmse_kept(train, &full[..train_len], &keep[..train_len]),
        nrmse_validation: nrmse_kept(&measured[split..], &full[split..], &keep[split..]),
        flags,
        evaluations,
    })
}

/// Fitted values and their standard uncertainties (none where the fit gives none).
type Fitted = (Vec<f64>, Vec<Option<f64>>);

/// A quantised parameter `g` (a delay in controller samples) searched on its grid, the others (if
/// any) fitted by Levenberg–Marquardt at each grid point tried: a derivative cannot see a staircase.
/// The parameters and their uncertainties (half a grid step for `g`), none when the fit failed at
/// every grid point; and the model runs.
fn fit_on_grid(
    residuals: &lm::Residuals<'_>,
    x0: &[f64],
    bounds: &[Bound],
    fitted: &[FittedParameter],
    g: usize,
    pool: &rayon::ThreadPool,
    input_error: &[Vec<f64>],
) -> (Option<Fitted>, usize) {
    let step = fitted[g].grid.expect("a grid parameter");
    let value_at = |k: usize| bounds[g].lo + k as f64 * step;
    let others: Vec<usize> = (0..fitted.len()).filter(|&i| i != g).collect();
    let full_x = |k: usize, rest: &[f64]| -> Vec<f64> {
        let mut x = x0.to_vec();
        x[g] = value_at(k);
        for (&i, &v) in others.iter().zip(rest) {
            x[i] = v;
        }
        x
    };
    let tried = std::sync::Mutex::new(std::collections::BTreeMap::new());
    let sse = |k: usize| {
        let fit = if others.is_empty() {
            residuals(&full_x(k, &[]))
                .map(|r| (r.iter().map(|v| v * v).sum(), x0.to_vec(), vec![None; fitted.len()], 1))
        } else {
            let rest = |x: &[f64]| residuals(&full_x(k, x));
            let start: Vec<f64> = others.iter().map(|&i| x0[i]).collect();
            let scales: Vec<Bound> = others.iter().map(|&i| bounds[i]).collect();
            lm::solve(&rest, &start, &scales, pool, FIT_OPTIONS, input_error).map(|s| {
                let mut errors = vec![None; fitted.len()];
                for (j, &i) in others.iter().enumerate() {
                    errors[i] = s.std_error(j);
                }
                (s.cost, full_x(k, &s.x), errors, s.model_runs)
            })
        };
        let cost = fit.as_ref().map_or(f64::INFINITY, |f| f.0);
        tried.lock().expect("no fit panicked").insert(k, fit.ok());
        cost
    };
    let n = ((bounds[g].hi - bounds[g].lo) / step).round() as usize;
    let (best, _) = grid_minimum(sse, n);
    let tried = tried.into_inner().expect("no fit panicked");
    let runs = tried.values().flatten().map(|f| f.3).sum::<usize>() + tried.values().filter(|f| f.is_none()).count();
    let fit = tried.get(&best).cloned().flatten().map(|(_, mut x, mut errors, _)| {
        x[g] = value_at(best);
        errors[g] = Some(0.5 * step);
        (x, errors)
    });
    (fit, runs)
}

/// Why the fitted values `x` are not plausible: each at its search bound or outside its
/// plausible range.
fn range_flags(fitted: &[FittedParameter], x: &[f64]) -> Vec<String> {
    let mut flags = Vec::new();
    for (s, &x) in fitted.iter().zip(x) {
        if bound(s).near_bound(x, AT_BOUND) {
            flags.push(format!("{} = {x:.4e} at its search bound", s.name));
        } else if x < s.plausible.0 || x > s.plausible.1 {
            flags.push(format!(
                "{} = {x:.4e} outside the plausible {:.3e}–{:.3e}",
                s.name, s.plausible.0, s.plausible.1
            ));
        }
    }
    flags
}

/// Why a fit of `keys` on `baseline` found nothing: a refit of effects already on that stays within
/// its uncertainty of the model's values (`x0`), or an effect switched on whose size (its first
/// parameter, zero when off) is within its uncertainty of zero. `(x, x0)`: fitted and start values.
fn nothing_found_flags(
    baseline: &Parameters,
    keys: &[&str],
    fitted: &[FittedParameter],
    (x, x0): (&[f64], &[f64]),
    errors: &[Option<f64>],
) -> Result<Vec<String>, Error> {
    let mut flags = Vec::new();
    let was_on = keys.iter().map(|k| effect_on(baseline, k)).collect::<Result<Vec<_>, _>>()?;
    if was_on.iter().all(|&on| on) {
        let moved = fitted.iter().zip(x).zip(x0).zip(errors).any(|(((s, &x), &x0), e)| match (s.grid, e) {
            (Some(step), _) => (x - x0).abs() >= 0.5 * step,
            (None, Some(e)) => (x - x0).abs() > MOVED_SIGMAS * e,
            (None, None) => (x - x0).abs() > 1e-3 * x0.abs(),
        });
        if !moved {
            flags.push(format!("within {MOVED_SIGMAS} standard uncertainties of the model's value: {NOTHING_MOVED}"));
        }
    }
    // (a spurious viscous friction of 313 ± 286 N·s/m had been kept beside a hidden cracking)
    for (key, on) in keys.iter().zip(&was_on) {
        let size = catalog().find(|e| e.key == *key).and_then(|e| e.fitted.first()).map(|f| f.name);
        let Some(i) = size.and_then(|name| fitted.iter().position(|f| f.name == name)) else { continue };
        if let (false, Some(e)) = (*on, errors[i]) {
            if x[i].abs() <= MOVED_SIGMAS * e {
                flags.push(format!(
                    "{} = {:.4e} ± {e:.1e}: within {MOVED_SIGMAS} standard uncertainties of zero, {key} {INDISTINGUISHABLE}",
                    fitted[i].name, x[i]
                ));
            }
        }
    }
    Ok(flags)
}

/// Coarse grid step of [`grid_minimum`].
const GRID_COARSE: usize = 3;

/// The grid point k in 0..=n where `sse` is least, and the runs it took: every
/// [`GRID_COARSE`]-th point (and the last), then the points between the best of them and its
/// coarse neighbours. Exact when `sse` falls and rises once around its minimum on the scale of
/// the coarse step, as a delay's error does (the amplifier delay: 12 runs instead of 21).
fn grid_minimum(sse: impl Fn(usize) -> f64, n: usize) -> (usize, usize) {
    let mut points: Vec<usize> = (0..=n).step_by(GRID_COARSE).collect();
    if points.last() != Some(&n) {
        points.push(n);
    }
    let mut tried: Vec<(usize, f64)> = points.iter().map(|&k| (k, sse(k))).collect();
    let coarse_best = tried.iter().min_by(|a, b| a.1.total_cmp(&b.1)).expect("non-empty grid").0;
    let near = coarse_best.saturating_sub(GRID_COARSE - 1)..=(coarse_best + GRID_COARSE - 1).min(n);
    for k in near {
        if !points.contains(&k) {
            tried.push((k, sse(k)));
        }
    }
    // the first of equal values, in grid order: independent of the order tried
    tried.sort_by_key(|t| t.0);
    let best = tried.iter().min_by(|a, b| a.1.total_cmp(&b.1)).expect("non-empty grid").0;
    (best, tried.len())
}

impl Candidate {
    /// Plausible as a refinement of an effect already kept: a refit that stays within its
    /// uncertainty of the kept value has not found nothing, it has confirmed it.
    pub fn plausible_refinement(&self) -> bool {
        self.flags.iter().all(|f| f.ends_with(NOTHING_MOVED))
    }
}

impl JointFit {
    /// The fit as a candidate of effect `spec` against the error it starts from.
    pub fn candidate(self, spec: &EffectInfo, action: &'static str, (b, f): (f64, f64)) -> Candidate {
        Candidate {
            effect: spec.key,
            action,
            params: self.params,
            inherited: Vec::new(),
            nrmse_train: self.nrmse_train,
            nrmse_validation: self.nrmse_validation,
            reduction: 1.0 - self.nrmse_validation / b,
            explained: share(b, self.nrmse_validation, f),
            plausible: self.flags.is_empty(),
            flags: self.flags,
            signature: spec.signature,
            evaluations: self.evaluations,
        }
    }
}

/// Fits `spec` on top of `baseline` and scores it (the first of `errors` is the validation NRMSE
/// it starts from, the second the floor).
pub fn try_candidate(
    simulate: &Simulator<'_>,
    baseline: &Parameters,
    data: Data<'_>,
    errors: (f64, f64),
    spec: &EffectInfo,
) -> Result<Candidate, Error> {
    let action = if effect_on(baseline, spec.key)? { "refitted" } else { "switched on" };
    let fit = fit_effects(simulate, baseline, data, &[spec.key], spec.fitted)?;
    Ok(fit.candidate(spec, action, errors))
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn grid_minimum_finds_the_least_point_of_a_valley() {
        for n in [0, 1, 2, 5, 20, 21] {
            for target in 0..=n {
                let (best, runs) = grid_minimum(|k| (k as f64 - target as f64).abs(), n);
                assert_eq!(best, target, "n {n}");
                assert!(runs <= n + 1);
            }
        }
        assert_eq!(grid_minimum(|k| (k as f64 - 13.0).powi(2), 20), (13, 12));
    }

    #[test]
    fn catalog_names_are_fmu_parameters() {
        let mut p = semi_active_damper::physics::params::Parameters::default();
        for e in catalog() {
            set_effect(&mut p, e.key, true).unwrap();
            for s in e.fitted {
                let v = real(&p, s.name).unwrap();
                set_real(&mut p, s.name, v).unwrap();
                assert!(s.plausible.0 >= s.search.0 && s.plausible.1 <= s.search.1, "{}", s.name);
            }
            for s in e.secondary {
                let v = real(&p, s.name).unwrap();
                set_real(&mut p, s.name, v).unwrap();
            }
        }
    }
}
