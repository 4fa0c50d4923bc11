//! The traps of real records, checked before a model run, each with a clear message: the force's
//! sign convention, a channel flat at its amplifier's rail, a logger's stated sample rate that the
//! time column contradicts, and a load-cell zero that drifts. A reversed sign, a clipped input and
//! a contradicted rate stop the run (the comparison would be meaningless); a clipped force leaves
//! its samples out of every score and fit; a drift is reported.

use crate::dsp::{mean, std};
use crate::error::{Error, Place};
use crate::measurement::Measurement;
use crate::units::Column;

/// The correlation of force and velocity below which the sign convention is reversed: a damper's
/// force opposes its motion (tension + when extending), so the two rise together.
pub const MIN_SIGN_CORRELATION: f64 = -0.2;
/// A plateau at a channel's extreme this long or longer (samples) may be a rail.
pub const MIN_RAIL_RUN: usize = 5;
/// ... and is one when the slope it arrived with, held for half the plateau, would have gone this
/// share of the channel's range beyond it (a smooth peak arrives flat).
pub const RAIL_OVERSHOOT: f64 = 0.05;
/// Samples left out on each side of a clipped stretch (the amplifier's recovery).
pub const RAIL_MARGIN: usize = 3;
/// A stated sample rate that differs from the time column's by more than this share contradicts it.
pub const RATE_TOLERANCE: f64 = 0.01;
/// Rests (|v| below this, m/s, or 2 % of the largest |v|) at least this long (s) measure the
/// force's zero.
pub const REST_VELOCITY: f64 = 2e-3;
pub const MIN_REST: f64 = 0.05;
/// A drift of the force at rest over the record beyond this many noise sigmas is reported.
pub const DRIFT_SIGMAS: f64 = 5.0;

/// What the checks leave out and report.
#[derive(Clone, Debug, Default)]
pub struct Findings {
    pub warnings: Vec<String>,
    /// Per sample: left out of scores and fits.
    pub excluded: Vec<bool>,
}

/// Checks `m`; `trust_time`: the time column wins over a stated sample rate.
pub fn check(m: &Measurement, trust_time: bool) -> Result<Findings, Error> {
    let mut f = Findings { warnings: Vec::new(), excluded: vec![false; m.len()] };
    if !trust_time {
        stated_rate(m)?;
    }
    for c in [Column::VDamper, Column::XDamper] {
        if let Some((start, end)) = m.get(c).and_then(|x| rails(x).into_iter().next()) {
            return Err(Error::InFile {
                at: Place {
                    file: m.path.clone(),
                    line: None,
                    field: Some(format!("lines {}–{}", m.lines[start], m.lines[end - 1])),
                },
                problem: format!(
                    "{} ({}) sits flat at its extreme {} for {} samples: the channel is clipped at its \
                     amplifier's rail, and the model cannot be driven by a motion it does not know; cut the record \
                     there, or re-range the transducer",
                    c.name(),
                    m.describe_column(c),
                    m.get(c).expect("checked")[start],
                    end - start
                ),
            });
        }
    }
    if let Some(y) = m.get(Column::FDamper) {
        for (start, end) in rails(y) {
            let (a, b) = (start.saturating_sub(RAIL_MARGIN), (end + RAIL_MARGIN).min(m.len()));
            f.excluded[a..b].iter_mut().for_each(|e| *e = true);
            f.warnings.push(format!(
                "F_damper ({}) sits flat at {} N, its extreme, at lines {}–{} ({} samples): clipped at the load cell's \
                 rail; those samples (±{RAIL_MARGIN}) are left out of every score and fit",
                m.describe_column(Column::FDamper),
                y[start],
                m.lines[start],
                m.lines[end - 1],
                end - start
            ));
        }
    }
    sign_convention(m, &f.excluded)?;
    if let Some(w) = drifting_zero(m) {
        f.warnings.push(w);
    }
    Ok(f)
}

/// The stretches [start, end) where `x` sits at its global maximum or minimum for
/// [`MIN_RAIL_RUN`] samples or more, having arrived there with a slope that would have carried
/// it [`RAIL_OVERSHOOT`] of the range further (a clipped channel, not a smooth peak).
pub fn rails(x: &[f64]) -> Vec<(usize, usize)> {
    let (lo, hi) = x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let range = hi - lo;
    let mut out = Vec::new();
    if range.is_nan() || range <= 0.0 {
        return out;
    }
    let mut k = 0;
    while k < x.len() {
        if x[k] != hi && x[k] != lo {
            k += 1;
            continue;
        }
        let start = k;
        while k < x.len() && x[k] == x[start] {
            k += 1;
        }
        let run = k - start;
        if run < MIN_RAIL_RUN {
            continue;
        }
        // the slope it arrived (or left) with, over three samples
        let arriving = if start >= 3 { (x[start] - x[start - 3]).abs() / 3.0 } else { 0.0 };
        let leaving = if k + 3 <= x.len() { (x[k + 2] - x[k - 1]).abs() / 3.0 } else { 0.0 };
        if arriving.max(leaving) * run as f64 / 2.0 > RAIL_OVERSHOOT * range {
            out.push((start, k));
        }
    }
    out
}

/// A damper's force opposes its motion: refuses a record whose force falls as the velocity rises.
fn sign_convention(m: &Measurement, excluded: &[bool]) -> Result<(), Error> {
    let (Some(y), Some(v)) = (m.get(Column::FDamper), m.get(Column::VDamper)) else { return Ok(()) };
    let largest = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let moving: Vec<usize> = (0..v.len()).filter(|&k| !excluded[k] && v[k].abs() > 0.05 * largest).collect();
    if moving.len() < 20 {
        return Ok(());
    }
    let (fy, fv): (Vec<f64>, Vec<f64>) = moving.iter().map(|&k| (y[k], v[k])).unzip();
    let (my, mv) = (mean(&fy), mean(&fv));
    let cov = fy.iter().zip(&fv).map(|(a, b)| (a - my) * (b - mv)).sum::<f64>() / fy.len() as f64;
    let corr = cov / (std(&fy) * std(&fv)).max(1e-300);
    if corr < MIN_SIGN_CORRELATION {
        return Err(Error::InFile {
            at: Place { file: m.path.clone(), line: None, field: None },
            problem: format!(
                "the force falls as the velocity rises (correlation {corr:+.2} of {} and {} where the damper moves): \
                 a damper's force opposes its motion, tension positive when extending. One of the two is written with \
                 the other sign convention (compression positive): give --flip F_damper, or --flip v_damper if the \
                 velocity (or --flip x_damper the displacement) is the one that counts compression positive",
                m.describe_column(Column::FDamper),
                m.describe_column(Column::VDamper)
            ),
        });
    }
    Ok(())
}

/// A sample rate a logger states in a comment line (`# Sample rate: 500 Hz`, `# fs = 2 kHz`): the
/// line and the rate (Hz).
pub fn stated_rate_of(comments: &[(usize, String)]) -> Option<(usize, f64)> {
    for (line, text) in comments {
        let lower = text.to_ascii_lowercase();
        let Some(at) = ["sample rate", "sampling rate", "sample frequency", "sampling frequency", "samplerate", "fs"]
            .iter()
            .find_map(|key| lower.find(key).map(|i| i + key.len()))
        else {
            continue;
        };
        let rest = lower[at..].trim_start_matches(|c: char| c == ':' || c == '=' || c.is_whitespace());
        let number: String = rest.chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
        let Ok(value) = number.parse::<f64>() else { continue };
        let unit = rest[number.len()..].trim_start();
        let factor = if unit.starts_with("khz") {
            1e3
        } else if unit.starts_with("hz") || unit.is_empty() {
            1.0
        } else {
            continue;
        };
        return Some((*line, value * factor));
    }
    None
}

fn stated_rate(m: &Measurement) -> Result<(), Error> {
    let Some((line, stated)) = stated_rate_of(&m.comments) else { return Ok(()) };
    let measured = 1.0 / m.median_interval();
    if (stated - measured).abs() > RATE_TOLERANCE * measured {
        return Err(Error::InFile {
            at: Place::line(&m.path, line),
            problem: format!(
                "the logger states a sample rate of {stated} Hz, but the time column's median interval gives \
                 {measured:.4} Hz: one of them is wrong (a logger set to one rate and writing at another, or a time \
                 column in another unit). If the time column is right, give --trust-time-column; if the stated rate \
                 is, fix the time column's unit (e.g. 'time [ms]' or --map)",
            ),
        });
    }
    Ok(())
}

/// The force at rest drifting over the record beyond what the stroke explains: the rests' mean
/// forces fitted by b·t plus one level per stroke (rests within [`SAME_STROKE`] of each other
/// share it: any force that hangs on the stroke, the gas spring or an end stop, is the level's),
/// and a slope on the stroke within each level whose rests spread over more than
/// [`LEVEL_SPREAD`] (in an end stop the force hangs on the stroke by kilonewtons per millimetre,
/// and rests a few hundredths of a millimetre apart differ by hundreds of newtons); where no
/// stroke is rested at twice, a + b·t + c·x (the gas spring linear over the rests' strokes, where
/// they spread over a millimetre). Reported when the drift b·T is above [`DRIFT_SIGMAS`] of the
/// force's noise and b stands out of the rests' scatter about the fit ([`drift_stands_out`]).
fn drifting_zero(m: &Measurement) -> Option<String> {
    let (y, v) = (m.get(Column::FDamper)?, m.get(Column::VDamper)?);
    let t = &m.time;
    let largest = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let threshold = REST_VELOCITY.max(0.02 * largest);
    let stroke = m.get(Column::XDamper).map_or_else(|| crate::dsp::integrate(t, v, 0.0), <[f64]>::to_vec);
    // (time, stroke, mean force) of each rest
    let mut rests: Vec<(f64, f64, f64)> = Vec::new();
    let mut k = 0;
    while k < v.len() {
        let start = k;
        while k < v.len() && v[k].abs() < threshold {
            k += 1;
        }
        if k > start && t[k - 1] - t[start] >= MIN_REST {
            let n = (k - start) as f64;
            rests.push((mean(&t[start..k]), stroke[start..k].iter().sum::<f64>() / n, mean(&y[start..k])));
        }
        k += 1;
    }
    if rests.len() < 4 || rests.last()?.0 - rests[0].0 < 0.5 * (t[t.len() - 1] - t[0]) {
        return None;
    }
    let tm = mean(&rests.iter().map(|r| r.0).collect::<Vec<_>>());
    let levels = stroke_levels(&rests);
    let repeated = (0..levels.len()).any(|i| levels[i + 1..].contains(&levels[i]));
    let a = if repeated {
        // b·t and one level per stroke: column 0 time, then one indicator per level, then a
        // stroke slope for each level whose rests spread
        let n_levels = levels.iter().max().map_or(0, |g| g + 1);
        let sloped = spread_levels(&rests, &levels, n_levels);
        nalgebra::DMatrix::from_fn(rests.len(), 1 + n_levels + sloped.len(), |i, j| match j {
            0 => rests[i].0 - tm,
            j if j <= n_levels => f64::from(u8::from(levels[i] == j - 1)),
            j => {
                let (level, centre) = sloped[j - 1 - n_levels];
                if levels[i] == level {
                    rests[i].1 - centre
                } else {
                    0.0
                }
            }
        })
    } else {
        let xm = mean(&rests.iter().map(|r| r.1).collect::<Vec<_>>());
        let x_spread = rests.iter().map(|r| (r.1 - xm).abs()).fold(0.0, f64::max) > 1e-3;
        nalgebra::DMatrix::from_fn(rests.len(), if x_spread { 3 } else { 2 }, |i, j| match j {
            0 => rests[i].0 - tm,
            1 => 1.0,
            _ => rests[i].1 - xm,
        })
    };
    let f = nalgebra::DVector::from_iterator(rests.len(), rests.iter().map(|r| r.2));
    let solution = a.clone().svd(true, true).solve(&f, 1e-12).ok()?;
    let drift = solution[0] * (t[t.len() - 1] - t[0]);
    // a rest's mean over 50 samples or more has a noise of σ/7 at most: 5σ is far beyond it
    let sigma = crate::dsp::noise_sigma(y);
    if drift.abs() > DRIFT_SIGMAS * sigma && drift_stands_out(&a, &f, &solution) {
        let why = if m.has(Column::TOil) {
            "the oil heating (see T_oil), or the load cell's zero"
        } else {
            "the load cell's zero (temperature, amplifier)"
        };
        return Some(format!(
            "the force at rest drifts by {drift:+.0} N over the record ({:+.2} N/s, {} rests), beyond what the \
             stroke explains (the gas force, an end stop): {why}. A drifting zero is outside the model; tare the \
             load cell per segment, or expect the diagnosis to find a slow residual",
            solution[0],
            rests.len()
        ));
    }
    None
}

/// Rests within this distance of each other's stroke (m) are at the same stroke.
const SAME_STROKE: f64 = 1e-3;
/// A level whose rests' mean strokes spread over more than this (m) gets a slope on the stroke:
/// two displacement quanta of a dyno's LVDT.
pub const LEVEL_SPREAD: f64 = 1e-5;
/// A fitted drift stands out of the rests' scatter beyond this many of its standard errors.
pub const DRIFT_T: f64 = 3.0;

/// The levels (of `n_levels`) with three rests or more whose mean strokes spread over more than
/// [`LEVEL_SPREAD`], each with its rests' mean stroke (m).
fn spread_levels(rests: &[(f64, f64, f64)], levels: &[usize], n_levels: usize) -> Vec<(usize, f64)> {
    (0..n_levels)
        .filter_map(|level| {
            let x: Vec<f64> = rests.iter().zip(levels).filter(|(_, l)| **l == level).map(|(r, _)| r.1).collect();
            let spread =
                x.iter().fold(f64::NEG_INFINITY, |a, v| a.max(*v)) - x.iter().fold(f64::INFINITY, |a, v| a.min(*v));
            (x.len() >= 3 && spread > LEVEL_SPREAD).then(|| (level, mean(&x)))
        })
        .collect()
}

/// Whether the drift b (the first column's coefficient of the least-squares `solution` of
/// a·θ = f) stands out of the rests' scatter about the fit: |b| > [`DRIFT_T`]·SE(b), SE(b)² =
/// s²·[(aᵀa)⁺]₀₀, s² the residual variance over n − p degrees of freedom. With none left the
/// noise threshold alone judges. A drift along the stroke's own change (a rig's end position
/// creeping in an end stop) cannot be told from it and is not reported.
fn drift_stands_out(a: &nalgebra::DMatrix<f64>, f: &nalgebra::DVector<f64>, solution: &nalgebra::DVector<f64>) -> bool {
    let dof = a.nrows().saturating_sub(a.ncols());
    if dof == 0 {
        return true;
    }
    let Ok(inverse) = (a.transpose() * a).pseudo_inverse(1e-12) else { return true };
    let s2 = (f - a * solution).norm_squared() / dof as f64;
    solution[0].abs() > DRIFT_T * (s2 * inverse[(0, 0)]).max(0.0).sqrt()
}

/// Each rest's stroke level: rests sorted by stroke, a new level where the gap to the previous
/// one exceeds [`SAME_STROKE`].
fn stroke_levels(rests: &[(f64, f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..rests.len()).collect();
    order.sort_by(|&a, &b| rests[a].1.total_cmp(&rests[b].1));
    let mut levels = vec![0; rests.len()];
    let mut level = 0;
    for w in 1..order.len() {
        if rests[order[w]].1 - rests[order[w - 1]].1 > SAME_STROKE {
            level += 1;
        }
        levels[order[w]] = level;
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clipped_plateau_is_a_rail_a_smooth_peak_is_not() {
        // a sine quantised to 1 N: its peaks repeat for a dozen samples, arriving flat
        let smooth: Vec<f64> =
            (0..4000).map(|k| (3000.0 * libm::sin(2.0 * std::f64::consts::PI * k as f64 * 5e-4)).round()).collect();
        assert!(rails(&smooth).is_empty());
        // the same clipped at 2500 N: it arrives steeply
        let clipped: Vec<f64> = smooth.iter().map(|x| x.min(2500.0)).collect();
        let found = rails(&clipped);
        assert!(!found.is_empty() && found.iter().all(|&(a, b)| clipped[a] == 2500.0 && b - a > 100), "{found:?}");
    }

    #[test]
    fn a_logger_s_stated_rate_is_read() {
        let c = |t: &str| vec![(3, t.to_string())];
        assert_eq!(stated_rate_of(&c("Sample rate: 500 Hz")), Some((3, 500.0)));
        assert_eq!(stated_rate_of(&c("SamplingFrequency n/a; fs = 2 kHz")), Some((3, 2000.0)));
        assert_eq!(stated_rate_of(&c("Sampling rate=1000")), Some((3, 1000.0)));
        assert_eq!(stated_rate_of(&c("Test: rig 2, force control")), None);
    }
}
