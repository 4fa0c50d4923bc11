//! What the force residual follows: the quantities a missing effect would hang on (stroke,
//! velocity, force, force rate, oil temperature, time), ranked by the share of the residual's
//! variance above the noise that a smooth function of each explains, and the frequency band that
//! holds most of it. When no catalog effect explains a record, this ranking tells the user which
//! effect to write: a residual that follows the stroke is a position-dependent force (an end stop,
//! a bump rubber, a leaking piston groove), one that follows time is a drift (heating, a zero),
//! one that follows the force rate is a compliance or a lag.
//!
//! The share of a quantity z is its correlation ratio: the record's kept samples are sorted by z
//! into [`BINS`] bins of equal width, and the variance of the bins' mean residuals (less what
//! pure chance gives, (bins − 1)/n of the variance) is divided by the residual's variance above
//! the white noise. It catches any monotone or non-monotone dependence a bin mean can follow,
//! and it does not depend on the residual's sign or scale.

/// Bins of equal count the samples are sorted into, at most.
pub const BINS: usize = 20;
/// Least samples per bin: fewer, and the bin means are mostly noise.
pub const MIN_PER_BIN: usize = 25;

/// A quantity the residual may follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// The damper's stroke x_damper (m), from the model's integrated (or fused) motion.
    Stroke,
    /// The damper's velocity v_damper (m/s).
    Velocity,
    /// The model's force F_damper (N).
    Force,
    /// The measured force's rate (N/s).
    ForceRate,
    /// The oil temperature T_oil (K), when the record has it.
    Temperature,
    /// The time since the record's start (s).
    Time,
}

impl Quantity {
    /// The quantity's key in `summary.json`.
    pub fn key(self) -> &'static str {
        match self {
            Quantity::ForceRate => "force_rate",
            Quantity::Temperature => "temperature",
            other => other.name(),
        }
    }

    /// The quantity's name as the report prints it.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Stroke => "stroke",
            Quantity::Velocity => "velocity",
            Quantity::Force => "force",
            Quantity::ForceRate => "force rate",
            Quantity::Temperature => "oil temperature",
            Quantity::Time => "time",
        }
    }
}

/// The share of the residual's variance above the noise that follows one quantity.
#[derive(Clone, Copy, Debug)]
pub struct Follows {
    pub quantity: Quantity,
    /// 0 (nothing) to 1 (all of it) ([module docs](self)).
    pub share: f64,
}

/// The frequency band holding the most of the residual's power above the white noise.
#[derive(Clone, Copy, Debug)]
pub struct DominantBand {
    pub lo_hz: f64,
    pub hi_hz: f64,
    /// Its share of the residual's power above the white noise (1).
    pub share: f64,
}

/// The bin means of `residual` against `z` over the kept samples: (bin centres of z, mean
/// residual, samples per bin), empty bins left out; empty when too few samples. The bins have
/// equal widths over z's range, so that the tails (where an end stop acts) get bins of their own.
pub fn binned(z: &[f64], residual: &[f64], keep: &[bool]) -> (Vec<f64>, Vec<f64>, Vec<usize>) {
    let idx: Vec<usize> = (0..z.len()).filter(|&i| keep[i] && z[i].is_finite() && residual[i].is_finite()).collect();
    let bins = BINS.min(idx.len() / MIN_PER_BIN);
    let (lo, hi) = idx.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &i| (lo.min(z[i]), hi.max(z[i])));
    if bins < 2 || hi <= lo {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let width = (hi - lo) / bins as f64;
    let mut sums = vec![(0.0, 0.0, 0usize); bins];
    for &i in &idx {
        let b = (((z[i] - lo) / width) as usize).min(bins - 1);
        sums[b].0 += z[i];
        sums[b].1 += residual[i];
        sums[b].2 += 1;
    }
    let filled = sums.iter().filter(|s| s.2 > 0);
    (
        filled.clone().map(|s| s.0 / s.2 as f64).collect(),
        filled.clone().map(|s| s.1 / s.2 as f64).collect(),
        filled.map(|s| s.2).collect(),
    )
}

/// The share of `residual`'s variance above `noise_sigma`² that follows `z` ([module docs](self)).
pub fn share(z: &[f64], residual: &[f64], keep: &[bool], noise_sigma: f64) -> f64 {
    let (_, means, counts) = binned(z, residual, keep);
    let n: usize = counts.iter().sum();
    if n == 0 {
        return 0.0;
    }
    let nf = n as f64;
    let mean = means.iter().zip(&counts).map(|(m, &c)| m * c as f64).sum::<f64>() / nf;
    let var = (0..z.len())
        .filter(|&i| keep[i] && z[i].is_finite())
        .map(|i| (residual[i] - mean) * (residual[i] - mean))
        .sum::<f64>()
        / nf;
    let between = means.iter().zip(&counts).map(|(m, &c)| c as f64 * (m - mean) * (m - mean)).sum::<f64>() / nf;
    let chance = (means.len() as f64 - 1.0) / nf * var;
    let above_noise = var - noise_sigma * noise_sigma;
    if above_noise <= 0.0 {
        return 0.0;
    }
    ((between - chance) / above_noise).clamp(0.0, 1.0)
}

/// The quantities in `series`, ranked stepwise: the one a function of which explains most of
/// the residual first; its bin means are taken out, and the next is the one that explains most of
/// what is left, and so on. Each share is of the residual's variance above the noise, so that two
/// quantities that move together (the stroke and time, in a periodic motion) do not both claim
/// the same error.
pub fn rank(series: &[(Quantity, &[f64])], residual: &[f64], keep: &[bool], noise_sigma: f64) -> Vec<Follows> {
    let n = residual.len() as f64;
    let above_noise = residual.iter().zip(keep).filter(|(_, &k)| k).map(|(r, _)| r * r).sum::<f64>()
        / keep.iter().filter(|&&k| k).count().max(1) as f64
        - noise_sigma * noise_sigma;
    let mut left = residual.to_vec();
    let mut remaining: Vec<(Quantity, &[f64])> = series.to_vec();
    let mut ranked = Vec::new();
    while !remaining.is_empty() {
        let shares: Vec<f64> = remaining.iter().map(|(_, z)| share(z, &left, keep, noise_sigma)).collect();
        let (best, _) = shares.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).expect("not empty");
        let (quantity, z) = remaining.remove(best);
        let before: f64 = left.iter().map(|r| r * r).sum::<f64>() / n;
        take_out(z, &mut left, keep);
        let after: f64 = left.iter().map(|r| r * r).sum::<f64>() / n;
        let explained = if above_noise > 0.0 { ((before - after) / above_noise).clamp(0.0, 1.0) } else { 0.0 };
        ranked.push(Follows { quantity, share: explained.min(shares[best].max(0.0)) });
    }
    ranked
}

/// Subtracts from `residual` its bin means against `z` (the function of z that explains it).
fn take_out(z: &[f64], residual: &mut [f64], keep: &[bool]) {
    let (centres, means, _) = binned(z, residual, keep);
    if centres.len() < 2 {
        return;
    }
    let (lo, hi) = (centres[0], centres[centres.len() - 1]);
    for (r, &x) in residual.iter_mut().zip(z) {
        if x.is_finite() {
            // the mean of the nearest bin centre: a step function of z
            let k = centres.partition_point(|c| *c < x.clamp(lo, hi));
            let k = if k > 0 && (k == centres.len() || (x - centres[k - 1]).abs() <= (centres[k] - x).abs()) {
                k - 1
            } else {
                k
            };
            *r -= means[k];
        }
    }
}

/// The band of `bands` ((lo, hi, residual power), Hz and N²) with the most power above the white
/// noise `noise_sigma` of a record sampled at `fs`.
pub fn dominant_band(bands: &[(f64, f64, f64)], noise_sigma: f64, fs: f64) -> Option<DominantBand> {
    let excess: Vec<f64> = bands
        .iter()
        .map(|&(lo, hi, power)| (power - noise_sigma * noise_sigma * (hi - lo) / (fs / 2.0)).max(0.0))
        .collect();
    let total: f64 = excess.iter().sum();
    let (i, best) = excess.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    (total > 0.0).then(|| DominantBand { lo_hz: bands[i].0, hi_hz: bands[i].1, share: best / total })
}

/// One sentence: what the residual follows, for a verdict that leaves an error unexplained.
pub fn sentence(ranked: &[Follows], band: Option<DominantBand>) -> String {
    let listed: Vec<String> = ranked
        .iter()
        .filter(|f| f.share >= 0.05)
        .take(3)
        .map(|f| format!("{} ({:.0} %)", f.quantity.name(), 100.0 * f.share))
        .collect();
    let follows = if listed.is_empty() {
        "no single quantity (stroke, velocity, force, force rate, temperature, time) holds 5 % of the residual above the noise".to_string()
    } else {
        format!("the residual above the noise follows {}", listed.join(", "))
    };
    match band {
        Some(b) => format!("{follows}; {:.0} % of its power is in {:.0}–{:.0} Hz", 100.0 * b.share, b.lo_hz, b.hi_hz),
        None => follows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_residual_that_hangs_on_the_stroke_ranks_stroke_first() {
        let n = 4000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        let x: Vec<f64> = t.iter().map(|t| 0.05 * libm::sin(2.0 * std::f64::consts::PI * 1.3 * t)).collect();
        let v: Vec<f64> = t
            .iter()
            .map(|t| 0.05 * 2.6 * std::f64::consts::PI * libm::cos(2.0 * std::f64::consts::PI * 1.3 * t))
            .collect();
        let mut rng = crate::rng::Rng::new(7);
        // a stop beyond 30 mm, plus white noise
        let r: Vec<f64> =
            x.iter().map(|x| 1e5 * (x.abs() - 0.03).max(0.0) * x.signum() + 20.0 * rng.normal()).collect();
        let keep = vec![true; n];
        let ranked = rank(&[(Quantity::Velocity, &v), (Quantity::Time, &t), (Quantity::Stroke, &x)], &r, &keep, 20.0);
        assert_eq!(ranked[0].quantity, Quantity::Stroke);
        assert!(ranked[0].share > 0.9, "{ranked:?}");
        assert!(ranked[1].share < 0.2, "{ranked:?}");
    }

    #[test]
    fn white_noise_follows_nothing() {
        let n = 4000;
        let z: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let mut rng = crate::rng::Rng::new(3);
        let r: Vec<f64> = (0..n).map(|_| 5.0 * rng.normal()).collect();
        // the noise level slightly under-estimated: the chance term still keeps the share small
        assert!(share(&z, &r, &vec![true; n], 4.9) < 0.1);
    }
}
