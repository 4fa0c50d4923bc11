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
//! The kept effects are the answer only when they reach the noise floor or the first of them is
//! named on its own (the verdict of [`crate::diagnose`]).

use crate::candidate::{Candidate, FitSetup};
use crate::criteria::{FLOOR_FACTOR, MIN_EXPLAINED};
use crate::parameters::{set_effect, set_real};
use semi_active_damper::effects::EffectInfo;
use semi_active_damper::physics::params::Parameters;

/// Most rounds of refitting the kept effects with the others in place.
pub const POLISH_PASSES: usize = 2;

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
    pub fn add(&mut self, c: &Candidate) -> Result<(), String> {
        if self.effects.contains(&c.effect) {
            return Ok(());
        }
        self.push(c, false, true)
    }

    /// Records `c` as a rung (`refit`: of an effect already kept); a kept one enters the model.
    fn push(&mut self, c: &Candidate, refit: bool, kept: bool) -> Result<(), String> {
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
) -> Result<Parameters, String> {
    let mut q = *p;
    set_effect(&mut q, effect, true)?;
    for (name, value, _) in params {
        set_real(&mut q, name, *value)?;
    }
    Ok(q)
}

/// Climbs the ladder from the diagnosis's `ranked` candidates (best first) over `specs`.
pub fn climb(
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    ranked: &[Candidate],
    (nrmse_baseline, nrmse_floor): (f64, f64),
) -> Result<Ladder, String> {
    let base = Rung {
        added: "baseline",
        refit: false,
        params: Vec::new(),
        nrmse_validation: nrmse_baseline,
        explained: 0.0,
        kept: true,
    };
    let mut ladder =
        Ladder { rungs: vec![base], effects: Vec::new(), params: *baseline, nrmse_validation: nrmse_baseline };
    let mut round: Vec<Candidate> = ranked.to_vec();
    while ladder.nrmse_validation > FLOOR_FACTOR * nrmse_floor {
        let Some(best) = round.iter().find(|c| c.plausible).or(round.first()) else { break };
        let least = if ladder.effects.is_empty() { 0.5 * MIN_EXPLAINED } else { MIN_EXPLAINED };
        let kept = best.plausible && best.explained >= least;
        ladder.push(best, false, kept)?;
        if !kept {
            break;
        }
        let rest: Vec<&'static EffectInfo> =
            specs.iter().copied().filter(|s| !ladder.effects.contains(&s.key)).collect();
        if rest.is_empty() || ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
            break;
        }
        round = fit.all(&rest, &ladder.params, (ladder.nrmse_validation, nrmse_floor))?;
    }
    for _ in 0..POLISH_PASSES {
        if ladder.effects.len() < 2 || ladder.nrmse_validation <= FLOOR_FACTOR * nrmse_floor {
            break;
        }
        let start = ladder.nrmse_validation;
        for key in ladder.effects.clone() {
            let spec = specs.iter().copied().find(|s| s.key == key).ok_or("a kept effect outside the catalog")?;
            let c = fit.all(&[spec], &ladder.params, (ladder.nrmse_validation, nrmse_floor))?.remove(0);
            let kept = c.plausible && c.nrmse_validation < ladder.nrmse_validation;
            ladder.push(&c, true, kept)?;
        }
        if ladder.nrmse_validation > 0.99 * start {
            break;
        }
    }
    Ok(ladder)
}
