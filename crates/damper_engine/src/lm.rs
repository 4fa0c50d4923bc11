//! Bounded Levenberg–Marquardt for nonlinear least squares, generic over the residual function,
//! with the parameters' covariance and correlation at the optimum.
//!
//! ```text
//! minimise   S(θ) = Σ rᵢ(θ)²            θ in the box [lo, hi]
//! step       (JᵀJ + λ·diag(JᵀJ)) δ = −Jᵀr  on the internal scale u (ln θ or θ), then projected
//!            onto the box; λ shrinks (÷3) after a step that lowers S, grows (×4) otherwise
//! converged  a step with λ ≤ 0.01 (nearly Gauss–Newton) lowers S by less than `tolerance`·S, or
//!            no step lowers S (a heavily damped step that gains little is no sign of a minimum)
//! Jacobian   forward differences, one column per parameter, the columns run in parallel on the
//!            caller's thread pool (each a pure function of its inputs: the result does not depend
//!            on the thread count)
//! covariance cov(θ̂) = (J_θᵀJ_θ)⁻¹ Ω (J_θᵀJ_θ)⁻¹ · m/(m − n),  Ω = Σ_b s_b s_bᵀ,
//!            s_b = Σ_{i in batch b} J_θ,i r_i,  J_θ = ∂r/∂θ on the physical scale
//! ```
//! Ω is the long-run covariance of the scores by batch means ([`score_block`] residuals a batch):
//! residuals coloured by the model's remaining error do not make the covariance optimistic, and
//! each parameter is inflated by how much that error lines up with its own signature
//! ([`covariance`]). With white residuals it is σ²(JᵀJ)⁻¹. `JᵀJ` is called singular when its
//! eigenvalues, after scaling it to unit diagonal, span more than [`MAX_CONDITION`]; the parameters
//! that carry the smallest eigenvector are named.

use crate::error::Error;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Largest condition number of the unit-diagonal JᵀJ still inverted.
pub const MAX_CONDITION: f64 = 1e12;

pub use crate::bounds::Bound;

/// A fitted value within this fraction of its box's (searched) range of a bound is at the bound.
pub const AT_BOUND: f64 = 1e-3;

/// Settings of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Most Jacobians computed (each one iteration).
    pub max_iterations: usize,
    /// Finite-difference step: relative (Δln θ) on a log scale, times max(|θ|, 1 % of the box) on
    /// a linear one.
    pub step: f64,
    /// Stop when an accepted step lowers S by less than this share.
    pub tolerance: f64,
}

impl Default for Options {
    fn default() -> Options {
        Options { max_iterations: 40, step: 3e-3, tolerance: 1e-5 }
    }
}

/// The result of [`solve`].
#[derive(Clone, Debug)]
pub struct Solution {
    /// The parameters at the optimum (physical scale).
    pub x: Vec<f64>,
    /// S at the optimum.
    pub cost: f64,
    /// Residuals (m).
    pub residuals: usize,
    /// σ² = S/(m − n), the residual variance.
    pub sigma2: f64,
    /// Residuals per batch of the scores' long-run covariance ([`score_block`]; 1: white).
    pub block: usize,
    /// (JᵀJ)⁻¹·Ω·(JᵀJ)⁻¹ on the physical scale, Ω the long-run covariance of the scores Jᵢrᵢ
    /// by batch means ([`covariance`]); None when JᵀJ is singular.
    pub covariance: Option<DMatrix<f64>>,
    /// The correlation matrix of `covariance` without the inputs' term: how well the records tell
    /// the parameters apart. The inputs' term, from a few draws (two to four), is of rank at most
    /// their number and would make any two parameters it moves look inseparable.
    pub correlation: Option<DMatrix<f64>>,
    /// When JᵀJ is singular: the index of each parameter with a large share (|component| > 0.3)
    /// of the eigenvector of the smallest eigenvalue, largest first.
    pub singular: Vec<usize>,
    /// Condition number of the unit-diagonal JᵀJ.
    pub condition: f64,
    /// Iterations (Jacobians) taken.
    pub iterations: usize,
    /// Calls of the residual function.
    pub model_runs: usize,
    /// False when the iteration limit stopped it.
    pub converged: bool,
}

impl Solution {
    /// Standard uncertainty of parameter `i` (physical unit), if the covariance exists.
    pub fn std_error(&self, i: usize) -> Option<f64> {
        self.covariance.as_ref().map(|c| c[(i, i)].max(0.0).sqrt())
    }

    /// The strongest correlation of parameter `i` with another: (index, coefficient).
    pub fn strongest_correlation(&self, i: usize) -> Option<(usize, f64)> {
        let c = self.correlation.as_ref()?;
        (0..c.ncols()).filter(|&j| j != i).map(|j| (j, c[(i, j)])).max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
    }
}

/// The residual function: parameters (physical scale) → residuals, the same length every call.
pub type Residuals<'a> = dyn Fn(&[f64]) -> Result<Vec<f64>, Error> + Sync + 'a;

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimises Σ r(θ)² over the box of `scales` from `x0` (clamped into the box), with the
/// Jacobian's columns on `pool`. An error of `f` at the start or in a Jacobian column is returned;
/// at a trial step it counts as a rejected step. `inputs`: draws of the residuals' change that the
/// noise of the measured inputs makes (each as long as the residuals; may be empty), whose spread
/// the fitted parameters inherit ([`covariance`]).
pub fn solve(
    f: &Residuals<'_>,
    x0: &[f64],
    scales: &[Bound],
    pool: &rayon::ThreadPool,
    opts: Options,
    inputs: &[Vec<f64>],
) -> Result<Solution, Error> {
    let n = x0.len();
    if scales.len() != n || n == 0 {
        return Err(Error::ScaleCount { parameters: n, scales: scales.len() });
    }
    for s in scales {
        if s.lo.partial_cmp(&s.hi) != Some(std::cmp::Ordering::Less) || (s.log && s.lo <= 0.0) {
            return Err(Error::SearchBox { lo: s.lo, hi: s.hi, log: s.log });
        }
    }
    let runs = std::sync::atomic::AtomicUsize::new(0);
    let eval = |x: &[f64]| {
        runs.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        f(x)
    };
    let physical = |u: &[f64]| -> Vec<f64> { u.iter().zip(scales).map(|(&u, s)| s.to_physical(u)).collect() };
    let clamp = |u: &mut [f64]| {
        for (v, s) in u.iter_mut().zip(scales) {
            let (lo, hi) = s.internal_box();
            *v = v.clamp(lo, hi);
        }
    };
    let mut u: Vec<f64> = x0.iter().zip(scales).map(|(&x, s)| s.to_internal(x.clamp(s.lo, s.hi))).collect();
    clamp(&mut u);
    let mut r = eval(&physical(&u))?;
    let m = r.len();
    if m <= n {
        return Err(Error::TooFewResiduals { residuals: m, parameters: n });
    }
    if inputs.iter().any(|d| d.len() != m) {
        return Err(Error::NoiseDrawLength { residuals: m });
    }
    let mut cost = sum_sq(&r);
    let mut lambda = 1e-3;
    let (mut iterations, mut converged) = (0, false);
    while iterations < opts.max_iterations {
        iterations += 1;
        let j = jacobian(&eval, &u, &r, scales, pool, opts.step)?;
        let a = j.transpose() * &j;
        let g = j.transpose() * DVector::from_column_slice(&r);
        let d: Vec<f64> = (0..n).map(|i| a[(i, i)].max(1e-300)).collect();
        let mut accepted = false;
        while lambda < 1e12 {
            let mut lhs = a.clone();
            for (i, di) in d.iter().enumerate() {
                lhs[(i, i)] += lambda * di;
            }
            let step = match lhs.cholesky() {
                Some(ch) => ch.solve(&(-&g)),
                None => {
                    lambda *= 4.0;
                    continue;
                }
            };
            let mut trial: Vec<f64> = u.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            clamp(&mut trial);
            if trial == u {
                // the box cut the whole step: the same point, whose cost is known (a parameter
                // at its bound took some twenty runs of the model to learn this)
                lambda *= 4.0;
                continue;
            }
            let r_trial = eval(&physical(&trial)).ok().filter(|r| r.len() == m && r.iter().all(|v| v.is_finite()));
            match r_trial {
                Some(r_new) if sum_sq(&r_new) < cost => {
                    let new_cost = sum_sq(&r_new);
                    let gain = (cost - new_cost) / cost.max(1e-300);
                    converged = gain < opts.tolerance && lambda <= 1e-2;
                    u = trial;
                    r = r_new;
                    cost = new_cost;
                    lambda = (lambda / 3.0).max(1e-9);
                    accepted = true;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !accepted {
            // no step lowers S: a minimum within the finite differences' resolution
            converged = true;
        }
        if converged {
            break;
        }
    }
    let x = physical(&u);
    let j = jacobian(&eval, &u, &r, scales, pool, opts.step)?;
    // the physical scale: ∂r/∂θ = ∂r/∂u · du/dθ
    let jp = DMatrix::from_fn(m, n, |row, col| j[(row, col)] / scales[col].slope(x[col]));
    let sigma2 = cost / (m - n) as f64;
    let block = score_block(&r, n);
    let (parts, singular, condition) = covariance(&jp, &r, block, m as f64 / (m - n) as f64, inputs);
    let correlation = parts
        .as_ref()
        .map(|p| &p.of_residuals)
        .map(|c| DMatrix::from_fn(n, n, |i, k| c[(i, k)] / (c[(i, i)] * c[(k, k)]).sqrt().max(1e-300)));
    let covariance = parts.map(|p| p.total);
    Ok(Solution {
        x,
        cost,
        residuals: m,
        sigma2,
        block,
        covariance,
        correlation,
        singular,
        condition,
        iterations,
        model_runs: runs.into_inner(),
        converged,
    })
}

/// ∂r/∂u by forward differences (backward at the upper bound), columns in parallel.
fn jacobian(
    eval: &Residuals<'_>,
    u: &[f64],
    r: &[f64],
    scales: &[Bound],
    pool: &rayon::ThreadPool,
    step: f64,
) -> Result<DMatrix<f64>, Error> {
    let n = u.len();
    let columns: Vec<Result<Vec<f64>, Error>> = pool.install(|| {
        (0..n)
            .into_par_iter()
            .map(|k| {
                let s = scales[k];
                let h = if s.log { step } else { step * u[k].abs().max(0.01 * (s.hi - s.lo)) };
                let (_, hi) = s.internal_box();
                let h = if u[k] + h > hi { -h } else { h };
                let mut v = u.to_vec();
                v[k] += h;
                let x: Vec<f64> = v.iter().zip(scales).map(|(&u, s)| s.to_physical(u)).collect();
                let rk = eval(&x)?;
                if rk.len() != r.len() {
                    return Err(Error::ResidualsChangedLength { before: r.len(), after: rk.len() });
                }
                Ok(rk.iter().zip(r).map(|(a, b)| (a - b) / h).collect())
            })
            .collect()
    });
    let columns = columns.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(DMatrix::from_fn(r.len(), n, |i, k| columns[k][i]))
}

/// The residuals' correlation length: the first lag k ≥ 1 at which their autocorrelation ρ_k is
/// no longer positive (at most [`MAX_COLOUR_LAGS`]); 0 for white residuals.
pub fn correlation_length(r: &[f64]) -> usize {
    let n = r.len();
    let mean = r.iter().sum::<f64>() / n.max(1) as f64;
    let var = r.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>();
    if n < 3 || var <= 0.0 {
        return 0;
    }
    (1..MAX_COLOUR_LAGS.min(n - 1))
        .find(|&k| r[k..].iter().zip(r).map(|(a, b)| (a - mean) * (b - mean)).sum::<f64>() <= 0.0)
        .map_or(MAX_COLOUR_LAGS.min(n - 1), |k| k - 1)
}

/// Most lags [`correlation_length`] looks at.
pub const MAX_COLOUR_LAGS: usize = 500;

/// Least batches of the scores' long-run covariance per fitted parameter: fewer, and Ω (of rank at
/// most the number of batches) is too rough to invert along every direction.
pub const MIN_BATCHES_PER_PARAMETER: usize = 4;

/// Residuals per batch of the long-run covariance of `n` parameters' scores: twice the residuals'
/// [`correlation_length`], so that neighbouring batches are nearly independent, but no longer than
/// leaves [`MIN_BATCHES_PER_PARAMETER`]·n batches.
pub fn score_block(r: &[f64], n: usize) -> usize {
    let most = (r.len() / (MIN_BATCHES_PER_PARAMETER * n.max(1))).max(1);
    (2 * correlation_length(r)).clamp(1, most)
}

/// The parameters' covariance ([`covariance`]), whole and without the inputs' term.
pub struct Covariances {
    pub total: DMatrix<f64>,
    pub of_residuals: DMatrix<f64>,
}

/// The covariance of the fitted parameters, (JᵀJ)⁻¹·Ω·(JᵀJ)⁻¹·`dof`, Ω = Σ_b s_b s_bᵀ with s_b the
/// sum of the scores Jᵢrᵢ over batch b of `block` consecutive residuals (the "sandwich" with a
/// batch-means long-run covariance; `dof` = m/(m − n)), plus the spread the noise of the measured
/// inputs carries into the parameters, (JᵀJ)⁻¹·(1/P)Σ_p (Jᵀd_p)(Jᵀd_p)ᵀ·(JᵀJ)⁻¹ over the P draws d_p
/// of `inputs`. The residuals of a fit carry the model's remaining error, smooth in time, and Ω
/// inflates each parameter's uncertainty by how much that error lines up with the parameter's own
/// signature: a scalar inflation by the residuals' colour (1 + 2Σρ_k) overstates parameters the
/// slow error does not touch and understates those along a ridge of two laws that trade against
/// each other, where it does. With white residuals and
/// batches of one it is σ²(JᵀJ)⁻¹. (JᵀJ)⁻¹ via its unit-diagonal scaling; None, with the
/// parameters of the null space, when JᵀJ is singular ([`MAX_CONDITION`]). Returns the whole
/// covariance and its part without the inputs' term.
///
/// The inputs' term is needed besides Ω: an error of the model's input that bends the force the
/// same way wherever the motion does (a smoothed velocity rounds every corner) is absorbed by the
/// fit and leaves no trace in the residuals; on records whose velocity was made from a displacement,
/// clean ones had a mount compliance or compressibility "moved" by 3–4 of Ω's uncertainties.
pub fn covariance(
    jp: &DMatrix<f64>,
    r: &[f64],
    block: usize,
    dof: f64,
    inputs: &[Vec<f64>],
) -> (Option<Covariances>, Vec<usize>, f64) {
    let a = jp.transpose() * jp;
    let n = a.nrows();
    let d: Vec<f64> = (0..n).map(|i| a[(i, i)].max(0.0).sqrt()).collect();
    if let Some(i) = d.iter().position(|&v| v == 0.0) {
        return (None, vec![i], f64::INFINITY);
    }
    let scaled = DMatrix::from_fn(n, n, |i, k| a[(i, k)] / (d[i] * d[k]));
    let eig = scaled.clone().symmetric_eigen();
    let (mut min_i, mut min_v, mut max_v) = (0, f64::INFINITY, 0.0f64);
    for (i, &v) in eig.eigenvalues.iter().enumerate() {
        if v < min_v {
            (min_i, min_v) = (i, v);
        }
        max_v = max_v.max(v);
    }
    let condition = if min_v > 0.0 { max_v / min_v } else { f64::INFINITY };
    if condition > MAX_CONDITION {
        let vector = eig.eigenvectors.column(min_i);
        let mut carriers: Vec<usize> = (0..n).filter(|&i| vector[i].abs() > 0.3).collect();
        carriers.sort_by(|&x, &y| vector[y].abs().total_cmp(&vector[x].abs()));
        return (None, carriers, condition);
    }
    let Some(inv) = scaled.try_inverse() else { return (None, (0..n).collect(), condition) };
    let a_inv = DMatrix::from_fn(n, n, |i, k| inv[(i, k)] / (d[i] * d[k]));
    let mut omega = DMatrix::<f64>::zeros(n, n);
    for start in (0..r.len()).step_by(block.max(1)) {
        let end = (start + block).min(r.len());
        let s = DVector::from_fn(n, |k, _| (start..end).map(|i| jp[(i, k)] * r[i]).sum::<f64>());
        omega += &s * s.transpose();
    }
    omega *= dof;
    let mut of_inputs = DMatrix::<f64>::zeros(n, n);
    for d in inputs {
        let s = DVector::from_fn(n, |k, _| d.iter().enumerate().map(|(i, e)| jp[(i, k)] * e).sum::<f64>());
        of_inputs += &s * s.transpose() / inputs.len() as f64;
    }
    let of_residuals = &a_inv * omega * &a_inv;
    let total = &of_residuals + &a_inv * of_inputs * &a_inv;
    (Some(Covariances { total, of_residuals }), Vec::new(), condition)
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn the_correlation_length_of_white_and_of_ar1_residuals() {
        let mut rng = crate::rng::Rng::new(5);
        let white: Vec<f64> = (0..50_000).map(|_| rng.normal()).collect();
        assert!(correlation_length(&white) <= 1, "{}", correlation_length(&white));
        // AR(1), φ = 0.95: ρ_k = 0.95^k, sampled with ±1/√N ≈ 0.0045 noise, stays positive to
        // k ≈ ln(0.0045)/ln(0.95) ≈ 105 and beyond
        let mut x = 0.0;
        let ar: Vec<f64> = (0..50_000)
            .map(|_| {
                x = 0.95 * x + rng.normal();
                x
            })
            .collect();
        assert!(correlation_length(&ar) > 60, "{}", correlation_length(&ar));
    }

    #[test]
    fn the_mean_of_ar1_residuals_has_the_long_run_variance() {
        // y = μ + AR(1) noise of φ = 0.8, σ_e = 1: the mean's variance is σ_e²/(1 − φ)²/N, 25/N;
        // σ²(JᵀJ)⁻¹ would say Var(y)/N = (1/(1 − φ²))/N = 2.8/N
        let mut rng = crate::rng::Rng::new(11);
        let n = 40_000;
        let mut e = 0.0;
        let y: Vec<f64> = (0..n)
            .map(|_| {
                e = 0.8 * e + rng.normal();
                2.0 + e
            })
            .collect();
        let f = |x: &[f64]| -> Result<Vec<f64>, Error> { Ok(y.iter().map(|y| x[0] - y).collect()) };
        let s =
            solve(&f, &[0.0], &[Bound { lo: -10.0, hi: 10.0, log: false }], &pool(1), Options::default(), &[]).unwrap();
        let variance = s.std_error(0).unwrap().powi(2) * n as f64;
        assert!((variance / 25.0 - 1.0).abs() < 0.3, "{variance} against 25, batches of {}", s.block);
    }

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
    }

    /// y = a·exp(−b·t) + c with a little deterministic "noise".
    fn data() -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.05).collect();
        let y = t
            .iter()
            .enumerate()
            .map(|(i, t)| 3.0 * (-0.7 * t).exp() + 0.5 + 0.01 * ((i * 7919) % 13) as f64 / 13.0 - 0.005)
            .collect();
        (t, y)
    }

    #[test]
    fn fits_an_exponential_with_its_uncertainty_whatever_the_thread_count() {
        let (t, y) = data();
        let f = |x: &[f64]| -> Result<Vec<f64>, Error> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-x[1] * t).exp() + x[2] - y).collect())
        };
        let scales = [
            Bound { lo: 0.1, hi: 10.0, log: true },
            Bound { lo: 0.01, hi: 10.0, log: true },
            Bound { lo: -5.0, hi: 5.0, log: false },
        ];
        let one = solve(&f, &[1.0, 2.0, 0.0], &scales, &pool(1), Options::default(), &[]).unwrap();
        assert!(
            (one.x[0] - 3.0).abs() < 0.01 && (one.x[1] - 0.7).abs() < 0.01 && (one.x[2] - 0.5).abs() < 0.01,
            "{one:?}"
        );
        assert!(one.converged && one.std_error(0).unwrap() < 0.01, "{one:?}");
        let (j, c) = one.strongest_correlation(1).unwrap();
        assert!(j != 1 && c.abs() <= 1.0);
        let two = solve(&f, &[1.0, 2.0, 0.0], &scales, &pool(2), Options::default(), &[]).unwrap();
        assert_eq!(one.x, two.x);
        assert_eq!(one.model_runs, two.model_runs);
    }

    #[test]
    fn stays_in_the_box_and_names_a_parameter_the_data_do_not_see() {
        let (t, y) = data();
        // the minimum of a is 3, outside [0.1, 2]
        let f = |x: &[f64]| -> Result<Vec<f64>, Error> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-0.7 * t).exp() + 0.5 - y).collect())
        };
        let s = solve(&f, &[1.0], &[Bound { lo: 0.1, hi: 2.0, log: true }], &pool(1), Options::default(), &[]).unwrap();
        assert!(
            (s.x[0] - 2.0).abs() < 1e-9 && Bound { lo: 0.1, hi: 2.0, log: true }.near_bound(s.x[0], AT_BOUND),
            "{s:?}"
        );
        // the second parameter does not enter the residuals: singular, and named
        let g = |x: &[f64]| -> Result<Vec<f64>, Error> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-0.7 * t).exp() + 0.5 - y + 0.0 * x[1]).collect())
        };
        let scales = [Bound { lo: 0.1, hi: 10.0, log: true }, Bound { lo: 0.1, hi: 10.0, log: false }];
        let s = solve(&g, &[1.0, 1.0], &scales, &pool(2), Options::default(), &[]).unwrap();
        assert!(s.covariance.is_none() && s.singular == vec![1], "{s:?}");
        assert!((s.x[0] - 3.0).abs() < 0.01);
    }

    /// t = 0…49, y = 1 + 0.5·t ± 0.1 alternating: the times, the residuals p0 + p1·t − y and the
    /// parameters' boxes.
    fn straight_line() -> (Vec<f64>, Box<Residuals<'static>>, [Bound; 2]) {
        let t: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let y: Vec<f64> =
            t.iter().enumerate().map(|(i, t)| 1.0 + 0.5 * t + if i % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let times = t.clone();
        let f = move |x: &[f64]| -> Result<Vec<f64>, Error> {
            Ok(times.iter().zip(&y).map(|(t, y)| x[0] + x[1] * t - y).collect())
        };
        (t, Box::new(f), [Bound { lo: -10.0, hi: 10.0, log: false }; 2])
    }

    #[test]
    fn an_input_error_along_a_parameter_adds_its_spread() {
        // y = 1 + 0.5·t and an input error that draws the slope by ±0.02 (d = ±0.02·t, the kind
        // a fit absorbs without a residual): the slope's variance gains 0.02², the intercept's none
        let (t, f, scales) = straight_line();
        let without = solve(&f, &[0.0, 0.0], &scales, &pool(1), Options::default(), &[]).unwrap();
        let draws: Vec<Vec<f64>> = [0.02, -0.02].iter().map(|d| t.iter().map(|t| d * t).collect()).collect();
        let with = solve(&f, &[0.0, 0.0], &scales, &pool(1), Options::default(), &draws).unwrap();
        let var = |s: &Solution, i: usize| s.std_error(i).unwrap().powi(2);
        assert!((var(&with, 1) - var(&without, 1) - 0.02f64.powi(2)).abs() < 1e-9, "{with:?}");
        assert!((var(&with, 0) - var(&without, 0)).abs() < 1e-9, "{with:?}");
        // the correlation says how well the data tell the two apart: the inputs' term, of rank
        // one here, would have moved it
        let rho = |s: &Solution| s.strongest_correlation(0).unwrap().1;
        assert_eq!(rho(&with), rho(&without));
        let c = with.covariance.as_ref().unwrap();
        let total = c[(0, 1)] / (c[(0, 0)] * c[(1, 1)]).sqrt();
        assert!((total - rho(&without)).abs() > 0.05, "{total} vs {}", rho(&without));
    }

    #[test]
    fn covariance_of_a_straight_line_by_hand() {
        // y = p0 + p1·t, residuals alternating in sign (batches of one): the sandwich
        // (XᵀX)⁻¹(Σ xᵢxᵢᵀrᵢ²)(XᵀX)⁻¹·m/(m − n), within 1 % of σ²(XᵀX)⁻¹ as the residuals are of
        // nearly equal size (linear model, exact differences)
        let (t, f, scales) = straight_line();
        let s = solve(&f, &[0.0, 0.0], &scales, &pool(1), Options::default(), &[]).unwrap();
        assert_eq!(s.block, 1);
        let x = DMatrix::from_fn(50, 2, |i, k| if k == 0 { 1.0 } else { t[i] });
        let r = f(&s.x).unwrap();
        let inv = (x.transpose() * &x).try_inverse().unwrap();
        let meat = DMatrix::from_fn(2, 2, |j, k| (0..50).map(|i| x[(i, j)] * x[(i, k)] * r[i] * r[i]).sum::<f64>());
        let hand = &inv * meat * &inv * (50.0 / 48.0);
        let classical = &inv * s.sigma2;
        let c = s.covariance.as_ref().unwrap();
        for i in 0..2 {
            for k in 0..2 {
                assert!((c[(i, k)] - hand[(i, k)]).abs() < 1e-6 * hand[(i, i)].abs(), "{c} vs {hand}");
            }
            assert!((c[(i, i)] / classical[(i, i)] - 1.0).abs() < 0.01, "{c} vs {classical}");
        }
    }
}
