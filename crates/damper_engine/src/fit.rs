//! Fitting an effect's parameters: bounded Nelder–Mead on a transformed scale, and the
//! parameter uncertainty from the curvature of the sum of squared residuals.
//!
//! ```text
//! bounds:       θ = lo + (hi − lo)·(1 + sin u)/2           (any u maps into [lo, hi])
//!               on a log scale for parameters spanning decades (leakage, stiffness)
//! uncertainty:  SSE(θ) ≈ SSE(θ̂) + ½ Δθᵀ H Δθ,  cov(θ̂) ≈ 2 σ² H⁻¹,  σ² = SSE(θ̂)/(N − p)
//! ```
//! The covariance is the Gauss–Newton one (H ≈ 2 JᵀJ), valid for residuals that are roughly
//! independent; with coloured residuals it is optimistic, which the report says.

pub use crate::bounds::Bound;

/// A fitted value within this fraction of its box's (searched) range of a bound is "at its search
/// bound": Nelder–Mead on the sine transform creeps towards a bound, never reaching it.
pub const AT_BOUND: f64 = 0.01;

/// The result of a fit.
#[derive(Clone, Debug)]
pub struct Fit {
    pub x: Vec<f64>,
    pub value: f64,
    pub evaluations: usize,
}

/// Minimises `f` over the box `bounds`, starting at `x0`, with at most `max_evals` evaluations
/// (Nelder–Mead, standard coefficients, on the bounded transform of each parameter).
pub fn minimize(f: impl Fn(&[f64]) -> f64, x0: &[f64], bounds: &[Bound], max_evals: usize) -> Fit {
    let n = x0.len();
    let to_x = |u: &[f64]| -> Vec<f64> { u.iter().zip(bounds).map(|(&u, b)| b.value_at_unbounded(u)).collect() };
    let evals = std::cell::Cell::new(0usize);
    let eval = |u: &[f64]| {
        evals.set(evals.get() + 1);
        let v = f(&to_x(u));
        if v.is_finite() {
            v
        } else {
            f64::INFINITY
        }
    };
    let u0: Vec<f64> = x0.iter().zip(bounds).map(|(&x, b)| b.unbounded_at(x)).collect();
    let mut simplex: Vec<(Vec<f64>, f64)> = vec![(u0.clone(), eval(&u0))];
    for i in 0..n {
        let mut u = u0.clone();
        u[i] += if u[i] > 0.0 { -0.5 } else { 0.5 };
        let v = eval(&u);
        simplex.push((u, v));
    }
    while evals.get() < max_evals {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (best, worst) = (simplex[0].1, simplex[n].1);
        if (worst - best).abs() <= 1e-10 * best.abs().max(1e-300) {
            break;
        }
        let centroid: Vec<f64> = (0..n).map(|j| simplex[..n].iter().map(|p| p.0[j]).sum::<f64>() / n as f64).collect();
        let towards =
            |t: f64| -> Vec<f64> { (0..n).map(|j| centroid[j] + t * (simplex[n].0[j] - centroid[j])).collect() };
        let reflected = towards(-1.0);
        let fr = eval(&reflected);
        if fr < simplex[0].1 {
            let expanded = towards(-2.0);
            let fe = eval(&expanded);
            simplex[n] = if fe < fr { (expanded, fe) } else { (reflected, fr) };
        } else if fr < simplex[n - 1].1 {
            simplex[n] = (reflected, fr);
        } else {
            let contracted = if fr < simplex[n].1 { towards(-0.5) } else { towards(0.5) };
            let fc = eval(&contracted);
            if fc < fr.min(simplex[n].1) {
                simplex[n] = (contracted, fc);
            } else {
                let first = simplex[0].0.clone();
                for p in simplex.iter_mut().skip(1) {
                    p.0 = (0..n).map(|j| first[j] + 0.5 * (p.0[j] - first[j])).collect();
                    p.1 = eval(&p.0);
                }
            }
        }
    }
    simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
    Fit { x: to_x(&simplex[0].0), value: simplex[0].1, evaluations: evals.get() }
}

/// Standard deviations of the parameters at the minimum `x` of `sse` (a sum of `n_residuals`
/// squared residuals, `s0` at `x`), from a central-difference Hessian with relative steps
/// `rel_step`. `None` where the curvature is not positive (the data do not determine the parameter).
pub fn standard_errors(
    sse: impl Fn(&[f64]) -> f64,
    (x, s0): (&[f64], f64),
    n_residuals: usize,
    rel_step: f64,
) -> Vec<Option<f64>> {
    let p = x.len();
    let h: Vec<f64> = x.iter().map(|v| rel_step * v.abs().max(1e-300)).collect();
    let at = |d: &[(usize, f64)]| {
        let mut y = x.to_vec();
        for &(i, s) in d {
            y[i] += s * h[i];
        }
        sse(&y)
    };
    let mut hess = vec![vec![0.0; p]; p];
    for i in 0..p {
        hess[i][i] = (at(&[(i, 1.0)]) - 2.0 * s0 + at(&[(i, -1.0)])) / (h[i] * h[i]);
        for j in 0..i {
            let v = (at(&[(i, 1.0), (j, 1.0)]) - at(&[(i, 1.0), (j, -1.0)]) - at(&[(i, -1.0), (j, 1.0)])
                + at(&[(i, -1.0), (j, -1.0)]))
                / (4.0 * h[i] * h[j]);
            hess[i][j] = v;
            hess[j][i] = v;
        }
    }
    let sigma2 = s0 / (n_residuals.saturating_sub(p).max(1)) as f64;
    // positive definite, or the data do not determine every parameter
    match nalgebra::DMatrix::from_fn(p, p, |i, j| hess[i][j]).cholesky() {
        Some(c) => {
            let inv = c.inverse();
            (0..p).map(|i| Some((2.0 * sigma2 * inv[(i, i)]).sqrt())).collect()
        }
        None => vec![None; p],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_bounded_minimum_in_one_and_two_dimensions() {
        let b = Bound { lo: 0.0, hi: 10.0, log: false };
        let fit = minimize(|x| (x[0] - 3.7).powi(2), &[5.0], &[b], 200);
        assert!((fit.x[0] - 3.7).abs() < 1e-4, "{fit:?}");
        // Rosenbrock inside [−2, 2] × [−1, 3]
        let bounds = [Bound { lo: -2.0, hi: 2.0, log: false }, Bound { lo: -1.0, hi: 3.0, log: false }];
        let fit =
            minimize(|x| 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2), &[-1.0, 1.0], &bounds, 2000);
        assert!((fit.x[0] - 1.0).abs() < 1e-3 && (fit.x[1] - 1.0).abs() < 2e-3, "{fit:?}");
    }

    #[test]
    fn minimum_outside_the_box_lands_on_the_bound_and_is_flagged() {
        let b = Bound { lo: 1e-14, hi: 1e-11, log: true };
        let fit = minimize(|x| (x[0].ln() - (1e-9f64).ln()).powi(2), &[1e-13], &[b], 300);
        assert!(b.near_bound(fit.x[0], AT_BOUND) && fit.x[0] > 0.9e-11, "{fit:?}");
        assert!(!b.near_bound(1e-12, AT_BOUND));
    }

    #[test]
    fn standard_error_of_a_mean_by_hand() {
        // y_i = θ + noise: SSE(θ) = Σ (y_i − θ)², the estimate is the mean with σ/√N
        let y: Vec<f64> = (0..400).map(|i| 5.0 + if i % 2 == 0 { 0.3 } else { -0.3 }).collect();
        let sse = |x: &[f64]| y.iter().map(|v| (v - x[0]).powi(2)).sum::<f64>();
        let s0 = sse(&[5.0]);
        let se = standard_errors(sse, (&[5.0], s0), y.len(), 1e-3)[0].unwrap();
        let hand = (y.iter().map(|v| (v - 5.0f64).powi(2)).sum::<f64>() / 399.0).sqrt() / 20.0;
        assert!((se - hand).abs() < 1e-6 * hand, "{se} vs {hand}");
        // a parameter the data do not see has no finite error
        assert_eq!(standard_errors(|_| 1.0, (&[2.0], 1.0), 10, 1e-3), vec![None]);
    }
}
