//! LU factorisation with partial pivoting of a small fixed-size matrix, for the Rosenbrock stages
//! of a system without the damper's structure (one factorisation, four solves per step; the
//! damper's own matrix goes through `crate::physics::iteration_matrix`). Written out rather than
//! nalgebra's `LU`: on the damper's 7×7 iteration matrix nalgebra's generic views made the four
//! solves alone 20 % of the benchmark (`cargo bench --bench realtime`); plain loops over arrays cost
//! a fraction. The operation sequence is fixed, so results are bitwise deterministic.

use nalgebra::{SMatrix, SVector};

/// P·A = L·U, L unit lower (below the diagonal) and U upper (on and above it) in one array.
#[derive(Clone, Copy, Debug)]
pub struct Lu<const N: usize> {
    /// Row `i` of the factors (row-major).
    rows: [[f64; N]; N],
    /// 1/U_ii.
    inverse_diagonal: [f64; N],
    /// Row `i` of P·A is row `perm[i]` of A.
    perm: [usize; N],
}

impl<const N: usize> Lu<N> {
    /// Factorises `a`; None when a pivot is zero or not finite (singular or overflowed matrix).
    // the elimination's index loops: clippy's iterator form is the one that did not unroll
    #[allow(clippy::needless_range_loop)]
    pub fn factor(a: &SMatrix<f64, N, N>) -> Option<Self> {
        let mut rows: [[f64; N]; N] = std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)]));
        let mut perm: [usize; N] = std::array::from_fn(|i| i);
        let mut inverse_diagonal = [0.0; N];
        for k in 0..N {
            let mut pivot = k;
            for i in k + 1..N {
                if rows[i][k].abs() > rows[pivot][k].abs() {
                    pivot = i;
                }
            }
            if !(rows[pivot][k] != 0.0 && rows[pivot][k].is_finite()) {
                return None;
            }
            rows.swap(k, pivot);
            perm.swap(k, pivot);
            let inverse = 1.0 / rows[k][k];
            inverse_diagonal[k] = inverse;
            let pivot_row = rows[k];
            // index loops over constant bounds, which the compiler unrolls for a small N (an
            // iterator chain, `skip` over `zip`, is not unrolled, and costs twice the arithmetic)
            for i in k + 1..N {
                let factor = rows[i][k] * inverse;
                rows[i][k] = factor;
                for j in k + 1..N {
                    rows[i][j] -= factor * pivot_row[j];
                }
            }
        }
        Some(Lu { rows, inverse_diagonal, perm })
    }

    /// The solution x of A x = b. Column by column: each x_j, once known, updates the rows below
    /// (above) it independently, which keeps the dependency chain N long, not N²/2.
    pub fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        let mut x: [f64; N] = std::array::from_fn(|i| b[self.perm[i]]);
        for j in 0..N {
            for i in j + 1..N {
                x[i] -= self.rows[i][j] * x[j];
            }
        }
        for j in (0..N).rev() {
            x[j] *= self.inverse_diagonal[j];
            for i in 0..j {
                x[i] -= self.rows[i][j] * x[j];
            }
        }
        SVector::from(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        // a zero on the first diagonal entry, scales from 1e-6 to 1e9 as in the plant
        let a = SMatrix::<f64, 4, 4>::from_row_slice(&[
            0.0, 2.0, 0.0, 1e9, //
            3.0, -1.0, 4e-6, 0.0, //
            1.0, 0.5, 2.0, 0.0, //
            0.0, 0.0, 1e-6, 5.0,
        ]);
        let x = SVector::<f64, 4>::new(1.0, -2.0, 3e3, 0.25);
        let b = a * x;
        let solved = Lu::factor(&a).unwrap().solve(&b);
        // backward stable: the residual is at rounding level of ‖A‖‖x‖ (the solution itself loses
        // digits to the 1e9 entry, as any solver's does)
        let residual = (a * solved - b).amax();
        assert!(residual <= 40.0 * f64::EPSILON * a.amax() * solved.amax(), "residual {residual:e}");
        let reference = a.lu().solve(&b).unwrap();
        assert!((solved - reference).norm() <= 1e-7 * x.norm(), "{solved} vs nalgebra's {reference}");
    }

    #[test]
    fn refuses_singular_and_non_finite_matrices() {
        let singular = SMatrix::<f64, 2, 2>::from_row_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert!(Lu::factor(&singular).is_none());
        let nan = SMatrix::<f64, 2, 2>::from_row_slice(&[f64::NAN, 0.0, 0.0, 1.0]);
        assert!(Lu::factor(&nan).is_none());
    }
}
