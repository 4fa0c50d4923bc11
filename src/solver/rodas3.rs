//! Rodas3: a 4-stage Rosenbrock method of order 3, L-stable and stiffly accurate, with an
//! embedded order-2 solution for error estimates.
//!
//! ```text
//! (I/(γh) − J) k_i = f(t + α_i h, y + Σ_j a_ij k_j) + Σ_j (c_ij/h) k_j + γ_i h ∂f/∂t ,   i = 1..4
//! y₁ = y₀ + Σ m_i k_i ,   error estimate e = Σ e_i k_i
//! γ = 1/2;  a31 = 2, a41 = 2, a43 = 1 (others 0);
//! c21 = 4, c31 = 1, c32 = −1, c41 = 1, c42 = −1, c43 = −8/3;  m = (2, 0, 1, 1);  e = (0, 0, 0, 1)
//! α = (0, 0, 1, 1),  γ_i = (1/2, 3/2, 0, 0)   (for a right-hand side that depends on time)
//! ```
//! # Reference
//! Sandu, Verwer, Blom, Spee, Carmichael, Potra: "Benchmarking stiff ODE solvers for atmospheric
//! chemistry problems II: Rosenbrock solvers", Atmos. Environ. 31 (1997), Rodas3 coefficients
//! (as used in KPP); Hairer & Wanner, Solving ODEs II, §IV.7 for the method class.

use super::{OdeSystem, SolverError};
use nalgebra::{Const, DimMin, SMatrix, SVector};

const GAMMA: f64 = 0.5;

/// Advances `y` by one step `h` (s) of an autonomous system; returns the new state and the
/// embedded error estimate. One Jacobian, one LU factorisation and three right-hand-side
/// evaluations per step.
pub fn rodas3_step<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    rodas3_step_timed(sys, sys, None, y, h)
}

/// The time derivative ∂f/∂t of a right-hand side, from f at the step's start.
pub type TimeDerivative<'a, const N: usize> = &'a dyn Fn(&SVector<f64, N>) -> SVector<f64, N>;

/// One step of a system whose right-hand side depends on time: `sys` is the system at the step's
/// start, `sys_end` at its end, and `f_t` gives ∂f/∂t over the step from f(y) at the start, which
/// the step computes anyway (None: autonomous).
pub fn rodas3_step_timed<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    sys_end: &S,
    f_t: Option<TimeDerivative<'_, N>>,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    let f0 = sys.rhs(y);
    let jac = sys.jacobian(y, &f0);
    let matrix = SMatrix::<f64, N, N>::identity() / (GAMMA * h) - jac;
    let lu = matrix.lu();
    let solve = |mut b: SVector<f64, N>| -> Result<SVector<f64, N>, SolverError> {
        if lu.solve_mut(&mut b) {
            Ok(b)
        } else {
            Err(SolverError::Singular)
        }
    };
    let f_t = f_t.map(|d| d(&f0));
    let time_term = |gamma_i: f64| f_t.map_or_else(SVector::<f64, N>::zeros, |ft| ft * (gamma_i * h));
    let k1 = solve(f0 + time_term(0.5))?;
    let k2 = solve(f0 + k1 * (4.0 / h) + time_term(1.5))?;
    let f3 = sys_end.rhs(&(y + k1 * 2.0));
    let k3 = solve(f3 + (k1 - k2) / h)?;
    let f4 = sys_end.rhs(&(y + k1 * 2.0 + k3));
    let k4 = solve(f4 + (k1 - k2 - k3 * (8.0 / 3.0)) / h)?;
    let y1 = y + k1 * 2.0 + k3 + k4;
    if y1.iter().all(|v| v.is_finite()) {
        Ok((y1, k4))
    } else {
        Err(SolverError::NonFinite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{SMatrix, SVector};

    /// A forced linear system y' = −λ y + cos t, with the exact solution of y(0) = 0:
    /// (λ cos t + sin t − λ e^{−λt})/(1 + λ²).
    struct Forced {
        t: f64,
        lambda: f64,
    }

    impl OdeSystem<1> for Forced {
        fn rhs(&self, y: &SVector<f64, 1>) -> SVector<f64, 1> {
            SVector::<f64, 1>::new(-self.lambda * y[0] + self.t.cos())
        }
        fn jacobian(&self, _y: &SVector<f64, 1>, _f0: &SVector<f64, 1>) -> SMatrix<f64, 1, 1> {
            SMatrix::<f64, 1, 1>::new(-self.lambda)
        }
    }

    fn error_at_one(steps: usize, lambda: f64, with_f_t: bool) -> f64 {
        let h = 1.0 / steps as f64;
        let mut y = SVector::<f64, 1>::zeros();
        for k in 0..steps {
            let t = k as f64 * h;
            let f_t = |_: &SVector<f64, 1>| SVector::<f64, 1>::new(-t.sin());
            let (s0, s1) = (Forced { t, lambda }, Forced { t: t + h, lambda });
            let f_t: Option<TimeDerivative<'_, 1>> = if with_f_t { Some(&f_t) } else { None };
            y = rodas3_step_timed(&s0, &s1, f_t, &y, h).unwrap().0;
        }
        let exact = (lambda * 1f64.cos() + 1f64.sin() - lambda * (-lambda).exp()) / (1.0 + lambda * lambda);
        (y[0] - exact).abs()
    }

    #[test]
    fn a_time_dependent_right_hand_side_converges_at_third_order() {
        let (coarse, fine) = (error_at_one(20, 1.0, true), error_at_one(40, 1.0, true));
        let order = (coarse / fine).log2();
        assert!(order > 2.8, "errors {coarse:e} → {fine:e}, order {order:.2}");
        // without the ∂f/∂t terms the method drops an order
        let (coarse, fine) = (error_at_one(20, 1.0, false), error_at_one(40, 1.0, false));
        assert!((coarse / fine).log2() < 2.3, "{coarse:e} → {fine:e}");
        // stiff (λh = 1.25): order reduction, but the terms still pay
        assert!(error_at_one(40, 50.0, true) < 0.3 * error_at_one(40, 50.0, false));
    }
}
