//! Rodas3, the damper's integrator: a Rosenbrock method of order 3, L-stable and stiffly accurate,
//! with an embedded error estimate; one Jacobian and one LU factorisation per step, four stages
//! and three evaluations, the last at the step's end:
//!
//! ```text
//! (I/(γh) − J) k_i = f(t + α_i h, y + Σ_j a_ij k_j) + Σ_j (c_ij/h) k_j + γ_i h ∂f/∂t ,   i = 1..4
//! y₁ = y₀ + Σ m_i k_i ,   error estimate e = Σ e_i k_i
//! ```
//!
//! Ros3 (Sandu et al. 1997: three stages, two evaluations, L-stable) was tried in its place: 16 %
//! faster and more accurate on average (at rtol 1e-3, 18.9 N RMS force error against 24.1 N;
//! 0.60 N against 0.88 N at 3e-5), but it evaluates f only at the step's start and at 0.44 h, so
//! an event in the rest of the step (the relief valve cracking) is invisible to its error
//! estimate: against the Python cross-check at rtol 1e-6 one sample was 2.4 N off (60× the
//! tolerance; Rodas3 0.006 N). Hairer & Wanner's L-stable ROS4 (order 4, the cost of Rodas3) was
//! no better than Rodas3 (1.9 N at 160× against 2 N at about 165×).
//!
//! # References
//! Sandu, Verwer, Blom, Spee, Carmichael, Potra: "Benchmarking stiff ODE solvers for atmospheric
//! chemistry problems II: Rosenbrock solvers", Atmos. Environ. 31 (1997): the Rodas3
//! coefficients (as used in KPP); Hairer & Wanner, Solving ODEs II, §IV.7 for the method class.

use super::lu::Lu;
use super::{IterationMatrix, OdeSystem, SolverError};
use nalgebra::{SMatrix, SVector};

/// Rodas3's γ: every stage's iteration matrix is I/(γh) − J.
const GAMMA: f64 = 0.5;

/// What a Rosenbrock step needs at its start: f(y₀), the Jacobian ∂f/∂y at y₀, and, for a
/// right-hand side that depends on time, ∂f/∂t over the step (None: autonomous). A caller that
/// evaluates the system at y₀ anyway (a controller sample, a rejected step tried again) passes
/// them in instead of evaluating twice.
#[derive(Clone, Copy, Debug)]
pub struct StepStart<'a, const N: usize> {
    pub f0: &'a SVector<f64, N>,
    pub jacobian: &'a SMatrix<f64, N, N>,
    pub f_t: Option<SVector<f64, N>>,
}

/// Advances `y` by one Rodas3 step `h` (s) of an autonomous system; returns the new state and the
/// embedded error estimate.
pub fn rodas3_step<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError> {
    let f0 = sys.rhs(y);
    let jacobian = sys.jacobian(y, &f0);
    let start = StepStart { f0: &f0, jacobian: &jacobian, f_t: None };
    rodas3_step_from::<N, Lu<N>>(&start, |y| sys.rhs(y), y, h)
}

/// One Rodas3 step from a prepared start: `rhs_at_end(y)` is the right-hand side at the step's end
/// (where Rodas3's two evaluations after the start sit); `M` factorises and solves the iteration
/// matrix. The coefficients (Sandu et al. 1997, in the form above) are written out, not
/// looped over as a tableau: the stages' zero coefficients then cost nothing.
///
/// ```text
/// a₃ = (2, 0),  a₄ = (2, 0, 1);   c₂ = (4),  c₃ = (1, −1),  c₄ = (1, −1, −8/3);   γ_i = (½, 3/2, 0, 0)
/// y₁ = y₀ + 2k₁ + k₃ + k₄ (the fourth stage's point plus k₄: stiffly accurate),   e = k₄
/// ```
pub fn rodas3_step_from<const N: usize, M: IterationMatrix<N>>(
    start: &StepStart<'_, N>,
    rhs_at_end: impl Fn(&SVector<f64, N>) -> SVector<f64, N>,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError> {
    let lu = M::factor(start.jacobian, 1.0 / (GAMMA * h)).ok_or(SolverError::Singular)?;
    let with_f_t = |b: SVector<f64, N>, gamma_i: f64| match start.f_t {
        Some(f_t) => b + f_t * (gamma_i * h),
        None => b,
    };
    let f0 = start.f0;
    let k1 = lu.solve(&with_f_t(*f0, 0.5));
    let k2 = lu.solve(&with_f_t(f0 + k1 * (4.0 / h), 1.5));
    let y3 = y + k1 * 2.0;
    let k3 = lu.solve(&(rhs_at_end(&y3) + k1 * (1.0 / h) + k2 * (-1.0 / h)));
    let y4 = y3 + k3;
    let k4 = lu.solve(&(rhs_at_end(&y4) + k1 * (1.0 / h) + k2 * (-1.0 / h) + k3 * ((-8.0 / 3.0) / h)));
    let y1 = y4 + k4;
    if y1.iter().all(|v| v.is_finite()) {
        Ok((y1, k4))
    } else {
        Err(SolverError::NonFinite)
    }
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
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
            let s0 = Forced { t, lambda };
            let f0 = s0.rhs(&y);
            let f_t = with_f_t.then(|| SVector::<f64, 1>::new(-t.sin()));
            let jacobian = s0.jacobian(&y, &f0);
            let start = StepStart { f0: &f0, jacobian: &jacobian, f_t };
            let at = |y: &SVector<f64, 1>| Forced { t: t + h, lambda }.rhs(y);
            y = rodas3_step_from::<1, Lu<1>>(&start, at, &y, h).unwrap().0;
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
