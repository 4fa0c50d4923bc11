//! Stiff integration: a linearly-implicit, L-stable Rosenbrock method of order 3 on fixed-size nalgebra
//! vectors (no heap allocation, fixed operation sequence, hence bitwise deterministic).
mod inverse4;
mod lu;
mod rosenbrock;

pub use inverse4::inverse_4x4;
pub use lu::Lu;
pub use rosenbrock::{rosenbrock_step, rosenbrock_step_from, StepStart};

use nalgebra::{SMatrix, SVector};

/// An autonomous ODE system y' = f(y) of dimension N.
pub trait OdeSystem<const N: usize> {
    /// The right-hand side f(y).
    fn rhs(&self, y: &SVector<f64, N>) -> SVector<f64, N>;

    /// The Jacobian ∂f/∂y at `y`, where `f0 = f(y)`. Default: forward differences, with an
    /// increment scaled per component.
    fn jacobian(&self, y: &SVector<f64, N>, f0: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let mut j = SMatrix::<f64, N, N>::zeros();
        for col in 0..N {
            let mut yp = *y;
            yp[col] += 1.5e-8 * y[col].abs().max(1e-6);
            let step = yp[col] - y[col];
            j.set_column(col, &((self.rhs(&yp) - f0) / step));
        }
        j
    }
}

/// The linear algebra of a Rosenbrock step: the iteration matrix I/(γh) − J, factorised once per
/// step and solved once per stage. [`Lu`] is the dense one; a system whose Jacobian has rows of a
/// known form can eliminate them first (the damper's plant does:
/// `crate::physics::iteration_matrix`).
pub trait IterationMatrix<const N: usize>: Sized {
    /// Factorises I/(γh) − J for `inv_gamma_h` = 1/(γh); None when it is singular or not finite.
    fn factor(jacobian: &SMatrix<f64, N, N>, inv_gamma_h: f64) -> Option<Self>;
    /// The solution x of (I/(γh) − J) x = b.
    fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N>;
}

impl<const N: usize> IterationMatrix<N> for Lu<N> {
    fn factor(jacobian: &SMatrix<f64, N, N>, inv_gamma_h: f64) -> Option<Self> {
        Lu::factor(&(SMatrix::<f64, N, N>::identity() * inv_gamma_h - jacobian))
    }
    fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        Lu::solve(self, b)
    }
}

/// ∛x (x > 0) within 1e-4 relative, for starting values and step-size factors, at a fraction of
/// `f64::cbrt`'s cost (compiler-builtins' cube root had been 3–4 % of the damper's time): a third
/// of the exponent from the bits (within 3.2 %), then one Halley step y (y³ + 2x)/(2y³ + x), which
/// cubes the relative error.
pub fn cube_root_estimate(x: f64) -> f64 {
    cube_root_halley_step(f64::from_bits(x.to_bits() / 3 + 0x2a9f_7893_782d_a1ce), x)
}

/// One Halley step from y towards ∛x: y (y³ + 2x)/(2y³ + x), which cubes the relative error
/// (1e-4 from [`cube_root_estimate`] to 1e-12).
pub fn cube_root_halley_step(y: f64, x: f64) -> f64 {
    let y3 = y * y * y;
    y * (y3 + 2.0 * x) / (2.0 * y3 + x)
}

/// Why an integration step failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolverError {
    /// The iteration matrix (I/(γh) − J) could not be factorised.
    Singular,
    /// The step produced NaN or infinity.
    NonFinite,
    /// The step-size control could not meet the tolerance.
    StepSizeTooSmall,
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SolverError::Singular => write!(f, "singular iteration matrix"),
            SolverError::NonFinite => write!(f, "non-finite state"),
            SolverError::StepSizeTooSmall => write!(f, "step size too small for the tolerance rtol"),
        }
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
    fn cube_root_estimate_is_within_its_bound() {
        for k in 0..=4000 {
            let x = 10f64.powf(-12.0 + 24.0 * k as f64 / 4000.0);
            let e = (cube_root_estimate(x) / x.cbrt() - 1.0).abs();
            assert!(e < 1e-4, "x {x}: {e}");
        }
    }
}
