//! Samples that tell nothing about the damper: where the model's force hangs on the velocity by
//! less than the record resolves it. When the motion only touches zero (a rig's wave meeting the
//! next part, a truck's damper almost at rest under a large force), whether the controller's
//! semi-active clip and the check valves see extension or compression depends on tenths of a
//! mm/s, and a held force of 15–25 kN goes one way or the other for tens of milliseconds. On
//! independent truths (the true motion every 0.1 ms) the model differed there by up to 5 kN while
//! agreeing to the noise elsewhere; a fit then bent an effect's parameter to absorb it (piston
//! leakage 9 % off and 2.4× the floor left), and clean records ended `unexplained`.
//!
//! The test: the baseline is run twice more with white noise of the velocity's resolution δ
//! added to the velocity (estimated from the record, [`velocity_resolution`]; two fixed seeds,
//! [`SENSITIVITY_SEEDS`]): other velocities the record cannot tell from its own. A sample whose
//! force moves by more than [`SENSITIVE_SIGMAS`] load-cell noise sigmas in either run is left out
//! of the fits and of every NRMSE the diagnosis judges by. Ordinary reversals move the force far
//! less and stay in (a seal friction's jump is spread over its `v_friction`, millimetres per
//! second). Noise, not an offset: an offset would drift the stroke over a long record.

use crate::dsp::{median, rms};
use crate::rng::Rng;
use crate::velocity_noise::velocity_resolution;
use crate::velocity_noise::{NoiseSource, VelocityNoise};
use rayon::prelude::*;

/// A sample is left out when a velocity shift of ±δ moves the model's force by more than this
/// many load-cell noise sigmas.
pub const SENSITIVE_SIGMAS: f64 = 3.0;
/// The seeds of the two perturbed runs.
pub const SENSITIVITY_SEEDS: [u64; 2] = [0x5E45_0001, 0x5E45_0002];
/// Which samples inform the diagnosis.
#[derive(Clone, Debug)]
pub struct Informative {
    /// Per sample: the force does not hang on the velocity below its resolution.
    pub keep: Vec<bool>,
    /// The velocity noise δ added (m/s).
    pub delta_v: f64,
    /// The force's shift that leaves a sample out (N).
    pub threshold: f64,
}

impl Informative {
    /// Every sample kept.
    pub fn all(n: usize) -> Informative {
        Informative { keep: vec![true; n], delta_v: 0.0, threshold: f64::INFINITY }
    }

    /// Samples left out from `from` on.
    pub fn left_out(&self, from: usize) -> usize {
        self.keep[from..].iter().filter(|k| !**k).count()
    }
}

/// The samples of a baseline force `base` kept, given the same run with the velocity's noise
/// added (`perturbed`, two or more runs) and with other velocities the record cannot tell from its
/// own (`also`: the sign runs of a velocity made from the displacement), and the load-cell noise
/// `noise_sigma` (N).
///
/// The threshold is [`SENSITIVE_SIGMAS`] times the load-cell noise and the typical shift together
/// (√(σ² + s²), s the standard deviation of one run's shift, from the median of all runs' absolute
/// shifts): a velocity made from a displacement carries its noise everywhere (tens of newtons on
/// an LVDT's derivative), and only the samples that hang on the velocity far more than the rest
/// tell nothing.
pub fn informative(
    base: &[f64],
    perturbed: &[Vec<f64>],
    also: &[Vec<f64>],
    delta_v: f64,
    noise_sigma: f64,
) -> Informative {
    let shift: Vec<f64> = base
        .iter()
        .enumerate()
        .map(|(i, b)| perturbed.iter().chain(also).map(|run| (run[i] - b).abs()).fold(0.0, f64::max))
        .collect();
    let mut all: Vec<f64> = perturbed.iter().flat_map(|run| run.iter().zip(base).map(|(p, b)| (p - b).abs())).collect();
    // median |N(0, s²)| = 0.6745·s
    let typical = median(&mut all) / 0.674_489_75;
    let threshold =
        SENSITIVE_SIGMAS * if typical.is_finite() { libm::hypot(noise_sigma, typical) } else { noise_sigma };
    let keep = shift.iter().map(|s| *s <= threshold).collect();
    Informative { keep, delta_v, threshold }
}

/// The velocity's noise paths the model is run with, each as long as `v`, and their level δ (m/s,
/// the first path's RMS): coloured, made from the displacement's noise where the velocity was,
/// or the smoothed transducer noise where it was smoothed (`coloured`), else white at the record's
/// resolution ([`velocity_resolution`]), one per
/// [`SENSITIVITY_SEEDS`]. A coloured path runs both ways (antithetic): at a slow reversal one of the
/// two moves the zero crossing earlier and the other later, so the semi-active clip's sign is
/// always tried.
fn velocity_noise_paths(coloured: Option<&VelocityNoise>, v: &[f64]) -> (Vec<Vec<f64>>, f64) {
    let n = v.len();
    match coloured {
        None => {
            let delta_v = velocity_resolution(v);
            let paths = SENSITIVITY_SEEDS
                .iter()
                .map(|seed| {
                    let mut rng = Rng::new(*seed);
                    (0..n).map(|_| delta_v * rng.normal()).collect()
                })
                .collect();
            (paths, delta_v)
        }
        Some(noise) => {
            let paths: Vec<Vec<f64>> = SENSITIVITY_SEEDS
                .iter()
                .flat_map(|seed| {
                    let path = noise.path(*seed, n);
                    [path.iter().map(|e| -e).collect(), path]
                })
                .collect();
            let delta_v = rms(&paths[1]);
            (paths, delta_v)
        }
    }
}

/// The model's force with the record's velocity shifted by what the record cannot tell from it.
#[derive(Clone, Debug)]
pub struct ShiftedRuns {
    /// One run per velocity noise path: coloured (both ways) where the velocity was made from the
    /// displacement or smoothed, else white at its resolution ([`velocity_resolution`]).
    pub perturbed: Vec<Vec<f64>>,
    /// The two sign runs of a velocity made from the displacement (the sign of the motion tried
    /// both ways where the velocity is within its noise of zero); else none.
    pub signed: Vec<Vec<f64>>,
    /// The noise paths' level δ (m/s).
    pub delta_v: f64,
    /// The paths are coloured (a velocity made from the displacement, or smoothed), not white.
    pub coloured: bool,
}

impl ShiftedRuns {
    /// Runs `run` (the model's force driven by the velocity it is given) on the record's velocity
    /// `v` shifted by each noise path and sign run, on the caller's rayon pool. `coloured`: the
    /// velocity's noise where it was made from the displacement or smoothed. The error is `run`'s.
    pub fn new(
        coloured: Option<&VelocityNoise>,
        v: &[f64],
        run: impl Fn(Vec<f64>) -> Result<Vec<f64>, crate::Error> + Sync,
    ) -> Result<ShiftedRuns, crate::Error> {
        let (paths, delta_v) = velocity_noise_paths(coloured, v);
        let derived = coloured.is_some_and(|n| n.source == NoiseSource::Displacement);
        let signs: Vec<Vec<f64>> = if derived { sign_runs(v, delta_v).into() } else { Vec::new() };
        let shifted = |noise: &Vec<f64>| run(v.iter().zip(noise).map(|(v, e)| v + e).collect());
        let (perturbed, signed) = rayon::join(
            || paths.par_iter().map(shifted).collect::<Result<Vec<_>, _>>(),
            || signs.par_iter().map(shifted).collect::<Result<Vec<_>, _>>(),
        );
        Ok(ShiftedRuns { perturbed: perturbed?, signed: signed?, delta_v, coloured: coloured.is_some() })
    }

    /// The samples of the unshifted run `base` that inform a fit ([`informative`]), given the
    /// load-cell noise `noise_sigma` (N).
    pub fn informative(&self, base: &[f64], noise_sigma: f64) -> Informative {
        informative(base, &self.perturbed, &self.signed, self.delta_v, noise_sigma)
    }

    /// The noise paths' changes of the force over the samples `fitted` holds, one draw per path:
    /// the input error whose spread a fit's parameters inherit ([`crate::lm`]). None for white
    /// paths: a white velocity noise carried into the force is white too, in the residuals (and
    /// the sandwich's Ω) where the damper moved with the true motion, and not there at all where
    /// it sensed the logged velocity; added, it would be counted twice or for nothing (on the
    /// generated rig records of the calibration tests it made V_hose's uncertainty 3.6 times as
    /// large, and its fit lay 0.6 of it from the truth, where without it 2.1). A
    /// coloured one bends the force alike over many residuals' correlation lengths, and a fit
    /// absorbs it without a trace.
    pub fn input_error(&self, base: &[f64], fitted: impl Fn(usize) -> bool) -> Vec<Vec<f64>> {
        if !self.coloured {
            return Vec::new();
        }
        self.perturbed
            .iter()
            .map(|p| (0..base.len()).filter(|i| fitted(*i)).map(|i| p[i] - base[i]).collect())
            .collect()
    }
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

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn a_sample_is_left_out_only_where_the_force_hangs_on_the_velocity() {
        let base = [0.0, 10.0, 20.0, 30.0];
        let perturbed = [vec![1.0, 10.0, 200.0, 30.0], vec![-1.0, 50.0, 20.0, 30.0]];
        let i = informative(&base, &perturbed, &[], 1e-4, 20.0);
        assert_eq!(i.keep, [true, true, false, true]);
        assert_eq!(i.left_out(0), 1);
        assert_eq!(i.left_out(3), 0);
    }
}
