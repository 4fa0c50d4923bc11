//! The trucks' explicit integration: classical RK4 in equal steps no longer than `h_max`, and the
//! bounds that keep it stable and its work bounded (docs/robustness.md).

/// Most RK4 steps in one communication step: 2500 s at the default h_max of 0.25 ms.
pub const MAX_SUBSTEPS: f64 = 1e7;
/// Largest h_max·|λ| allowed: RK4 is stable on the left half-disk of this radius (|R(z)| ≤ 0.88).
pub const RK4_STABLE_RADIUS: f64 = 2.5;

/// RK4 steps for a communication step of `h` (s): equal steps of at most `h_max` (s).
pub fn substeps(h: f64, h_max: f64) -> f64 {
    ((h / h_max) - 1e-9).ceil().max(1.0)
}

/// A bound (1/s) on |λ| of λ²x + λCx + Kx = 0 from norms `k` = ‖K‖ (1/s²) and `c` = ‖C‖ (1/s) of a
/// consistent matrix norm: |λ|² ≤ |λ| c + k.
pub fn eigenvalue_bound(k: f64, c: f64) -> f64 {
    0.5 * (c + (c * c + 4.0 * k).sqrt())
}

/// One classical RK4 step of `dt` (s) from `y`, with `rate(y, s)` the derivatives at `s` (s) after
/// the step's start.
pub fn rk4_step<const N: usize>(y: &[f64; N], dt: f64, mut rate: impl FnMut(&[f64; N], f64) -> [f64; N]) -> [f64; N] {
    let add = |y: &[f64; N], k: &[f64; N], s: f64| -> [f64; N] { std::array::from_fn(|i| y[i] + s * k[i]) };
    let k1 = rate(y, 0.0);
    let k2 = rate(&add(y, &k1, 0.5 * dt), 0.5 * dt);
    let k3 = rate(&add(y, &k2, 0.5 * dt), 0.5 * dt);
    let k4 = rate(&add(y, &k3, dt), dt);
    std::array::from_fn(|i| y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

#[cfg(test)]
#[allow(clippy::disallowed_methods, reason = "a test: the platform's exp is the reference")]
mod tests {
    use super::*;

    #[test]
    fn rk4_is_fourth_order_on_exponential_decay() {
        let error = |dt: f64| {
            let mut y = [1.0];
            for _ in 0..(1.0 / dt).round() as usize {
                y = rk4_step(&y, dt, |y, _| [-y[0]]);
            }
            (y[0] - (-1.0f64).exp()).abs()
        };
        let ratio = error(0.1) / error(0.05);
        assert!((ratio - 16.0).abs() < 1.0, "error ratio {ratio}");
    }

    #[test]
    fn steps_and_bound() {
        assert_eq!(substeps(1e-3, 2.5e-4), 4.0);
        assert_eq!(substeps(1e-3 * (1.0 + 1e-12), 2.5e-4), 4.0, "rounding of h does not add a step");
        assert_eq!(substeps(1e-5, 2.5e-4), 1.0);
        // an undamped oscillator: |λ| = sqrt(k) exactly
        assert_eq!(eigenvalue_bound(100.0, 0.0), 10.0);
    }
}
