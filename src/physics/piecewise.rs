//! Smooth functions of one variable from tables of piecewise polynomials, where a closed form or
//! an iteration would sit on the plant's chain of dependent operations: the valve's port law and
//! its inverse, the mount's deflection. `scripts/fit_tables.py` fits and prints every table;
//! tests/python/test_fitted_tables.py holds the tables in the source to it, and each user's unit
//! tests hold its table against an independent reference.

/// The value at `x` (0 ≤ x ≤ `x_max`) of a table of `P` pieces: on each of the equal pieces of
/// [0, `x_max`] a polynomial of degree 8 in the piece's own z ∈ [−1, 1], monomial coefficients
/// lowest first (Chebyshev least-squares fits, converted). Estrin's scheme: a chain of four
/// dependent multiply-adds where Horner's takes eight. Beyond `x_max` the last piece extrapolates
/// (its callers do not go there).
#[inline]
pub fn octic<const P: usize>(table: &[[f64; 9]; P], x: f64, x_max: f64) -> f64 {
    let piece = ((x * (P as f64 / x_max)) as usize).min(P - 1);
    let z = x * (2.0 * P as f64 / x_max) - (2 * piece + 1) as f64;
    let c = &table[piece];
    let z2 = z * z;
    let z4 = z2 * z2;
    let low = (c[0] + c[1] * z) + z2 * (c[2] + c[3] * z);
    let high = (c[4] + c[5] * z) + z2 * (c[6] + c[7] * z);
    (low + z4 * high) + z4 * z4 * c[8]
}
