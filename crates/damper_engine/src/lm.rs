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
//! covariance cov(θ̂) = c·σ²·(J_θᵀ J_θ)⁻¹,  σ² = S(θ̂)/(m − n),  J_θ = ∂r/∂θ on the physical scale
//! ```
//! c ≥ 1 inflates the covariance for the residuals' correlation ([`colour_factor`]), so that
//! residuals coloured by the model's remaining error do not make it optimistic (equal variance is
//! still assumed). `JᵀJ` is called singular when its eigenvalues, after scaling it to unit diagonal,
//! span more than [`MAX_CONDITION`]; the parameters that carry the smallest eigenvector are named.

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
    /// How much the residuals' correlation inflates the covariance (1: white), [`colour_factor`].
    pub colour: f64,
    /// c·σ²·(JᵀJ)⁻¹ on the physical scale, c = `colour`; None when JᵀJ is singular.
    pub covariance: Option<DMatrix<f64>>,
    /// The correlation matrix of `covariance`.
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
pub type Residuals<'a> = dyn Fn(&[f64]) -> Result<Vec<f64>, String> + Sync + 'a;

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Minimises Σ r(θ)² over the box of `scales` from `x0` (clamped into the box), with the
/// Jacobian's columns on `pool`. An error of `f` at the start or in a Jacobian column is returned;
/// at a trial step it counts as a rejected step.
pub fn solve(
    f: &Residuals<'_>,
    x0: &[f64],
    scales: &[Bound],
    pool: &rayon::ThreadPool,
    opts: Options,
) -> Result<Solution, String> {
    let n = x0.len();
    if scales.len() != n || n == 0 {
        return Err(format!("{n} parameters but {} scales", scales.len()));
    }
    for s in scales {
        if s.lo.partial_cmp(&s.hi) != Some(std::cmp::Ordering::Less) || (s.log && s.lo <= 0.0) {
            return Err(format!("bad search box [{}, {}] (log {})", s.lo, s.hi, s.log));
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
        return Err(format!("{m} residuals for {n} parameters"));
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
    let colour = colour_factor(&r);
    let (covariance, singular, condition) = covariance(&(jp.transpose() * &jp), sigma2 * colour);
    let correlation = covariance
        .as_ref()
        .map(|c| DMatrix::from_fn(n, n, |i, k| c[(i, k)] / (c[(i, i)] * c[(k, k)]).sqrt().max(1e-300)));
    Ok(Solution {
        x,
        cost,
        residuals: m,
        sigma2,
        colour,
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
) -> Result<DMatrix<f64>, String> {
    let n = u.len();
    let columns: Vec<Result<Vec<f64>, String>> = pool.install(|| {
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
                    return Err(format!("the residuals changed length ({} → {})", r.len(), rk.len()));
                }
                Ok(rk.iter().zip(r).map(|(a, b)| (a - b) / h).collect())
            })
            .collect()
    });
    let columns = columns.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(DMatrix::from_fn(r.len(), n, |i, k| columns[k][i]))
}

/// The variance inflation of correlated residuals: 1 + 2 Σ ρ_k over the lags k = 1… while the
/// autocorrelation ρ_k stays positive (at most [`MAX_COLOUR_LAGS`]); 1 for white residuals. The
/// residuals of a fit carry the model's remaining error, which is smooth in time: N of them hold
/// the information of N/(1 + 2 Σ ρ_k) independent ones, and a covariance from N is too small by
/// that factor (a mean of an AR(1) series of coefficient φ has it exactly: (1 + φ)/(1 − φ)).
pub fn colour_factor(r: &[f64]) -> f64 {
    let n = r.len();
    let mean = r.iter().sum::<f64>() / n.max(1) as f64;
    let var = r.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>();
    if n < 3 || var <= 0.0 {
        return 1.0;
    }
    let mut sum = 0.0;
    for k in 1..MAX_COLOUR_LAGS.min(n - 1) {
        let rho = r[k..].iter().zip(r).map(|(a, b)| (a - mean) * (b - mean)).sum::<f64>() / var;
        if rho <= 0.0 {
            break;
        }
        sum += rho;
    }
    1.0 + 2.0 * sum
}

/// Most lags summed by [`colour_factor`].
pub const MAX_COLOUR_LAGS: usize = 500;

/// σ²·A⁻¹ via the unit-diagonal scaling of A; None with the parameters of the null space when A
/// is singular.
fn covariance(a: &DMatrix<f64>, sigma2: f64) -> (Option<DMatrix<f64>>, Vec<usize>, f64) {
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
    match scaled.try_inverse() {
        Some(inv) => (Some(DMatrix::from_fn(n, n, |i, k| sigma2 * inv[(i, k)] / (d[i] * d[k]))), Vec::new(), condition),
        None => (None, (0..n).collect(), condition),
    }
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_factor_of_white_and_of_ar1_residuals() {
        let mut rng = crate::rng::Rng::new(5);
        let white: Vec<f64> = (0..50_000).map(|_| rng.normal()).collect();
        assert!((colour_factor(&white) - 1.0).abs() < 0.05, "{}", colour_factor(&white));
        // AR(1), φ = 0.8: (1 + φ)/(1 − φ) = 9
        let mut x = 0.0;
        let ar: Vec<f64> = (0..50_000)
            .map(|_| {
                x = 0.8 * x + rng.normal();
                x
            })
            .collect();
        assert!((colour_factor(&ar) / 9.0 - 1.0).abs() < 0.15, "{}", colour_factor(&ar));
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
        let f = |x: &[f64]| -> Result<Vec<f64>, String> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-x[1] * t).exp() + x[2] - y).collect())
        };
        let scales = [
            Bound { lo: 0.1, hi: 10.0, log: true },
            Bound { lo: 0.01, hi: 10.0, log: true },
            Bound { lo: -5.0, hi: 5.0, log: false },
        ];
        let one = solve(&f, &[1.0, 2.0, 0.0], &scales, &pool(1), Options::default()).unwrap();
        assert!(
            (one.x[0] - 3.0).abs() < 0.01 && (one.x[1] - 0.7).abs() < 0.01 && (one.x[2] - 0.5).abs() < 0.01,
            "{one:?}"
        );
        assert!(one.converged && one.std_error(0).unwrap() < 0.01, "{one:?}");
        let (j, c) = one.strongest_correlation(1).unwrap();
        assert!(j != 1 && c.abs() <= 1.0);
        let two = solve(&f, &[1.0, 2.0, 0.0], &scales, &pool(2), Options::default()).unwrap();
        assert_eq!(one.x, two.x);
        assert_eq!(one.model_runs, two.model_runs);
    }

    #[test]
    fn stays_in_the_box_and_names_a_parameter_the_data_do_not_see() {
        let (t, y) = data();
        // the minimum of a is 3, outside [0.1, 2]
        let f = |x: &[f64]| -> Result<Vec<f64>, String> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-0.7 * t).exp() + 0.5 - y).collect())
        };
        let s = solve(&f, &[1.0], &[Bound { lo: 0.1, hi: 2.0, log: true }], &pool(1), Options::default()).unwrap();
        assert!(
            (s.x[0] - 2.0).abs() < 1e-9 && Bound { lo: 0.1, hi: 2.0, log: true }.near_bound(s.x[0], AT_BOUND),
            "{s:?}"
        );
        // the second parameter does not enter the residuals: singular, and named
        let g = |x: &[f64]| -> Result<Vec<f64>, String> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] * (-0.7 * t).exp() + 0.5 - y + 0.0 * x[1]).collect())
        };
        let scales = [Bound { lo: 0.1, hi: 10.0, log: true }, Bound { lo: 0.1, hi: 10.0, log: false }];
        let s = solve(&g, &[1.0, 1.0], &scales, &pool(2), Options::default()).unwrap();
        assert!(s.covariance.is_none() && s.singular == vec![1], "{s:?}");
        assert!((s.x[0] - 3.0).abs() < 0.01);
    }

    #[test]
    fn covariance_of_a_straight_line_by_hand() {
        // y = p0 + p1·t: cov = σ² (XᵀX)⁻¹ exactly (linear model, exact differences)
        let t: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let y: Vec<f64> =
            t.iter().enumerate().map(|(i, t)| 1.0 + 0.5 * t + if i % 2 == 0 { 0.1 } else { -0.1 }).collect();
        let f = |x: &[f64]| -> Result<Vec<f64>, String> {
            Ok(t.iter().zip(&y).map(|(t, y)| x[0] + x[1] * t - y).collect())
        };
        let scales = [Bound { lo: -10.0, hi: 10.0, log: false }; 2];
        let s = solve(&f, &[0.0, 0.0], &scales, &pool(1), Options::default()).unwrap();
        let x = DMatrix::from_fn(50, 2, |i, k| if k == 0 { 1.0 } else { t[i] });
        let hand = (x.transpose() * &x).try_inverse().unwrap() * s.sigma2;
        let c = s.covariance.as_ref().unwrap();
        for i in 0..2 {
            for k in 0..2 {
                assert!((c[(i, k)] - hand[(i, k)]).abs() < 1e-6 * hand[(i, i)].abs(), "{c} vs {hand}");
            }
        }
    }
}
