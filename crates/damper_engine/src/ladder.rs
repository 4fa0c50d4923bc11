//! Step 4 of the diagnosis, the ladder: effects are added to the model one at a time (forward
//! selection). The first rung is the best plausible candidate of the diagnosis; each further rung
//! refits every effect not yet added on top of the ones kept, so that the next effect explains what
//! they leave rather than what it explained alone, and adds the best. An effect is kept when it
//! explains at least [`MIN_EXPLAINED`] of the error still above the noise floor, with plausible
//! parameters (the first one already at half that: two effects of a size may each explain less than
//! half alone); the ladder stops at the noise floor or at the first effect not kept, which it shows.
//! With two or more effects kept and error left above the floor, the kept effects are refitted in
//! turn with the others in place (an early effect's fit absorbed some of the later ones' error),
//! up to [`POLISH_PASSES`] times while the error falls.
//!
//! Two refinements: an effect kept that has secondary parameters (the polytropic exponent, the
//! mount's cubic stiffness) is refitted with them once it is kept, if error is left above the floor; and when the best candidate of
//! a round fits only with implausible parameters (it absorbs the error of two effects that add
//! up), it is fitted jointly with each of the next [`PAIR_PARTNERS`] candidates, and the best
//! plausible pair is kept if it explains more than the best single effect. A ladder that ends above
//! the floor is climbed again from the best pair of the leading candidates ([`climb`]).
//!
//! The kept effects are judged by [`crate::verdict`].

use crate::candidate::{Candidate, FitSetup, JointFit, NOTHING_MOVED};
use crate::criteria::share;
use crate::criteria::{EXPLAINED_FACTOR, FLOOR_FACTOR, MIN_EXPLAINED};
use crate::error::Error;
use crate::parameters::{set_effect, set_real};
use semi_active_damper::effects::EffectInfo;
use semi_active_damper::physics::params::Parameters;

/// Most rounds of refitting the kept effects with the others in place.
pub const POLISH_PASSES: usize = 2;
/// Candidates after an implausible best that are each fitted jointly with it.
pub const PAIR_PARTNERS: usize = 3;
/// The best candidates whose pairs are fitted jointly when the ladder stalls above the floor.
pub const STALL_LEADERS: usize = 3;

/// A rung of the ladder: the model after adding one more effect.
#[derive(Clone, Debug)]
pub struct Rung {
    /// The effect added ("baseline" for the first rung).
    pub added: &'static str,
    /// A kept effect refitted with all the others in place, not a new one.
    pub refit: bool,
    /// Its parameters as fitted on top of the effects kept before.
    pub params: Vec<(&'static str, f64, Option<f64>)>,
    pub nrmse_validation: f64,
    /// Share of the error above the noise floor, left by the rungs before, that it explains.
    pub explained: f64,
    pub kept: bool,
}

/// The ladder and the model it ends with.
#[derive(Clone, Debug)]
pub struct Ladder {
    pub rungs: Vec<Rung>,
    /// The kept effects, in the order added.
    pub effects: Vec<&'static str>,
    /// The baseline with the kept effects at their fitted values.
    pub params: Parameters,
    pub nrmse_validation: f64,
}

impl Ladder {
    /// Adds `c` as a kept rung (an effect named near the noise floor, where the ladder stops).
    pub fn add(&mut self, c: &Candidate) -> Result<(), Error> {
        if self.effects.contains(&c.effect) {
            return Ok(());
        }
        self.push(c, false, true)
    }

    /// Records `c` as a rung (`refit`: of an effect already kept); a kept one enters the model.
    fn push(&mut self, c: &Candidate, refit: bool, kept: bool) -> Result<(), Error> {
        if kept {
            self.params = with_effect(&self.params, c.effect, &c.params)?;
            self.nrmse_validation = c.nrmse_validation;
            if !refit {
                self.effects.push(c.effect);
            }
        }
        self.rungs.push(Rung {
            added: c.effect,
            refit,
            params: c.params.clone(),
            nrmse_validation: c.nrmse_validation,
            explained: c.explained,
            kept,
        });
        Ok(())
    }
}

/// `p` with `effect` switched on at the fitted `params`.
pub fn with_effect(
    p: &Parameters,
    effect: &str,
    params: &[(&'static str, f64, Option<f64>)],
) -> Result<Parameters, Error> {
    let mut q = *p;
    set_effect(&mut q, effect, true)?;
    for (name, value, _) in params {
        set_real(&mut q, name, *value)?;
    }
    Ok(q)
}

/// The effect of `key` among `specs` (the candidates' effects).
fn spec_of(specs: &[&'static EffectInfo], key: &str) -> Result<&'static EffectInfo, Error> {
    specs.iter().copied().find(|s| s.key == key).ok_or_else(|| Error::NotACandidate { key: key.to_string() })
}

/// The candidates of the effects not yet kept, fitted on top of the ladder's model.
fn next_round(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    ladder: &Ladder,
    nrmse_floor: f64,
) -> Result<Vec<Candidate>, Error> {
    let rest: Vec<&'static EffectInfo> = specs.iter().copied().filter(|s| !ladder.effects.contains(&s.key)).collect();
    if rest.is_empty() {
        return Ok(Vec::new());
    }
    fit.all(&rest, &ladder.params, (ladder.nrmse_validation, nrmse_floor))
}

/// Refits the just-kept effect `spec` with its secondary parameters; kept when it lowers the
/// validation error with plausible values.
fn refine(fit: &FitSetup<'_>, spec: &'static EffectInfo, ladder: &mut Ladder, nrmse_floor: f64) -> Result<(), Error> {
    if spec.secondary.is_empty() {
        return Ok(());
    }
    let all: Vec<_> = spec.fitted.iter().chain(spec.secondary).copied().collect();
    let errors = (ladder.nrmse_validation, nrmse_floor);
    let c = fit.joint(&ladder.params, &[spec.key], &all)?.candidate(spec, "refitted", errors);
    let kept = c.plausible_refinement() && c.nrmse_validation < ladder.nrmse_validation;
    ladder.push(&c, true, kept)
}

/// Two effects fitted together.
struct Pair {
    specs: [&'static EffectInfo; 2],
    fit: JointFit,
}

impl Pair {
    fn explained(&self, (b, f): (f64, f64)) -> f64 {
        share(b, self.fit.nrmse_validation, f)
    }

    /// One rung per effect, each with its own parameters and the pair's error.
    fn candidates(&self, errors: (f64, f64)) -> Vec<Candidate> {
        let n0 = self.specs[0].fitted.len();
        self.specs
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                let mut part = self.fit.clone();
                part.params = if i == 0 { part.params[..n0].to_vec() } else { part.params[n0..].to_vec() };
                part.candidate(spec, "switched on with the other", errors)
            })
            .collect()
    }
}

/// When the best candidate of `round` fits only with implausible parameters, it fitted jointly
/// with each of the next [`PAIR_PARTNERS`]: the best plausible pair, if any.
fn best_pair(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    round: &[Candidate],
    params: &Parameters,
) -> Result<Option<Pair>, Error> {
    let Some(top) = round.first().filter(|c| !c.plausible && !c.flags.iter().any(|f| f.ends_with(NOTHING_MOVED)))
    else {
        return Ok(None);
    };
    let pairs: Vec<_> = round.iter().skip(1).take(PAIR_PARTNERS).map(|c| (top.effect, c.effect)).collect();
    fit_pairs(fit, specs, &pairs, params)
}

/// Each pair of effects fitted jointly on top of `params`: the plausible one that leaves the least
/// validation error, if any.
fn fit_pairs(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    pairs: &[(&'static str, &'static str)],
    params: &Parameters,
) -> Result<Option<Pair>, Error> {
    use rayon::prelude::*;
    let fits: Vec<Result<Pair, Error>> = fit.pool.install(|| {
        pairs
            .par_iter()
            .map(|&(a, b)| {
                let (first, second) = (spec_of(specs, a)?, spec_of(specs, b)?);
                let all: Vec<_> = first.fitted.iter().chain(second.fitted).copied().collect();
                let f = fit.joint(params, &[a, b], &all)?;
                Ok(Pair { specs: [first, second], fit: f })
            })
            .collect()
    });
    let mut best: Option<Pair> = None;
    for p in fits {
        let p = p?;
        if p.fit.flags.is_empty() && best.as_ref().is_none_or(|b| p.fit.nrmse_validation < b.fit.nrmse_validation) {
            best = Some(p);
        }
    }
    Ok(best)
}

/// `ladder` with the effects of `pair` kept.
fn keep_pair(ladder: &mut Ladder, pair: Pair, errors: (f64, f64)) -> Result<(), Error> {
    for c in pair.candidates(errors) {
        ladder.push(&c, false, true)?;
    }
    ladder.params = pair.fit.model;
    ladder.nrmse_validation = pair.fit.nrmse_validation;
    Ok(())
}

/// Climbs the ladder from the diagnosis's `ranked` candidates (best first) over `specs`. When it
/// ends above the floor ([`FLOOR_FACTOR`]), pairs are fitted jointly on the baseline: the
/// ladder's first effect (or the best candidate) with each other candidate, and the pairs of the
/// [`STALL_LEADERS`] best; every pair when it ends above [`EXPLAINED_FACTOR`] times the floor
/// (seal friction and check-valve cracking, each fitted alone, explained a quarter of the error or
/// made it worse, and cracking was not among the leaders). Two effects that add up can each,
/// fitted alone, absorb the other's error with plausible parameters and leave a residual that no
/// second effect explains, or that a wrong one half explains (piston leakage, then
/// compressibility instead of check-valve cracking). A ladder climbed from the best pair replaces
/// the first when it explains at least [`MIN_EXPLAINED`] of the error the first leaves above the
/// floor.
pub fn climb(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    ranked: &[Candidate],
    (nrmse_baseline, nrmse_floor): (f64, f64),
) -> Result<Ladder, Error> {
    let base = Rung {
        added: "baseline",
        refit: false,
        params: Vec::new(),
        nrmse_validation: nrmse_baseline,
        explained: 0.0,
        kept: true,
    };
    let start = Ladder { rungs: vec![base], effects: Vec::new(), params: *baseline, nrmse_validation: nrmse_baseline };
    let ladder = rise(fit, specs, start.clone(), ranked.to_vec(), nrmse_floor)?;
    if ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
        return Ok(ladder);
    }
    // the ladder's first effect (or the best candidate) with every other, and the leaders' pairs;
    // every pair when the ladder ends clearly above the floor
    let first = ladder.effects.first().copied().or(ranked.first().map(|c| c.effect));
    let stuck = ladder.nrmse_validation > EXPLAINED_FACTOR * nrmse_floor;
    let leaders: Vec<&'static str> =
        ranked.iter().take(if stuck { ranked.len() } else { STALL_LEADERS }).map(|c| c.effect).collect();
    let mut pairs: Vec<(&'static str, &'static str)> = Vec::new();
    let mut add = |a: &'static str, b: &'static str| {
        if a != b && !pairs.iter().any(|&(x, y)| (x, y) == (a, b) || (x, y) == (b, a)) {
            pairs.push((a, b));
        }
    };
    if let Some(first) = first {
        for c in ranked {
            add(first, c.effect);
        }
    }
    for (i, &a) in leaders.iter().enumerate() {
        for &b in &leaders[i + 1..] {
            add(a, b);
        }
    }
    let Some(pair) = fit_pairs(fit, specs, &pairs, baseline)? else { return Ok(ladder) };
    let errors = (nrmse_baseline, nrmse_floor);
    if pair.fit.nrmse_validation >= ladder.nrmse_validation || pair.explained(errors) < MIN_EXPLAINED {
        return Ok(ladder);
    }
    let mut alt = start;
    keep_pair(&mut alt, pair, errors)?;
    let round = next_round(fit, specs, &alt, nrmse_floor)?;
    let alt = rise(fit, specs, alt, round, nrmse_floor)?;
    // the other ladder must explain most of what the first leaves above the floor, not a little
    let better = share(ladder.nrmse_validation, alt.nrmse_validation, nrmse_floor) >= MIN_EXPLAINED;
    Ok(if better { alt } else { ladder })
}

/// Adds effects to `ladder` from `round` (the candidates fitted on top of it, best first) while
/// error is left above the floor, then refits the kept ones with the others in place.
fn rise(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    mut ladder: Ladder,
    mut round: Vec<Candidate>,
    nrmse_floor: f64,
) -> Result<Ladder, Error> {
    while ladder.nrmse_validation > FLOOR_FACTOR * nrmse_floor && !round.is_empty() {
        let Some(best) = round.iter().find(|c| c.plausible).or(round.first()) else { break };
        let least = if ladder.effects.is_empty() { 0.5 * MIN_EXPLAINED } else { MIN_EXPLAINED };
        let errors = (ladder.nrmse_validation, nrmse_floor);
        if let Some(pair) = best_pair(fit, specs, &round, &ladder.params)? {
            if pair.explained(errors) >= least && pair.fit.nrmse_validation < best.nrmse_validation {
                keep_pair(&mut ladder, pair, errors)?;
                round = next_round(fit, specs, &ladder, nrmse_floor)?;
                continue;
            }
        }
        let kept = best.plausible && best.explained >= least;
        ladder.push(best, false, kept)?;
        if !kept || ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
            break;
        }
        // the secondary parameters only where error is left for them
        refine(fit, spec_of(specs, best.effect)?, &mut ladder, nrmse_floor)?;
        if ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
            break;
        }
        round = next_round(fit, specs, &ladder, nrmse_floor)?;
    }
    for _ in 0..POLISH_PASSES {
        if ladder.effects.len() < 2 || ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
            break;
        }
        let start = ladder.nrmse_validation;
        for key in ladder.effects.clone() {
            let spec = spec_of(specs, key)?;
            let c = fit.all(&[spec], &ladder.params, (ladder.nrmse_validation, nrmse_floor))?.remove(0);
            let kept = c.plausible_refinement() && c.nrmse_validation < ladder.nrmse_validation;
            ladder.push(&c, true, kept)?;
        }
        if ladder.nrmse_validation > 0.99 * start {
            break;
        }
    }
    Ok(ladder)
}
