//! The stroke where a record measures both the velocity and the displacement. The model
//! integrates its velocity input, so a velocity sensor's noise and offset random-walk its stroke:
//! 1–2 mm/s of noise moved it by about 0.2 mm over 20 s on independent dyno records, and a stiff
//! end stop turned that into hundreds of newtons with the truth's parameters. The displacement
//! tells the slow stroke better, the velocity the fast motion; so the velocity is corrected below
//! a crossover to follow the displacement (a complementary filter):
//!
//! ```text
//! e   = x_measured − (x_measured[0] + ∫ v_measured dt)      (trapezoids)
//! e_s = e low-passed at STROKE_CROSSOVER_HZ, forwards then backwards (zero phase), its straight
//!       line (a velocity offset) kept whole
//! v   = v_measured + de_s/dt
//! ```

use crate::dsp::{std, Lowpass};

/// Below this (Hz) the displacement gives the stroke, above it the velocity gives the motion.
pub const STROKE_CROSSOVER_HZ: f64 = 1.0;
/// A disagreement of the two above the crossover of more than this share of the stroke's spread
/// (RMS) is a wrong unit, sign or sensor, not drift.
pub const MAX_DISAGREEMENT: f64 = 0.2;

/// The velocity whose integral follows `x` below the crossover, and the largest correction of
/// the stroke it makes (m); an error when the two disagree above the crossover by more than
/// [`MAX_DISAGREEMENT`] of the stroke's spread (RMS).
pub fn velocity_following_displacement(t: &[f64], v: &[f64], x: &[f64]) -> Result<(Vec<f64>, f64), String> {
    let n = t.len();
    let mut integral = vec![x[0]; n];
    for k in 1..n {
        integral[k] = integral[k - 1] + 0.5 * (v[k] + v[k - 1]) * (t[k] - t[k - 1]);
    }
    let e: Vec<f64> = x.iter().zip(&integral).map(|(x, i)| x - i).collect();
    let pass = |input: &[f64], order: &mut dyn Iterator<Item = usize>| {
        let mut out = vec![0.0; n];
        let first = order.next().expect("a record has samples");
        let mut f = Lowpass::new(STROKE_CROSSOVER_HZ, input[first]);
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
    // drift is slow; a disagreement above the crossover is a unit, a sign or a sensor
    let fast: Vec<f64> = e.iter().zip(&smooth).map(|(e, s)| e - s).collect();
    let spread = std(x);
    if std(&fast) > MAX_DISAGREEMENT * spread {
        return Err(format!(
            "the integral of v_damper departs from x_damper by {:.3} mm RMS above {STROKE_CROSSOVER_HZ} Hz, {:.0} % of \
             the stroke's spread: check the two columns' units and signs (velocity extension +, displacement \
             extension +)",
            std(&fast) * 1e3,
            100.0 * std(&fast) / spread.max(1e-300)
        ));
    }
    let rate = crate::dsp::differentiate(t, &smooth);
    let corrected = v.iter().zip(&rate).map(|(v, r)| v + r).collect();
    Ok((corrected, smooth.iter().fold(0.0f64, |a, s| a.max(s.abs()))))
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
        let (corrected, largest) = velocity_following_displacement(&t, &v, &x).unwrap();
        assert!((largest - 0.04).abs() < 2e-3, "{largest}");
        let mut stroke = x[0];
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
        assert!(velocity_following_displacement(&t, &v, &x_mm).unwrap_err().contains("units and signs"));
    }
}
