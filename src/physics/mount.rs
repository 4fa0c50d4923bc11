//! Mount: the nylon bushes and the frame as one cubic spring in series with the damper body
//! (the paper's Fig. 5).
//!
//! ```text
//! F = g(δ) = k1 δ + k3 δ³          δ = mount deflection (m), tension positive
//! δ = g⁻¹(F): the one real root, by Halley's iteration
//! ```
//! The spring is massless, so δ is not a state: it follows from the hydraulic force.

/// Cubic series spring.
#[derive(Clone, Copy, Debug)]
pub struct CubicMount {
    /// Linear stiffness (N/m).
    pub k1: f64,
    /// Cubic stiffness (N/m³).
    pub k3: f64,
    /// 1/k1 (m/N) and k3/k1 (1/m²), kept so that [`CubicMount::deflection`], which every
    /// evaluation of the plant waits for, starts without two divisions in a row.
    compliance: f64,
    cubic_share: f64,
}

impl CubicMount {
    /// The mount of linear stiffness `k1` (N/m) and cubic stiffness `k3` (N/m³).
    pub fn new(k1: f64, k3: f64) -> Self {
        CubicMount { k1, k3, compliance: 1.0 / k1, cubic_share: k3 / k1 }
    }

    /// Force (N) at deflection `delta` (m).
    pub fn force(&self, delta: f64) -> f64 {
        self.k1 * delta + self.k3 * delta * delta * delta
    }

    /// Tangent stiffness dF/dδ (N/m).
    pub fn stiffness(&self, delta: f64) -> f64 {
        self.k1 + 3.0 * self.k3 * delta * delta
    }

    /// Deflection (m) carrying `force` (N): the one real root of the cubic. The mount is solved at
    /// every evaluation of the plant, so the usual case is cheap: where the cubic term is a small
    /// share ε = k3 u²/k1 of the linear spring's deflection u = F/k1 (ε ≤ 0.1: up to 29 kN with the
    /// default mount), the root's series u (1 − ε + 3ε² − 12ε³ + 55ε⁴ − 273ε⁵) is within 1428 ε⁶
    /// of it, and a Halley iteration takes a relative error e to ε e³ (the cubic's own constant).
    /// So one iteration reaches rounding up to ε = 0.04 (2.4e-5 → 2e-17), two up to 0.1, with no
    /// test between them. Otherwise Halley's iteration runs to convergence from the smaller of
    /// the linear and the cubic spring's deflection alone (both bound the root from outside
    /// within a factor of 2). The closed form (hyperbolic Cardano) cost several times as much.
    pub fn deflection(&self, force: f64) -> f64 {
        let (k1, k3) = (self.k1, self.k3);
        let linear = force * self.compliance;
        if k3 == 0.0 || force == 0.0 {
            return force / k1;
        }
        let e = self.cubic_share * linear * linear;
        if e <= SERIES_LIMIT {
            let delta = linear * (1.0 - e * (1.0 - e * (3.0 - e * (12.0 - e * (55.0 - 273.0 * e)))));
            let delta = self.halley(delta, force);
            return if e <= ONE_STEP_LIMIT { delta } else { self.halley(delta, force) };
        }
        let mut delta = if k3 * linear * linear <= k1 { linear } else { libm::cbrt(force / k3) };
        for _ in 0..MAX_HALLEY_ITERATIONS {
            let next = self.halley(delta, force);
            let step = delta - next;
            delta = next;
            // also stops on a NaN step
            if step.abs().partial_cmp(&(4.0 * f64::EPSILON * delta.abs())) != Some(std::cmp::Ordering::Greater) {
                break;
            }
        }
        delta
    }

    /// One Halley iteration towards g(δ) = `force` from `delta`.
    #[inline(always)]
    fn halley(&self, delta: f64, force: f64) -> f64 {
        let (k1, k3) = (self.k1, self.k3);
        let g = (k1 + k3 * delta * delta) * delta - force;
        let slope = k1 + 3.0 * k3 * delta * delta;
        delta - 2.0 * g * slope / (2.0 * slope * slope - g * 6.0 * k3 * delta)
    }
}

/// Largest cubic share ε for the series start (its error 1428 ε⁶ is then ≤ 0.15 %).
const SERIES_LIMIT: f64 = 0.1;
/// Largest cubic share ε for which one Halley iteration from the series reaches rounding.
const ONE_STEP_LIMIT: f64 = 0.04;

/// Halley's iteration converges cubically from within a factor of 2: 3 iterations suffice; the
/// bound only makes the loop finite.
const MAX_HALLEY_ITERATIONS: usize = 8;

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn inverse_recovers_the_deflection() {
        let m = CubicMount::new(5e7, 2e13);
        for k in -50..=50 {
            let f = k as f64 * 1e3; // ±50 kN
            let d = m.deflection(f);
            assert!((m.force(d) - f).abs() < 1e-9 * f.abs().max(1.0), "F {f}");
        }
        // hand value: at δ = 1 mm, F = 5e7·1e-3 + 2e13·1e-9 = 50 kN + 20 kN
        assert!((m.force(1e-3) - 70e3).abs() < 1e-6);
        assert!((m.deflection(70e3) - 1e-3).abs() < 1e-15);
        let linear = CubicMount::new(5e7, 0.0);
        assert_eq!(linear.deflection(1e4), 2e-4);
        // k3 so small that k1/k3 overflows: the linear spring
        let tiny = CubicMount::new(5e7, 2.2e-308);
        assert_eq!(tiny.deflection(1e4), 2e-4);
        assert_eq!(tiny.deflection(-7e4), -7e4 / 5e7);
    }

    #[test]
    fn inverse_is_exact_over_every_stiffness_ratio() {
        // from a linear-dominated to a cubic-dominated spring, small to huge forces
        for k3_exp in [0, 5, 10, 13, 16, 20, 30] {
            let m = CubicMount::new(5e7, 10f64.powi(k3_exp));
            for f in [1e-3, 1.0, 1e3, 2e4, 5e4, 1e6, 1e9] {
                for f in [f, -f] {
                    let d = m.deflection(f);
                    assert!((m.force(d) - f).abs() <= 1e-13 * f.abs(), "k3 1e{k3_exp}, F {f}: {d}");
                }
            }
        }
    }

    #[test]
    fn series_start_reaches_rounding_up_to_its_limit() {
        // the cubic share ε from 0 to just past the series' limit, where the loop takes over
        let m = CubicMount::new(5e7, 2e13);
        for k in 0..=220 {
            let e = SERIES_LIMIT * k as f64 / 200.0;
            let f = m.k1 * (e * m.k1 / m.k3).sqrt();
            for f in [f, -f] {
                let d = m.deflection(f);
                assert!((m.force(d) - f).abs() <= 4.0 * f64::EPSILON * f.abs(), "ε {e}, F {f}: {d}");
            }
        }
    }

    #[test]
    fn stiffness_is_the_slope() {
        let m = CubicMount::new(5e7, 2e13);
        let d = 0.4e-3;
        let fd = (m.force(d + 1e-9) - m.force(d - 1e-9)) / 2e-9;
        assert!((fd - m.stiffness(d)).abs() < 1e-6 * fd);
    }
}
