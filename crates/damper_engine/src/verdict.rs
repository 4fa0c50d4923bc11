//! The verdict of a diagnosis, from the baseline's validation NRMSE b, the floor f
//! ([`Floor`]), the ranked candidates and the ladder's end L with its kept effects:
//!
//! - `none`: b ≤ [`FLOOR_FACTOR`]·f and no candidate cuts the error clearly (see `effect`);
//! - `effect` (the named effects explain the record): L ≤ [`EXPLAINED_FACTOR`]·f, and either the
//!   best candidate alone is confident (it explains ≥ [`MIN_EXPLAINED`] of the error above the
//!   floor with plausible, moved parameters, clearly more than any plausible runner-up, or it
//!   alone reaches the floor, or it leaves at most 2× the floor and every plausible rival leaves
//!   [`RIVAL_LEFT_FACTOR`] times its mean-square error above the floor) or two or more effects of
//!   the ladder reach it together. Near the floor, a weak effect is named when it cuts the
//!   mean-square error by at least [`MIN_GAIN`] of the noise variance and [`NUMERICS_MARGIN`]
//!   times the numerical error's, clearly more than any other candidate;
//! - `does_not_fit`: L ≥ [`DOES_NOT_FIT_NRMSE`] and ≥ [`DOES_NOT_FIT_FLOOR_FACTOR`]·f: the model,
//!   even with the catalog's effects, is far from this damper; calibrate it first;
//! - `partial`: the ladder's effects explain ≥ [`PARTIAL_MIN_EXPLAINED`] of the error above the floor but
//!   leave more than [`EXPLAINED_FACTOR`]·f: they are named, with what is left;
//! - `unexplained`: none of these.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

use crate::candidate::Candidate;
use crate::criteria::{
    share, DOES_NOT_FIT_FLOOR_FACTOR, DOES_NOT_FIT_NRMSE, EXPLAINED_FACTOR, FLOOR_FACTOR, MAX_RUNNER_UP_RATIO,
    MIN_EXPLAINED, MIN_GAIN, NUMERICS_MARGIN, PARTIAL_MIN_EXPLAINED, RIVAL_LEFT_FACTOR,
};
use crate::error::Error;
use crate::floor::Floor;
use crate::ladder::Ladder;

/// What a diagnosis concludes ([module docs](self)); written to `summary.json` as
/// [`Verdict::as_str`], the strings of the summary's schema.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Verdict {
    /// `none`: the baseline is at the floor; nothing is missing that the data show.
    #[serde(rename = "none")]
    NothingMissing,
    /// `effect`: the named effects explain the record down to the floor.
    #[serde(rename = "effect")]
    Effect,
    /// `does_not_fit`: the model, even with the catalog's effects, is far from this damper.
    #[serde(rename = "does_not_fit")]
    DoesNotFit,
    /// `partial`: the named effects explain part of the error; the rest is outside the catalog.
    #[serde(rename = "partial")]
    Partial,
    /// `unexplained`: no confident explanation.
    #[serde(rename = "unexplained")]
    Unexplained,
}

impl Verdict {
    /// Every verdict, in the order of the module docs' list and of the declaration.
    pub const ALL: [Verdict; 5] =
        [Verdict::NothingMissing, Verdict::Effect, Verdict::DoesNotFit, Verdict::Partial, Verdict::Unexplained];

    /// The name in `summary.json` and in the reports.
    pub const fn as_str(self) -> &'static str {
        match self {
            Verdict::NothingMissing => "none",
            Verdict::Effect => "effect",
            Verdict::DoesNotFit => "does_not_fit",
            Verdict::Partial => "partial",
            Verdict::Unexplained => "unexplained",
        }
    }

    /// The verdicts that name effects (the ladder's kept ones).
    pub const fn names_effects(self) -> bool {
        matches!(self, Verdict::Effect | Verdict::Partial)
    }

    /// The verdicts that leave an error unexplained, whose report says what the residual follows.
    pub const fn leaves_error(self) -> bool {
        matches!(self, Verdict::Partial | Verdict::DoesNotFit | Verdict::Unexplained)
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl From<Verdict> for String {
    fn from(v: Verdict) -> String {
        v.as_str().to_string()
    }
}

/// A name that is not one of [`Verdict::as_str`]'s.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown verdict {0:?} (one of none, effect, partial, does_not_fit, unexplained)")]
pub struct UnknownVerdict(pub String);

impl FromStr for Verdict {
    type Err = UnknownVerdict;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Verdict::ALL.into_iter().find(|v| v.as_str() == s).ok_or_else(|| UnknownVerdict(s.to_string()))
    }
}

/// A verdict with its explanation and the ladder it ends with.
pub struct Judged {
    pub verdict: Verdict,
    pub best_effect: Option<&'static str>,
    pub explanation: String,
    pub ladder: Ladder,
    pub effects: Vec<&'static str>,
}

/// Judges a diagnosis ([module docs](self)).
pub fn judge(b: f64, floor: &Floor, candidates: &[Candidate], mut ladder: Ladder) -> Result<Judged, Error> {
    let field = Field { candidates, f: floor.nrmse };
    if b <= FLOOR_FACTOR * field.f {
        return Ok(match weak_effect(b, floor, &field) {
            Some((c, text)) => {
                ladder.add(c)?;
                done(Verdict::Effect, ladder, text)
            }
            None => done(Verdict::NothingMissing, ladder, at_floor(b, field.f)),
        });
    }
    let (verdict, text) = explained(b, &field, &ladder)
        .or_else(|| does_not_fit(b, field.f, &ladder))
        .or_else(|| partial(b, field.f, &ladder))
        .unwrap_or_else(|| (Verdict::Unexplained, unconfident(b, &field)));
    Ok(done(verdict, ladder, text))
}

/// The judged outcome; only `effect` and `partial` name the ladder's effects.
fn done(verdict: Verdict, ladder: Ladder, explanation: String) -> Judged {
    let effects = if verdict.names_effects() { ladder.effects.clone() } else { Vec::new() };
    Judged { verdict, best_effect: effects.first().copied(), explanation, ladder, effects }
}

/// The ranked candidates against the floor `f`.
struct Field<'a> {
    candidates: &'a [Candidate],
    f: f64,
}

impl Field<'_> {
    fn best(&self) -> Option<&Candidate> {
        self.candidates.first()
    }

    /// The plausible candidates after the best: a rival that needs implausible parameters is no
    /// competing explanation.
    fn rivals(&self) -> impl Iterator<Item = &Candidate> + '_ {
        self.candidates.iter().skip(1).filter(|c| c.plausible)
    }

    /// The largest share of the error a plausible rival explains.
    fn runner_up(&self) -> f64 {
        self.rivals().map(|c| c.explained).fold(0.0, f64::max)
    }

    /// The mean-square error `c` leaves above the floor.
    fn left(&self, c: &Candidate) -> f64 {
        (c.nrmse_validation * c.nrmse_validation - self.f * self.f).max(f64::MIN_POSITIVE)
    }

    fn at_floor(&self, c: &Candidate) -> bool {
        c.nrmse_validation <= FLOOR_FACTOR * self.f
    }

    /// The best candidate when it alone explains the record with plausible parameters: clearly more
    /// than the runner-up, or alone at the floor, or near it with every plausible rival leaving far
    /// more (shares of the error explained compress the difference: 83 % against 100 % is 11× the
    /// residual).
    fn confident(&self) -> Option<&Candidate> {
        let only_best_at_floor =
            self.best().is_some_and(|c| self.at_floor(c)) && !self.rivals().any(|c| self.at_floor(c));
        let rivals_far_behind = |c: &Candidate| {
            c.nrmse_validation <= EXPLAINED_FACTOR * self.f
                && self.rivals().all(|r| self.left(r) >= RIVAL_LEFT_FACTOR * self.left(c))
        };
        self.best().filter(|c| {
            c.plausible
                && c.explained >= MIN_EXPLAINED
                && (self.runner_up() < MAX_RUNNER_UP_RATIO * c.explained || only_best_at_floor || rivals_far_behind(c))
        })
    }
}

/// Near the floor: the best candidate when it cuts the mean-square error by enough of the noise
/// variance (and of the numerical error's), clearly more than any rival; with its explanation.
fn weak_effect<'a>(b: f64, floor: &Floor, field: &Field<'a>) -> Option<(&'a Candidate, String)> {
    let f = field.f;
    // the cut of the mean-square error as a share of the noise variance
    let noise2 = floor.nrmse_noise * floor.nrmse_noise;
    let gain = |c: &Candidate| (b * b - c.nrmse_validation * c.nrmse_validation) / noise2;
    let least = MIN_GAIN.max(NUMERICS_MARGIN * floor.nrmse_numerics * floor.nrmse_numerics / noise2);
    let c = field.candidates.first().filter(|c| {
        c.plausible && gain(c) >= least && field.rivals().all(|r| gain(r) < MAX_RUNNER_UP_RATIO * gain(c))
    })?;
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
    Some((c, text))
}

fn at_floor(b: f64, f: f64) -> String {
    format!("the baseline's validation NRMSE {b:.4} is at the floor {f:.4}: nothing is missing that these data show")
}

/// How far the ladder's end is above the floor, in words.
fn left_of(ladder: &Ladder, f: f64) -> String {
    format!("{:.1}× the floor", ladder.nrmse_validation / f)
}

/// The ladder's effects reach [`EXPLAINED_FACTOR`]·f: `effect` when the best candidate is
/// confident or two or more effects do it together; `unexplained` when one effect does it but a
/// rival explains as much.
fn explained(b: f64, field: &Field<'_>, ladder: &Ladder) -> Option<(Verdict, String)> {
    let (f, l) = (field.f, ladder.nrmse_validation);
    if ladder.effects.is_empty() || l > EXPLAINED_FACTOR * f {
        return None;
    }
    let kept = ladder.effects.join(" + ");
    if let Some(c) = field.confident().filter(|c| ladder.effects.first() == Some(&c.effect)) {
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
        return Some((Verdict::Effect, text));
    }
    if let [one] = ladder.effects.as_slice() {
        return Some((Verdict::Unexplained, ambiguous(b, field, ladder, one)));
    }
    let left = left_of(ladder, f);
    let text = format!(
        "no single candidate explains the residual, but {kept} together bring the validation NRMSE from {b:.4} to {l:.4}, {left} {f:.4} (see the ladder)"
    );
    Some((Verdict::Effect, text))
}

/// One effect reaches the floor, but a plausible rival explains as much.
fn ambiguous(b: f64, field: &Field<'_>, ladder: &Ladder, one: &str) -> String {
    let (f, l) = (field.f, ladder.nrmse_validation);
    let rival = field
        .candidates
        .iter()
        .filter(|c| c.plausible && c.effect != one)
        .max_by(|x, y| x.explained.total_cmp(&y.explained));
    let own = field.candidates.iter().find(|c| c.effect == one).map_or(0.0, |c| c.explained);
    format!(
        "ambiguous: {one} brings the validation NRMSE from {b:.4} to {l:.4} ({} {f:.4}) and explains {:.0} % of the error above the floor, but {} explains {:.0} %: these data cannot tell them apart",
        left_of(ladder, f),
        100.0 * own,
        rival.map_or("another candidate", |r| r.effect),
        100.0 * rival.map_or(0.0, |r| r.explained),
    )
}

/// Even the ladder's end is far from the damper: `does_not_fit`.
fn does_not_fit(b: f64, f: f64, ladder: &Ladder) -> Option<(Verdict, String)> {
    let l = ladder.nrmse_validation;
    if l < DOES_NOT_FIT_NRMSE || l < DOES_NOT_FIT_FLOOR_FACTOR * f {
        return None;
    }
    let kept = ladder.effects.join(" + ");
    let text = format!(
        "the model does not fit this damper: the baseline's validation NRMSE is {b:.4} and the best the catalog's effects reach is {l:.4}{}, {} {f:.4}. A damper of another kind, or nominal parameters far from this damper's: calibrate the model first (damper calibrate) and diagnose with its parameter file.",
        if kept.is_empty() { String::new() } else { format!(" (with {kept})") },
        left_of(ladder, f)
    );
    Some((Verdict::DoesNotFit, text))
}

/// The ladder's effects explain enough of the error to be named, with what is left: `partial`.
fn partial(b: f64, f: f64, ladder: &Ladder) -> Option<(Verdict, String)> {
    let l = ladder.nrmse_validation;
    if ladder.effects.is_empty() || share(b, l, f) < PARTIAL_MIN_EXPLAINED {
        return None;
    }
    let missing = ladder.rungs.iter().rev().find(|r| !r.kept && !r.refit);
    let text = format!(
        "a partial explanation: {} explain {:.0} % of the error above the floor (validation NRMSE {b:.4} → {l:.4}), but {:.0} % of it is left, {} {f:.4}; {}",
        ladder.effects.join(" + "),
        100.0 * share(b, l, f),
        100.0 * (1.0 - share(b, l, f)),
        left_of(ladder, f),
        match missing {
            Some(r) => format!(
                "the best effect for the rest, {}, explains only {:.0} % of it: something outside the catalog, or a parameter to calibrate",
                r.added,
                100.0 * r.explained
            ),
            None => "no further effect of the catalog was left to try".into(),
        }
    );
    Some((Verdict::Partial, text))
}

/// No candidate explains the residual confidently.
fn unconfident(b: f64, field: &Field<'_>) -> String {
    let best = field.best();
    format!(
        "no candidate explains the residual confidently (best: {} explains {:.0} % of the error above the floor, best plausible runner-up {:.0} %); baseline NRMSE {b:.4} against a floor of {:.4}",
        best.map_or("none", |c| c.effect),
        100.0 * best.map_or(0.0, |c| c.explained),
        100.0 * field.runner_up(),
        field.f
    )
}

#[cfg(test)]
mod tests {
    use super::Verdict;

    #[test]
    fn a_verdict_is_written_and_read_as_the_schemas_string() {
        let names: Vec<&str> = Verdict::ALL.iter().map(|v| v.as_str()).collect();
        assert_eq!(names, ["none", "effect", "does_not_fit", "partial", "unexplained"]);
        for v in Verdict::ALL {
            assert_eq!(serde_json::to_string(&v).unwrap(), format!("\"{v}\""));
            assert_eq!(serde_json::from_str::<Verdict>(&format!("\"{v}\"")).unwrap(), v);
            assert_eq!(v.as_str().parse::<Verdict>(), Ok(v));
        }
        assert!("maybe".parse::<Verdict>().unwrap_err().to_string().contains("\"maybe\""));
    }
}
