//! The noise of a velocity made from a displacement. A dynamometer's logger often writes a
//! velocity it differentiated from its displacement transducer and filtered (an LVDT's central
//! differences under a zero-phase Butterworth, say): that velocity's noise is the displacement's,
//! differentiated and low-passed, so it is neither white nor visible in the velocity's own high
//! differences (an LVDT of 5 µm gave 0.74 mm/s below 100 Hz, while the fourth differences said
//! 0.01 mm/s). Its level is found from the record itself:
//!
//! ```text
//! v[i] ≈ c + Σ_{k=−K..K} g_k Δx[i+k]      least squares (on first differences), Δx[j] = x[j] − x[j−1]
//! d_j  = g_j − g_{j+1}                     the impulse response from x to v (1/s)
//! σ_x  = white noise of x (stroke::white_noise)
//! v is made from x  ⇔  RMS(v − fit) < DERIVED_SHARE · σ_x ‖d‖    (its noise is x's, carried by d)
//! ```
//!
//! A velocity sensor of its own leaves a residual of at least its noise plus x's noise carried by
//! the fit, so it is not taken for a derived one. The derived velocity is then smoothed by a
//! Wiener filter under its coloured noise spectrum σ_x²|D(f)|² ([`crate::dsp::WienerGains`]), and
//! noise paths of the same colour, smoothed alike, are what the sensitivity test and the floor
//! perturb the model's velocity with ([`VelocityNoise::path`]).

use crate::dsp::{median, rms, WienerGains};
use crate::rng::Rng;
use nalgebra::{DMatrix, DVector};

/// The fitted response spans ±this long (s): a logger's filter down to about 25 Hz.
pub const RESPONSE_SPAN_S: f64 = 0.04;
/// At most this many taps on each side of the response.
pub const MAX_TAPS: usize = 128;
/// The smoother's periodogram average (±bins): a derivative's noise rises as f², and its crossover
/// with a rig's motion is told better over wider bands (on LVDT records at 2 kHz the velocity's
/// error fell from 1.60 to 1.35 mm/s from ±15 to ±60 bins, against 1.25 for a smoother that knew
/// the motion's spectrum; 0.94 → 0.87 and 0.81 at 500 Hz).
pub const SMOOTH_BINS: usize = 60;
/// The window (s) over which what the smoother took out is compared with what noise alone makes
/// it take: about a corner of a rig's triangle wave rounded by a 30 Hz smoother.
pub const LOCAL_WINDOW_S: f64 = 0.016;
/// The seed of the noise path that measures the smoother's error and what it takes out of noise.
const LOCAL_SEED: u64 = 0x5E45_00FF;
/// A velocity whose misfit to the displacement's response is below this share of the noise the
/// response carries from the displacement is made from the displacement.
pub const DERIVED_SHARE: f64 = 0.5;

/// The smallest δ (m/s): a velocity channel's quantum (0.01 mm/s).
pub const MIN_VELOCITY_RESOLUTION: f64 = 1e-5;

/// The white-noise level of a velocity record (m/s), from its fourth differences (white noise of
/// variance σ² gives fourth differences of variance 70σ²; a damper's motion, smooth at the sample
/// rate, barely shows in them), by their median absolute value; at least
/// [`MIN_VELOCITY_RESOLUTION`].
pub fn velocity_resolution(v: &[f64]) -> f64 {
    let mut d4: Vec<f64> = v.windows(5).map(|w| (w[0] - 4.0 * w[1] + 6.0 * w[2] - 4.0 * w[3] + w[4]).abs()).collect();
    // median |N(0, 70σ²)| = 0.6745·√70·σ
    let sigma = median(&mut d4) / (0.674_489_75 * 70f64.sqrt());
    if sigma.is_finite() {
        sigma.max(MIN_VELOCITY_RESOLUTION)
    } else {
        MIN_VELOCITY_RESOLUTION
    }
}

/// Where a velocity's noise comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NoiseSource {
    /// A velocity made from the displacement: the displacement's noise, differentiated and filtered.
    Displacement,
    /// A velocity transducer's own white noise ([`VelocityNoise::of_sensor`]).
    Sensor,
}

/// The noise of a velocity made from a displacement, or of a transducer's, and the smoother applied
/// to it.
#[derive(Clone, Debug)]
pub struct VelocityNoise {
    pub source: NoiseSource,
    /// The displacement's white noise σ_x (m).
    pub sigma_x: f64,
    /// The impulse response from the displacement to the velocity (1/s), taps −K−1..=K.
    pub response: Vec<f64>,
    /// The velocity's misfit to the response (m/s, RMS): its own noise, white.
    pub white: f64,
    /// The smoother applied to the velocity, when it was smoothed.
    pub smoother: Option<WienerGains>,
    /// Per sample, how much larger the smoothed velocity's error is than its mean: 1 where the
    /// smoother took out only noise, more where it took out signal too.
    pub local_scale: Vec<f64>,
    /// The sample interval (s).
    pub dt: f64,
    /// The smoother's periodogram average (±bins).
    bins: usize,
}

impl VelocityNoise {
    /// The noise of `v` (m/s) when it is made from `x` (m) sampled every `dt` (s); `None` when it is
    /// not (an independent sensor) or the record is too short to tell.
    pub fn of_derived(v: &[f64], x: &[f64], dt: f64) -> Option<VelocityNoise> {
        let taps = ((RESPONSE_SPAN_S / dt).round() as usize).clamp(4, MAX_TAPS);
        let n = v.len();
        if n != x.len() || n < 20 * (2 * taps + 1) {
            return None;
        }
        let dx = differences(x);
        let g = fit_response(v, &dx, taps)?;
        let misfit = misfit_series(v, &dx, &g, taps);
        let mut response = vec![0.0; 2 * taps + 2];
        // x[i+j] enters as g_j (through Δx[i+j]) and −g_{j+1} (through Δx[i+j+1]), j = −K−1..K
        for (k, gk) in g.iter().enumerate() {
            response[k + 1] += gk;
            response[k] -= gk;
        }
        let sigma_x = crate::stroke::white_noise(x);
        let carried = sigma_x * response.iter().map(|d| d * d).sum::<f64>().sqrt();
        (sigma_x > 0.0 && carried.is_finite() && rms(&misfit) < DERIVED_SHARE * carried).then_some(VelocityNoise {
            source: NoiseSource::Displacement,
            sigma_x,
            response,
            white: crate::stroke::white_noise(&misfit),
            smoother: None,
            local_scale: Vec::new(),
            dt,
            bins: SMOOTH_BINS,
        })
    }

    /// The white noise `sigma` (m/s) of a velocity transducer sampled every `dt` (s). Smoothed
    /// ([`smooth`](Self::smooth), as [`crate::dsp::wiener_smooth`] does), what is left of it is no
    /// longer white: it lies where the motion stands above the noise, and a velocity's resolution
    /// from its high differences ([`velocity_resolution`]) no longer sees it.
    pub fn of_sensor(sigma: f64, dt: f64) -> VelocityNoise {
        VelocityNoise {
            source: NoiseSource::Sensor,
            sigma_x: 0.0,
            response: Vec::new(),
            white: sigma,
            smoother: None,
            local_scale: Vec::new(),
            dt,
            bins: crate::dsp::WHITE_NOISE_BINS,
        }
    }

    /// The noise's spectral density (as the variance per sample of white noise of that level) at
    /// `f` cycles per sample.
    pub fn density(&self, f: f64) -> f64 {
        let (re, im) = self.frequency_response(f);
        self.white * self.white + self.sigma_x * self.sigma_x * (re * re + im * im)
    }

    /// The response from the displacement to the velocity at `f` cycles per sample (1/s; re, im):
    /// v[i] = Σ d_o x[i+o] gives H(f) = Σ d_o e^{+i2πfo}.
    fn frequency_response(&self, f: f64) -> (f64, f64) {
        let k0 = (self.response.len() / 2) as f64;
        let (mut re, mut im) = (0.0, 0.0);
        for (j, d) in self.response.iter().enumerate() {
            let (s, c) = libm::sincos(2.0 * std::f64::consts::PI * f * (j as f64 - k0));
            re += d * c;
            im += d * s;
        }
        (re, im)
    }

    /// The velocity's expected error (m/s, RMS) before any smoothing of ours: its noise, and what its
    /// filter takes out of the motion (|1 − H(f)/(i·2πf/dt)|² over the motion's spectrum, from a
    /// smoother fitted to a velocity made again from the displacement: `motion`).
    pub fn error_unsmoothed(&self, motion: &WienerGains) -> f64 {
        let taken = motion.signal_mean_square(|f| {
            if f == 0.0 {
                return 0.0;
            }
            let (re, im) = self.frequency_response(f);
            // H / (i ω) with ω = 2πf/dt: (re + i im)/(i ω) = (im − i re)/ω
            let omega = 2.0 * std::f64::consts::PI * f / self.dt;
            let (a, b) = (im / omega, -re / omega);
            (1.0 - a) * (1.0 - a) + b * b
        });
        (self.rms() * self.rms() + taken).sqrt()
    }

    /// The velocity's noise (m/s, RMS) before smoothing.
    pub fn rms(&self) -> f64 {
        libm::hypot(self.white, self.sigma_x * self.response.iter().map(|d| d * d).sum::<f64>().sqrt())
    }

    /// `v` smoothed under this noise; the smoother, and where it took out more than noise, are
    /// kept for [`path`](Self::path).
    pub fn smooth(&mut self, v: &[f64]) -> Vec<f64> {
        let gains = WienerGains::new(v, |f| self.density(f), self.bins);
        let out = gains.apply(v);
        let removed: Vec<f64> = v.iter().zip(&out).map(|(a, b)| a - b).collect();
        let noise = self.raw_path(LOCAL_SEED, v.len());
        let error = mean_square(&gains.error_of(&noise));
        let removed_noise = mean_square(&gains.removed_of(&noise));
        let window = (LOCAL_WINDOW_S / self.dt).round().max(8.0) as usize;
        self.local_scale = moving_mean_square(&removed, window)
            .iter()
            .map(|ms| ((error + (ms - removed_noise).max(0.0)) / error).sqrt())
            .map(|s| if s.is_finite() { s } else { 1.0 })
            .collect();
        self.smoother = Some(gains);
        out
    }

    /// A path of `n` samples of the velocity's error, drawn from `seed`: this noise, or where the
    /// velocity was smoothed, the smoothed velocity's error ([`WienerGains::error_of`]), scaled up
    /// where the smoother took out more than noise (a corner of the motion rounded off: the
    /// smoothed velocity lacks what was taken there, [`LOCAL_WINDOW_S`]).
    pub fn path(&self, seed: u64, n: usize) -> Vec<f64> {
        let raw = self.raw_path(seed, n);
        let error = match &self.smoother {
            Some(gains) => gains.error_of(&raw),
            None => raw,
        };
        if self.local_scale.len() == n {
            error.iter().zip(&self.local_scale).map(|(e, s)| e * s).collect()
        } else {
            error
        }
    }

    /// A path of `n` samples of the velocity's noise before smoothing.
    fn raw_path(&self, seed: u64, n: usize) -> Vec<f64> {
        let mut rng = Rng::new(seed);
        let taps = self.response.len();
        let x_noise: Vec<f64> = (0..n + taps).map(|_| self.sigma_x * rng.normal()).collect();
        (0..n)
            .map(|i| {
                let carried: f64 = self.response.iter().zip(&x_noise[i..i + taps]).map(|(d, e)| d * e).sum();
                carried + self.white * rng.normal()
            })
            .collect()
    }

    /// The RMS (m/s) of a path of [`path`](Self::path) over `n` samples: what the velocity still
    /// carries.
    pub fn carried_rms(&self, seed: u64, n: usize) -> f64 {
        rms(&self.path(seed, n))
    }
}

/// The least-squares response g (taps −K..K) of `v` on `dx`; `None` when it cannot be solved. The fit
/// runs on the first differences of both (the same response relates them): a stroke's slow
/// motion dominates `dx` by orders of magnitude over its noise, and the normal equations, solved
/// by Cholesky, stay well conditioned.
fn fit_response(v: &[f64], dx: &[f64], taps: usize) -> Option<Vec<f64>> {
    let n = v.len();
    let width = 2 * taps + 1;
    let (dv, ddx) = (differences(v), differences(dx));
    let rows = taps + 2..n - taps;
    // the exact normal equations: G[a][a+l] = Σ_rows ddx[i+a−K]·ddx[i+a−K+l], by a prefix sum per lag
    let mut gram = DMatrix::zeros(width, width);
    let mut prefix = vec![0.0; n + 1];
    for l in 0..width {
        for j in 0..n {
            prefix[j + 1] = prefix[j] + if j + l < n { ddx[j] * ddx[j + l] } else { 0.0 };
        }
        for a in 0..width - l {
            let lo = rows.start + a - taps;
            let value = prefix[lo + rows.len()] - prefix[lo];
            gram[(a, a + l)] = value;
            gram[(a + l, a)] = value;
        }
    }
    let cross = DVector::from_fn(width, |a, _| rows.clone().map(|i| ddx[i + a - taps] * dv[i]).sum());
    let g = gram.cholesky()?.solve(&cross);
    g.iter().all(|gk| gk.is_finite()).then(|| g.iter().copied().collect())
}

/// `x[j] − x[j−1]`, with 0 first (the same length as `x`).
fn differences(x: &[f64]) -> Vec<f64> {
    std::iter::once(0.0).chain(x.windows(2).map(|w| w[1] - w[0])).collect()
}

fn mean_square(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>() / x.len().max(1) as f64
}

/// The mean square of `x` over a centred window of `window` samples (shorter at the ends).
fn moving_mean_square(x: &[f64], window: usize) -> Vec<f64> {
    let mut prefix = vec![0.0; x.len() + 1];
    for (k, v) in x.iter().enumerate() {
        prefix[k + 1] = prefix[k] + v * v;
    }
    (0..x.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(window / 2), (i + window / 2 + 1).min(x.len()));
            (prefix[b] - prefix[a]) / (b - a) as f64
        })
        .collect()
}

/// v − (mean + Σ g_k Δx[i+k]) over the rows the response covers.
fn misfit_series(v: &[f64], dx: &[f64], g: &[f64], taps: usize) -> Vec<f64> {
    let rows = taps..v.len() - taps;
    let fitted: Vec<f64> = rows.clone().map(|i| g.iter().zip(&dx[i - taps..]).map(|(gk, d)| gk * d).sum()).collect();
    let offset =
        rows.clone().map(|i| v[i]).sum::<f64>() / rows.len() as f64 - fitted.iter().sum::<f64>() / fitted.len() as f64;
    rows.zip(&fitted).map(|(i, f)| v[i] - offset - f).collect()
}

#[cfg(test)]
#[allow(clippy::disallowed_methods, clippy::unwrap_used, clippy::expect_used, clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::dsp::Lowpass;

    fn motion(n: usize, dt: f64) -> Vec<f64> {
        (0..n).map(|k| 0.03 * (2.0 * std::f64::consts::PI * 1.3 * k as f64 * dt).sin()).collect()
    }

    /// A velocity a logger differentiated from a 5 µm displacement and low-passed is found to be
    /// made from it, with its noise level within 15 % of the truth measured on the same noise.
    #[test]
    fn a_logged_derivative_is_recognised_with_its_noise() {
        let dt = 1e-3;
        let mut rng = Rng::new(3);
        let x_true = motion(8000, dt);
        let noise: Vec<f64> = (0..8000).map(|_| 5e-6 * rng.normal()).collect();
        let x: Vec<f64> = x_true.iter().zip(&noise).map(|(a, b)| a + b).collect();
        let derive = |x: &[f64]| {
            let d: Vec<f64> = std::iter::once(0.0).chain(x.windows(2).map(|w| (w[1] - w[0]) / dt)).collect();
            let mut f = Lowpass::new(80.0, d[0]);
            d.iter().map(|v| f.step(dt, *v)).collect::<Vec<f64>>()
        };
        let v = derive(&x);
        let truth = rms(&derive(&noise)[100..]);
        let found = VelocityNoise::of_derived(&v, &x, dt).expect("made from the displacement");
        assert!((found.rms() / truth - 1.0).abs() < 0.15, "{} against {truth}", found.rms());
    }

    #[test]
    fn the_velocity_resolution_is_the_noise_not_the_motion() {
        let mut rng = crate::rng::Rng::new(3);
        let h = 2e-3;
        let v: Vec<f64> = (0..4000)
            .map(|k| {
                let t = k as f64 * h;
                0.1 * (2.0 * std::f64::consts::PI * 8.0 * t).sin() + 1e-4 * rng.normal()
            })
            .collect();
        let r = velocity_resolution(&v);
        assert!((r / 1e-4 - 1.0).abs() < 0.1, "{r:e}");
        let quiet = vec![0.05; 100];
        assert_eq!(velocity_resolution(&quiet), MIN_VELOCITY_RESOLUTION);
    }

    /// A dyno's random motion (white noise through two 2 Hz low-passes, about 0.1 m/s RMS: a
    /// spectrum, not a line, as the Wiener error G·N assumes) measured by a transducer with 1 mm/s
    /// of white noise, smoothed: (the smoothed velocity's error against the truth, RMS; what its
    /// paths carry; its resolution from the high differences), m/s.
    fn smoothed_transducer(seed: u64) -> (f64, f64, f64) {
        let dt = 1e-3;
        let mut rng = Rng::new(seed);
        let (mut a, mut b) = (Lowpass::new(2.0, 0.0), Lowpass::new(2.0, 0.0));
        let truth: Vec<f64> = (0..8000).map(|_| 2.0 * b.step(dt, a.step(dt, rng.normal()))).collect();
        let v: Vec<f64> = truth.iter().map(|v| v + 1e-3 * rng.normal()).collect();
        let sigma = crate::stroke::white_noise(&v);
        let mut noise = VelocityNoise::of_sensor(sigma, dt);
        let smoothed = noise.smooth(&v);
        assert_eq!(smoothed, crate::dsp::wiener_smooth(&v, sigma));
        let error: Vec<f64> = smoothed.iter().zip(&truth).map(|(a, b)| a - b).collect();
        (rms(&error[100..7900]), noise.carried_rms(1, 8000), velocity_resolution(&smoothed))
    }

    /// A transducer's smoothed white noise, on twelve records: its paths never carry less than the
    /// smoothed velocity's error against the truth (1.2–1.5× it: the error spectrum G·N holds for
    /// exact gains, and the paths are scaled up where the smoother took out signal), where its
    /// resolution from the high differences, the white paths' level before, sees about half of it;
    /// the smoother is the white-noise one of `dsp::wiener_smooth`.
    #[test]
    fn a_smoothed_transducer_s_paths_carry_the_error_left() {
        let mut seen_share = 0.0;
        for seed in 1..13 {
            let (left, carried, seen) = smoothed_transducer(seed);
            assert!((1.0..1.6).contains(&(carried / left)), "seed {seed}: paths {carried:e}, error left {left:e}");
            seen_share += seen / left / 12.0;
        }
        assert!(seen_share < 0.6, "the high differences see {seen_share:.2} of the error left");
    }

    /// A velocity transducer of its own (white noise, 0.1 mm/s) beside the displacement is not
    /// taken for a derived velocity.
    #[test]
    fn an_independent_sensor_is_not_derived() {
        let dt = 1e-3;
        let mut rng = Rng::new(4);
        let x_true = motion(8000, dt);
        let x: Vec<f64> = x_true.iter().map(|a| a + 5e-6 * rng.normal()).collect();
        let v: Vec<f64> = (0..8000)
            .map(|k| 0.03 * 2.0 * std::f64::consts::PI * 1.3 * (2.0 * std::f64::consts::PI * 1.3 * k as f64 * dt).cos())
            .map(|v| v + 1e-4 * rng.normal())
            .collect();
        assert!(VelocityNoise::of_derived(&v, &x, dt).is_none());
    }
}
