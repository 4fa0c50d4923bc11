//! The grid of damper_tools.tracking_quality's fit, compiled: the sum of squared errors of a
//! delayed, lagged and clipped force demand against the force, for every bandwidth and delay of the
//! grid at once. It is the sweep's costliest metric (34 bandwidths × 41 delays × two directions over
//! 15 000 samples); numpy's matrix products take longer than the coupled run itself.
//!
//! The sums are accumulated directly, Σ (m − F)² (no expansion into Σ m² − 2 Σ m F + Σ F², which loses
//! about 1e-13 of the force's square to cancellation), in the samples' order, so the result is the
//! same bit for bit on any machine and vector width: every operation is an exact IEEE one, and no
//! multiply-add is fused (Rust does not contract floating-point expressions).

use crate::RunError;

/// Which half of the dissipative model a direction's samples see.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// v > 0: the model is max(lag, 0).
    Extension,
    /// v < 0: the model is min(lag, 0).
    Compression,
}

impl Direction {
    fn clip(self, force: f64) -> f64 {
        match self {
            Direction::Extension => force.max(0.0),
            Direction::Compression => force.min(0.0),
        }
    }
}

/// The demand through first-order lags of the given `poles` (exp(−2π·bandwidth·step), 0 for no lag),
/// each row of `out` one pole: y_k = (1 − p)·x_k + p·y_{k−1}, started at rest on x_0 — the arithmetic
/// of `scipy.signal.lfilter([1 − p], [1, −p], x, zi=[p·x_0])` (y = z + b₀x, then z = p·y), bit for bit.
pub fn first_order_lags(demand: &[f64], poles: &[f64], out: &mut [f64]) -> Result<(), RunError> {
    if demand.is_empty() || out.len() != demand.len() * poles.len() {
        return Err(RunError::TrackingFit(format!(
            "an output of {} values for {} poles × {} samples",
            out.len(),
            poles.len(),
            demand.len()
        )));
    }
    for (&pole, row) in poles.iter().zip(out.chunks_exact_mut(demand.len())) {
        let gain = 1.0 - pole;
        let mut z = pole * demand[0];
        for (y, &x) in row.iter_mut().zip(demand) {
            *y = z + gain * x;
            z = pole * *y;
        }
    }
    Ok(())
}

/// For each bandwidth b (row b of `lags`: the demand through that bandwidth's lag, N, one value per
/// sample) and each delay n = 0 .. n_delays − 1 (samples), the sum over `samples` (indices into
/// `force`) of `(clip(lag_b[i − n]) − force[i])²`, the lag's first value held before the start; written
/// to `out[b · n_delays + n]`.
pub fn squared_errors(
    lags: &[f64],
    force: &[f64],
    samples: &[usize],
    n_delays: usize,
    direction: Direction,
    out: &mut [f64],
) -> Result<(), RunError> {
    let size = force.len();
    let fail = |what: String| Err(RunError::TrackingFit(what));
    if size == 0 || n_delays == 0 || !lags.len().is_multiple_of(size) {
        return fail(format!("{} lag values for {size} samples and {n_delays} delays", lags.len()));
    }
    if out.len() != lags.len() / size * n_delays {
        return fail(format!(
            "an output of {} values for {} bandwidths × {n_delays} delays",
            out.len(),
            lags.len() / size
        ));
    }
    if let Some(&i) = samples.iter().find(|&&i| i >= size) {
        return fail(format!("sample index {i} beyond the {size} samples"));
    }
    // held[j] = clip(lag[j − (n_delays − 1)]), the first value before the start: delay n at sample i
    // reads held[i + k] with k = n_delays − 1 − n, so the delays of one sample are one contiguous
    // window, summed into `reversed` element by element (a loop the compiler vectorises).
    let mut held = vec![0.0; size + n_delays - 1];
    let mut reversed = vec![0.0; n_delays];
    for (lag, row) in lags.chunks_exact(size).zip(out.chunks_exact_mut(n_delays)) {
        held[..n_delays - 1].fill(direction.clip(lag[0]));
        for (h, &x) in held[n_delays - 1..].iter_mut().zip(lag) {
            *h = direction.clip(x);
        }
        reversed.fill(0.0);
        for &i in samples {
            let f = force[i];
            for (sum, &m) in reversed.iter_mut().zip(&held[i..i + n_delays]) {
                let e = m - f;
                *sum += e * e;
            }
        }
        for (o, &s) in row.iter_mut().zip(reversed.iter().rev()) {
            *o = s;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sums by their definition, one (bandwidth, delay) at a time.
    fn by_definition(lags: &[f64], force: &[f64], samples: &[usize], n_delays: usize, d: Direction) -> Vec<f64> {
        let size = force.len();
        let mut out = Vec::new();
        for lag in lags.chunks_exact(size) {
            for n in 0..n_delays {
                let errors = samples.iter().map(|&i| d.clip(lag[i.saturating_sub(n)]) - force[i]);
                out.push(errors.map(|e| e * e).sum());
            }
        }
        out
    }

    #[test]
    fn equals_the_definition_for_both_directions() {
        let size: usize = 200;
        // forces and lags of both signs, irregular
        let force: Vec<f64> = (0..size).map(|i| ((i * 37) % 101) as f64 * 20.0 - 1e3).collect();
        let lags: Vec<f64> = (0..3 * size).map(|j| ((j * 53) % 97) as f64 * 25.0 - 1.2e3).collect();
        let samples: Vec<usize> = (0..size).filter(|i| i % 3 != 1).collect();
        for d in [Direction::Extension, Direction::Compression] {
            let mut out = vec![0.0; 3 * 7];
            squared_errors(&lags, &force, &samples, 7, d, &mut out).unwrap();
            // the same sums in the same order: equal bit for bit
            assert_eq!(out, by_definition(&lags, &force, &samples, 7, d));
        }
    }

    #[test]
    fn an_exact_match_scores_zero_at_its_delay_only() {
        let lag: Vec<f64> = (0..50).map(|i| 10.0 + i as f64).collect();
        let force: Vec<f64> = (0..50usize).map(|i| lag[i.saturating_sub(2)]).collect();
        let mut out = vec![0.0; 4];
        squared_errors(&lag, &force, &(0..50).collect::<Vec<_>>(), 4, Direction::Extension, &mut out).unwrap();
        assert_eq!(out[2], 0.0);
        assert!(out[0] > 0.0 && out[1] > 0.0 && out[3] > 0.0);
    }

    #[test]
    fn no_lag_is_the_demand_and_a_lag_settles_on_a_step() {
        let demand = [0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0];
        let mut out = [0.0; 16];
        first_order_lags(&demand, &[0.0, 0.5], &mut out).unwrap();
        assert_eq!(out[..8], demand);
        // 1 − 0.5^k after the step: exact in binary
        assert_eq!(out[8..], [0.0, 0.5, 0.75, 0.875, 0.9375, 0.96875, 0.984375, 0.9921875]);
    }

    #[test]
    fn bad_shapes_and_indices_are_named() {
        let mut out = vec![0.0; 2];
        let err = squared_errors(&[0.0; 5], &[0.0; 5], &[5], 2, Direction::Extension, &mut out).unwrap_err();
        assert!(err.to_string().contains("sample index 5"), "{err}");
        let err = squared_errors(&[0.0; 7], &[0.0; 5], &[0], 2, Direction::Extension, &mut out).unwrap_err();
        assert!(err.to_string().contains("7 lag values"), "{err}");
    }
}
