//! What `damper diagnose` finds: the comparison (steps 1–2), the missing effect (step 3), the
//! ladder of effects added in turn (step 4) and the model with the named effects.

use crate::before_after::{self, After};
use crate::candidate::{FitSetup, Progress, MAX_FIT_SECONDS};
use crate::comparison::{self, CompareOptions, Comparison, ANALYSIS_RTOL};
use crate::criteria::NUMERICS_CHECK_FACTOR;
use crate::dsp::noise_sigma;
use crate::error::Error;
use crate::floor::Numerics;
use crate::force_velocity;
use crate::missing_effect::{diagnose, Diagnosis};
use crate::model::{force_simulator, thread_pool, Drive};
use crate::parameters::{set_effect, set_real};
use crate::propagation::{inherited, CalibrationCovariance};
use crate::residual_signature::{self, Quantity};
use crate::sensitivity::ShiftedRuns;
use crate::units::Column;
use crate::verdict::Verdict;
use semi_active_damper::physics::params::Parameters;

/// A finished diagnosis with its comparison.
pub struct Diagnosed {
    pub comparison: Comparison,
    pub diagnosis: Diagnosis,
    /// The model with the named effects, when the verdict is `effect` or `partial`.
    pub after: Option<After>,
}

/// Reads, compares and diagnoses (no files written, nothing printed) on `threads` threads;
/// `progress` is told of each candidate fitted.
pub fn diagnose_measurement(
    opts: &CompareOptions,
    threads: usize,
    progress: &Progress<'_>,
) -> Result<Diagnosed, Error> {
    let opts = &CompareOptions { rtol_at_most: Some(ANALYSIS_RTOL), velocity_made_again: true, ..opts.clone() };
    let c = comparison::compare(opts)?;
    let split = comparison::split_index(&c.measurement, opts.split)?;
    let measured = c.measurement.get(Column::FDamper).ok_or(Error::NoForceColumn)?.to_vec();
    let simulate = force_simulator(c.setup.backend.as_ref(), &c.drive, opts.load_cell_lowpass_hz);
    let baseline = c.setup.model.params;
    let skipped =
        opts.skip.iter().map(|k| crate::parameters::effect(k).map(|e| e.key)).collect::<Result<Vec<_>, _>>()?;
    let candidates: Vec<_> = crate::candidate::candidates(&baseline, c.drive.t_oil.is_some())
        .filter(|e| !skipped.contains(&e.key))
        .collect();
    if candidates.is_empty() {
        return Err(Error::NoCandidates);
    }
    let pool = thread_pool(threads)?;
    let train = split.min((MAX_FIT_SECONDS / c.measurement.median_interval()).round() as usize);
    let largest_stroke = c.prediction.x_damper[..train].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut check = baseline;
    check.rtol = baseline.rtol * NUMERICS_CHECK_FACTOR;
    let shifted = |v_damper: Vec<f64>| {
        let drive = Drive { v_damper, ..c.drive.clone() };
        let run = force_simulator(c.setup.backend.as_ref(), &drive, opts.load_cell_lowpass_hz);
        run(&baseline, drive.len())
    };
    let coloured = c.measurement.velocity_noise.as_ref();
    let (base_check, runs) = pool.install(|| {
        rayon::join(|| simulate(&check, measured.len()), || ShiftedRuns::new(coloured, &c.drive.v_damper, shifted))
    });
    let base = &c.prediction.f_damper;
    let residual: Vec<f64> = base.iter().zip(&measured).map(|(m, y)| m - y).collect();
    let runs = runs?;
    let mut informative = runs.informative(base, noise_sigma(&residual));
    // the samples the record's checks leave out (a clipped force)
    for (keep, excluded) in informative.keep.iter_mut().zip(&c.measurement.excluded) {
        *keep &= !excluded;
    }
    // the velocity noise's change of the force, over the samples a fit's residuals hold
    let input_error = runs.input_error(&base[..train], |i| informative.keep[i]);
    let fit = FitSetup {
        input_error: &input_error,
        simulate: &simulate,
        measured: &measured,
        informative: &informative,
        split,
        train,
        largest_stroke,
        pool: &pool,
        progress,
    };
    let numerics = Numerics {
        base,
        perturbed: &runs.perturbed,
        base_check: &base_check?,
        rtol: baseline.rtol,
        rtol_check: check.rtol,
    };
    let mut d = diagnose(&c.measurement.time, &fit, &candidates, &baseline, &numerics)?;
    if let Some((path, setting)) = &opts.calibration {
        inherit(&mut d, &fit, &baseline, &CalibrationCovariance::read(path, setting.as_deref())?)?;
    }
    drop(simulate);
    let after = match d.effects.as_slice() {
        [] => None,
        effects => Some(before_after::after(&c, effects, d.ladder.params)?),
    };
    let left = after.as_ref().map_or(&c.analysis, |a| &a.analysis);
    if d.verdict == Verdict::DoesNotFit {
        let (verdict, explanation) = does_not_fit_why(&d.explanation, left, &c.drive.v_damper, &measured, base);
        (d.verdict, d.explanation) = (verdict, explanation);
    }
    // what is left unexplained, and what it follows: where to look for the effect to write
    if d.verdict.leaves_error() {
        let follows = residual_signature::sentence(&left.signature, left.dominant_band);
        d.explanation = format!("{}. What is left: {follows}.", d.explanation.trim_end_matches('.'));
    }
    Ok(Diagnosed { comparison: c, diagnosis: d, after })
}

/// Widens the uncertainties of the named effects' fits by what they inherit from the calibration
/// whose values the baseline holds ([`crate::propagation`]).
fn inherit(
    d: &mut Diagnosis,
    fit: &FitSetup<'_>,
    baseline: &Parameters,
    calibration: &CalibrationCovariance,
) -> Result<(), Error> {
    for c in d.candidates.iter_mut().filter(|c| d.effects.contains(&c.effect)) {
        let mut model = *baseline;
        set_effect(&mut model, c.effect, true)?;
        for (name, value, _) in &c.params {
            set_real(&mut model, name, *value)?;
        }
        let keep = &fit.informative.keep;
        let inherited =
            inherited(fit.simulate, &model, fit.measured, keep, fit.train, &c.params, calibration, fit.pool)?;
        for ((_, _, sigma), added) in c.params.iter_mut().zip(&inherited) {
            if let (Some(s), Some(a)) = (sigma.as_mut(), added) {
                *s = libm::hypot(*s, *a);
            }
        }
        c.inherited = inherited;
    }
    Ok(())
}

/// Why the model does not fit, in physical terms. A residual that mostly follows the stroke, the
/// time or the temperature is one local effect the catalog lacks, not a damper of another kind:
/// the verdict becomes `unexplained`. Otherwise the measured force–velocity law is set beside the
/// model's ([`force_velocity::contrast`]).
fn does_not_fit_why(
    explanation: &str,
    left: &crate::analysis::Analysis,
    v: &[f64],
    measured: &[f64],
    model: &[f64],
) -> (Verdict, String) {
    let local = left.signature.first().filter(|f| {
        f.share >= LOCAL_SHARE && matches!(f.quantity, Quantity::Stroke | Quantity::Time | Quantity::Temperature)
    });
    if let Some(f) = local {
        return (
            Verdict::Unexplained,
            format!(
                "the model misses one effect the catalog lacks, not the damper's kind: {:.0} % of the error above the noise follows the {} alone, where the model's laws of velocity and force would spread it; write the effect (docs/effects.md) and diagnose again",
                100.0 * f.share,
                f.quantity.name()
            ),
        );
    }
    match force_velocity::contrast(v, measured, model) {
        Some(laws) => (
            Verdict::DoesNotFit,
            format!("{}. The force–velocity laws differ: {laws}", explanation.trim_end_matches('.')),
        ),
        None => (Verdict::DoesNotFit, explanation.to_string()),
    }
}

/// A residual whose variance above the noise follows one local quantity (stroke, time,
/// temperature) by at least this share is one missing effect, not a misfit of the model's laws.
pub const LOCAL_SHARE: f64 = 0.6;
