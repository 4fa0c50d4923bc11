//! Inner loop: discrete PID on spool position plus a feed-forward current that cancels the oil
//! flow force (the paper's "solenoid current proportional to oil flow rate").
//!
//! ```text
//! e = x_dem − x_s ;   ẋ_f = filtered backward difference of x_s (τ_dx)
//! Q̂ = A_a max(v,0) + A_r max(−v,0)                     estimated valve flow
//! i_fc = C_v cosθ sqrt(2ρ Δp̂) Q̂ / K_sol,  Δp̂ = |F|/(A_a or A_r)   (fc_mode 2)
//!        or with Δp̂ ≡ dp_fc_nominal                                 (fc_mode 1, paper-literal)
//! i = Kp e + Ki Σe T − Kd ẋ_f + i_fc + (spool-spring hold in the integrator),  clamp [0, I_max]
//! ```
//! Anti-windup: the integrator only moves while the command is not clamped.

use super::{FilteredDerivative, Measurements};
use crate::physics::params::{Derived, FlowForceCompensation, Parameters};

/// Inner-loop state.
#[derive(Clone, Copy, Debug, Default)]
pub struct SpoolLoop {
    /// Integral term [A].
    pub integral: f64,
    /// Spool velocity estimate.
    pub velocity: FilteredDerivative,
}

impl SpoolLoop {
    /// Loop at rest with its integrator holding `i0` [A].
    pub fn at_rest(i0: f64) -> Self {
        SpoolLoop { integral: i0, velocity: FilteredDerivative::default() }
    }

    /// Current command [A] for spool demand `x_demand` [m].
    pub fn step(&mut self, p: &Parameters, d: &Derived, x_demand: f64, m: Measurements) -> f64 {
        let ts = p.t_sample;
        let error = x_demand - m.x_spool;
        let velocity = self.velocity.update(m.x_spool, ts, p.tau_dx);
        let i_fc = flow_force_compensation(p, d, m);
        let integral = self.integral + p.ki_x * error * ts;
        let i = p.kp_x * error + integral - p.kd_x * velocity + i_fc;
        if i > 0.0 && i < p.i_max {
            self.integral = integral;
        }
        i.clamp(0.0, p.i_max)
    }
}

/// Feed-forward current [A] that balances the estimated steady flow force.
pub fn flow_force_compensation(p: &Parameters, d: &Derived, m: Measurements) -> f64 {
    let cyl = &d.cylinder;
    let v = m.v_damper;
    let q_est = cyl.a_annulus * v.max(0.0) + cyl.a_rod * (-v).max(0.0);
    let dp_est = match d.fc_mode {
        FlowForceCompensation::None => return 0.0,
        FlowForceCompensation::FixedGain => p.dp_fc_nominal,
        FlowForceCompensation::Scheduled => m.force.abs() / if v >= 0.0 { cyl.a_annulus } else { cyl.a_rod },
    };
    p.cv_valve * p.theta_jet.cos() * (2.0 * p.rho * dp_est).sqrt() * q_est / p.k_sol
}
