//! What `damper diagnose` finds: the comparison (steps 1–2), the missing effect (step 3), the
//! ladder of effects added in turn (step 4) and the model with the named effects.

use crate::before_after::{self, After};
use crate::candidate::{FitSetup, Progress, MAX_FIT_SECONDS};
use crate::comparison::{self, CompareOptions, Comparison, ANALYSIS_RTOL};
use crate::criteria::NUMERICS_CHECK_FACTOR;
use crate::diagnose::{diagnose, Diagnosis};
use crate::dsp::noise_sigma;
use crate::floor::Numerics;
use crate::force_velocity;
use crate::model::{force_simulator, thread_pool, Drive};
use crate::parameters::{set_effect, set_real};
use crate::propagation::{inherited, CalibrationCovariance};
use crate::residual_signature::{self, Quantity};
use crate::sensitivity::{informative, velocity_noise_paths};
use crate::units::Column;
use rayon::prelude::*;
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
) -> Result<Diagnosed, String> {
    let opts = &CompareOptions { rtol_at_most: Some(ANALYSIS_RTOL), velocity_made_again: true, ..opts.clone() };
    let c = comparison::compare(opts)?;
    let split = comparison::split_index(&c.measurement, opts.split)?;
    let measured = c.measurement.get(Column::FDamper).ok_or("the measurement has no F_damper column")?.to_vec();
    let simulate = force_simulator(c.setup.backend.as_ref(), &c.drive, opts.load_cell_lowpass_hz);
    let baseline = c.setup.model.params;
    let skipped =
        opts.skip.iter().map(|k| crate::parameters::effect(k).map(|e| e.key)).collect::<Result<Vec<_>, _>>()?;
    let candidates: Vec<_> = crate::candidate::candidates(&baseline, c.drive.t_oil.is_some())
        .filter(|e| !skipped.contains(&e.key))
        .collect();
    if candidates.is_empty() {
        return Err("--skip leaves no candidate effect".into());
    }
    let pool = thread_pool(threads)?;
    let train = split.min((MAX_FIT_SECONDS / c.measurement.median_interval()).round() as usize);
    let largest_stroke = c.prediction.x_damper[..train].iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut check = baseline;
    check.rtol = baseline.rtol * NUMERICS_CHECK_FACTOR;
    let coloured = c.measurement.velocity_noise.as_ref();
    let (paths, delta_v) = velocity_noise_paths(coloured, &c.drive.v_damper);
    let signs: Vec<Vec<f64>> =
        if coloured.is_some() { sign_runs(&c.drive.v_damper, delta_v).into() } else { Vec::new() };
    let shifted = |noise: &Vec<f64>| {
        let v_damper = c.drive.v_damper.iter().zip(noise).map(|(v, e)| v + e).collect();
        let drive = Drive { v_damper, ..c.drive.clone() };
        let run = force_simulator(c.setup.backend.as_ref(), &drive, opts.load_cell_lowpass_hz);
        run(&baseline, drive.len())
    };
    let (base_check, (perturbed, signed)) = pool.install(|| {
        rayon::join(
            || simulate(&check, measured.len()),
            || {
                rayon::join(
                    || paths.par_iter().map(shifted).collect::<Result<Vec<_>, _>>(),
                    || signs.par_iter().map(shifted).collect::<Result<Vec<_>, _>>(),
                )
            },
        )
    });
    let base = &c.prediction.f_damper;
    let residual: Vec<f64> = base.iter().zip(&measured).map(|(m, y)| m - y).collect();
    let (perturbed, signed) = (perturbed?, signed?);
    let mut informative = informative(base, &perturbed, &signed, delta_v, noise_sigma(&residual));
    // the samples the record's checks leave out (a clipped force)
    for (keep, excluded) in informative.keep.iter_mut().zip(&c.measurement.excluded) {
        *keep &= !excluded;
    }
    // the velocity noise's change of the force, over the samples a fit's residuals hold
    let fitted = |i: &usize| informative.keep[*i];
    let input_error: Vec<Vec<f64>> =
        perturbed.iter().map(|p| (0..train).filter(fitted).map(|i| p[i] - base[i]).collect()).collect();
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
    let numerics =
        Numerics { base, perturbed: &perturbed, base_check: &base_check?, rtol: baseline.rtol, rtol_check: check.rtol };
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
    if d.verdict == "does_not_fit" {
        let (verdict, explanation) = does_not_fit_why(&d.explanation, left, &c.drive.v_damper, &measured, base);
        (d.verdict, d.explanation) = (verdict, explanation);
    }
    // what is left unexplained, and what it follows: where to look for the effect to write
    if matches!(d.verdict, "unexplained" | "partial" | "does_not_fit") {
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
) -> Result<(), String> {
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

/// Two velocity shifts that try the sign of the motion both ways where the velocity is within its
/// noise `delta_v` of zero: `±SIGN_SHIFT·δ·exp(−(v/δ)²)`, which makes every |v| < δ positive in one
/// run and negative in the other, and fades out by 2δ. A velocity made from the displacement is
/// not the one the damper's controller sensed, and where the motion rests or turns slowly the
/// semi-active clip's sign, and with it the force for a few hundred milliseconds, hangs on what
/// the record cannot tell (a rig's wave touching zero between its parts: up to 1.3 kN).
fn sign_runs(v: &[f64], delta_v: f64) -> [Vec<f64>; 2] {
    let up: Vec<f64> = v
        .iter()
        .map(|v| {
            let u = v / delta_v;
            SIGN_SHIFT * delta_v * libm::exp(-u * u)
        })
        .collect();
    [up.iter().map(|e| -e).collect(), up]
}

/// The sign runs' largest shift, in the velocity's noise: 3 > e makes v + 3δ·exp(−(v/δ)²) positive
/// for every v ≥ −δ.
const SIGN_SHIFT: f64 = 3.0;

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
) -> (&'static str, String) {
    let local = left.signature.first().filter(|f| {
        f.share >= LOCAL_SHARE && matches!(f.quantity, Quantity::Stroke | Quantity::Time | Quantity::Temperature)
    });
    if let Some(f) = local {
        return (
            "unexplained",
            format!(
                "the model misses one effect the catalog lacks, not the damper's kind: {:.0} % of the error above the noise follows the {} alone, where the model's laws of velocity and force would spread it; write the effect (docs/effects.md) and diagnose again",
                100.0 * f.share,
                f.quantity.name()
            ),
        );
    }
    match force_velocity::contrast(v, measured, model) {
        Some(laws) => {
            ("does_not_fit", format!("{}. The force–velocity laws differ: {laws}", explanation.trim_end_matches('.')))
        }
        None => ("does_not_fit", explanation.to_string()),
    }
}

/// A residual whose variance above the noise follows one local quantity (stroke, time,
/// temperature) by at least this share is one missing effect, not a misfit of the model's laws.
pub const LOCAL_SHARE: f64 = 0.6;
