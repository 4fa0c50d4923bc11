//! Signal arithmetic: error metrics, spectra, correlations and the load-cell filter.

use std::f64::consts::PI;

pub fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    x.iter().sum::<f64>() / x.len() as f64
}

/// Population standard deviation.
pub fn std(x: &[f64]) -> f64 {
    let m = mean(x);
    (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64).sqrt()
}

pub fn rms(x: &[f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Fit metrics of a model `yhat` against a measurement `y`.
#[derive(Clone, Copy, Debug)]
pub struct Metrics {
    /// 100·(1 − ‖y − ŷ‖/‖y − ȳ‖) (%).
    pub fit_percent: f64,
    /// RMSE/std(y).
    pub nrmse: f64,
    /// sqrt(mean((ŷ − y)²)).
    pub rmse: f64,
    /// mean(ŷ − y): positive when the model is above the measurement.
    pub bias: f64,
    /// std(y).
    pub std_measured: f64,
    pub samples: usize,
}

/// The fit metrics of a model `yhat` against a measurement `y`.
pub fn metrics(y: &[f64], yhat: &[f64]) -> Metrics {
    let r: Vec<f64> = yhat.iter().zip(y).map(|(m, y)| m - y).collect();
    let rmse = rms(&r);
    let s = std(y);
    let nrmse = rmse / s;
    Metrics { fit_percent: 100.0 * (1.0 - nrmse), nrmse, rmse, bias: mean(&r), std_measured: s, samples: y.len() }
}

/// The normalised RMS error of a model `yhat` against a measurement `y` ([`Metrics::nrmse`]).
pub fn nrmse(y: &[f64], yhat: &[f64]) -> f64 {
    metrics(y, yhat).nrmse
}

/// The samples of `x` where `keep` is true (`crate::sensitivity`).
pub fn kept(x: &[f64], keep: &[bool]) -> Vec<f64> {
    x.iter().zip(keep).filter(|(_, k)| **k).map(|(x, _)| *x).collect()
}

/// [`nrmse`] over the samples where `keep` is true.
pub fn nrmse_kept(y: &[f64], yhat: &[f64], keep: &[bool]) -> f64 {
    nrmse(&kept(y, keep), &kept(yhat, keep))
}

/// Samples per window of [`noise_floor`]'s windowed estimate.
pub const NOISE_WINDOW: usize = 64;

/// The white-noise level of a residual, estimated three ways from its second differences (white
/// noise of variance σ² gives second differences of variance 6σ², while a model error, smooth at
/// the sample rate, barely shows in them, except at its fast transients).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseEstimate {
    /// The estimate used: the smaller of [`sigma_window`](Self::sigma_window) and
    /// [`sigma_mad`](Self::sigma_mad), both robust to a model error that shows at few samples;
    /// each alone is exact for white Gaussian noise, and the smaller is the less contaminated.
    pub sigma: f64,
    /// The median over windows of [`NOISE_WINDOW`] samples of the mean-square second difference:
    /// a model error at fast transients inflates the windows it falls in, not the median, while
    /// it occupies less than half of them.
    pub sigma_window: f64,
    /// The median absolute second difference: robust to errors at up to half of the samples.
    pub sigma_mad: f64,
    /// The plain estimate over every sample: what a model error at transients inflates.
    pub sigma_all: f64,
}

impl NoiseEstimate {
    /// How the estimate is made, for reports.
    pub const METHOD: &'static str = "second differences of the residual: the smaller of the median over 64-sample windows of their mean square and their median absolute value (both scaled to σ)";
}

/// The noise level of `r` ([`NoiseEstimate`]).
pub fn noise_floor(r: &[f64]) -> NoiseEstimate {
    let d2: Vec<f64> = r.windows(3).map(|w| w[0] - 2.0 * w[1] + w[2]).collect();
    let sigma_all = (d2.iter().map(|d| d * d).sum::<f64>() / d2.len().max(1) as f64 / 6.0).sqrt();
    let mut windows: Vec<f64> = d2
        .chunks(NOISE_WINDOW)
        .filter(|c| c.len() == NOISE_WINDOW)
        .map(|c| c.iter().map(|d| d * d).sum::<f64>() / c.len() as f64)
        .collect();
    let sigma_window = if windows.len() < 5 { sigma_all } else { (median(&mut windows) / 6.0).sqrt() };
    let mut abs: Vec<f64> = d2.iter().map(|d| d.abs()).collect();
    // median |N(0, 6σ²)| = 0.6745·√6·σ
    let sigma_mad = if abs.is_empty() { f64::NAN } else { median(&mut abs) / (0.674_489_75 * 6f64.sqrt()) };
    NoiseEstimate { sigma: sigma_window.min(sigma_mad), sigma_window, sigma_mad, sigma_all }
}

/// Standard deviation of white noise in `r` ([`NoiseEstimate::sigma`]).
pub fn noise_sigma(r: &[f64]) -> f64 {
    noise_floor(r).sigma
}

/// The median (the slice is reordered); NaN when empty.
pub fn median(x: &mut [f64]) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    x.sort_by(f64::total_cmp);
    let n = x.len();
    if n % 2 == 1 {
        x[n / 2]
    } else {
        0.5 * (x[n / 2 - 1] + x[n / 2])
    }
}

/// In-place radix-2 FFT of (re, im); the length must be a power of two.
pub fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    assert!(n.is_power_of_two() && im.len() == n);
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * PI / len as f64;
        let (wi, wr) = libm::sincos(ang);
        for start in (0..n).step_by(len) {
            let (mut cr, mut ci) = (1.0, 0.0);
            for k in 0..len / 2 {
                let (a, b) = (start + k, start + k + len / 2);
                let (xr, xi) = (re[b] * cr - im[b] * ci, re[b] * ci + im[b] * cr);
                re[b] = re[a] - xr;
                im[b] = im[a] - xi;
                re[a] += xr;
                im[a] += xi;
                let t = cr * wr - ci * wi;
                ci = cr * wi + ci * wr;
                cr = t;
            }
        }
        len <<= 1;
    }
}

/// One-sided power spectral density by Welch's method: Hann window, 50 % overlap, each segment's
/// mean removed. Returns (frequencies (Hz), PSD (unit²/Hz)); its sum times the bin width is the
/// variance. `segment` is rounded down to a power of two and to the record length.
pub fn welch(x: &[f64], fs: f64, segment: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nseg = segment.min(x.len()).max(8);
    nseg = 1 << (usize::BITS - 1 - nseg.leading_zeros());
    let window: Vec<f64> = (0..nseg).map(|i| 0.5 - 0.5 * libm::cos(2.0 * PI * i as f64 / nseg as f64)).collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let hop = nseg / 2;
    let mut psd = vec![0.0; nseg / 2 + 1];
    let mut count = 0;
    let mut start = 0;
    while start + nseg <= x.len() {
        let seg = &x[start..start + nseg];
        let m = mean(seg);
        let mut re: Vec<f64> = seg.iter().zip(&window).map(|(v, w)| (v - m) * w).collect();
        let mut im = vec![0.0; nseg];
        fft(&mut re, &mut im);
        for (k, p) in psd.iter_mut().enumerate() {
            let s = if k == 0 || k == nseg / 2 { 1.0 } else { 2.0 };
            *p += s * (re[k] * re[k] + im[k] * im[k]) / (fs * w2);
        }
        count += 1;
        start += hop;
    }
    for p in &mut psd {
        *p /= count.max(1) as f64;
    }
    let freqs = (0..=nseg / 2).map(|k| k as f64 * fs / nseg as f64).collect();
    (freqs, psd)
}

/// Normalised autocorrelation r(k) = Σ (x_i − x̄)(x_{i+k} − x̄) / Σ (x_i − x̄)², k = 0..=max_lag.
pub fn autocorrelation(x: &[f64], max_lag: usize) -> Vec<f64> {
    let m = mean(x);
    let d: Vec<f64> = x.iter().map(|v| v - m).collect();
    let c0: f64 = d.iter().map(|v| v * v).sum();
    (0..=max_lag.min(x.len().saturating_sub(1)))
        .map(|k| d[..d.len() - k].iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>() / c0)
        .collect()
}

/// Normalised cross-correlation c(k) = Σ_t a(t+k)·b(t) / sqrt(Σa² Σb²) of the mean-removed signals,
/// k = −max_lag..=max_lag (index k + max_lag). A peak at k > 0 means `a` follows `b` by k samples.
pub fn cross_correlation(a: &[f64], b: &[f64], max_lag: usize) -> Vec<f64> {
    let n = a.len().min(b.len());
    let (ma, mb) = (mean(&a[..n]), mean(&b[..n]));
    let da: Vec<f64> = a[..n].iter().map(|v| v - ma).collect();
    let db: Vec<f64> = b[..n].iter().map(|v| v - mb).collect();
    let norm = (da.iter().map(|v| v * v).sum::<f64>() * db.iter().map(|v| v * v).sum::<f64>()).sqrt();
    let l = max_lag.min(n.saturating_sub(1)) as isize;
    (-l..=l)
        .map(|k| {
            let s: f64 = if k >= 0 {
                let k = k as usize;
                da[k..].iter().zip(&db[..n - k]).map(|(x, y)| x * y).sum()
            } else {
                let k = (-k) as usize;
                da[..n - k].iter().zip(&db[k..]).map(|(x, y)| x * y).sum()
            };
            if norm > 0.0 {
                s / norm
            } else {
                0.0
            }
        })
        .collect()
}

/// The lag (samples) of the largest value of a cross-correlation from [`cross_correlation`], and
/// its parabolic refinement (fractional samples).
pub fn peak_lag(c: &[f64]) -> (isize, f64, f64) {
    let l = (c.len() / 2) as isize;
    let (i, &v) = c.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).expect("nonempty");
    let k = i as isize - l;
    let refined = if i > 0 && i + 1 < c.len() {
        let (a, b, d) = (c[i - 1], c[i], c[i + 1]);
        let den = a - 2.0 * b + d;
        if den < 0.0 {
            k as f64 + 0.5 * (a - d) / den
        } else {
            k as f64
        }
    } else {
        k as f64
    };
    (k, refined, v)
}

/// Ljung–Box statistic Q = n(n+2) Σ_{k=1..m} r_k²/(n−k) of an autocorrelation `r` (r(0) = 1).
pub fn ljung_box(r: &[f64], n: usize, m: usize) -> f64 {
    let n = n as f64;
    n * (n + 2.0) * (1..=m.min(r.len() - 1)).map(|k| r[k] * r[k] / (n - k as f64)).sum::<f64>()
}

/// 95 % quantile of χ² with `dof` degrees of freedom (Wilson–Hilferty, within 0.5 % for dof ≥ 5).
pub fn chi2_95(dof: usize) -> f64 {
    let k = dof as f64;
    let h = 2.0 / (9.0 * k);
    let c = 1.0 - h + 1.644_853_6 * h.sqrt();
    k * (c * (c * c))
}

/// First-order low-pass of cut-off `fc` (Hz), fed one sample at a time, exact for an input that
/// varies linearly between samples (first-order hold), starting in steady state at the first input:
/// y_k = α y_{k−1} + u_k − α u_{k−1} − τ r (1 − α),  α = exp(−h/τ),  r = (u_k − u_{k−1})/h.
#[derive(Clone, Copy, Debug)]
pub struct Lowpass {
    /// Time constant τ = 1/(2π fc) (s).
    tau: f64,
    /// The last input (N or any unit) and output.
    u: f64,
    y: f64,
}

impl Lowpass {
    pub fn new(fc: f64, u0: f64) -> Lowpass {
        Lowpass { tau: 1.0 / (2.0 * PI * fc), u: u0, y: u0 }
    }

    /// The output after `h` seconds over which the input went linearly to `u`.
    pub fn step(&mut self, h: f64, u: f64) -> f64 {
        let a = libm::exp(-h / self.tau);
        let r = (u - self.u) / h;
        self.y = a * self.y + u - a * self.u - self.tau * r * (1.0 - a);
        self.u = u;
        self.y
    }
}

/// Derivative by a central difference over ±`half` samples (one-sided near the ends): a smoothed
/// rate for classifying regimes, not for the model.
pub fn smooth_rate(t: &[f64], x: &[f64], half: usize) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|i| {
            let a = i.saturating_sub(half);
            let b = (i + half).min(n - 1);
            if b > a {
                (x[b] - x[a]) / (t[b] - t[a])
            } else {
                0.0
            }
        })
        .collect()
}

/// The integral of `v` sampled at `t` from `x0` at the first sample, by trapezoids: the stroke
/// along a velocity.
pub fn integrate(t: &[f64], v: &[f64], x0: f64) -> Vec<f64> {
    let mut x = vec![x0; t.len()];
    for k in 1..t.len() {
        x[k] = x[k - 1] + 0.5 * (v[k] + v[k - 1]) * (t[k] - t[k - 1]);
    }
    x
}

/// Velocity from displacement: three-point central difference on a possibly non-uniform grid,
/// second-order one-sided differences at the ends.
pub fn differentiate(t: &[f64], x: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut v = vec![0.0; n];
    for i in 1..n - 1 {
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        v[i] =
            (-h1 / (h0 * (h0 + h1))) * x[i - 1] + ((h1 - h0) / (h0 * h1)) * x[i] + (h0 / (h1 * (h0 + h1))) * x[i + 1];
    }
    let (h0, h1) = (t[1] - t[0], t[2] - t[1]);
    let s = h0 + h1;
    v[0] = -(2.0 * h0 + h1) / (h0 * s) * x[0] + s / (h0 * h1) * x[1] - h0 / (h1 * s) * x[2];
    // mirror for the last point: differentiate in reversed time
    let (h0, h1) = (t[n - 1] - t[n - 2], t[n - 2] - t[n - 3]);
    let s = h0 + h1;
    v[n - 1] = (2.0 * h0 + h1) / (h0 * s) * x[n - 1] - s / (h0 * h1) * x[n - 2] + h0 / (h1 * s) * x[n - 3];
    v
}

/// The periodogram's average of [`wiener_smooth`]: ±15 bins.
pub const WHITE_NOISE_BINS: usize = 15;

/// Zero-phase Wiener smoothing of a signal carrying white noise of standard deviation `sigma`
/// ([`WienerGains`] with a flat noise spectrum).
pub fn wiener_smooth(x: &[f64], sigma: f64) -> Vec<f64> {
    if x.len() < 8 || sigma.is_nan() || sigma <= 0.0 {
        return x.to_vec();
    }
    WienerGains::new(x, |_| sigma * sigma, WHITE_NOISE_BINS).apply(x)
}

/// The gains of a zero-phase Wiener smoother fitted to a signal: each frequency's share kept is
/// max(0, 1 − N(f)/P̄(f)), N the noise's power spectral density (as the variance per sample of
/// white noise of that level) and P̄ the periodogram averaged over `2·bins + 1`
/// neighbouring bins; the record is mirrored at both ends against edge effects. Where the signal
/// stands above the noise it passes unchanged; where the noise dominates it is removed. The gains
/// are fixed once fitted, so that the same linear smoother can be applied to a noise path
/// (what the smoothed signal still carries of its noise).
#[derive(Clone, Debug)]
pub struct WienerGains {
    n: usize,
    gain: Vec<f64>,
    /// Per bin, the signal's share of the mean square (P̄ − N, at least 0, over m²).
    signal: Vec<f64>,
}

impl WienerGains {
    /// Gains for `x` under noise of spectral density `noise(f)`, `f` in cycles per sample (0–0.5),
    /// its periodogram averaged over ±`bins`.
    pub fn new(x: &[f64], noise: impl Fn(f64) -> f64, bins: usize) -> WienerGains {
        let n = x.len();
        let (mut re, mut im) = even_extension(x);
        let m = re.len();
        fft(&mut re, &mut im);
        let power: Vec<f64> = re.iter().zip(&im).map(|(r, i)| r * r + i * i).collect();
        let (gain, signal) = (0..m)
            .map(|k| {
                // the averaged power around bin k, symmetric (bin m − k is its conjugate)
                let f = k.min(m - k);
                let (lo, hi) = (f.saturating_sub(bins), (f + bins).min(m / 2));
                let mean = power[lo..=hi].iter().sum::<f64>() / (hi - lo + 1) as f64;
                let noise = m as f64 * noise(f as f64 / m as f64);
                ((1.0 - noise / mean.max(1e-300)).max(0.0), (mean - noise).max(0.0) / (m * m) as f64)
            })
            .unzip();
        WienerGains { n, gain, signal }
    }

    /// The mean square of the signal weighted by `weight(f)`, `f` in cycles per sample (0–0.5): with
    /// weight |1 − H(f)|², what a filter H takes out of it. Counted where the signal stands at least
    /// as high as the noise (a gain of at least ½): below, P̄ − N is the noise estimate's error, not
    /// signal (counted everywhere, a 60 Hz filter took 2.3 mm/s out of a pure 1.5 Hz stroke).
    pub fn signal_mean_square(&self, weight: impl Fn(f64) -> f64) -> f64 {
        let m = self.signal.len();
        self.signal
            .iter()
            .zip(&self.gain)
            .enumerate()
            .filter(|(_, (_, g))| **g >= 0.5)
            .map(|(k, (s, _))| s * weight(k.min(m - k) as f64 / m as f64))
            .sum()
    }

    /// The smoother applied to `y` (of the fitted signal's length).
    pub fn apply(&self, y: &[f64]) -> Vec<f64> {
        self.filter(y, |g| g)
    }

    /// `y` filtered by the square roots of the gains: white noise of the noise spectrum N becomes
    /// noise of the smoothed signal's error spectrum. The gain G = 1 − N/P is S/(S + N) for a
    /// signal of spectrum S = P − N, and the smoothed signal's error (G·noise − (1 − G)·signal)
    /// has the spectrum G²N + (1 − G)²S = G·N: what the record cannot tell, noise left in where
    /// the signal dominates and signal taken out with the noise near the crossover.
    pub fn error_of(&self, y: &[f64]) -> Vec<f64> {
        self.filter(y, f64::sqrt)
    }

    /// What the smoother takes out of `y` (the gains' complements applied).
    pub fn removed_of(&self, y: &[f64]) -> Vec<f64> {
        self.filter(y, |g| 1.0 - g)
    }

    fn filter(&self, y: &[f64], of_gain: impl Fn(f64) -> f64) -> Vec<f64> {
        debug_assert_eq!(y.len(), self.n);
        let (mut re, mut im) = even_extension(y);
        let m = re.len();
        fft(&mut re, &mut im);
        for ((r, i), g) in re.iter_mut().zip(im.iter_mut()).zip(&self.gain) {
            let g = of_gain(*g);
            *r *= g;
            *i *= g;
        }
        // the inverse transform: the forward one of the conjugate, conjugated and scaled
        for v in im.iter_mut() {
            *v = -*v;
        }
        fft(&mut re, &mut im);
        re[..self.n].iter().map(|r| r / m as f64).collect()
    }
}

/// `x`, then `x` reversed, repeated to a power of two: the circular transform sees no jump at the
/// ends. Returns (re, im).
fn even_extension(x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    let m = (2 * n).next_power_of_two();
    let re = (0..m)
        .map(|k| {
            let j = k % (2 * n);
            if j < n {
                x[j]
            } else {
                x[2 * n - 1 - j]
            }
        })
        .collect();
    (re, vec![0.0; m])
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn noise_sigma_sees_white_noise_not_smooth_error() {
        let mut s = 1u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // uniform noise of width 1: σ = 1/√12; plus a smooth 2 Hz error sampled at 1 kHz
        let r: Vec<f64> =
            (0..20_000).map(|k| rnd() + 50.0 * (k as f64 * 2e-3 * std::f64::consts::PI * 2.0).sin()).collect();
        let sigma = noise_sigma(&r);
        assert!((sigma - 1.0 / 12f64.sqrt()).abs() < 0.02, "{sigma}");
    }

    #[test]
    fn the_noise_floor_is_not_inflated_by_errors_at_transients() {
        let mut rng = crate::rng::Rng::new(3);
        // Gaussian noise σ = 20 plus a model error that jumps by 1 kN and decays over 3 ms after
        // a step every 150 ms (the transients of a demand-step record): sharp at the sample rate
        let r: Vec<f64> =
            (0..30_000).map(|k| 20.0 * rng.normal() + 1000.0 * (-((k % 150) as f64) / 3.0).exp()).collect();
        let e = noise_floor(&r);
        assert!((e.sigma / 20.0 - 1.0).abs() < 0.05 && e.sigma == e.sigma_mad, "{e:?}");
        // the error falls in 43 % of the windows: their median is inflated a little, not much
        assert!(e.sigma_window < 1.2 * 20.0, "{e:?}");
        assert!(e.sigma_all > 2.0 * 20.0, "the plain estimate absorbs the error: {e:?}");
    }

    #[test]
    fn fft_matches_dft() {
        let x: Vec<f64> = (0..16).map(|i| ((i * 7 % 5) as f64).sin() + i as f64 * 0.1).collect();
        let mut re = x.clone();
        let mut im = vec![0.0; 16];
        fft(&mut re, &mut im);
        for k in 0..16 {
            let (mut a, mut b) = (0.0, 0.0);
            for (i, v) in x.iter().enumerate() {
                let ang = -2.0 * PI * (k * i) as f64 / 16.0;
                a += v * ang.cos();
                b += v * ang.sin();
            }
            assert!((re[k] - a).abs() < 1e-9 && (im[k] - b).abs() < 1e-9);
        }
    }

    #[test]
    fn welch_integrates_to_the_variance() {
        let fs = 1000.0;
        let x: Vec<f64> = (0..20000).map(|i| 3.0 * (2.0 * PI * 50.0 * i as f64 / fs).sin() + 1.0).collect();
        let (f, p) = welch(&x, fs, 1024);
        let df = f[1] - f[0];
        let var: f64 = p.iter().sum::<f64>() * df;
        assert!((var - 4.5).abs() < 0.05, "{var}");
        let peak = p.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).unwrap().0;
        assert!((f[peak] - 50.0).abs() < 1.0);
    }

    #[test]
    fn cross_correlation_finds_a_delay() {
        let x: Vec<f64> = (0..2000).map(|i| ((i as f64) * 0.05).sin() + ((i as f64) * 0.13).cos()).collect();
        let delayed: Vec<f64> = (0..2000).map(|i| if i >= 7 { x[i - 7] } else { 0.0 }).collect();
        let c = cross_correlation(&delayed, &x, 30);
        let (k, refined, _) = peak_lag(&c);
        assert_eq!(k, 7);
        assert!((refined - 7.0).abs() < 0.1);
    }

    /// [`Lowpass`] over a whole sampled signal `u(t)`, from steady state at `u[0]`.
    fn lowpass(t: &[f64], u: &[f64], fc: f64) -> Vec<f64> {
        let mut filter = Lowpass::new(fc, u[0]);
        std::iter::once(u[0]).chain((1..u.len()).map(|k| filter.step(t[k] - t[k - 1], u[k]))).collect()
    }

    #[test]
    fn lowpass_is_exact_for_ramps_and_steps() {
        let fc = 400.0;
        let tau = 1.0 / (2.0 * PI * fc);
        let t: Vec<f64> = (0..100).map(|k| k as f64 * 1e-3).collect();
        let u: Vec<f64> = t.iter().map(|t| 5.0 * t).collect(); // ramp from rest: y = u − τ·5·(1 − e^(−t/τ))
        let y = lowpass(&t, &u, fc);
        for k in 0..100 {
            let exact = u[k] - tau * 5.0 * (1.0 - (-t[k] / tau).exp());
            assert!((y[k] - exact).abs() < 1e-12, "{k}");
        }
        let step: Vec<f64> = (0..10).map(|_| 2.0).collect();
        assert!(lowpass(&t[..10], &step, fc).iter().all(|v| (v - 2.0).abs() < 1e-12));
    }

    #[test]
    fn chi2_quantiles() {
        assert!((chi2_95(20) - 31.41).abs() < 0.1);
        assert!((chi2_95(10) - 18.31).abs() < 0.1);
    }

    /// The smoothed signal's error is what [`WienerGains::error_of`] makes of white noise: on a
    /// broadband motion (white noise through two 15 Hz low-passes, a damper's random drive) under
    /// white noise, the RMS of the two agree within 15 %; the smoother's gains alone
    /// ([`WienerGains::apply`]) leave out the signal taken out with the noise.
    #[test]
    fn the_error_path_has_the_smoothed_signals_error() {
        let mut rng = crate::rng::Rng::new(21);
        let (mut a, mut b) = (Lowpass::new(15.0, 0.0), Lowpass::new(15.0, 0.0));
        let motion: Vec<f64> = (0..16000).map(|_| b.step(1e-3, a.step(1e-3, rng.normal()))).collect();
        let sigma = 0.05 * std(&motion);
        let noisy: Vec<f64> = motion.iter().map(|m| m + sigma * rng.normal()).collect();
        let gains = WienerGains::new(&noisy, |_| sigma * sigma, WHITE_NOISE_BINS);
        let error: Vec<f64> = gains.apply(&noisy).iter().zip(&motion).map(|(a, b)| a - b).collect();
        let noise: Vec<f64> = (0..16000).map(|_| sigma * rng.normal()).collect();
        let (path, applied) = (gains.error_of(&noise), gains.apply(&noise));
        eprintln!("error {:.3e}, error path {:.3e}, gains alone {:.3e}", rms(&error), rms(&path), rms(&applied));
        assert!((rms(&path) / rms(&error) - 1.0).abs() < 0.15);
        assert!(rms(&applied) < rms(&path));
    }

    /// A motion of 80 sines up to 20 Hz under white noise of a fiftieth of its spread: the
    /// smoothed signal is within 0.6 of the noise of the motion (the error's power cut at least
    /// 2.8-fold; 0.46 measured with numpy on the same case); the motion alone is moved by less
    /// than 0.5 of the noise (its spectrum's leakage below the noise is cut with the noise).
    #[test]
    fn wiener_smoothing_removes_white_noise_and_keeps_the_motion() {
        let mut s = 7u64;
        let mut gauss = || {
            let mut u = || {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64
            };
            (-2.0 * u().max(1e-300).ln()).sqrt() * (2.0 * PI * u()).cos()
        };
        let sines: Vec<(f64, f64)> = (1..=80).map(|i| (0.25 * i as f64, 2.0 * PI * (gauss().abs() % 1.0))).collect();
        let motion: Vec<f64> = (0..8000)
            .map(|k| sines.iter().map(|(f, phase)| 0.05 * (2.0 * PI * f * k as f64 * 1e-3 + phase).sin()).sum())
            .collect();
        let sigma = 0.01;
        let noisy: Vec<f64> = motion.iter().map(|m| m + sigma * gauss()).collect();
        let smooth = wiener_smooth(&noisy, sigma);
        let error: Vec<f64> = smooth.iter().zip(&motion).map(|(a, b)| a - b).collect();
        eprintln!("smoothed: {:.3} of the noise", rms(&error) / sigma);
        assert!(rms(&error) < 0.75 * sigma, "{}", rms(&error));
        let clean = wiener_smooth(&motion, sigma);
        let error: Vec<f64> = clean.iter().zip(&motion).map(|(a, b)| a - b).collect();
        eprintln!("the motion alone moved by {:.3} of the noise", rms(&error) / sigma);
        assert!(rms(&error) < 0.7 * sigma, "{}", rms(&error));
    }
}
