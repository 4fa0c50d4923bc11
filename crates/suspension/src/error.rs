//! Why a truck's parameters or restored state are refused.

use crate::integration::RK4_STABLE_RADIUS;

/// A truck's parameters or restored state that the integration cannot take.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum SuspensionError {
    /// RK4 with steps of h_max could be unstable: `z` = h_max·|λ|max; `advice` names the
    /// parameters to change.
    #[error("h_max·|λ|max = {z:.3} exceeds RK4's stable {radius}: lower h_max, or {advice}", radius = RK4_STABLE_RADIUS)]
    Unstable { z: f64, advice: &'static str },
    #[error("the demand's past holds a number that is not finite")]
    PastNotFinite,
    #[error("the demand's past has an index beyond its ring")]
    PastIndex,
}

/// A road's parameters that [`crate::road`] cannot take, or a time at which the wheel is off the
/// profile; each names the bad value.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum RoadError {
    #[error("road parameter {name} = {value} is not a finite number")]
    NotFinite { name: &'static str, value: f64 },
    #[error("road parameter {name} = {value} must be positive")]
    NotPositive { name: &'static str, value: f64 },
    #[error("road parameter {name} = {value} must not be negative")]
    Negative { name: &'static str, value: f64 },
    #[error("road parameter n_max = {n_max} cycle/m is above the Nyquist frequency 1/(2 dx) = {nyquist} cycle/m of dx = {dx} m")]
    AboveNyquist { n_max: f64, dx: f64, nyquist: f64 },
    #[error("road parameters n_min = {n_min} > n_max = {n_max} cycle/m: the band is empty")]
    BandReversed { n_min: f64, n_max: f64 },
    #[error("no frequency of the road profile lies in the band n_min = {n_min} .. n_max = {n_max} cycle/m (the frequencies are multiples of {spacing} cycle/m): lengthen the road or widen the band")]
    EmptyBand { n_min: f64, n_max: f64, spacing: f64 },
    #[error("a road of length {length} m at dx = {dx} m needs {samples} samples, more than the {max} allowed: shorten the road or coarsen dx")]
    TooManySamples { length: f64, dx: f64, samples: f64, max: usize },
    #[error("a road profile needs at least 2 samples, got {samples}")]
    TooFewSamples { samples: usize },
    #[error("road profile height z[{index}] = {value} m is not a finite number")]
    ProfileNotFinite { index: usize, value: f64 },
    #[error("road parameter offset = {offset} m is off the road profile (0 .. {end} m)")]
    OffsetOutside { offset: f64, end: f64 },
    #[error("at t = {t} s the wheel is at s = {s} m, off the road profile (0 .. {end} m): lengthen the road to at least offset + speed·t")]
    OffProfile { t: f64, s: f64, end: f64 },
    #[error("road time t = {t} s is not a finite number")]
    TimeNotFinite { t: f64 },
    #[error("road step h = {h} s must be positive and finite")]
    Step { h: f64 },
    #[error("uniform(low = {low}, high = {high}): high − low must be finite and not negative")]
    UniformRange { low: f64, high: f64 },
}
