//! The verdict of a diagnosis, from the baseline's validation NRMSE b, the floor f
//! ([`Floor`]), the ranked candidates and the ladder's end L with its kept effects:
//!
//! - `none`: b ≤ [`FLOOR_FACTOR`]·f and no candidate cuts the error clearly (see `effect`);
//! - `effect` (the named effects explain the record): L ≤ [`EXPLAINED_FACTOR`]·f, and either the
//!   best candidate alone is confident (it explains ≥ [`MIN_EXPLAINED`] of the error above the
//!   floor with plausible, moved parameters, clearly more than any plausible runner-up, or it
//!   alone reaches the floor, or it leaves at most 2× the floor and every plausible rival leaves
//!   [`RIVAL_LEFT_FACTOR`] times its mean-square error above the floor) or two or more effects of the ladder reach it together. Near the
//!   floor, a weak effect is named when it cuts the mean-square error by at least [`MIN_GAIN`] of
//!   the noise variance and [`NUMERICS_MARGIN`] times the numerical error's, clearly more than
//!   any other candidate;
//! - `does_not_fit`: L ≥ [`DOES_NOT_FIT_NRMSE`] and ≥ [`DOES_NOT_FIT_FLOOR_FACTOR`]·f: the model,
//!   even with the catalog's effects, is far from this damper; calibrate it first;
//! - `partial`: the ladder's effects explain ≥ [`PARTIAL_MIN_EXPLAINED`] of the error above the floor but
//!   leave more than [`EXPLAINED_FACTOR`]·f: they are named, with what is left;
//! - `unexplained`: none of these.

use crate::candidate::Candidate;
use crate::criteria::{
    share, DOES_NOT_FIT_FLOOR_FACTOR, DOES_NOT_FIT_NRMSE, EXPLAINED_FACTOR, FLOOR_FACTOR, MAX_RUNNER_UP_RATIO,
    MIN_EXPLAINED, MIN_GAIN, NUMERICS_MARGIN, PARTIAL_MIN_EXPLAINED, RIVAL_LEFT_FACTOR,
};
use crate::floor::Floor;
use crate::ladder::Ladder;

/// A verdict with its explanation and the ladder it ends with.
pub struct Judged {
    pub verdict: &'static str,
    pub best_effect: Option<&'static str>,
    pub explanation: String,
    pub ladder: Ladder,
    pub effects: Vec<&'static str>,
}

/// Judges a diagnosis ([module docs](self)).
pub fn judge(b: f64, floor: &Floor, candidates: &[Candidate], mut ladder: Ladder) -> Result<Judged, String> {
    let f = floor.nrmse;
    let best = candidates.first();
    // a rival that needs implausible parameters is no competing explanation
    let rivals = || candidates.iter().skip(1).filter(|c| c.plausible);
    let runner_up = rivals().map(|c| c.explained).fold(0.0, f64::max);
    let at = |c: &Candidate| c.nrmse_validation <= FLOOR_FACTOR * f;
    let only_best_at_floor = best.is_some_and(at) && !rivals().any(at);
    // the mean-square error a candidate leaves above the floor
    let left = |c: &Candidate| (c.nrmse_validation * c.nrmse_validation - f * f).max(f64::MIN_POSITIVE);
    // every plausible rival leaves far more than the best, which is near the floor: shares of the
    // error explained compress the difference (83 % against 100 % is 11× the residual)
    let rivals_far_behind = |c: &Candidate| {
        c.nrmse_validation <= EXPLAINED_FACTOR * f && rivals().all(|r| left(r) >= RIVAL_LEFT_FACTOR * left(c))
    };
    let confident = best.filter(|c| {
        c.plausible
            && c.explained >= MIN_EXPLAINED
            && (runner_up < MAX_RUNNER_UP_RATIO * c.explained || only_best_at_floor || rivals_far_behind(c))
    });
    let done = |verdict, ladder: Ladder, explanation: String| {
        let effects = if matches!(verdict, "effect" | "partial") { ladder.effects.clone() } else { Vec::new() };
        Ok(Judged { verdict, best_effect: effects.first().copied(), explanation, ladder, effects })
    };

    if b <= FLOOR_FACTOR * f {
        // the cut of the mean-square error as a share of the noise variance
        let noise2 = floor.nrmse_noise * floor.nrmse_noise;
        let gain = |c: &Candidate| (b * b - c.nrmse_validation * c.nrmse_validation) / noise2;
        let least = MIN_GAIN.max(NUMERICS_MARGIN * floor.nrmse_numerics * floor.nrmse_numerics / noise2);
        let weak = best
            .filter(|c| c.plausible && gain(c) >= least && rivals().all(|r| gain(r) < MAX_RUNNER_UP_RATIO * gain(c)));
        return match weak {
            Some(c) => {
                let text = format!(
                    "a weak effect near the noise floor: the baseline's validation NRMSE {b:.4} is only {:.2}× the floor {f:.4}, but {} {} cuts its mean-square error by {:.0} % of the noise variance (NRMSE {:.4}; the least counted {:.1} %), clearly more than any other candidate, with plausible parameters. Its signature: {}.",
                    b / f,
                    c.effect,
                    c.action,
                    100.0 * gain(c),
                    c.nrmse_validation,
                    100.0 * least,
                    c.signature
                );
                ladder.add(c)?;
                done("effect", ladder, text)
            }
            None => done(
                "none",
                ladder,
                format!("the baseline's validation NRMSE {b:.4} is at the floor {f:.4}: nothing is missing that these data show"),
            ),
        };
    }

    let l = ladder.nrmse_validation;
    let kept = ladder.effects.join(" + ");
    let left = format!("{:.1}× the floor", l / f);
    if !ladder.effects.is_empty() && l <= EXPLAINED_FACTOR * f {
        if let Some(c) = confident.filter(|c| ladder.effects.first() == Some(&c.effect)) {
            let mut text = format!(
                "{} {} explains {:.0} % of the error above the floor and cuts the validation NRMSE by {:.0} % ({b:.4} → {:.4}; floor {f:.4}). Its signature: {}.",
                c.effect,
                c.action,
                100.0 * c.explained,
                100.0 * c.reduction,
                c.nrmse_validation,
                c.signature
            );
            if ladder.effects.len() > 1 {
                text.push_str(&format!(" With {kept} together the validation NRMSE is {l:.4}."));
            }
            return done("effect", ladder, text);
        }
        if let [one] = ladder.effects.as_slice() {
            let rival = candidates
                .iter()
                .filter(|c| c.plausible && c.effect != *one)
                .max_by(|x, y| x.explained.total_cmp(&y.explained));
            let own = candidates.iter().find(|c| c.effect == *one).map_or(0.0, |c| c.explained);
            let text = format!(
                "ambiguous: {one} brings the validation NRMSE from {b:.4} to {l:.4} ({left} {f:.4}) and explains {:.0} % of the error above the floor, but {} explains {:.0} %: these data cannot tell them apart",
                100.0 * own,
                rival.map_or("another candidate", |r| r.effect),
                100.0 * rival.map_or(0.0, |r| r.explained),
            );
            return done("unexplained", ladder, text);
        }
        if ladder.effects.len() > 1 {
            let text = format!(
                "no single candidate explains the residual, but {kept} together bring the validation NRMSE from {b:.4} to {l:.4}, {left} {f:.4} (see the ladder)"
            );
            return done("effect", ladder, text);
        }
    }
    if l >= DOES_NOT_FIT_NRMSE && l >= DOES_NOT_FIT_FLOOR_FACTOR * f {
        let text = format!(
            "the model does not fit this damper: the baseline's validation NRMSE is {b:.4} and the best the catalog's effects reach is {l:.4}{}, {left} {f:.4}. A damper of another kind, or nominal parameters far from this damper's: calibrate the model first (damper calibrate) and diagnose with its parameter file.",
            if kept.is_empty() { String::new() } else { format!(" (with {kept})") }
        );
        return done("does_not_fit", ladder, text);
    }
    if !ladder.effects.is_empty() && share(b, l, f) >= PARTIAL_MIN_EXPLAINED {
        let missing = ladder.rungs.iter().rev().find(|r| !r.kept && !r.refit);
        let text = format!(
            "a partial explanation: {kept} explain {:.0} % of the error above the floor (validation NRMSE {b:.4} → {l:.4}), but {:.0} % of it is left, {left} {f:.4}; {}",
            100.0 * share(b, l, f),
            100.0 * (1.0 - share(b, l, f)),
            match missing {
                Some(r) => format!(
                    "the best effect for the rest, {}, explains only {:.0} % of it: something outside the catalog, or a parameter to calibrate",
                    r.added,
                    100.0 * r.explained
                ),
                None => "no further effect of the catalog was left to try".into(),
            }
        );
        return done("partial", ladder, text);
    }
    let text = format!(
        "no candidate explains the residual confidently (best: {} explains {:.0} % of the error above the floor, best plausible runner-up {:.0} %); baseline NRMSE {b:.4} against a floor of {f:.4}",
        best.map_or("none", |c| c.effect),
        100.0 * best.map_or(0.0, |c| c.explained),
        100.0 * runner_up
    );
    done("unexplained", ladder, text)
}
