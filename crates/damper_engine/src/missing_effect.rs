//! Which physical effect is missing: every effect of the catalog (docs/effects.md) is tried in
//! turn. An effect the baseline lacks is switched on; one it has is refitted ("a parameter
//! moved"). Its parameters are fitted on the training part, and the candidate is scored on the
//! held-out validation part. Then the ladder adds effects one at a time ([`crate::ladder`]) and
//! [`crate::verdict`] judges the outcome.
//!
//! The floor the verdict judges by has two parts, both reported: the sensor noise, estimated from
//! the residual so that the model's error cannot inflate it ([`crate::dsp::noise_floor`]), and the model's own
//! numerical error, measured on each record as the difference between the baseline run and the
//! same run at a tenth of its tolerance ([`crate::floor`]). Samples whose force hangs on the
//! velocity by less than the record resolves it inform nothing and are left out of the fits and
//! the scores ([`crate::sensitivity`]).

use crate::candidate::{Candidate, FitSetup};
use crate::dsp::nrmse_kept;
use crate::error::Error;
use crate::floor::{floor, Numerics};
use crate::ladder::{climb, Ladder};
use crate::record_parts::{self, Part};
use crate::verdict::{judge, Judged, Verdict};
use semi_active_damper::effects::EffectInfo;
use semi_active_damper::physics::params::Parameters;

/// The outcome of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// What the diagnosis concludes ([`crate::verdict`]).
    pub verdict: Verdict,
    pub best_effect: Option<&'static str>,
    pub nrmse_baseline: f64,
    /// The floor the verdict judges by ([`crate::floor::Floor::nrmse`]).
    pub nrmse_noise_floor: f64,
    pub floor: crate::floor::Floor,
    pub candidates: Vec<Candidate>,
    pub explanation: String,
    /// Step 4: the effects added one at a time.
    pub ladder: Ladder,
    /// The answer: the effects the model lacks, in the ladder's order (verdict `effect`), or
    /// those that explain part of the error (verdict `partial`); else none.
    pub effects: Vec<&'static str>,
    /// The baseline's error in each part of the record against that part's floor.
    pub parts: Vec<Part>,
}

/// Runs the diagnosis of a record sampled at `time` over `specs` (usually the whole [`catalog`](crate::candidate::catalog)) with
/// the model, data and thread pool of `fit`, from the `baseline` parameters whose force over the
/// measurement is `numerics.base` (the comparison has it already), over the samples
/// `fit.informative` keeps.
pub fn diagnose(
    time: &[f64],
    fit: &FitSetup<'_>,
    specs: &[&'static EffectInfo],
    baseline: &Parameters,
    numerics: &Numerics<'_>,
) -> Result<Diagnosis, Error> {
    let (measured, split, informative) = (fit.measured, fit.split, fit.informative);
    let nrmse_baseline = nrmse_kept(&measured[split..], &numerics.base[split..], &informative.keep[split..]);
    let floor = floor(measured, numerics, split, informative);
    if !nrmse_baseline.is_finite() || !floor.nrmse.is_finite() {
        return Err(Error::NothingToDiagnose { nrmse: nrmse_baseline, floor: floor.nrmse });
    }
    let errors = (nrmse_baseline, floor.nrmse);
    let candidates = fit.all(specs, baseline, errors)?;
    let ladder = climb(fit, specs, baseline, &candidates, errors)?;
    let judged = judge(nrmse_baseline, &floor, &candidates, ladder)?;
    let parts = record_parts::parts(time, measured, numerics, split, &informative.keep);
    let Judged { verdict, best_effect, explanation, ladder, effects } = whole_record(judged, &parts);
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
        parts,
    })
}

/// No `none` while a part of the record is far above its floor ([`record_parts`]): the verdict
/// becomes `unexplained`, naming the part.
fn whole_record(judged: Judged, parts: &[Part]) -> Judged {
    let Some(far) = record_parts::far_above_floor(parts).filter(|_| judged.verdict == Verdict::NothingMissing) else {
        return judged;
    };
    let explanation = format!(
        "{}; but not over the whole record: {} ({:.2}–{:.2} s) is {:.1}× its floor (RMS residual {:.3} N against {:.3} N). The error lies where the validation part does not reach: diagnose with a --split whose validation part covers it, or cut the record there.",
        judged.explanation,
        far.name,
        far.t_start,
        far.t_end,
        far.ratio(),
        far.rms_residual,
        far.rms_floor
    );
    Judged { verdict: Verdict::Unexplained, explanation, ..judged }
}
