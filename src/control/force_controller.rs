//! Outer loop: damper force → spool demand. Two laws (parameter `force_controller`):
//!
//! ```text
//! both:   s = sign(v),  e = s (F_dem − F) / max(|F_dem|, F_ref_min)        relative force error
//! 0 (default, docs/physics.md §4.3): u = Kp e + Ki Σe T + Kd ė
//!         A_ff = Q̂ / (C_d sqrt(2 Δp_dem/ρ))     inverse valve law at the demanded force
//!         A_dem = A_ff exp(−u),  x_dem = A⁻¹(A_dem)
//! 1 (the paper's PID):  x_dem = x_bias − (Kp e + Ki Σe T + Kd ė)
//! ```
//! Since d ln F / d ln A ≈ −2 everywhere on the valve map, law 0 has a loop gain independent of
//! the operating point; law 1 is tuned for one point and slows down or rings elsewhere.
//! Anti-windup: where the demand would be clipped, the integrator moves only as far as puts it on
//! the clip ([`super::integral_at_saturation`]).

use super::{integral_at_saturation, FilteredDerivative, Measurements};
use crate::physics::params::{Derived, ForceLaw, Parameters};

/// Smallest valve-area demand (m²).
const A_DEMAND_MIN: f64 = 1e-7;
/// Smallest feed-forward area (m²); parameters whose largest demanded area is not at least twice
/// this are refused (`Parameters::validate`).
pub const A_FEEDFORWARD_MIN: f64 = 2e-7;

/// Outer-loop state.
#[derive(Clone, Copy, Debug, Default)]
pub struct ForceController {
    /// Integral term (1 for law 0, m for law 1).
    pub integral: f64,
    /// Derivative of the relative error.
    pub error_rate: FilteredDerivative,
}

/// The semi-active limit: a damper can only resist the motion. Returns the demand (N) where it
/// resists the velocity `v` (m/s), 0 where it would push.
pub fn clip_to_dissipative(force_demand: f64, v: f64) -> f64 {
    let s = if v >= 0.0 { 1.0 } else { -1.0 };
    s * (s * force_demand).max(0.0)
}

impl ForceController {
    /// Spool demand (m) for the (already clipped) force demand `f_demand` (N).
    pub fn step(&mut self, p: &Parameters, d: &Derived, f_demand: f64, m: Measurements) -> f64 {
        let ts = p.t_sample;
        let s = if m.v_damper >= 0.0 { 1.0 } else { -1.0 };
        // a product by the reciprocal: the division does not wait for the measured force
        let error = s * (f_demand - m.force) * (1.0 / f_demand.abs().max(p.f_ref_min));
        match d.force_law {
            ForceLaw::FeedforwardLogArea => {
                let rate = self.error_rate.update(error, ts, p.tau_df);
                let integral = self.integral + p.ki_f * error * ts;
                let others = p.kp_f * error + p.kd_f * rate;
                let u = others + integral;
                let a_feedforward = feedforward_area(p, d, f_demand, m.v_damper);
                let a_demand = a_feedforward * libm::exp(-u.clamp(-20.0, 20.0));
                // the area falls as u rises: on a bound A, u = ln(A_ff/A)
                self.integral = if a_demand > d.a_demand_max {
                    integral_at_saturation(self.integral, integral, libm::log(a_feedforward / d.a_demand_max) - others)
                } else if a_demand < A_DEMAND_MIN {
                    integral_at_saturation(self.integral, integral, libm::log(a_feedforward / A_DEMAND_MIN) - others)
                } else {
                    integral
                };
                // max then min: the same as clamp for ordered bounds, but no panic if they were not
                d.ports
                    .position_for_area(a_demand.max(A_DEMAND_MIN).min(d.a_demand_max))
                    .max(p.x_lap)
                    .min(d.x_demand_max)
            }
            ForceLaw::PaperPid => {
                let rate = self.error_rate.update(error, ts, p.tau_df);
                let integral = self.integral + p.ki_f_pid * error * ts;
                let others = p.kp_f_pid * error + p.kd_f_pid * rate;
                let x = p.x_spool_bias - (others + integral);
                // x falls as the integral rises: on a bound X, integral = x_bias − X − others
                self.integral = if x > d.x_demand_max {
                    integral_at_saturation(self.integral, integral, p.x_spool_bias - d.x_demand_max - others)
                } else if x < p.x_lap {
                    integral_at_saturation(self.integral, integral, p.x_spool_bias - p.x_lap - others)
                } else {
                    integral
                };
                x.max(p.x_lap).min(d.x_demand_max)
            }
        }
    }
}

/// Valve area (m²) that gives the load-cell force `f_demand` (N) at velocity `v` (m/s) in steady
/// state (inverse orifice law with the nominal reservoir pressure), within the valve's range:
/// extension F = Δp·A_a − p_r·A_r, compression F = −(p_r + Δp)·A_r.
pub fn feedforward_area(p: &Parameters, d: &Derived, f_demand: f64, v: f64) -> f64 {
    let cyl = &d.cylinder;
    let (q, dp) = if v >= 0.0 {
        (cyl.a_annulus * v, (f_demand + p.p_reservoir0 * cyl.a_rod) / cyl.a_annulus)
    } else {
        (cyl.a_rod * -v, -f_demand / cyl.a_rod - p.p_reservoir0)
    };
    let area = q / (p.cd_valve * (2.0 * dp.max(1e4) / p.rho).sqrt());
    area.max(A_FEEDFORWARD_MIN).min(d.a_demand_max)
}
