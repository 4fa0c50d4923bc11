//! Model against measurement: fit per signal on the train and validation parts, and where the
//! force error lives (regimes, frequency bands, events, worst windows, whiteness, lag).
//!
//! Definitions (also printed in the report):
//! - residual r = ŷ − y (model minus measured, as in docs/effects.md): positive where the model is
//!   above the measurement;
//! - fit % = 100·(1 − ‖y − ŷ‖/‖y − ȳ‖), NRMSE = RMSE/std(y), so fit % = 100·(1 − NRMSE);
//!   ȳ and std(y) are taken over the part being scored (train or validation);
//! - the train part is the first `split` of the samples, validation the rest;
//! - regimes, spectra, worst windows and the lag use the whole record; whiteness and the
//!   residual–input cross-correlations use the validation part (the held-out data, as a
//!   residual test should).

use crate::dsp::{
    autocorrelation, chi2_95, cross_correlation, kept, ljung_box, mean, metrics, noise_sigma, peak_lag, rms,
    smooth_rate, std, welch, Metrics,
};
use crate::measurement::Measurement;
use crate::model::{Demand, Drive, Prediction};
use crate::residual_signature::{self, DominantBand, Follows, Quantity};
use crate::units::Column;

/// Velocity below which the damper counts as at standstill for the direction split (m/s).
pub const V_STANDSTILL: f64 = 0.02;
/// Velocity the motion must cross, both ways, to count as a reversal (m/s).
pub const V_REVERSAL: f64 = 0.01;
/// Half-width of the window around a velocity reversal (s).
pub const REVERSAL_WINDOW: f64 = 0.02;
/// Window after a demand step (s).
pub const STEP_WINDOW: f64 = 0.06;
/// A force-demand jump of at least this within one sample is a step (N).
pub const FORCE_STEP: f64 = 1000.0;
/// A spool-demand jump of at least this within one sample is a step (m).
pub const SPOOL_STEP: f64 = 1e-4;
/// Length of the windows ranked as worst (s).
pub const WORST_WINDOW: f64 = 0.1;
/// Number of worst windows reported.
pub const N_WORST: usize = 5;
/// Longest lag searched for the measured–model delay (s).
pub const MAX_LAG: f64 = 0.05;
/// Longest lag of the correlation plots (s).
pub const CORR_LAG: f64 = 0.1;
/// Lags of the Ljung–Box whiteness statistic.
pub const LJUNG_BOX_LAGS: usize = 20;
/// Half-width of the smoothed derivative used for force rate and acceleration (s).
pub const RATE_HALF_WIDTH: f64 = 0.0025;

const VELOCITY_BANDS: [f64; 7] = [0.0, 0.02, 0.05, 0.1, 0.2, 0.4, f64::INFINITY];
const FORCE_BANDS: [f64; 6] = [0.0, 1e3, 3e3, 10e3, 20e3, f64::INFINITY];
const FORCE_RATE_BANDS: [f64; 5] = [0.0, 20e3, 100e3, 300e3, f64::INFINITY];
const FREQUENCY_BANDS: [f64; 7] = [0.0, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0];

/// Delay between measurement and model.
#[derive(Clone, Copy, Debug)]
pub struct Lag {
    /// Whole samples; positive: the measurement comes later than the model.
    pub samples: isize,
    pub seconds: f64,
    /// Parabolic refinement of the peak (s).
    pub refined_seconds: f64,
    /// Correlation at the peak.
    pub peak: f64,
    /// Search range ± (s).
    pub max_seconds: f64,
    /// The same estimate on the sample-to-sample changes of both signals, which weights fast
    /// content (steps) and ignores slow drifts: a delay in the valve path shows here even when
    /// the velocity-driven part of the force dominates the signal itself (s).
    pub changes_seconds: f64,
    /// Whether a lag was found: false where the correlation peaks at the edge of the search (or
    /// nowhere: a constant signal), which is the search's limit, not a delay; the lags in seconds
    /// are then NaN.
    pub found: bool,
}

/// A lag in milliseconds with a sign, or "not found" (NaN, see [`Lag::found`]).
pub fn lag_ms(seconds: f64, decimals: usize) -> String {
    if seconds.is_nan() {
        "not found".into()
    } else {
        format!("{:+.*}", decimals, seconds * 1e3)
    }
}

/// Fit of one measured signal.
#[derive(Clone, Debug)]
pub struct SignalFit {
    pub column: Column,
    pub train: Metrics,
    pub validation: Metrics,
    pub lag: Lag,
}

/// The force error inside one regime.
#[derive(Clone, Debug)]
pub struct Regime {
    pub group: &'static str,
    pub name: String,
    pub samples: usize,
    pub time_share: f64,
    pub rms: f64,
    /// Mean residual (model − measured) (N).
    pub mean: f64,
    /// Share of the record's squared error.
    pub error_share: f64,
    /// error_share / time_share: above 1 the error concentrates here.
    pub concentration: f64,
}

/// Residual power in a frequency band.
#[derive(Clone, Debug)]
pub struct Band {
    pub lo: f64,
    pub hi: f64,
    /// Share of the residual variance.
    pub residual_share: f64,
    /// RMS residual in the band (N).
    pub residual_rms: f64,
    /// sqrt(residual power / measured power) in the band.
    pub band_nrmse: f64,
}

/// A stretch of the record with a large error.
#[derive(Clone, Debug)]
pub struct Window {
    pub start: usize,
    pub end: usize,
    pub t_start: f64,
    pub t_end: f64,
    pub rms: f64,
    pub mean: f64,
    pub mean_abs_velocity: f64,
    pub tags: Vec<String>,
}

/// Whiteness of the validation residual.
#[derive(Clone, Debug)]
pub struct Whiteness {
    pub samples: usize,
    pub max_lag: usize,
    /// 1.96/√N.
    pub band: f64,
    /// Share of the lags 1..=max_lag whose autocorrelation is outside ±band (≈5 % if white).
    pub fraction_outside: f64,
    pub ljung_box_q: f64,
    pub ljung_box_lags: usize,
    pub chi2_95: f64,
    /// Q below the 95 % quantile.
    pub white: bool,
}

/// Cross-correlation of the validation residual with an input.
#[derive(Clone, Debug)]
pub struct InputCorrelation {
    pub input: Column,
    /// Lags −L..=L samples.
    pub values: Vec<f64>,
    pub band: f64,
    pub max_abs: f64,
    pub at_lag_seconds: f64,
}

/// Mean residual against velocity, on rising and falling velocity (hysteresis).
#[derive(Clone, Debug)]
pub struct VelocityBin {
    pub v: f64,
    pub rising: Option<f64>,
    pub falling: Option<f64>,
}

/// Everything compare reports.
#[derive(Clone, Debug)]
pub struct Analysis {
    pub samples: usize,
    /// First validation sample.
    pub split: usize,
    pub split_fraction: f64,
    /// Median sample interval (s).
    pub dt: f64,
    pub fits: Vec<SignalFit>,
    /// Force residual, model − measured (N).
    pub residual: Vec<f64>,
    pub regimes: Vec<Regime>,
    pub bands: Vec<Band>,
    pub psd_freq: Vec<f64>,
    pub psd_residual: Vec<f64>,
    pub psd_measured: Vec<f64>,
    pub autocorrelation: Vec<f64>,
    pub whiteness: Whiteness,
    pub input_correlations: Vec<InputCorrelation>,
    /// Cross-correlation of measured and model force, lags −L..=L.
    pub lag_curve: Vec<f64>,
    pub worst: Vec<Window>,
    pub reversals: Vec<usize>,
    pub demand_steps: Vec<usize>,
    pub velocity_bins: Vec<VelocityBin>,
    /// Mean change of the residual across a velocity reversal, signed by the direction of the
    /// reversal (compression → extension counts +): mean r over 5–25 ms after the zero crossing
    /// minus over 25–5 ms before. A friction-like force F·sign(v) the model lacks gives −2F.
    pub reversal_jump: Option<f64>,
    /// White-noise level of the validation residual from its second differences, as an NRMSE:
    /// the floor the residual would sit at if only white sensor noise were left.
    pub noise_floor_estimate: f64,
    /// What the force residual follows, ranked ([`residual_signature`]).
    pub signature: Vec<Follows>,
    /// The frequency band holding most of the residual's power above the noise.
    pub dominant_band: Option<DominantBand>,
}

impl Analysis {
    pub fn force(&self) -> &SignalFit {
        &self.fits[0]
    }
}

/// Signals compared, in report order, and the model signal each is compared with.
pub fn compared_columns(m: &Measurement, drive: &Drive) -> Vec<Column> {
    let mut cols = vec![Column::FDamper];
    for c in [Column::XDamper, Column::XSpool, Column::ISol, Column::PExt, Column::PComp] {
        if m.has(c) {
            cols.push(c);
        }
    }
    if matches!(drive.demand, Demand::Force(_)) && m.has(Column::XSpoolDemand) {
        cols.push(Column::XSpoolDemand);
    }
    cols
}

fn lag_of(y: &[f64], yhat: &[f64], dt: f64) -> (Lag, Vec<f64>) {
    let max = ((MAX_LAG / dt).round() as usize).clamp(1, (y.len() / 4).max(1));
    let c = cross_correlation(y, yhat, max);
    let (k, refined, peak) = peak_lag(&c);
    let dy: Vec<f64> = y.windows(2).map(|w| w[1] - w[0]).collect();
    let dyhat: Vec<f64> = yhat.windows(2).map(|w| w[1] - w[0]).collect();
    let (k_changes, changes, _) = peak_lag(&cross_correlation(&dy, &dyhat, max));
    // a peak on the search's edge is its limit, not a delay (a model of another damper, a
    // constant channel)
    let inside = |k: isize| k.unsigned_abs() < max;
    let found = inside(k) && peak.is_finite();
    let or_nan = |ok: bool, x: f64| if ok { x } else { f64::NAN };
    (
        Lag {
            samples: k,
            seconds: or_nan(found, k as f64 * dt),
            refined_seconds: or_nan(found, refined * dt),
            peak,
            max_seconds: max as f64 * dt,
            changes_seconds: or_nan(inside(k_changes), changes * dt),
            found,
        },
        c,
    )
}

/// Two-sided 95 % quantile of the standard normal distribution (-): an autocorrelation or
/// cross-correlation of white noise over N samples lies within ±1.96/√N 95 % of the time.
const Z_95: f64 = 1.96;
/// The residual's spectrum: Welch segments of at most this length (s), for a resolution of
/// 0.25 Hz…
const WELCH_SEGMENT: f64 = 4.0;
/// … and at least this many segments in the record (-), so that the estimate averages…
const WELCH_MIN_SEGMENTS: usize = 4;
/// … and at least this many samples per segment, for a spectrum with some bins.
const WELCH_MIN_SAMPLES: usize = 64;
/// Fewest lags of the correlation plots (samples).
const CORR_MIN_LAGS: usize = 2;
/// The correlation plots' lags reach at most the validation part's length over this (-): a
/// correlation over fewer overlapping samples is noise.
const CORR_MAX_LAG_DIVISOR: usize = 4;
/// Speed below which the damper stands still for the first-motion tag (m/s): the rig's noise on
/// a velocity at rest.
const STANDSTILL_SPEED: f64 = 2e-3;
/// Shortest standstill after which the first motion is tagged (s): long enough for the
/// controller's state to settle at rest, which the first motion then depends on.
const STANDSTILL_MIN: f64 = 0.05;
/// How long after a standstill's end a worst window counts as its first motion (s).
const FIRST_MOTION: f64 = 0.2;
/// Fewest samples of a worst window.
const WORST_MIN_SAMPLES: usize = 5;
/// A window is mostly in one direction when it has more than this many times the samples of the
/// other (-).
const DIRECTION_DOMINANCE: usize = 2;
/// The hysteresis bins span the velocity up to this quantile of |v| (-): the extremes, a few
/// samples, would stretch the bins over empty velocity.
const VELOCITY_RANGE_QUANTILE: f64 = 0.995;
/// Smallest velocity range of the hysteresis bins (m/s), for a record at rest.
const MIN_VELOCITY_RANGE: f64 = 1e-3;
/// Number of hysteresis bins over −v_max..v_max.
const VELOCITY_BINS: usize = 40;
/// Fewest samples of a hysteresis bin's branch for its mean to be shown.
const MIN_BIN_SAMPLES: usize = 10;
/// The residual's jump at a reversal compares means from this long (s) after the zero crossing…
const JUMP_GAP: f64 = 0.005;
/// … to this long after it (s), minus the same span before: the gap leaves out the crossing's
/// own transient.
const JUMP_REACH: f64 = 0.025;

/// Compares a prediction with a measurement; `split` is the first validation sample.
pub fn analyse(m: &Measurement, drive: &Drive, p: &Prediction, split: usize) -> Analysis {
    let n = m.len();
    let dt = m.median_interval();
    let (fits, lag_curve) = signal_fits(m, drive, p, split, dt);

    let y = m.get(Column::FDamper).expect("F_damper");
    let v = m.get(Column::VDamper).expect("v_damper");
    let r: Vec<f64> = p.f_damper.iter().zip(y).map(|(model, measured)| model - measured).collect();
    let half = ((RATE_HALF_WIDTH / dt).round() as usize).max(1);
    let force_rate = smooth_rate(&m.time, y, half);
    let accel = smooth_rate(&m.time, v, half);
    let reversals = find_reversals(v);
    let demand_steps = find_steps(drive, dt);
    let regimes = regimes(&r, v, y, &force_rate, &reversals, &demand_steps, dt);

    let fs = 1.0 / dt;
    let spectrum = residual_spectrum(&r, y, fs);
    let rv = &r[split..];
    let (autocorr, whiteness) = whiteness_of(rv, dt);
    let input_correlations = input_correlations(rv, v, drive, split, whiteness.max_lag, whiteness.band, dt);
    let worst = worst_windows(&r, v, &m.time, &reversals, &demand_steps, split, dt);
    let velocity_bins = velocity_bins(v, &accel, &r);
    let reversal_jump = reversal_jump(&reversals, v, &r, dt);
    let noise_floor_estimate = noise_sigma(rv) / std(&y[split..]);
    let (signature, dominant_band) = signature_of(m, drive, p, &r, &force_rate, &spectrum.bands, fs);

    Analysis {
        samples: n,
        split,
        split_fraction: split as f64 / n as f64,
        dt,
        fits,
        residual: r,
        regimes,
        bands: spectrum.bands,
        psd_freq: spectrum.freq,
        psd_residual: spectrum.residual,
        psd_measured: spectrum.measured,
        autocorrelation: autocorr,
        whiteness,
        input_correlations,
        lag_curve,
        worst,
        reversals,
        demand_steps,
        velocity_bins,
        reversal_jump,
        noise_floor_estimate,
        signature,
        dominant_band,
    }
}

/// Each compared signal's scores on the train and validation parts and its lag, with the force's
/// measured–model cross-correlation (the lag curve).
fn signal_fits(m: &Measurement, drive: &Drive, p: &Prediction, split: usize, dt: f64) -> (Vec<SignalFit>, Vec<f64>) {
    let n = m.len();
    let mut fits = Vec::new();
    let mut lag_curve = Vec::new();
    for c in compared_columns(m, drive) {
        let (y, yhat) = (m.get(c).expect("measured"), p.get(c).expect("modelled"));
        let (lag, curve) = lag_of(y, yhat, dt);
        if c == Column::FDamper {
            lag_curve = curve;
        }
        // the force's scores leave out what the record's checks exclude (a clipped channel)
        let score = |range: std::ops::Range<usize>| {
            if c == Column::FDamper && m.excluded[range.clone()].iter().any(|&e| e) {
                let keep: Vec<bool> = m.excluded[range.clone()].iter().map(|e| !e).collect();
                metrics(&kept(&y[range.clone()], &keep), &kept(&yhat[range], &keep))
            } else {
                metrics(&y[range.clone()], &yhat[range])
            }
        };
        fits.push(SignalFit { column: c, train: score(0..split), validation: score(split..n), lag });
    }
    (fits, lag_curve)
}

/// Flags the samples within `before` samples before and `after` samples after each event, in a
/// record of `n` samples.
fn near_events(events: &[usize], before: usize, after: usize, n: usize) -> Vec<bool> {
    let mut near = vec![false; n];
    for &i in events {
        for flag in &mut near[i.saturating_sub(before)..(i + after + 1).min(n)] {
            *flag = true;
        }
    }
    near
}

/// The force error in each regime: direction, velocity, force and force-rate bands, and the
/// events (velocity reversals, demand steps).
fn regimes(
    r: &[f64],
    v: &[f64],
    y: &[f64],
    force_rate: &[f64],
    reversals: &[usize],
    demand_steps: &[usize],
    dt: f64,
) -> Vec<Regime> {
    let n = r.len();
    let rev_half = (REVERSAL_WINDOW / dt).round() as usize;
    let step_len = (STEP_WINDOW / dt).round() as usize;
    let near_reversal = near_events(reversals, rev_half, rev_half, n);
    let after_step = near_events(demand_steps, 0, step_len, n);
    let sse_total: f64 = r.iter().map(|x| x * x).sum();
    let mut regimes = Vec::new();
    let mut add = |group: &'static str, name: String, select: &dyn Fn(usize) -> bool| {
        regimes.push(regime(r, sse_total, group, name, select));
    };
    add("direction", format!("extension (v > {V_STANDSTILL} m/s)"), &|i| v[i] > V_STANDSTILL);
    add("direction", format!("compression (v < −{V_STANDSTILL} m/s)"), &|i| v[i] < -V_STANDSTILL);
    add("direction", format!("standstill (|v| ≤ {V_STANDSTILL} m/s)"), &|i| v[i].abs() <= V_STANDSTILL);
    for w in VELOCITY_BANDS.windows(2) {
        add("velocity", band_name("|v|", w[0], w[1], 1.0, "m/s"), &|i| v[i].abs() >= w[0] && v[i].abs() < w[1]);
    }
    for w in FORCE_BANDS.windows(2) {
        add("force", band_name("|F|", w[0], w[1], 1e-3, "kN"), &|i| y[i].abs() >= w[0] && y[i].abs() < w[1]);
    }
    for w in FORCE_RATE_BANDS.windows(2) {
        add("force rate", band_name("|dF/dt|", w[0], w[1], 1e-3, "kN/s"), &|i| {
            force_rate[i].abs() >= w[0] && force_rate[i].abs() < w[1]
        });
    }
    let ms = |s: f64| s * 1e3;
    add("events", format!("velocity reversal (±{:.0} ms)", ms(REVERSAL_WINDOW)), &|i| near_reversal[i]);
    add("events", format!("after a demand step (0–{:.0} ms)", ms(STEP_WINDOW)), &|i| after_step[i]);
    add("events", "neither".to_string(), &|i| !near_reversal[i] && !after_step[i]);
    regimes
}

/// The force error of the samples `select` picks, against the record's squared error
/// `sse_total` (N²).
fn regime(r: &[f64], sse_total: f64, group: &'static str, name: String, select: &dyn Fn(usize) -> bool) -> Regime {
    let n = r.len();
    let idx: Vec<usize> = (0..n).filter(|&i| select(i)).collect();
    let res: Vec<f64> = idx.iter().map(|&i| r[i]).collect();
    let sse: f64 = res.iter().map(|x| x * x).sum();
    let time_share = idx.len() as f64 / n as f64;
    let error_share = if sse_total > 0.0 { sse / sse_total } else { f64::NAN };
    Regime {
        group,
        name,
        samples: idx.len(),
        time_share,
        rms: rms(&res),
        mean: mean(&res),
        error_share,
        concentration: if idx.is_empty() { f64::NAN } else { error_share / time_share },
    }
}

/// The residual's and the measured force's power spectral densities, and the residual per band.
struct Spectrum {
    /// Frequencies (Hz).
    freq: Vec<f64>,
    /// Residual PSD (N²/Hz).
    residual: Vec<f64>,
    /// Measured force PSD (N²/Hz).
    measured: Vec<f64>,
    bands: Vec<Band>,
}

/// The spectra of the residual `r` and the measured force `y` (whole record, sample rate `fs`
/// in Hz), and the residual's power in each of [`FREQUENCY_BANDS`] below the Nyquist frequency.
fn residual_spectrum(r: &[f64], y: &[f64], fs: f64) -> Spectrum {
    let n = r.len();
    let segment = (n / WELCH_MIN_SEGMENTS).min((WELCH_SEGMENT * fs) as usize).max(WELCH_MIN_SAMPLES);
    let (psd_freq, psd_residual) = welch(r, fs, segment);
    let (_, psd_measured) = welch(y, fs, segment);
    let df = psd_freq.get(1).copied().unwrap_or(1.0);
    let total: f64 = psd_residual.iter().sum::<f64>() * df;
    let mut edges: Vec<f64> = FREQUENCY_BANDS.iter().copied().filter(|&f| f < fs / 2.0).collect();
    edges.push(fs / 2.0 + df);
    let bands: Vec<Band> = edges
        .windows(2)
        .map(|w| {
            let sel = |p: &[f64]| {
                psd_freq.iter().zip(p).filter(|(f, _)| **f >= w[0] && **f < w[1]).map(|(_, p)| p).sum::<f64>() * df
            };
            let (pr, pm) = (sel(&psd_residual), sel(&psd_measured));
            Band {
                lo: w[0],
                hi: w[1].min(fs / 2.0),
                residual_share: pr / total,
                residual_rms: pr.sqrt(),
                band_nrmse: (pr / pm).sqrt(),
            }
        })
        .collect();
    Spectrum { freq: psd_freq, residual: psd_residual, measured: psd_measured, bands }
}

/// The validation residual `rv`'s autocorrelation and its whiteness (the share of lags outside
/// the white-noise band, Ljung–Box).
fn whiteness_of(rv: &[f64], dt: f64) -> (Vec<f64>, Whiteness) {
    let nv = rv.len();
    let corr_lag = ((CORR_LAG / dt).round() as usize).clamp(CORR_MIN_LAGS, nv / CORR_MAX_LAG_DIVISOR);
    let autocorr = autocorrelation(rv, corr_lag);
    let band = Z_95 / (nv as f64).sqrt();
    let outside = autocorr[1..].iter().filter(|c| c.abs() > band).count();
    let lb_lags = LJUNG_BOX_LAGS.min(corr_lag);
    let q = ljung_box(&autocorr, nv, lb_lags);
    let whiteness = Whiteness {
        samples: nv,
        max_lag: corr_lag,
        band,
        fraction_outside: outside as f64 / (autocorr.len() - 1) as f64,
        ljung_box_q: q,
        ljung_box_lags: lb_lags,
        chi2_95: chi2_95(lb_lags),
        white: q < chi2_95(lb_lags),
    };
    (autocorr, whiteness)
}

/// The validation residual `rv`'s cross-correlation with the velocity and the demand, over
/// ±`corr_lag` samples, with the white-noise `band`.
fn input_correlations(
    rv: &[f64],
    v: &[f64],
    drive: &Drive,
    split: usize,
    corr_lag: usize,
    band: f64,
    dt: f64,
) -> Vec<InputCorrelation> {
    let mut inputs: Vec<(Column, &[f64])> = vec![(Column::VDamper, &v[split..])];
    match &drive.demand {
        Demand::Force(f) => inputs.push((Column::FDemand, &f[split..])),
        Demand::SpoolPosition(x) => inputs.push((Column::XSpoolDemand, &x[split..])),
        Demand::Held => {}
    }
    inputs
        .into_iter()
        .map(|(c, u)| {
            let values = cross_correlation(rv, u, corr_lag);
            let (i, max_abs) =
                values.iter().map(|x| x.abs()).enumerate().max_by(|a, b| a.1.total_cmp(&b.1)).expect("nonempty");
            InputCorrelation { input: c, at_lag_seconds: (i as f64 - corr_lag as f64) * dt, values, band, max_abs }
        })
        .collect()
}

/// Ends of standstills (|v| below [`STANDSTILL_SPEED`] for at least [`STANDSTILL_MIN`]): the
/// first motion after one depends on the controller's state at rest.
fn standstill_ends(v: &[f64], dt: f64) -> Vec<usize> {
    let still = (STANDSTILL_MIN / dt).round() as usize;
    let mut starts = Vec::new();
    let mut run = 0;
    for (i, vi) in v.iter().enumerate() {
        if vi.abs() < STANDSTILL_SPEED {
            run += 1;
        } else {
            if run >= still {
                starts.push(i);
            }
            run = 0;
        }
    }
    starts
}

/// The [`N_WORST`] windows of [`WORST_WINDOW`] with the largest RMS residual, not overlapping,
/// each tagged with what happens in it.
fn worst_windows(
    r: &[f64],
    v: &[f64],
    t: &[f64],
    reversals: &[usize],
    demand_steps: &[usize],
    split: usize,
    dt: f64,
) -> Vec<Window> {
    let n = r.len();
    let events = Events {
        reversals,
        demand_steps,
        step_len: (STEP_WINDOW / dt).round() as usize,
        standstill_ends: standstill_ends(v, dt),
        first_motion: (FIRST_MOTION / dt).round() as usize,
    };
    let wlen = ((WORST_WINDOW / dt).round() as usize).clamp(WORST_MIN_SAMPLES, n);
    let hop = (wlen / 2).max(1);
    let mut candidates: Vec<(f64, usize)> = (0..=n - wlen).step_by(hop).map(|s| (rms(&r[s..s + wlen]), s)).collect();
    candidates.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut worst: Vec<Window> = Vec::new();
    for (_, s) in candidates {
        if worst.len() == N_WORST {
            break;
        }
        let e = s + wlen;
        if worst.iter().any(|w| s < w.end && w.start < e) {
            continue;
        }
        let seg = &r[s..e];
        worst.push(Window {
            start: s,
            end: e,
            t_start: t[s],
            t_end: t[e - 1],
            rms: rms(seg),
            mean: mean(seg),
            mean_abs_velocity: mean(&v[s..e].iter().map(|x| x.abs()).collect::<Vec<_>>()),
            tags: window_tags(s, e, v, &events, split),
        });
    }
    worst
}

/// The events a worst window is tagged with (sample indices; lengths in samples).
struct Events<'a> {
    reversals: &'a [usize],
    demand_steps: &'a [usize],
    /// How long after a demand step it counts.
    step_len: usize,
    standstill_ends: Vec<usize>,
    /// How long after a standstill's end the first motion counts.
    first_motion: usize,
}

/// What happens in the window `s..e`: reversals, demand steps, a first motion after a
/// standstill, the direction of motion, and the part of the record.
fn window_tags(s: usize, e: usize, v: &[f64], events: &Events, split: usize) -> Vec<String> {
    let mut tags = Vec::new();
    let nrev = events.reversals.iter().filter(|&&i| i >= s && i < e).count();
    if nrev > 0 {
        tags.push(format!("{nrev} velocity reversal{}", if nrev > 1 { "s" } else { "" }));
    }
    if events.demand_steps.iter().any(|&i| i + events.step_len >= s && i < e) {
        tags.push("demand step".to_string());
    }
    if events.standstill_ends.iter().any(|&i| i < e && i + events.first_motion >= s) {
        tags.push("first motion after a standstill".to_string());
    }
    let ext = (s..e).filter(|&i| v[i] > V_STANDSTILL).count();
    let comp = (s..e).filter(|&i| v[i] < -V_STANDSTILL).count();
    tags.push(
        if ext > DIRECTION_DOMINANCE * comp {
            "mostly extension"
        } else if comp > DIRECTION_DOMINANCE * ext {
            "mostly compression"
        } else {
            "both directions"
        }
        .to_string(),
    );
    tags.push(if s >= split { "validation" } else { "train" }.to_string());
    tags
}

/// Hysteresis: the mean residual against velocity, separately on rising and falling velocity
/// (the sign of the acceleration `accel`).
fn velocity_bins(v: &[f64], accel: &[f64], r: &[f64]) -> Vec<VelocityBin> {
    let n = r.len();
    let mut av: Vec<f64> = v.iter().map(|x| x.abs()).collect();
    av.sort_by(|a, b| a.total_cmp(b));
    let vmax = av[((av.len() - 1) as f64 * VELOCITY_RANGE_QUANTILE) as usize].max(MIN_VELOCITY_RANGE);
    let nbins = VELOCITY_BINS;
    let width = 2.0 * vmax / nbins as f64;
    // per bin: the rising branch's sum and count, then the falling branch's
    let mut sums = vec![(0.0, 0usize, 0.0, 0usize); nbins];
    for i in 0..n {
        let b = ((v[i] + vmax) / width).floor();
        if b < 0.0 || b >= nbins as f64 {
            continue;
        }
        let s = &mut sums[b as usize];
        if accel[i] >= 0.0 {
            s.0 += r[i];
            s.1 += 1;
        } else {
            s.2 += r[i];
            s.3 += 1;
        }
    }
    sums.iter()
        .enumerate()
        .map(|(b, s)| VelocityBin {
            v: -vmax + (b as f64 + 0.5) * width,
            rising: (s.1 >= MIN_BIN_SAMPLES).then(|| s.0 / s.1 as f64),
            falling: (s.3 >= MIN_BIN_SAMPLES).then(|| s.2 / s.3 as f64),
        })
        .collect()
}

/// The mean jump of the residual across the velocity reversals (see
/// [`Analysis::reversal_jump`]), or `None` without a reversal far enough from the record's ends.
fn reversal_jump(reversals: &[usize], v: &[f64], r: &[f64], dt: f64) -> Option<f64> {
    let n = r.len();
    let (j0, j1) = ((JUMP_GAP / dt).round() as usize, ((JUMP_REACH / dt).round() as usize).max(1));
    let jumps: Vec<f64> = reversals
        .iter()
        .filter(|&&i| i >= j1 && i + j1 < n && j1 > j0)
        .map(|&i| {
            let sign = if v[i + 1] > v[i] { 1.0 } else { -1.0 };
            sign * (mean(&r[i + 1 + j0..i + 1 + j1]) - mean(&r[i - j1..i - j0]))
        })
        .collect();
    (!jumps.is_empty()).then(|| mean(&jumps))
}

/// What the force residual `r` follows over the whole record ([`residual_signature`]).
fn signature_of(
    m: &Measurement,
    drive: &Drive,
    p: &Prediction,
    r: &[f64],
    force_rate: &[f64],
    bands: &[Band],
    fs: f64,
) -> (Vec<Follows>, Option<DominantBand>) {
    let keep: Vec<bool> = m.excluded.iter().map(|e| !e).collect();
    let sigma = noise_sigma(r);
    let mut series: Vec<(Quantity, &[f64])> = vec![
        (Quantity::Stroke, &p.x_damper),
        (Quantity::Velocity, &drive.v_damper),
        (Quantity::Force, &p.f_damper),
        (Quantity::ForceRate, force_rate),
        (Quantity::Time, &m.time),
    ];
    if let Some(t_oil) = &drive.t_oil {
        series.push((Quantity::Temperature, t_oil));
    }
    // the bands' power: mean squares (N²), as the Welch density summed over each band
    let powers: Vec<(f64, f64, f64)> = bands.iter().map(|b| (b.lo, b.hi, b.residual_rms * b.residual_rms)).collect();
    (residual_signature::rank(&series, r, &keep, sigma), residual_signature::dominant_band(&powers, sigma, fs))
}

fn band_name(what: &str, lo: f64, hi: f64, scale: f64, unit: &str) -> String {
    let f = |x: f64| {
        let s = x * scale;
        if s == s.round() {
            format!("{s:.0}")
        } else {
            format!("{s}")
        }
    };
    if hi.is_infinite() {
        format!("{what} ≥ {} {unit}", f(lo))
    } else {
        format!("{} ≤ {what} < {} {unit}", f(lo), f(hi))
    }
}

/// Indices where the velocity changes sign, crossing ±`V_REVERSAL` both ways (noise around zero
/// does not count): the last sample before the zero crossing.
pub fn find_reversals(v: &[f64]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut state = 0.0f64;
    let mut last_cross = 0;
    for i in 1..v.len() {
        if (v[i] >= 0.0) != (v[i - 1] >= 0.0) {
            last_cross = i - 1;
        }
        let s = if v[i] > V_REVERSAL {
            1.0
        } else if v[i] < -V_REVERSAL {
            -1.0
        } else {
            continue;
        };
        if state != 0.0 && s != state {
            out.push(last_cross);
        }
        state = s;
    }
    out
}

/// Samples where the demand jumps (first sample after the jump); steps closer than the step
/// window to the previous one are merged into it.
pub fn find_steps(drive: &Drive, dt: f64) -> Vec<usize> {
    let (x, threshold) = match &drive.demand {
        Demand::Force(f) => (f, FORCE_STEP),
        Demand::SpoolPosition(x) => (x, SPOOL_STEP),
        Demand::Held => return Vec::new(),
    };
    let gap = (STEP_WINDOW / dt).round() as usize;
    let mut out: Vec<usize> = Vec::new();
    for i in 1..x.len() {
        if (x[i] - x[i - 1]).abs() >= threshold && out.last().is_none_or(|&l| i > l + gap) {
            out.push(i);
        }
    }
    out
}

/// Plain observations on the force residual, for the summaries: how far above the noise floor it
/// is, where it concentrates, offsets by direction, the jump at reversals and the lag. They
/// describe the residual; naming the missing effect is `diagnose`'s job.
pub fn observations(a: &Analysis) -> Vec<String> {
    let mut out = Vec::new();
    let f = a.force();
    let sigma = a.noise_floor_estimate * f.validation.std_measured;
    let ratio = f.validation.nrmse / a.noise_floor_estimate;
    out.push(if ratio < 1.25 && a.whiteness.white {
        format!(
            "the validation residual is at the noise floor ({:.4} against {:.4}) and white: these data show nothing the model lacks",
            f.validation.nrmse, a.noise_floor_estimate
        )
    } else {
        format!(
            "the validation NRMSE {:.4} is {ratio:.1}× the white-noise floor {:.4}, and the residual is {}",
            f.validation.nrmse,
            a.noise_floor_estimate,
            if a.whiteness.white { "white" } else { "not white: the model misses something systematic" }
        )
    });
    let by_name = |group: &str, start: &str| a.regimes.iter().find(|r| r.group == group && r.name.starts_with(start));
    if let (Some(e), Some(c)) = (by_name("direction", "extension"), by_name("direction", "compression")) {
        let notable = |r: &Regime| {
            r.samples > 0 && r.mean.abs() > 0.5 * r.rms && r.mean.abs() > 3.0 * sigma / (r.samples as f64).sqrt()
        };
        if notable(e) && notable(c) {
            out.push(if e.mean.signum() != c.mean.signum() {
                format!(
                    "an offset with the sign of the motion: mean residual {:+.0} N in extension, {:+.0} N in compression{}",
                    e.mean,
                    c.mean,
                    if e.mean < 0.0 {
                        " (the measurement resists motion more than the model: friction-like)"
                    } else {
                        " (the measurement resists motion less than the model)"
                    }
                )
            } else {
                format!(
                    "an offset of the same sign in both directions: {:+.0} N in extension, {:+.0} N in compression (a force offset, e.g. the load-cell tare)",
                    e.mean, c.mean
                )
            });
        } else if notable(e) || notable(c) {
            let r = if notable(e) { e } else { c };
            out.push(format!("an offset in {} only: mean residual {:+.0} N", r.name, r.mean));
        }
    }
    if let Some(j) = a.reversal_jump {
        if j.abs() > 5.0 * sigma.max(1e-9) / 10f64.sqrt() && j.abs() > 0.3 * f.validation.rmse {
            out.push(format!("the residual steps by {j:+.0} N across a velocity reversal (compression → extension)"));
        }
    }
    let mut hot: Vec<&Regime> =
        a.regimes.iter().filter(|r| r.samples > 0 && r.time_share >= 0.02 && r.concentration > 1.5).collect();
    hot.sort_by(|x, y| y.concentration.total_cmp(&x.concentration));
    if !hot.is_empty() {
        let list: Vec<String> = hot
            .iter()
            .take(3)
            .map(|r| {
                format!(
                    "{} ({:.0} % of the squared error in {:.0} % of the time)",
                    r.name,
                    100.0 * r.error_share,
                    100.0 * r.time_share
                )
            })
            .collect();
        out.push(format!("the error gathers in: {}", list.join("; ")));
    }
    let half = 0.5 * a.dt;
    if !f.lag.found {
        out.push(format!(
            "no lag between the measured and the modelled force within ±{:.0} ms: their cross-correlation peaks at the \
             search's edge, so the two do not share their shape (another kind of damper, or far other parameters)",
            f.lag.max_seconds * 1e3
        ));
    } else if f.lag.refined_seconds.abs() >= half || f.lag.changes_seconds.abs() >= half {
        out.push(format!(
            "the measured force comes {} ms after the model's ({} ms on its changes){}",
            lag_ms(f.lag.refined_seconds, 2),
            lag_ms(f.lag.changes_seconds, 2),
            a.fits
                .iter()
                .find(|s| s.column == Column::XSpool && s.lag.changes_seconds.abs() >= half)
                .map_or(String::new(), |s| format!("; the spool position {} ms", lag_ms(s.lag.changes_seconds, 2)))
        ));
    }
    let top = a.bands.iter().max_by(|x, y| x.residual_share.total_cmp(&y.residual_share));
    if let Some(b) = top {
        if b.residual_share > 0.5 && ratio >= 1.25 {
            out.push(format!(
                "{:.0} % of the residual variance lies between {:.0} and {:.0} Hz",
                100.0 * b.residual_share,
                b.lo,
                b.hi
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A delay within the search is found to the sample; a correlation that peaks on the
    /// search's edge (a force the model does not share the shape of) is "not found", not ±50 ms.
    #[test]
    fn a_lag_at_the_edge_of_the_search_is_not_found() {
        let dt = 1e-3;
        let t: Vec<f64> = (0..4000).map(|k| k as f64 * dt).collect();
        let wave = |t: f64| {
            libm::sin(2.0 * std::f64::consts::PI * 3.0 * t) + 0.3 * libm::sin(2.0 * std::f64::consts::PI * 7.0 * t)
        };
        let model: Vec<f64> = t.iter().map(|&t| wave(t)).collect();
        let delayed: Vec<f64> = t.iter().map(|&t| wave(t - 0.004)).collect();
        let (lag, _) = lag_of(&delayed, &model, dt);
        assert!(lag.found && lag.samples == 4, "{lag:?}");
        // the measurement a ramp the model does not have: the correlation grows towards the edge
        let ramp: Vec<f64> = t.iter().map(|&t| t * t).collect();
        let (lag, _) = lag_of(&ramp, &model, dt);
        assert!(!lag.found && lag.refined_seconds.is_nan(), "{lag:?}");
        assert_eq!(lag_ms(lag.refined_seconds, 2), "not found");
        assert_eq!(lag_ms(0.00123, 2), "+1.23");
    }
}
