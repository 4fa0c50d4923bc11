//! Rodas3: a 4-stage Rosenbrock method of order 3, L-stable and stiffly accurate, with an
//! embedded order-2 solution for error estimates.
//!
//! ```text
//! (I/(γh) − J) k_i = f(y + Σ_j a_ij k_j) + Σ_j (c_ij/h) k_j ,   i = 1..4
//! y₁ = y₀ + Σ m_i k_i ,   error estimate e = Σ e_i k_i
//! γ = 1/2;  a31 = 2, a41 = 2, a43 = 1 (others 0);
//! c21 = 4, c31 = 1, c32 = −1, c41 = 1, c42 = −1, c43 = −8/3;  m = (2, 0, 1, 1);  e = (0, 0, 0, 1)
//! ```
//! # Reference
//! Sandu, Verwer, Blom, Spee, Carmichael, Potra: "Benchmarking stiff ODE solvers for atmospheric
//! chemistry problems II: Rosenbrock solvers", Atmos. Environ. 31 (1997), Rodas3 coefficients
//! (as used in KPP); Hairer & Wanner, Solving ODEs II, §IV.7 for the method class.

use super::{OdeSystem, SolverError};
use nalgebra::{Const, DimMin, SMatrix, SVector};

const GAMMA: f64 = 0.5;

/// Advances `y` by one step `h` (s); returns the new state and the embedded error estimate.
/// One Jacobian, one LU factorisation and three right-hand-side evaluations per step.
pub fn rodas3_step<const N: usize, S: OdeSystem<N>>(
    sys: &S,
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
    let k1 = solve(f0)?;
    let k2 = solve(f0 + k1 * (4.0 / h))?;
    let f3 = sys.rhs(&(y + k1 * 2.0));
    let k3 = solve(f3 + (k1 - k2) / h)?;
    let f4 = sys.rhs(&(y + k1 * 2.0 + k3));
    let k4 = solve(f4 + (k1 - k2 - k3 * (8.0 / 3.0)) / h)?;
    let y1 = y + k1 * 2.0 + k3 + k4;
    if y1.iter().all(|v| v.is_finite()) {
        Ok((y1, k4))
    } else {
        Err(SolverError::NonFinite)
    }
}
