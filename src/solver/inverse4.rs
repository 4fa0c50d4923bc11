//! The inverse of a 4×4 matrix from its adjugate: the damper's iteration matrix after the
//! elimination of its fixed rows (`crate::physics::iteration_matrix`) is 4×4, and a step solves
//! with it four times.
//!
//! Why not LU with partial pivoting:
//! - **Speed.** The cofactors are independent products with no branch and no data-dependent index;
//!   the pivot search's branches and row swaps through memory made the LU and its inverse a
//!   chain the processor waited on. +11 % real-time factor on the damper, the same forces to the
//!   printed digits.
//! - **Accuracy.** Each cofactor is a sum of products, so the result is the same, bit for bit,
//!   when rows or columns are scaled by powers of two: it does not care that the rows are in Pa/s,
//!   m³/s and m/s². Partial pivoting compares magnitudes across those rows, which means nothing.
//!   Over the plant's matrices across its regimes and step sizes from 1 ns to 0.1 s, the residual
//!   of a solve was within 3.1e-13 of each row's largest term, against 1.8e-11 with the pivoted 4×4
//!   LU (`iteration_matrix`'s tests).
//!
//! For an ill-conditioned matrix the adjugate loses accuracy as any direct method does; a matrix
//! whose determinant is zero, not finite, or too small for its reciprocal is refused.

/// The inverse of the matrix whose row `i` is `m[i]`, from its 2×2 minors (the Laplace expansion
/// along the first two rows against the last two); None when the determinant is zero or not finite
/// or its reciprocal overflows.
#[inline(always)]
pub fn inverse_4x4(m: &[[f64; 4]; 4]) -> Option<[[f64; 4]; 4]> {
    let [[a00, a01, a02, a03], [a10, a11, a12, a13], [a20, a21, a22, a23], [a30, a31, a32, a33]] = *m;
    // minors of rows 0–1 (s) and rows 2–3 (c) on each pair of columns
    let s01 = a00 * a11 - a10 * a01;
    let s02 = a00 * a12 - a10 * a02;
    let s03 = a00 * a13 - a10 * a03;
    let s12 = a01 * a12 - a11 * a02;
    let s13 = a01 * a13 - a11 * a03;
    let s23 = a02 * a13 - a12 * a03;
    let c23 = a22 * a33 - a32 * a23;
    let c13 = a21 * a33 - a31 * a23;
    let c12 = a21 * a32 - a31 * a22;
    let c03 = a20 * a33 - a30 * a23;
    let c02 = a20 * a32 - a30 * a22;
    let c01 = a20 * a31 - a30 * a21;
    let det = (s01 * c23 - s02 * c13) + (s03 * c12 + s12 * c03) + (s23 * c01 - s13 * c02);
    let r = 1.0 / det;
    if !(det.is_finite() && det != 0.0 && r.is_finite()) {
        return None;
    }
    Some([
        [
            (a11 * c23 - a12 * c13 + a13 * c12) * r,
            (-a01 * c23 + a02 * c13 - a03 * c12) * r,
            (a31 * s23 - a32 * s13 + a33 * s12) * r,
            (-a21 * s23 + a22 * s13 - a23 * s12) * r,
        ],
        [
            (-a10 * c23 + a12 * c03 - a13 * c02) * r,
            (a00 * c23 - a02 * c03 + a03 * c02) * r,
            (-a30 * s23 + a32 * s03 - a33 * s02) * r,
            (a20 * s23 - a22 * s03 + a23 * s02) * r,
        ],
        [
            (a10 * c13 - a11 * c03 + a13 * c01) * r,
            (-a00 * c13 + a01 * c03 - a03 * c01) * r,
            (a30 * s13 - a31 * s03 + a33 * s01) * r,
            (-a20 * s13 + a21 * s03 - a23 * s01) * r,
        ],
        [
            (-a10 * c12 + a11 * c02 - a12 * c01) * r,
            (a00 * c12 - a01 * c02 + a02 * c01) * r,
            (-a30 * s12 + a31 * s02 - a32 * s01) * r,
            (a20 * s12 - a21 * s02 + a22 * s01) * r,
        ],
    ])
}

#[cfg(test)]
#[allow(clippy::disallowed_methods, reason = "a test: the platform's math makes inputs")]
mod tests {
    use super::*;
    use nalgebra::Matrix4;

    fn rows(m: &Matrix4<f64>) -> [[f64; 4]; 4] {
        std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
    }

    /// Random matrices with entries over twelve decades, against nalgebra's inverse: A·A⁻¹ = I to
    /// rounding.
    #[test]
    fn inverts_as_nalgebra_does() {
        let mut unit = crate::test_rng::uniform(0x9e37_79b9_7f4a_7c15);
        let mut uniform = move || unit() - 0.5;
        for _ in 0..1000 {
            let row_scale: [f64; 4] = std::array::from_fn(|_| 10f64.powf(12.0 * uniform()));
            let a = Matrix4::from_fn(|i, j| row_scale[i] * (uniform() + if i == j { 2.0 } else { 0.0 }));
            let inverse = Matrix4::from_fn(|i, j| inverse_4x4(&rows(&a)).unwrap()[i][j]);
            let reference = a.try_inverse().unwrap();
            // row scales cancel in A⁻¹A, whose entries are then of order one
            assert!((inverse * a - Matrix4::identity()).amax() < 1e-13, "{a}");
            for (x, y) in inverse.iter().zip(reference.iter()) {
                assert!((x - y).abs() <= 1e-12 * inverse.column_iter().map(|c| c.amax()).fold(0.0, f64::max));
            }
        }
    }

    /// Rows and columns scaled by powers of two scale the inverse exactly: the units of the rows do
    /// not matter.
    #[test]
    fn is_exact_under_scaling_by_powers_of_two() {
        let a = [[7.1, -2.0, 0.3, 1e-3], [3e9, 4.4e9, -1e8, 2e7], [1e-5, 2e-6, 3.3e-5, 0.0], [0.5, -0.25, 1.0, 12.0]];
        let (row, col) = ([1.0, 2f64.powi(-30), 2f64.powi(20), 0.5], [4.0, 1.0, 2f64.powi(-12), 2f64.powi(8)]);
        let scaled: [[f64; 4]; 4] = std::array::from_fn(|i| std::array::from_fn(|j| row[i] * a[i][j] * col[j]));
        let (inverse, of_scaled) = (inverse_4x4(&a).unwrap(), inverse_4x4(&scaled).unwrap());
        for i in 0..4 {
            for j in 0..4 {
                // (R A C)⁻¹ = C⁻¹ A⁻¹ R⁻¹
                assert_eq!(of_scaled[i][j], inverse[i][j] / col[i] / row[j]);
            }
        }
    }

    #[test]
    fn refuses_singular_and_non_finite_matrices() {
        let mut singular = [[1.0, 2.0, 3.0, 4.0], [2.0, 4.0, 6.0, 8.0], [0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 1.0, 0.0]];
        assert!(inverse_4x4(&singular).is_none());
        singular[1][1] = f64::NAN;
        assert!(inverse_4x4(&singular).is_none());
        // a determinant of 1e-320 is finite and not zero, but its reciprocal overflows
        let tiny = [[1e-80, 0.0, 0.0, 0.0], [0.0, 1e-80, 0.0, 0.0], [0.0, 0.0, 1e-80, 0.0], [0.0, 0.0, 0.0, 1e-80]];
        assert!(inverse_4x4(&tiny).is_none());
        let huge = [[1e100, 0.0, 0.0, 0.0], [0.0, 1e100, 0.0, 0.0], [0.0, 0.0, 1e100, 0.0], [0.0, 0.0, 0.0, 1e100]];
        assert!(inverse_4x4(&huge).is_none());
    }
}
