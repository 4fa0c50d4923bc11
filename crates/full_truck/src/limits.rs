//! What keeps the truck's steps bounded and its explicit integration stable (docs/robustness.md).

use crate::body::{Params, State, CORNERS, DOF, MODE_IDEAL, MODE_PASSIVE, MODE_TRACKING};

use suspension::error::SuspensionError;
use suspension::integration::{eigenvalue_bound, substeps};
pub use suspension::integration::{MAX_SUBSTEPS, RK4_STABLE_RADIUS};

/// The row-sum norm of a 9×9 matrix given by its columns.
fn row_sum_norm(columns: &[[f64; DOF]; DOF]) -> f64 {
    (0..DOF).map(|i| columns.iter().map(|c| c[i].abs()).sum::<f64>()).fold(0.0, f64::max)
}

impl Params {
    /// RK4 steps for a communication step of `h` (s): equal steps of at most `h_max`.
    pub fn substeps(&self, h: f64) -> f64 {
        substeps(h, self.h_max)
    }

    /// The largest damping coefficient (N·s/m) a damper puts between body and axle, by mode (an
    /// external damper force: none the truck knows of).
    fn damper_coefficient(&self) -> f64 {
        match self.damper_mode {
            MODE_IDEAL | MODE_TRACKING => self.demand_law().largest_coefficient(),
            MODE_PASSIVE => self.passive_damper().largest_coefficient(),
            _ => 0.0,
        }
    }

    /// The columns of M⁻¹K and M⁻¹C (the truck's stiffness and damping, each damper as a linear
    /// one of its largest coefficient), from the equations themselves: the accelerations of a unit
    /// displacement, and of a unit rate.
    fn stiffness_and_damping(&self) -> ([[f64; DOF]; DOF], [[f64; DOF]; DOF]) {
        let zero = [0.0; CORNERS];
        let c = self.damper_coefficient();
        let column = |j: usize| {
            let mut y: State = [0.0; crate::body::STATES];
            y[j] = 1.0;
            let f: [f64; CORNERS] = std::array::from_fn(|k| c * self.at_damper(&y, k).v_rel());
            self.accelerations(&y, &f, &zero, &zero).0.map(|a| -a)
        };
        (std::array::from_fn(column), std::array::from_fn(|j| column(DOF + j)))
    }

    /// A bound on the largest |eigenvalue| (1/s) of the truck with its damper law: with K = M⁻¹·
    /// stiffness and C = M⁻¹·damping, λ²x + λCx + Kx = 0 gives |λ| ≤ (‖C‖ + sqrt(‖C‖² + 4‖K‖))/2 in
    /// the row-sum norm; the tracking damper's lags have eigenvalues −1/τ.
    pub fn eigenvalue_bound(&self) -> f64 {
        let (k, c) = self.stiffness_and_damping();
        let (k, c) = (row_sum_norm(&k), row_sum_norm(&c));
        let lag = if self.damper_mode == MODE_TRACKING { self.tracking().fastest_rate() } else { 0.0 };
        eigenvalue_bound(k, c).max(lag)
    }

    /// Refuses parameters for which RK4 with steps of `h_max` could be unstable.
    pub fn validate(&self) -> Result<(), SuspensionError> {
        let z = self.h_max * self.eigenvalue_bound();
        if z > RK4_STABLE_RADIUS {
            return Err(SuspensionError::Unstable {
                z,
                advice: "the stiffness or damping (*.k_susp, *.k_tyre, *.k_roll, c_susp, c_tyre, Cm/c_passive/c_min) \
                         against the masses and inertias (m_body, I_pitch, I_roll, *.m_axle, *.J_axle), or a \
                         tracking_time_constant_* shorter than h_max/2.5",
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
            assert!(p.h_max * p.eigenvalue_bound() < 0.2, "mode {damper_mode}: {}", p.h_max * p.eigenvalue_bound());
            assert!(p.validate().is_ok());
        }
    }

    #[test]
    fn a_light_axle_roll_is_refused_with_its_name() {
        // an axle of 0.01 kg·m² rolling on 1.95 MN/m tyres 0.925 m out: |λ| ≈ sqrt(2 k a²/J) ≈ 18 000/s
        let p = Params { drive1_j_axle: 0.01, ..Params::default() };
        assert!(p.validate().unwrap_err().to_string().contains("J_axle"));
    }
}
