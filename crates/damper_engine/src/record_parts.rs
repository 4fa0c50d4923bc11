//! The baseline's error in every part of the record, against the floor of that part: the train
//! and validation parts, and [`BLOCKS`] blocks of equal length (those of a blocked
//! cross-validation). The verdict scores the validation part; a missing effect that acts only
//! where the validation part does not reach (an end stop hit while the stroke is large, early in
//! the record) would leave it at the floor. No `none` is then given while a part is far above its
//! floor ([`crate::missing_effect`]), and the part that holds the error is named.

use crate::dsp::{kept, noise_floor, rms};
use crate::floor::{carried, Numerics};

/// Blocks of equal length the record is cut into.
pub const BLOCKS: usize = 5;
/// A part whose RMS residual exceeds this factor of its floor is far above it. Clean records made
/// with other numerics (tests/python/test_independent_truth.py) reach 2.6× in one 0.6 s block at
/// 500 Hz, where the cubic through 2 ms samples bends least like the true motion, with their
/// validation part at 1.0×; an end stop hit only early in a record puts its block at 17–500×.
pub const FAR_FACTOR: f64 = 4.0;

/// One part of the record and its baseline error.
#[derive(Clone, Debug)]
pub struct Part {
    /// `train`, `validation` or `block k of 5`.
    pub name: String,
    /// The part's time span (s).
    pub t_start: f64,
    pub t_end: f64,
    /// RMS of the baseline's residual over the part's kept samples (N).
    pub rms_residual: f64,
    /// The part's floor (N): its white-noise level (from the residual's second differences), the
    /// model's numerical error and the velocity's noise carried into the force that the noise
    /// estimate cannot see ([`carried`]) over the part, in quadrature.
    pub rms_floor: f64,
}

impl Part {
    /// The part's error as a multiple of its floor.
    pub fn ratio(&self) -> f64 {
        self.rms_residual / self.rms_floor
    }
}

/// The parts of a record sampled at `time`, with the baseline's force, the same run at the check's
/// tolerance and with the velocity's noise (`numerics`), the `measured` force, the validation part
/// from `split` and the samples `keep` keeps.
pub fn parts(time: &[f64], measured: &[f64], numerics: &Numerics<'_>, split: usize, keep: &[bool]) -> Vec<Part> {
    let n = measured.len();
    let (base, base_check) = (numerics.base, numerics.base_check);
    let part = |name: String, range: std::ops::Range<usize>| {
        let residual: Vec<f64> = base[range.clone()].iter().zip(&measured[range.clone()]).map(|(m, y)| m - y).collect();
        let keep = &keep[range.clone()];
        let numerical: Vec<f64> =
            base[range.clone()].iter().zip(&base_check[range.clone()]).map(|(a, b)| a - b).collect();
        let sigma = noise_floor(&residual).sigma;
        let (_, unseen) = carried(numerics, range.clone(), keep);
        Part {
            name,
            t_start: time[range.start],
            t_end: time[range.end - 1],
            rms_residual: rms(&kept(&residual, keep)),
            rms_floor: libm::hypot(libm::hypot(sigma, rms(&kept(&numerical, keep))), unseen),
        }
    };
    let mut out = vec![part("train".into(), 0..split), part("validation".into(), split..n)];
    for k in 0..BLOCKS {
        let range = k * n / BLOCKS..(k + 1) * n / BLOCKS;
        if range.len() > 3 {
            out.push(part(format!("block {} of {BLOCKS}", k + 1), range));
        }
    }
    out.retain(|p| p.rms_residual.is_finite() && p.rms_floor > 0.0);
    out
}

/// The part furthest above its floor, when it is more than [`FAR_FACTOR`] above.
pub fn far_above_floor(parts: &[Part]) -> Option<&Part> {
    parts.iter().filter(|p| p.ratio() > FAR_FACTOR).max_by(|a, b| a.ratio().total_cmp(&b.ratio()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_early_in_the_record_is_found_in_its_part() {
        let n = 5000;
        let time: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        let mut rng = crate::rng::Rng::new(11);
        let truth: Vec<f64> = time.iter().map(|t| 1e3 * libm::sin(6.0 * t)).collect();
        let measured: Vec<f64> = truth.iter().map(|f| f + 10.0 * rng.normal()).collect();
        // the model misses a slow 200 N force in the first second only
        let base: Vec<f64> =
            time.iter().zip(&truth).map(|(t, f)| f + if *t < 1.0 { 200.0 * libm::sin(3.0 * t) } else { 0.0 }).collect();
        let keep = vec![true; n];
        let perturbed = [base.clone(), base.clone()];
        let numerics = Numerics { base: &base, perturbed: &perturbed, base_check: &base, rtol: 1e-4, rtol_check: 1e-5 };
        let parts = parts(&time, &measured, &numerics, 3500, &keep);
        let far = far_above_floor(&parts).expect("a part far above the floor");
        assert_eq!(far.name, "block 1 of 5");
        let validation = parts.iter().find(|p| p.name == "validation").unwrap();
        assert!(validation.ratio() < 1.2, "{validation:?}");
    }
}
