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
    /// √(noise² + numerics²): what the verdict judges by.
    pub nrmse: f64,
    /// The measured velocity's white noise carried through the model into its force: RMS of the
    /// baseline with white noise of the velocity's resolution δ added, less the baseline, over the
    /// validation part / std(measured). Reported, not in [`nrmse`](Self::nrmse): a dyno's force
    /// comes from the true motion, so there it belongs to the floor, but a rig's controller acts
    /// on the measured velocity, so there part of it is in the force too.
    pub nrmse_inputs: f64,
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
    /// The baseline with white noise of the velocity's resolution added to its velocity (two
    /// seeds, [`crate::sensitivity`]).
    pub perturbed: [&'a [f64]; 2],
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
    let carried: Vec<f64> = numerics
        .perturbed
        .iter()
        .flat_map(|run| {
            kept(&run[split..].iter().zip(&numerics.base[split..]).map(|(p, b)| p - b).collect::<Vec<_>>(), keep)
        })
        .collect();
    let nrmse_inputs = rms(&carried) / val_std;
    Floor {
        nrmse_noise,
        nrmse_numerics,
        nrmse: libm::hypot(nrmse_noise, nrmse_numerics),
        nrmse_inputs,
        noise,
        rtol: numerics.rtol,
        rtol_check: numerics.rtol_check,
        delta_v: informative.delta_v,
        sensitive_threshold: informative.threshold,
        left_out_validation: informative.left_out(split),
    }
}
