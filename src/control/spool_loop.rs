//! Inner loop: discrete PID on spool position plus a feed-forward current that cancels the oil
//! flow force (the paper's "solenoid current proportional to oil flow rate").
//!
//! ```text
//! e = x_dem − x_s ;   ẋ_f = filtered backward difference of x_s (τ_dx)
//! Q̂ = A_a max(v,0) + A_r max(−v,0)                     estimated valve flow
//! i_fc = C_v,nom cosθ sqrt(2ρ Δp̂) Q̂ / K_sol,  Δp̂ = |F|/(A_a or A_r)   (flow_force_compensation 2)
//!        or with Δp̂ ≡ dp_fc_nominal                                 (flow_force_compensation 1, paper-literal)
//! i = Kp e + Ki Σe T − Kd ẋ_f + i_fc + (spool-spring hold in the integrator),  clamp [0, I_max]
//! ```
//! Anti-windup: where the command would leave [0, I_max], the integrator moves only as far as puts it
//! on the bound ([`super::integral_at_saturation`]).

use super::{integral_at_saturation, FilteredDerivative, Measurements};
use crate::physics::params::{Derived, FlowForceCompensation, Parameters};

/// Inner-loop state.
#[derive(Clone, Copy, Debug, Default)]
pub struct SpoolLoop {
    /// Integral term (A).
    pub integral: f64,
    /// Spool velocity estimate.
    pub velocity: FilteredDerivative,
}

impl SpoolLoop {
    /// Loop at rest with its integrator holding `i0` (A).
    pub fn at_rest(i0: f64) -> Self {
        SpoolLoop { integral: i0, velocity: FilteredDerivative::default() }
    }

    /// Current command (A) for spool demand `x_demand` (m).
    pub fn step(&mut self, p: &Parameters, d: &Derived, x_demand: f64, m: Measurements) -> f64 {
        let ts = p.t_sample;
        let error = x_demand - m.x_spool;
        let velocity = self.velocity.update(m.x_spool, ts, p.tau_dx);
        let i_fc = flow_force_compensation(p, d, m);
        let integral = self.integral + p.ki_x * error * ts;
        let others = p.kp_x * error - p.kd_x * velocity + i_fc;
        let i = others + integral;
        self.integral = if i > p.i_max {
            integral_at_saturation(self.integral, integral, p.i_max - others)
        } else if i < 0.0 {
            integral_at_saturation(self.integral, integral, -others)
        } else {
            integral
        };
        i.clamp(0.0, p.i_max)
    }
}

/// Feed-forward current (A) that balances the estimated steady flow force.
pub fn flow_force_compensation(p: &Parameters, d: &Derived, m: Measurements) -> f64 {
    let cyl = &d.cylinder;
    let v = m.v_damper;
    let q_est = cyl.a_annulus * v.max(0.0) + cyl.a_rod * (-v).max(0.0);
    let dp_est = match d.flow_force_compensation {
        FlowForceCompensation::None => return 0.0,
        FlowForceCompensation::FixedGain => p.dp_fc_nominal,
        FlowForceCompensation::Scheduled => m.force.abs() / if v >= 0.0 { cyl.a_annulus } else { cyl.a_rod },
    };
    d.compensation_gain * dp_est.sqrt() * q_est
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    fn at(x_spool: f64, v: f64) -> Measurements {
        Measurements { force: 0.0, x_spool, v_damper: v }
    }

    #[test]
    fn pid_terms_by_hand() {
        let p = Parameters { flow_force_compensation: 0, ..Default::default() };
        let d = p.derive();
        let mut pid = SpoolLoop::at_rest(1.0);
        // first sample: no derivative kick; i = Kp e + (I0 + Ki e T)
        let e = 0.1e-3;
        let i1 = pid.step(&p, &d, 2.0e-3 + e, at(2.0e-3, 0.0));
        assert!((i1 - (p.kp_x * e + 1.0 + p.ki_x * e * p.t_sample)).abs() < 1e-12);
        // spool moved by dx: the filtered derivative term subtracts Kd·a·dx/T
        let dx = 0.05e-3;
        let i2 = pid.step(&p, &d, 2.0e-3 + e, at(2.0e-3 + dx, 0.0));
        let a = p.t_sample / (p.tau_dx + p.t_sample);
        let integral = 1.0 + p.ki_x * e * p.t_sample + p.ki_x * (e - dx) * p.t_sample;
        let hand = p.kp_x * (e - dx) + integral - p.kd_x * a * dx / p.t_sample;
        assert!((i2 - hand).abs() < 1e-12, "{i2} vs {hand}");
    }

    #[test]
    fn clamped_command_holds_the_integrator_on_the_bound() {
        let p = Parameters { flow_force_compensation: 0, ..Default::default() };
        let d = p.derive();
        // a demand far beyond reach: the proportional term alone saturates the amplifier, and the
        // integral stays where it was (neither wound up nor pulled down)
        let mut pid = SpoolLoop::at_rest(1.0);
        for _ in 0..1000 {
            assert_eq!(pid.step(&p, &d, 0.05, at(0.0, 0.0)), p.i_max);
        }
        assert_eq!(pid.integral, 1.0);
        // back in range, the command leaves saturation at once
        assert!(pid.step(&p, &d, 0.0, at(0.0, 0.0)) < p.i_max);
        // an error the proportional term alone does not saturate on: the integral winds up to the
        // value that puts the command on I_max, and stops there (the spool stands still, so the
        // filtered derivative is 0)
        let error = 0.5 * (p.i_max - 1.0) / p.kp_x;
        let mut pid = SpoolLoop::at_rest(1.0);
        for _ in 0..100_000 {
            pid.step(&p, &d, error, at(0.0, 0.0));
        }
        let on_bound = p.i_max - p.kp_x * error;
        assert!((pid.integral - on_bound).abs() <= 1e-12 * p.i_max, "integrator at {}, bound {on_bound}", pid.integral);
    }

    #[test]
    fn flow_force_compensation_modes() {
        let mut p = Parameters::default();
        let m = Measurements { force: 10e3, x_spool: 1e-3, v_damper: 0.5 };
        p.flow_force_compensation = 0;
        assert_eq!(flow_force_compensation(&p, &p.derive(), m), 0.0);
        // scheduled: Cv cos θ sqrt(2ρ Δp) Q / K with Δp = F/A_a, Q = A_a v
        p.flow_force_compensation = 2;
        let d = p.derive();
        let a = d.cylinder.a_annulus;
        let hand = p.cv_compensation * p.theta_jet.cos() * (2.0 * p.rho * 10e3 / a).sqrt() * a * 0.5 / p.k_sol;
        assert!((flow_force_compensation(&p, &d, m) - hand).abs() < 1e-12);
    }
}
