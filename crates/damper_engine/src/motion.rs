//! The model's motion from a record's velocity and displacement columns. A noisy velocity is
//! smoothed before it drives the model (the model's force would carry its noise through the valve
//! law's slope); a velocity made from the displacement (a logger's derivative of its LVDT) is made
//! again from the displacement and smoothed under its coloured noise
//! ([`crate::velocity_noise`]); a velocity beside a measured displacement is then made to follow it
//! below the frequency where their noises cross ([`crate::stroke`]). `damper generate` drives a
//! displacement record's truth with the same motion.

use crate::dsp::differentiate;
use crate::error::Error;
use crate::velocity_noise::VelocityNoise;

/// The motion the model is driven with.
#[derive(Clone, Debug)]
pub struct Motion {
    /// The velocity (m/s), when the record has a velocity or a displacement.
    pub v: Option<Vec<f64>>,
    /// The stroke at the first sample (m), where the record measures the displacement.
    pub x_start: Option<f64>,
    /// The velocity's noise when it is made from the displacement, or when a transducer's was
    /// smoothed.
    pub velocity_noise: Option<VelocityNoise>,
    /// What was decided, for the user.
    pub notes: Vec<String>,
    /// Where a logger's velocity made from the displacement was kept: the motion made again from
    /// the displacement, whose whole error the diagnosis can carry into its floor.
    pub made_again: Option<Box<Motion>>,
}

/// The motion from the velocity `v` (m/s; made from `x` by central differences when
/// `from_displacement`) and the displacement `x` (m) sampled at `time`. An error when the two
/// disagree beyond drift ([`crate::stroke::MAX_DISAGREEMENT`]).
///
/// A logger's velocity made from the displacement holds nothing the displacement does not. It is
/// kept when its expected error (its noise, and what its filter takes out of the motion) is the
/// smaller: a calibration wants the least noise in its velocity (errors in variables bias the
/// fitted laws). The velocity made again from the displacement and smoothed under its noise is
/// kept beside it ([`Motion::made_again`]): its error, noise and rounded-off corners alike, is what
/// [`VelocityNoise::path`] draws, so a diagnosis can carry all of it into the floor, where the
/// logger's filter leaves an error it cannot (a rig's triangle corners rounded off).
pub fn motion(time: &[f64], v: Option<Vec<f64>>, x: Option<&[f64]>, from_displacement: bool) -> Result<Motion, Error> {
    let Some(mut v) = v else {
        return Ok(Motion {
            v: None,
            x_start: x.map(|x| x[0]),
            velocity_noise: None,
            notes: Vec::new(),
            made_again: None,
        });
    };
    let dt = (time[time.len() - 1] - time[0]) / (time.len() - 1).max(1) as f64;
    let mut velocity_noise = x.and_then(|x| VelocityNoise::of_derived(&v, x, dt));
    let mut notes = Vec::new();
    let mut made_again = None;
    if let (Some(logged), Some(x), false) = (&velocity_noise, x, from_displacement) {
        let again = motion(time, Some(differentiate(time, x)), Some(x), true)?;
        let (ours, theirs) =
            match (&again.velocity_noise, again.velocity_noise.as_ref().and_then(|n| n.smoother.as_ref())) {
                (Some(noise), Some(gains)) => (
                    noise.carried_rms(crate::sensitivity::SENSITIVITY_SEEDS[0], v.len()),
                    logged.error_unsmoothed(gains),
                ),
                _ => (f64::INFINITY, 0.0),
            };
        notes.push(format!(
            "v_damper is made from x_damper (a differentiator and filter of {} taps explain it to {:.3} mm/s; it \
             carries the displacement's {:.1} µm of noise as {:.2} mm/s and, with what its filter takes out of the \
             motion, an error of {:.2} mm/s; made again from x_damper and smoothed it would err by {:.2} mm/s)",
            logged.response.len(),
            logged.white * 1e3,
            logged.sigma_x * 1e6,
            logged.rms() * 1e3,
            theirs * 1e3,
            ours * 1e3,
        ));
        if ours < theirs {
            notes.push("v_damper made again from x_damper: the smaller error".into());
            return Ok(Motion { notes: [notes, again.notes].concat(), ..again });
        }
        notes.push("v_damper kept: the smaller error".into());
        made_again = Some(Box::new(again));
    }
    if let Some(note) = smooth_velocity(&mut v, &mut velocity_noise, dt) {
        notes.push(note);
    }
    let Some(x) = x else {
        return Ok(Motion { v: Some(v), x_start: None, velocity_noise, notes, made_again });
    };
    let fused = crate::stroke::velocity_following_displacement(time, &v, x)?;
    if !from_displacement {
        notes.push(format!(
            "v_damper fused with x_damper: below {:.1} Hz (where their noise spectra cross) the motion is the \
             displacement's, above it the velocity sensor's; the velocity's integral had drifted from x_damper by \
             up to {:.3} mm",
            fused.crossover_hz,
            fused.largest_correction * 1e3
        ));
    }
    Ok(Motion { v: Some(fused.v), x_start: Some(fused.start), velocity_noise, notes, made_again })
}

/// A velocity carrying more white noise than this (m/s) is smoothed before it drives the model:
/// on independent passive-damper dyno records with a 1–2 mm/s transducer the calibrated valve
/// parameters were biased by 2–10 % (4–13 of their standard uncertainties) by the noise carried
/// through the law's slope, and by 0.02–3.5 % (at most 3.5) once smoothed; a lab's transducer or
/// encoder resolves 0.01–0.1 mm/s, which is left as it is.
pub const SMOOTHED_VELOCITY_NOISE: f64 = 3e-4;

/// Smooths `v` in place when its noise exceeds [`SMOOTHED_VELOCITY_NOISE`]: under the coloured
/// spectrum of a velocity made from the displacement (`noise`, whose smoother is kept), else as a
/// transducer's white noise, whose [`VelocityNoise::of_sensor`] then becomes `noise` (what the
/// smoothed velocity still carries is what the diagnosis and calibration perturb the model with).
/// `dt`: the sample interval (s). Returns the note that says so.
fn smooth_velocity(v: &mut Vec<f64>, noise: &mut Option<VelocityNoise>, dt: f64) -> Option<String> {
    match noise {
        Some(derived) if derived.rms() > SMOOTHED_VELOCITY_NOISE => {
            *v = derived.smooth(v);
            Some(format!(
                "v_damper carries the displacement's {:.1} µm of noise as {:.2} mm/s: smoothed (zero-phase Wiener \
                 filter under that coloured noise), {:.2} mm/s of error left",
                derived.sigma_x * 1e6,
                derived.rms() * 1e3,
                derived.carried_rms(crate::sensitivity::SENSITIVITY_SEEDS[0], v.len()) * 1e3
            ))
        }
        Some(_) => None,
        None => {
            let sigma = crate::stroke::white_noise(v);
            (sigma > SMOOTHED_VELOCITY_NOISE).then(|| {
                let mut sensor = VelocityNoise::of_sensor(sigma, dt);
                *v = sensor.smooth(v);
                let left = sensor.carried_rms(crate::sensitivity::SENSITIVITY_SEEDS[0], v.len());
                *noise = Some(sensor);
                format!(
                    "v_damper carries {:.2} mm/s of white noise (more than {} mm/s): smoothed (zero-phase Wiener \
                     filter), since the model's force would carry it through the valve law's slope, and a fit bends \
                     its parameters to the noise (errors in variables); {:.2} mm/s of error left",
                    sigma * 1e3,
                    SMOOTHED_VELOCITY_NOISE * 1e3,
                    left * 1e3
                )
            })
        }
    }
}
