//! Mount: the nylon bushes and the frame as one cubic spring in series with the damper body
//! (the paper's Fig. 5).
//!
//! ```text
//! F = g(δ) = k1 δ + k3 δ³          δ = mount deflection (m), tension positive
//! δ = g⁻¹(F) = −2 sqrt(k1/(3k3)) sinh( asinh( −(3F/(2k1)) sqrt(3k3/k1) ) / 3 )   (k3 > 0)
//! ```
//! The spring is massless, so δ is not a state: it follows from the hydraulic force.

/// Cubic series spring.
#[derive(Clone, Copy, Debug)]
pub struct CubicMount {
    /// Linear stiffness (N/m).
    pub k1: f64,
    /// Cubic stiffness (N/m³).
    pub k3: f64,
}

impl CubicMount {
    /// Force (N) at deflection `delta` (m).
    pub fn force(&self, delta: f64) -> f64 {
        self.k1 * delta + self.k3 * delta * delta * delta
    }

    /// Tangent stiffness dF/dδ (N/m).
    pub fn stiffness(&self, delta: f64) -> f64 {
        self.k1 + 3.0 * self.k3 * delta * delta
    }

    /// Deflection (m) carrying `force` (N): the one real root of the cubic, in closed form
    /// (hyperbolic form of Cardano, no cancellation).
    pub fn deflection(&self, force: f64) -> f64 {
        if self.k3 == 0.0 {
            return force / self.k1;
        }
        let p = self.k1 / self.k3;
        let q = -force / self.k3;
        let s = (p / 3.0).sqrt();
        let delta = -2.0 * s * ((1.5 * q / p / s).asinh() / 3.0).sinh();
        if delta.is_finite() {
            return delta;
        }
        // k3 so small against k1 that k1/k3 overflows (2.2e-308): the cubic term is a perturbation,
        // δ = F/k1 − k3 F³/k1⁴ + O(k3²)
        let linear = force / self.k1;
        linear - self.k3 * linear * linear * linear / self.k1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_recovers_the_deflection() {
        let m = CubicMount { k1: 5e7, k3: 2e13 };
        for k in -50..=50 {
            let f = k as f64 * 1e3; // ±50 kN
            let d = m.deflection(f);
            assert!((m.force(d) - f).abs() < 1e-9 * f.abs().max(1.0), "F {f}");
        }
        // hand value: at δ = 1 mm, F = 5e7·1e-3 + 2e13·1e-9 = 50 kN + 20 kN
        assert!((m.force(1e-3) - 70e3).abs() < 1e-6);
        assert!((m.deflection(70e3) - 1e-3).abs() < 1e-15);
        let linear = CubicMount { k1: 5e7, k3: 0.0 };
        assert_eq!(linear.deflection(1e4), 2e-4);
        // k1/k3 overflows: the closed form gives ∞·0, the perturbation series the linear spring
        let tiny = CubicMount { k1: 5e7, k3: 2.2e-308 };
        assert_eq!(tiny.deflection(1e4), 2e-4);
        assert_eq!(tiny.deflection(-7e4), -7e4 / 5e7);
    }

    #[test]
    fn stiffness_is_the_slope() {
        let m = CubicMount { k1: 5e7, k3: 2e13 };
        let d = 0.4e-3;
        let fd = (m.force(d + 1e-9) - m.force(d - 1e-9)) / 2e-9;
        assert!((fd - m.stiffness(d)).abs() < 1e-6 * fd);
    }
}
