//! The continuous plant: hydraulics, mount, spool and coil, with the damper stroke as a state
//! (docs/physics.md §3). The digital controller is outside; it holds the coil command `i_command`
//! constant between samples.
//!
//! ```text
//! states y = [p_A, p_B, V_g, x_s, v_s, i, x]        (Pa, Pa, m³, m, m/s, A, m)
//! R_A = Q_cv1 − Q_v − Q_rv − Q_l,   R_B = −Q_cv1 + Q_cv2 + Q_l,   a = β(p_A)/V_A,  b = β(p_B)/V_B
//! mount constraint g(δ) = F_h + F_fr:
//!   K_h = a A_a² + b A_p²,  S = a A_a R_A − b A_p R_B,  δ̇ = (K_h v + S)/(g'(δ) + K_h),  ẋ_p = v − δ̇
//! ṗ_A = a (A_a ẋ_p + R_A),  ṗ_B = b (−A_p ẋ_p + R_B),  V̇_g = Q_cv2 − Q_v − Q_rv
//! m_s ẍ_s = F_sol − k_s x_s − c_s ẋ_s − F_flow − F_stop,   i̇ = (i_cmd − i)/τ_coil,   ẋ = v
//! F (load cell) = g(δ) = p_A A_a − p_B A_p + F_e
//! ```
//! The effect switches (`effect_*` parameters) remove terms: air in the oil (α₀ → 0), the mount
//! (rigid: δ = 0), flow force, check-valve cracking pressure; or add them through the
//! [`effects`] catalog: the force F_e in parallel with the piston (seal friction, viscous
//! friction) and the bypass flow Q_l (piston leakage). The amplifier delay is the controller's.

use super::fluid::{effective_bulk_modulus, orifice_flow, smoothstep};
use super::hydraulics::{check_valve_area, reservoir_pressure};
use super::params::{Derived, Parameters};
use super::valve::{flow_force, solenoid_force};
use crate::effects::{self, PlantSignals};
use crate::solver::OdeSystem;
use nalgebra::{SMatrix, SVector};

/// Number of continuous states.
pub const N_STATES: usize = 7;
/// State vector of the plant.
pub type State = SVector<f64, N_STATES>;

/// Index of each state in [`State`].
pub mod idx {
    /// Annulus (extension) chamber gauge pressure (Pa).
    pub const P_A: usize = 0;
    /// Full-bore (compression) chamber gauge pressure (Pa).
    pub const P_B: usize = 1;
    /// Reservoir gas volume (m³).
    pub const V_GAS: usize = 2;
    /// Spool position (m).
    pub const X_SPOOL: usize = 3;
    /// Spool velocity (m/s).
    pub const V_SPOOL: usize = 4;
    /// Coil current (A).
    pub const I_COIL: usize = 5;
    /// Damper stroke (m).
    pub const X_DAMPER: usize = 6;
}

/// Everything the plant computes at one state: derivatives and the measurable quantities.
#[derive(Clone, Copy, Debug, Default)]
pub struct PlantOutputs {
    /// dy/dt.
    pub dydt: State,
    /// Load-cell force (N), tension positive.
    pub force: f64,
    /// Reservoir gauge pressure (Pa).
    pub p_reservoir: f64,
    /// Flow through the proportional valve (m³/s).
    pub q_valve: f64,
    /// Steady flow force on the spool (N).
    pub flow_force: f64,
    /// Mount deflection (m).
    pub delta_mount: f64,
}

/// The plant for one controller sample: parameters, the held damper velocity and coil command.
pub struct Plant<'a> {
    pub p: &'a Parameters,
    pub d: &'a Derived,
    /// Damper extension velocity (m/s) (held over the communication step).
    pub v_damper: f64,
    /// Delayed amplifier command to the coil (A) (held over the controller sample).
    pub i_command: f64,
}

impl Plant<'_> {
    /// Derivatives and outputs at state `y`.
    pub fn evaluate(&self, y: &State) -> PlantOutputs {
        let (p, d) = (self.p, self.d);
        let cyl = &d.cylinder;
        let v = self.v_damper;
        let (p_a, p_b, v_gas, x_s, v_s, i_coil) =
            (y[idx::P_A], y[idx::P_B], y[idx::V_GAS], y[idx::X_SPOOL], y[idx::V_SPOOL], y[idx::I_COIL]);

        let p_r = reservoir_pressure(p.p_reservoir0, p.v_gas0, p.n_polytropic, v_gas);
        let signals = PlantSignals {
            v_damper: v,
            x_damper: y[idx::X_DAMPER],
            p_ext: p_a,
            p_comp: p_b,
            p_reservoir: p_r,
            x_spool: x_s,
        };
        let force = p_a * cyl.a_annulus - p_b * cyl.a_piston + effects::total_force(p, &signals);
        let delta = d.mount.map_or(0.0, |m| m.deflection(force));
        let (vol_a, vol_b) = cyl.volumes(y[idx::X_DAMPER] - delta);

        let orifice = |cd: f64, area: f64, dp: f64| orifice_flow(cd, area, dp, p.rho, p.p_transition);
        let a_valve = d.ports.area(x_s);
        let dp_valve = p_a - p_r;
        let q_valve = orifice(p.cd_valve, a_valve + p.a_valve_leak, dp_valve);
        let dp_cv1 = p_b - p_a;
        let q_cv1 =
            orifice(p.cd_cv, check_valve_area(p.a_cv_leak, p.a_cv_max, d.p_cv_crack, p.p_cv_full, dp_cv1), dp_cv1);
        let dp_cv2 = p_r - p_b;
        let q_cv2 =
            orifice(p.cd_cv, check_valve_area(p.a_cv_leak, p.a_cv_max, d.p_cv_crack, p.p_cv_full, dp_cv2), dp_cv2);
        let q_relief = if dp_valve > p.p_relief {
            orifice(p.cd_valve, p.a_relief * smoothstep((dp_valve - p.p_relief) / p.dp_relief), dp_valve)
        } else {
            0.0
        };
        let q_leak = effects::total_bypass_flow(p, &signals);
        let r_a = q_cv1 - q_valve - q_relief - q_leak;
        let r_b = -q_cv1 + q_cv2 + q_leak;

        let a = effective_bulk_modulus(p_a, p.beta_oil, d.air_fraction, p.n_polytropic) / vol_a;
        let b = effective_bulk_modulus(p_b, p.beta_oil, d.air_fraction, p.n_polytropic) / vol_b;
        let k_h = a * cyl.a_annulus * cyl.a_annulus + b * cyl.a_piston * cyl.a_piston;
        let s = a * cyl.a_annulus * r_a - b * cyl.a_piston * r_b;
        let delta_rate = d.mount.map_or(0.0, |m| (k_h * v + s) / (m.stiffness(delta) + k_h));
        let v_piston = v - delta_rate;

        let f_flow =
            if p.effect_flow_forces { flow_force(p.cd_valve, p.cv_valve, p.theta_jet, a_valve, dp_valve) } else { 0.0 };
        let f_stop = self.stop_force(x_s, v_s);
        let f_sol = solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, i_coil, x_s);

        let mut dydt = State::zeros();
        dydt[idx::P_A] = a * (cyl.a_annulus * v_piston + r_a);
        dydt[idx::P_B] = b * (-cyl.a_piston * v_piston + r_b);
        dydt[idx::V_GAS] = q_cv2 - q_valve - q_relief;
        dydt[idx::X_SPOOL] = v_s;
        dydt[idx::V_SPOOL] = (f_sol - p.k_spool * x_s - p.c_spool * v_s - f_flow - f_stop) / p.m_spool;
        dydt[idx::I_COIL] = (self.i_command - i_coil) / p.tau_coil;
        dydt[idx::X_DAMPER] = v;
        PlantOutputs { dydt, force, p_reservoir: p_r, q_valve, flow_force: f_flow, delta_mount: delta }
    }

    /// Contact force (N) of the spool end stops (spring-damper beyond the travel).
    fn stop_force(&self, x_s: f64, v_s: f64) -> f64 {
        let p = self.p;
        if x_s < p.x_spool_min {
            p.k_stop * (x_s - p.x_spool_min) + p.c_stop * v_s
        } else if x_s > p.x_spool_max {
            p.k_stop * (x_s - p.x_spool_max) + p.c_stop * v_s
        } else {
            0.0
        }
    }

    /// Static equilibrium at rest: both chambers at the reservoir pressure of stroke `x`, spool at
    /// `x_spool` held by the coil current that balances the centring spring.
    pub fn rest_state(p: &Parameters, d: &Derived, x: f64, x_spool: f64) -> State {
        let v_gas = p.v_gas0 + d.cylinder.a_rod * x;
        let p_r = reservoir_pressure(p.p_reservoir0, p.v_gas0, p.n_polytropic, v_gas);
        let i0 = rest_current(p, x_spool);
        State::from([p_r, p_r, v_gas, x_spool, 0.0, i0, x])
    }
}

/// Coil current (A) that holds the spool at `x_spool` against its centring spring.
pub fn rest_current(p: &Parameters, x_spool: f64) -> f64 {
    (p.k_spool * x_spool / solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, 1.0, x_spool)).clamp(0.0, p.i_max)
}

impl OdeSystem<N_STATES> for Plant<'_> {
    fn rhs(&self, y: &State) -> State {
        self.evaluate(y).dydt
    }

    /// Finite differences for the nonlinear columns; the spool-velocity and coil columns are
    /// linear and written out.
    fn jacobian(&self, y: &State, f0: &State) -> SMatrix<f64, N_STATES, N_STATES> {
        const SCALE: [f64; N_STATES] = [1e5, 1e5, 1e-4, 1e-3, 1e-2, 1.0, 1e-2];
        let mut j = SMatrix::<f64, N_STATES, N_STATES>::zeros();
        for col in [idx::P_A, idx::P_B, idx::V_GAS, idx::X_SPOOL, idx::X_DAMPER] {
            let step = 1.5e-8 * y[col].abs().max(SCALE[col]);
            let mut yp = *y;
            yp[col] += step;
            let step = yp[col] - y[col];
            j.set_column(col, &((self.rhs(&yp) - f0) / step));
        }
        let p = self.p;
        let x_s = y[idx::X_SPOOL];
        let c_stop = if x_s < p.x_spool_min || x_s > p.x_spool_max { p.c_stop } else { 0.0 };
        j[(idx::X_SPOOL, idx::V_SPOOL)] = 1.0;
        j[(idx::V_SPOOL, idx::V_SPOOL)] = -(p.c_spool + c_stop) / p.m_spool;
        j[(idx::V_SPOOL, idx::I_COIL)] = solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, 1.0, x_s) / p.m_spool;
        j[(idx::I_COIL, idx::I_COIL)] = -1.0 / p.tau_coil;
        j
    }
}
