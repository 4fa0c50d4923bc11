//! The floor of a diagnosis: the validation NRMSE below which nothing can be explained, made of
//! the sensor noise (estimated robustly from the residual, [`noise_floor`]) and the model's own
//! numerical error (measured on each record against a run at a tenth of the tolerance), over
//! the samples that inform the diagnosis (`crate::sensitivity`).

use crate::dsp::{kept, noise_floor, rms, std, NoiseEstimate};
use crate::sensitivity::Informative;

/// The floor of the validation NRMSE below which nothing can be explained.
#[derive(Clone, Copy, Debug)]
pub struct Floor {
    /// The sensor noise's share: σ_noise / std(measured) on the validation part.
    pub nrmse_noise: f64,
    /// The model's numerical error: RMS(F(rtol) − F(rtol·[`NUMERICS_CHECK_FACTOR`](crate::criteria::NUMERICS_CHECK_FACTOR)))
    /// / std(measured) on the validation part.
    pub nrmse_numerics: f64,
    /// √(noise² + numerics² + inputs unseen²): what the verdict judges by.
    pub nrmse: f64,
    /// The measured velocity's noise carried through the model into its force: RMS of the
    /// baseline with the velocity's noise added ([`crate::sensitivity`], coloured where the
    /// velocity is made from the displacement or was smoothed: [`crate::velocity_noise`]) less the
    /// baseline, over
    /// the validation part / std(measured).
    pub nrmse_inputs: f64,
    /// The part of [`nrmse_inputs`](Self::nrmse_inputs) the noise estimate cannot see, in
    /// [`nrmse`](Self::nrmse): what is left of its mean square once its white part (by the same
    /// second differences that estimate the sensor noise) is taken away. A white velocity noise
    /// carried into the force is white too, and where the measured force carries it (a rig whose
    /// damper senses the logged velocity) the noise estimate already has it; a velocity made from
    /// a displacement and low-passed carries it below the filter's corner, where the second
    /// differences do not look, and a dyno's force never carries it (the damper moved with the
    /// true motion).
    pub nrmse_inputs_unseen: f64,
    /// The noise estimate (N), three ways.
    pub noise: NoiseEstimate,
    /// The tolerance the model ran at, and the one of the check.
    pub rtol: f64,
    pub rtol_check: f64,
    /// The velocity noise δ (m/s) of the sensitivity test, the force's change (N) that leaves a
    /// sample out, and the samples left out of the validation part.
    pub delta_v: f64,
    pub sensitive_threshold: f64,
    pub left_out_validation: usize,
}

/// The force of the model at its tolerance and at the check's tighter one, over the measurement.
pub struct Numerics<'a> {
    pub base: &'a [f64],
    /// The baseline with the velocity's noise added to its velocity ([`crate::sensitivity`]).
    pub perturbed: &'a [Vec<f64>],
    pub base_check: &'a [f64],
    pub rtol: f64,
    pub rtol_check: f64,
}

/// The floor of a baseline residual `measured − numerics.base` on the validation part from `split`,
/// over the samples `informative` keeps (the noise is estimated on them all: its estimate is
/// robust, and needs the samples' succession).
pub fn floor(measured: &[f64], numerics: &Numerics<'_>, split: usize, informative: &Informative) -> Floor {
    let residual: Vec<f64> = numerics.base[split..].iter().zip(&measured[split..]).map(|(m, y)| m - y).collect();
    let noise = noise_floor(&residual);
    let keep = &informative.keep[split..];
    let val_std = std(&kept(&measured[split..], keep));
    let nrmse_noise = noise.sigma / val_std;
    let diff: Vec<f64> = numerics.base[split..].iter().zip(&numerics.base_check[split..]).map(|(a, b)| a - b).collect();
    let nrmse_numerics = rms(&kept(&diff, keep)) / val_std;
    let (inputs, unseen) = carried(numerics, split..measured.len(), keep);
    let nrmse_inputs = inputs / val_std;
    let nrmse_inputs_unseen = unseen / val_std;
    Floor {
        nrmse_noise,
        nrmse_numerics,
        nrmse: libm::hypot(libm::hypot(nrmse_noise, nrmse_numerics), nrmse_inputs_unseen),
        nrmse_inputs,
        nrmse_inputs_unseen,
        noise,
        rtol: numerics.rtol,
        rtol_check: numerics.rtol_check,
        delta_v: informative.delta_v,
        sensitive_threshold: informative.threshold,
        left_out_validation: informative.left_out(split),
    }
}

/// The velocity's noise carried into the force over `range` of the record (N, RMS over the samples
/// `keep` keeps there, every perturbed run), and the part of it the noise estimate cannot see
/// ([`Floor::nrmse_inputs_unseen`]).
pub fn carried(numerics: &Numerics<'_>, range: std::ops::Range<usize>, keep: &[bool]) -> (f64, f64) {
    let runs: Vec<Vec<f64>> = numerics
        .perturbed
        .iter()
        .map(|run| run[range.clone()].iter().zip(&numerics.base[range.clone()]).map(|(p, b)| p - b).collect())
        .collect();
    let all: Vec<f64> = runs.iter().flat_map(|r| kept(r, keep)).collect();
    let total = rms(&all);
    let white = rms(&runs.iter().map(|r| noise_floor(r).sigma).collect::<Vec<_>>());
    (total, (total * total - white * white).max(0.0).sqrt())
}
