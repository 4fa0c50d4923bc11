//! What keeps the truck's steps bounded and its explicit integration stable (docs/robustness.md).

use crate::truck::{Params, MODE_IDEAL, MODE_PASSIVE, MODE_TRACKING};
use suspension::error::SuspensionError;
use suspension::integration::{eigenvalue_bound, substeps};
pub use suspension::integration::{MAX_SUBSTEPS, RK4_STABLE_RADIUS};

impl Params {
    /// RK4 steps for a communication step of `h` (s): equal steps of at most `h_max`.
    pub fn substeps(&self, h: f64) -> f64 {
        substeps(h, self.h_max)
    }

    /// A bound on the largest |eigenvalue| (1/s) of the truck with its damper law: with
    /// K = M⁻¹·stiffness and C = M⁻¹·damping, λ²x + λCx + Kx = 0 gives
    /// |λ| ≤ (‖C‖ + sqrt(‖C‖² + 4‖K‖))/2 in the row-sum norm. The MSD law adds at most Cm
    /// (clipped to its floor c_min or applied), an external damper force nothing; the tracking
    /// damper's lags have eigenvalues −1/τ.
    pub fn eigenvalue_bound(&self) -> f64 {
        let c = self.c_susp
            + match self.damper_mode {
                MODE_IDEAL | MODE_TRACKING => self.demand_law().largest_coefficient(),
                MODE_PASSIVE => self.passive_damper().largest_coefficient(),
                _ => 0.0,
            };
        let k = (2.0 * self.k_susp / self.m_body).max((2.0 * self.k_susp + self.k_tyre) / self.m_axle);
        let c = (2.0 * c / self.m_body).max((2.0 * c + self.c_tyre) / self.m_axle);
        let lag = if self.damper_mode == MODE_TRACKING { self.tracking().fastest_rate() } else { 0.0 };
        eigenvalue_bound(k, c).max(lag)
    }

    /// Refuses parameters for which RK4 with steps of `h_max` could be unstable.
    pub fn validate(&self) -> Result<(), SuspensionError> {
        let z = self.h_max * self.eigenvalue_bound();
        if z > RK4_STABLE_RADIUS {
            return Err(SuspensionError::Unstable {
                z,
                advice: "the stiffness or damping (k_susp, k_tyre, c_susp, c_tyre, Cm/c_passive/c_min) against the \
                         masses (m_body, m_axle), or a tracking_time_constant_* shorter than h_max/2.5",
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_far_inside_the_stable_region() {
        for damper_mode in 0..=3 {
            let p = Params { damper_mode, ..Params::default() };
            assert!(p.h_max * p.eigenvalue_bound() < 0.1, "mode {damper_mode}");
            assert!(p.validate().is_ok());
        }
    }

    #[test]
    fn the_bound_holds_for_one_mass() {
        // a stiff light body on a rigid axle: λ = ±i sqrt(k/m), the bound sqrt(2k/m) ≥ it
        let p = Params { m_body: 1.7, k_susp: 1e9, m_axle: 1e5, k_tyre: 1.0, ..Params::default() };
        let exact = (1e9f64 / 1.7).sqrt();
        assert!(p.eigenvalue_bound() >= exact && p.eigenvalue_bound() < 2.0 * exact);
        assert!(p.validate().unwrap_err().to_string().contains("m_body"));
    }
}
