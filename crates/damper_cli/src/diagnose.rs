//! Which physical effect is missing: every effect of the catalog (docs/effects.md) is tried in
//! turn. An effect the baseline lacks is switched on; one it has is refitted ("a parameter
//! moved"). Its one or two parameters are fitted on the training part, and the candidate is scored
//! on the held-out validation part. The verdict:
//!
//! - `none`: the baseline's validation residual is at the noise floor and no candidate improves it;
//! - `effect`: the best candidate explains at least [`MIN_EXPLAINED`] of the validation error above
//!   the noise floor, clearly more than the runner-up, with plausible parameters;
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
use crate::parameters::{get_parameter, get_real, set_bool, set_real, Value};
use semi_active_damper::physics::params::Parameters;

/// Least share of the validation error above the noise floor an effect must explain to be named.
pub const MIN_EXPLAINED: f64 = 0.5;
/// The runner-up's cut must be below this fraction of the best's for a confident answer.
pub const MAX_RUNNER_UP_RATIO: f64 = 0.7;
/// A baseline within this factor of the noise floor has nothing to explain.
pub const FLOOR_FACTOR: f64 = 1.3;
/// Objective evaluations per fit.
pub const MAX_EVALS: usize = 25;

/// A fitted parameter of an effect.
#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    pub name: &'static str,
    pub bound: Bound,
    /// Range of physically plausible values (docs/effects.md).
    pub plausible: (f64, f64),
    /// Grid step for a parameter the model quantises (a delay in controller samples): searched on
    /// the grid instead of by Nelder–Mead, whose simplex cannot move on a staircase.
    pub grid: Option<f64>,
}

/// One entry of the effect catalog.
#[derive(Clone, Copy, Debug)]
pub struct EffectSpec {
    pub key: &'static str,
    pub params: &'static [ParamSpec],
    /// The residual signature that points to it, in plain words.
    pub signature: &'static str,
}

const fn lin(lo: f64, hi: f64) -> Bound {
    Bound { lo, hi, log: false }
}
const fn log(lo: f64, hi: f64) -> Bound {
    Bound { lo, hi, log: true }
}

/// The catalog, in the order of docs/effects.md.
pub const CATALOG: [EffectSpec; 7] = [
    EffectSpec {
        key: "compressibility",
        params: &[ParamSpec { name: "air_fraction", bound: log(1e-4, 0.2), plausible: (0.005, 0.05), grid: None }],
        signature: "error proportional to the force rate during transients, larger at low pressure and in compression, gone in steady state",
    },
    EffectSpec {
        key: "mount_compliance",
        params: &[ParamSpec { name: "k1_mount", bound: log(2e6, 1e10), plausible: (2e7, 1e8), grid: None }],
        signature: "a phase lag growing with the force rate: a hysteresis loop of the error against velocity, the same in both directions",
    },
    EffectSpec {
        key: "amplifier_delay",
        params: &[ParamSpec { name: "tau_amp", bound: lin(0.0, 0.01), plausible: (0.001, 0.006), grid: Some(0.5e-3) }],
        signature: "a constant time shift between model and measurement, the same in both directions, largest after demand steps",
    },
    EffectSpec {
        key: "flow_forces",
        params: &[ParamSpec { name: "Cv_valve", bound: lin(0.5, 1.0), plausible: (0.9, 1.0), grid: None }],
        signature: "a force error growing with velocity and force: spool pushed towards closing by the jet",
    },
    EffectSpec {
        key: "seal_friction",
        params: &[
            ParamSpec { name: "F_coulomb", bound: lin(0.0, 2000.0), plausible: (50.0, 600.0), grid: None },
            ParamSpec { name: "v_friction", bound: log(1e-4, 0.1), plausible: (5e-4, 0.02), grid: None },
        ],
        signature: "an error jump of twice the friction force at every velocity reversal, independent of the valve and the demand",
    },
    EffectSpec {
        key: "piston_leakage",
        params: &[ParamSpec { name: "G_leak", bound: log(1e-15, 1e-10), plausible: (5e-14, 1e-12), grid: None }],
        signature: "the model too strong at low velocity, roughly proportional to the pressure; lost motion after reversals",
    },
    EffectSpec {
        key: "check_valve_cracking",
        params: &[ParamSpec { name: "p_cv_crack", bound: lin(0.0, 0.9e5), plausible: (0.2e5, 0.8e5), grid: None }],
        signature: "a small offset with the sign of the direction of motion and a delayed force build-up after reversals",
    },
];

/// Switches the effect `key` (`effect_<key>`) on or off.
pub fn set_effect(p: &mut Parameters, key: &str, on: bool) -> Result<(), String> {
    set_bool(p, &format!("effect_{key}"), on)
}

/// Whether the effect `key` is on in `p`.
pub fn effect_on(p: &Parameters, key: &str) -> Result<bool, String> {
    match get_parameter(p, &format!("effect_{key}"))? {
        Value::Boolean(b) => Ok(b),
        other => Err(format!("effect_{key} is {other}, not a switch")),
    }
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
}

/// Runs the diagnosis. `simulate(params, n)` returns the model's force for the first `n` samples
/// of the measurement; `measured` is the measured force; samples `[..split]` train, the rest
/// validate. Candidates run on `threads` threads; `progress` is told when each one is done.
pub fn diagnose(
    simulate: &Simulator<'_>,
    baseline: &Parameters,
    measured: &[f64],
    split: usize,
    threads: usize,
    progress: &(dyn Fn(&Candidate) + Sync),
) -> Result<Diagnosis, String> {
    let n = measured.len();
    let base = simulate(baseline, n)?;
    let nrmse_baseline = nrmse(&base[split..], &measured[split..]);
    let residual: Vec<f64> = base.iter().zip(measured).map(|(m, y)| m - y).collect();
    let sigma = noise_sigma(&residual[split..]);
    let val = &measured[split..];
    let val_std = (val.iter().map(|y| y * y).sum::<f64>() / val.len() as f64
        - (val.iter().sum::<f64>() / val.len() as f64).powi(2))
    .sqrt();
    let nrmse_noise_floor = sigma / val_std;

    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads.max(1) {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(spec) = CATALOG.get(i) else { break };
                let c = try_candidate(simulate, baseline, measured, split, (nrmse_baseline, nrmse_noise_floor), spec);
                if let Ok(c) = &c {
                    progress(c);
                }
                results.lock().unwrap().push((i, c));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|r| r.0);
    let mut candidates = Vec::new();
    for (_, c) in results {
        candidates.push(c?);
    }
    candidates.sort_by(|a, b| a.nrmse_validation.total_cmp(&b.nrmse_validation));

    let at_floor = nrmse_baseline <= FLOOR_FACTOR * nrmse_noise_floor;
    let best = candidates.first();
    let runner_up = candidates.get(1).map_or(0.0, |c| c.explained);
    let (verdict, best_effect, explanation) = match best {
        Some(b)
            if !at_floor
                && b.explained >= MIN_EXPLAINED
                && b.plausible
                && runner_up < MAX_RUNNER_UP_RATIO * b.explained =>
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
                "no candidate explains the residual confidently (best: {} explains {:.0} % of the error above the noise floor, runner-up {:.0} %); baseline NRMSE {nrmse_baseline:.4} against a noise floor of {nrmse_noise_floor:.4}",
                best.map_or("none", |b| b.effect),
                100.0 * best.map_or(0.0, |b| b.explained),
                100.0 * runner_up
            ),
        ),
    };
    Ok(Diagnosis { verdict, best_effect, nrmse_baseline, nrmse_noise_floor, candidates, explanation })
}

fn try_candidate(
    simulate: &Simulator<'_>,
    baseline: &Parameters,
    measured: &[f64],
    split: usize,
    (nrmse_baseline, nrmse_floor): (f64, f64),
    spec: &EffectSpec,
) -> Result<Candidate, String> {
    let mut start = *baseline;
    let action = if effect_on(baseline, spec.key)? { "refitted" } else { "switched on" };
    set_effect(&mut start, spec.key, true)?;
    let with = |x: &[f64]| -> Result<Parameters, String> {
        let mut p = start;
        for (s, &v) in spec.params.iter().zip(x) {
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
        .params
        .iter()
        .map(|s| get_real(&start, s.name).map(|v| v.clamp(s.bound.lo.max(1e-300), s.bound.hi)))
        .collect::<Result<_, _>>()?;
    let bounds: Vec<Bound> = spec.params.iter().map(|s| s.bound).collect();
    let (fit, errors) = match spec.params {
        [ParamSpec { bound, grid: Some(step), .. }] => {
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
            let fit = minimize(sse, &x0, &bounds, MAX_EVALS * spec.params.len());
            let errors = standard_errors(sse, &fit.x, split, 1e-2);
            (fit, errors)
        }
    };
    let fitted = with(&fit.x)?;
    let full = simulate(&fitted, measured.len())?;
    let nrmse_validation = nrmse(&full[split..], &measured[split..]);
    let nrmse_train = nrmse(&full[..split], train);
    let mut flags = Vec::new();
    for (s, &x) in spec.params.iter().zip(&fit.x) {
        if s.bound.at_bound(x) {
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
        params: spec.params.iter().zip(&fit.x).zip(errors).map(|((s, &x), e)| (s.name, x, e)).collect(),
        nrmse_train,
        nrmse_validation,
        reduction: 1.0 - nrmse_validation / nrmse_baseline,
        explained: ((nrmse_baseline.powi(2) - nrmse_validation.powi(2))
            / (nrmse_baseline.powi(2) - nrmse_floor.powi(2)).max(1e-300))
        .min(1.0),
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
        for e in CATALOG {
            set_effect(&mut p, e.key, true).unwrap();
            for s in e.params {
                let v = get_real(&p, s.name).unwrap();
                set_real(&mut p, s.name, v).unwrap();
                assert!(s.plausible.0 >= s.bound.lo && s.plausible.1 <= s.bound.hi, "{}", s.name);
            }
        }
    }
}
