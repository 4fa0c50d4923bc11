//! The motion where a record measures both the velocity and the displacement. The model
//! integrates its velocity input, so a velocity sensor's noise and offset random-walk its stroke:
//! 1–2 mm/s of noise moved it by about 0.2 mm over 20 s on independent dyno records, and a stiff
//! end stop turned that into hundreds of newtons with the truth's parameters. And the model's
//! force carries the velocity's noise through the valve law's slope (errors in variables: a
//! 1.8 mm/s transducer against a 12 kN·s/m low-speed slope is 22 N). The displacement tells the
//! slow motion better, the velocity sensor the fast one; so the two are fused by a complementary
//! filter at the frequency where their noise spectra cross:
//!
//! ```text
//! e   = x_measured − (x_measured[0] + ∫ v_measured dt)      (trapezoids)
//! e_s = e low-passed at f_c, forwards then backwards (zero phase), its straight line (a velocity
//!       offset) kept whole
//! v   = v_measured + de_s/dt           (= low-passed dx/dt + high-passed v_measured)
//! f_c = σ_v/(2π σ_x) within [STROKE_CROSSOVER_HZ, rate/4]: white noise of σ_x differentiated
//!       has the spectrum (2πf)²·σ_x², the velocity sensor's is flat at σ_v²; each noise σ from the
//!       signal's fourth differences
//! ```

use crate::dsp::{std, Lowpass};
use crate::error::Error;

/// The lowest crossover (Hz): below it the displacement always gives the stroke.
pub const STROKE_CROSSOVER_HZ: f64 = 1.0;
/// A disagreement of the two above the crossover of more than this share of the stroke's spread
/// (RMS) is a wrong unit, sign or sensor, not drift.
pub const MAX_DISAGREEMENT: f64 = 0.2;

/// The white-noise level (σ) of a record `x`, from its k-th differences for k = 4, 6 and 8 (white
/// noise of variance σ² gives k-th differences of variance C(2k, k)·σ²), each by its median
/// absolute value, the smallest of the three. For white noise the three agree; a motion with
/// content near the Nyquist frequency (a truck's velocity sampled at 500 Hz) inflates the lower
/// orders most (0.60, 0.31 and 0.19 mm/s on a HiL record with 0.1 mm/s of sensor noise), so the
/// smallest is the least contaminated.
pub fn white_noise(x: &[f64]) -> f64 {
    [(4, 70.0), (6, 924.0), (8, 12_870.0)]
        .into_iter()
        .map(|(order, variance_factor): (usize, f64)| {
            let mut d = x.to_vec();
            for _ in 0..order {
                d = d.windows(2).map(|w| w[1] - w[0]).collect();
            }
            let mut abs: Vec<f64> = d.iter().map(|v| v.abs()).collect();
            // median |N(0, cσ²)| = 0.6745·√c·σ
            crate::dsp::median(&mut abs) / (0.674_489_75 * variance_factor.sqrt())
        })
        .fold(f64::NAN, f64::min)
}

/// The fused motion: the velocity, the crossover (Hz) and the largest correction of the stroke (m).
#[derive(Clone, Debug)]
pub struct Fused {
    pub v: Vec<f64>,
    /// The stroke the model starts at (m): `x[0]` plus the smoothed disagreement there, so that the
    /// integral of `v` from it follows x.
    pub start: f64,
    pub crossover_hz: f64,
    pub largest_correction: f64,
}

/// The velocity whose integral follows `x` below the crossover ([`Fused`]); an error when the two
/// disagree above it by more than [`MAX_DISAGREEMENT`] of the stroke's spread (RMS).
pub fn velocity_following_displacement(t: &[f64], v: &[f64], x: &[f64]) -> Result<Fused, Error> {
    let n = t.len();
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let (sigma_v, sigma_x) = (white_noise(v), white_noise(x));
    let crossover = if sigma_x > 0.0 && sigma_v.is_finite() {
        (sigma_v / (2.0 * std::f64::consts::PI * sigma_x)).clamp(STROKE_CROSSOVER_HZ, 0.25 / dt)
    } else {
        0.25 / dt
    };
    let integral = crate::dsp::integrate(t, v, x[0]);
    let e: Vec<f64> = x.iter().zip(&integral).map(|(x, i)| x - i).collect();
    let pass = |input: &[f64], order: &mut dyn Iterator<Item = usize>| {
        let mut out = vec![0.0; n];
        let first = order.next().expect("a record has samples");
        let mut f = Lowpass::new(crossover, input[first]);
        out[first] = input[first];
        let mut last = first;
        for k in order {
            out[k] = f.step((t[k] - t[last]).abs(), input[k]);
            last = k;
        }
        out
    };
    // the straight line through e (a velocity offset) is kept whole: filtered, its ends would lag
    let (t_mean, e_mean) = (crate::dsp::mean(t), crate::dsp::mean(&e));
    let slope = t.iter().zip(&e).map(|(t, e)| (t - t_mean) * (e - e_mean)).sum::<f64>()
        / t.iter().map(|t| (t - t_mean) * (t - t_mean)).sum::<f64>().max(1e-300);
    let line = |k: usize| e_mean + slope * (t[k] - t_mean);
    let rest: Vec<f64> = (0..n).map(|k| e[k] - line(k)).collect();
    let forwards = pass(&rest, &mut (0..n));
    let smooth: Vec<f64> = pass(&forwards, &mut (0..n).rev()).iter().enumerate().map(|(k, r)| r + line(k)).collect();
    // drift is slow; a disagreement above the lowest crossover is a unit, a sign or a sensor
    let slow = if crossover > STROKE_CROSSOVER_HZ {
        let low = |input: &[f64], order: &mut dyn Iterator<Item = usize>| {
            let mut out = vec![0.0; n];
            let mut f = Lowpass::new(STROKE_CROSSOVER_HZ, input[0]);
            for k in order {
                out[k] = f.step(dt, input[k]);
            }
            out
        };
        let forwards = low(&rest, &mut (0..n));
        low(&forwards, &mut (0..n).rev()).iter().enumerate().map(|(k, r)| r + line(k)).collect()
    } else {
        smooth.clone()
    };
    let fast: Vec<f64> = e.iter().zip(&slow).map(|(e, s)| e - s).collect();
    let spread = std(x);
    if std(&fast) > MAX_DISAGREEMENT * spread {
        return Err(Error::VelocityDisplacement {
            rms: std(&fast) * 1e3,
            crossover_hz: STROKE_CROSSOVER_HZ,
            share: 100.0 * std(&fast) / spread.max(1e-300),
        });
    }
    let rate = crate::dsp::differentiate(t, &smooth);
    Ok(Fused {
        v: v.iter().zip(&rate).map(|(v, r)| v + r).collect(),
        start: x[0] + smooth[0],
        crossover_hz: crossover,
        largest_correction: slow.iter().fold(0.0f64, |a, s| a.max(s.abs())),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A velocity with an offset of 2 mm/s: its integral drifts 40 mm over 20 s; corrected, it
    /// follows the displacement within a few µm, and its fast motion is the velocity's.
    #[test]
    fn an_offset_velocity_follows_the_displacement() {
        let dt = 1e-3;
        let t: Vec<f64> = (0..20_001).map(|k| k as f64 * dt).collect();
        let w = 2.0 * std::f64::consts::PI * 2.0;
        let x: Vec<f64> = t.iter().map(|&t| 0.02 * libm::sin(w * t)).collect();
        let v: Vec<f64> = t.iter().map(|&t| 0.02 * w * libm::cos(w * t) + 2e-3).collect();
        let fused = velocity_following_displacement(&t, &v, &x).unwrap();
        let (corrected, largest) = (fused.v, fused.largest_correction);
        let mut worst = 0.0f64;
        let mut stroke = fused.start;
        for k in 1..t.len() {
            stroke += 0.5 * (corrected[k] + corrected[k - 1]) * dt;
            worst = worst.max((stroke - x[k]).abs());
        }
        assert!(worst < 1e-4, "from its start, the corrected stroke is {worst} m off");
        assert!((largest - 0.04).abs() < 2e-3, "{largest}");
        let mut stroke = fused.start;
        let mut worst = 0.0f64;
        for k in 1..t.len() {
            stroke += 0.5 * (corrected[k] + corrected[k - 1]) * dt;
            // away from the ends, where the zero-phase filter starts
            if (2000..18_000).contains(&k) {
                worst = worst.max((stroke - x[k]).abs());
            }
        }
        assert!(worst < 5e-5, "the corrected stroke is {worst} m off");
        // a displacement in the wrong unit is refused
        let x_mm: Vec<f64> = x.iter().map(|x| x * 1e3).collect();
        assert!(velocity_following_displacement(&t, &v, &x_mm).unwrap_err().to_string().contains("units and signs"));
    }
}
