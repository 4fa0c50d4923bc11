//! Rosenbrock methods of up to four stages with an embedded error estimate, one Jacobian and one
//! LU factorisation per step, their coefficients as data:
//!
//! ```text
//! (I/(γh) − J) k_i = f(t + α_i h, y + Σ_j a_ij k_j) + Σ_j (c_ij/h) k_j + γ_i h ∂f/∂t ,   i = 1..s
//! y₁ = y₀ + Σ m_i k_i ,   error estimate e = Σ e_i k_i
//! ```
//! - [`RODAS3`], the damper's: order 3, L-stable and stiffly accurate; four stages and three
//!   evaluations, the last at the step's end.
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

/// The coefficients of a Rosenbrock method of up to four stages in the transformed form above.
#[derive(Clone, Copy, Debug)]
pub struct Tableau {
    pub gamma: f64,
    /// a_ij (j < i).
    pub a: [[f64; 4]; 4],
    /// c_ij (j < i).
    pub c: [[f64; 4]; 4],
    pub m: [f64; 4],
    pub e: [f64; 4],
    /// Stage times as fractions of the step.
    pub alpha: [f64; 4],
    /// γ_i = Σ_j γ_ij, for a right-hand side that depends on time.
    pub gamma_i: [f64; 4],
    /// Whether stage i evaluates f anew (else it reuses the previous stage's).
    pub new_f: [bool; 4],
    /// Number of stages, s ≤ 4.
    pub stages: usize,
}

/// Rodas3 (Sandu et al. 1997).
pub const RODAS3: Tableau = Tableau {
    gamma: 0.5,
    a: [[0.0; 4], [0.0; 4], [2.0, 0.0, 0.0, 0.0], [2.0, 0.0, 1.0, 0.0]],
    c: [[0.0; 4], [4.0, 0.0, 0.0, 0.0], [1.0, -1.0, 0.0, 0.0], [1.0, -1.0, -8.0 / 3.0, 0.0]],
    m: [2.0, 0.0, 1.0, 1.0],
    e: [0.0, 0.0, 0.0, 1.0],
    alpha: [0.0, 0.0, 1.0, 1.0],
    gamma_i: [0.5, 1.5, 0.0, 0.0],
    new_f: [true, false, true, true],
    stages: 4,
};

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

/// Advances `y` by one step `h` (s) of an autonomous system with `method`; returns the new state
/// and the embedded error estimate.
pub fn rosenbrock_step<const N: usize, S: OdeSystem<N>>(
    method: &Tableau,
    sys: &S,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError> {
    let f0 = sys.rhs(y);
    let jacobian = sys.jacobian(y, &f0);
    let start = StepStart { f0: &f0, jacobian: &jacobian, f_t: None };
    rosenbrock_step_from::<N, Lu<N>>(method, &start, |_, y| sys.rhs(y), y, h)
}

/// One step from a prepared start: `rhs_at(α, y)` is the right-hand side at the fraction α of the
/// step (the stages sit at the method's α_i); `M` factorises and solves the iteration matrix.
pub fn rosenbrock_step_from<const N: usize, M: IterationMatrix<N>>(
    method: &Tableau,
    start: &StepStart<'_, N>,
    rhs_at: impl Fn(f64, &SVector<f64, N>) -> SVector<f64, N>,
    y: &SVector<f64, N>,
    h: f64,
) -> Result<(SVector<f64, N>, SVector<f64, N>), SolverError> {
    let lu = M::factor(start.jacobian, 1.0 / (method.gamma * h)).ok_or(SolverError::Singular)?;
    let mut k = [SVector::<f64, N>::zeros(); 4];
    let mut f = *start.f0;
    for i in 0..method.stages {
        if i > 0 && method.new_f[i] {
            let mut stage = *y;
            for (a, kj) in method.a[i].iter().zip(&k).take(i) {
                if *a != 0.0 {
                    stage += kj * *a;
                }
            }
            f = rhs_at(method.alpha[i], &stage);
        }
        let mut b = f;
        for (c, kj) in method.c[i].iter().zip(&k).take(i) {
            if *c != 0.0 {
                b += kj * (*c / h);
            }
        }
        if let Some(f_t) = start.f_t {
            b += f_t * (method.gamma_i[i] * h);
        }
        k[i] = lu.solve(&b);
    }
    let (mut y1, mut error) = (*y, SVector::<f64, N>::zeros());
    for ((ki, m), e) in k.iter().zip(method.m).zip(method.e) {
        if m != 0.0 {
            y1 += ki * m;
        }
        if e != 0.0 {
            error += ki * e;
        }
    }
    if y1.iter().all(|v| v.is_finite()) {
        Ok((y1, error))
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

    fn error_at_one(method: &Tableau, steps: usize, lambda: f64, with_f_t: bool) -> f64 {
        let h = 1.0 / steps as f64;
        let mut y = SVector::<f64, 1>::zeros();
        for k in 0..steps {
            let t = k as f64 * h;
            let s0 = Forced { t, lambda };
            let f0 = s0.rhs(&y);
            let f_t = with_f_t.then(|| SVector::<f64, 1>::new(-t.sin()));
            let jacobian = s0.jacobian(&y, &f0);
            let start = StepStart { f0: &f0, jacobian: &jacobian, f_t };
            let at = |alpha: f64, y: &SVector<f64, 1>| Forced { t: t + alpha * h, lambda }.rhs(y);
            y = rosenbrock_step_from::<1, Lu<1>>(method, &start, at, &y, h).unwrap().0;
        }
        let exact = (lambda * 1f64.cos() + 1f64.sin() - lambda * (-lambda).exp()) / (1.0 + lambda * lambda);
        (y[0] - exact).abs()
    }

    #[test]
    fn a_time_dependent_right_hand_side_converges_at_third_order() {
        third_order(&RODAS3);
    }

    fn third_order(method: &Tableau) {
        let (coarse, fine) = (error_at_one(method, 20, 1.0, true), error_at_one(method, 40, 1.0, true));
        let order = (coarse / fine).log2();
        assert!(order > 2.8, "errors {coarse:e} → {fine:e}, order {order:.2}");
        // without the ∂f/∂t terms the method drops an order
        let (coarse, fine) = (error_at_one(method, 20, 1.0, false), error_at_one(method, 40, 1.0, false));
        assert!((coarse / fine).log2() < 2.3, "{coarse:e} → {fine:e}");
        // stiff (λh = 1.25): order reduction, but the terms still pay
        assert!(error_at_one(method, 40, 50.0, true) < 0.3 * error_at_one(method, 40, 50.0, false));
    }
}
