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
//! [`crate::effects`] catalog: the force F_e in parallel with the piston (seal friction, viscous
//! friction) and the bypass flow Q_l (piston leakage). The amplifier delay is the controller's.

use super::fluid::{
    effective_bulk_modulus_and_slope, orifice_flow_partials, smoothstep, smoothstep_slope, viscosity_ratio, P_ATM,
};
use super::hydraulics::{check_valve_area, check_valve_area_slope, reservoir_pressure_and_slope, VOLUME_FLOOR};
use super::params::{Derived, Parameters};
use super::valve::{flow_force, solenoid_force};
use crate::effects::{numeric_gradient, PlantSignals};
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
    /// Oil temperature (K), the input `T_oil` (held over the communication step).
    pub t_oil: f64,
    /// The damper's acceleration (m/s²), the input `a_damper`: the slope of `v_damper` over the
    /// step, which the effects' forces' rate carries into the mount (§3.4).
    pub a_damper: f64,
}

/// The plant linearised at a state: the Jacobian ∂f/∂y and the derivative ∂f/∂v with respect to
/// the damper velocity (for a velocity that moves over a step: ∂f/∂t = ∂f/∂v · a).
#[derive(Clone, Copy, Debug)]
pub struct Linearisation {
    pub jacobian: SMatrix<f64, N_STATES, N_STATES>,
    pub df_dv: State,
}

impl Linearisation {
    /// An all-zero linearisation, for a buffer that [`Plant::linearise`] fills.
    pub fn zeros() -> Self {
        Linearisation { jacobian: SMatrix::zeros(), df_dv: State::zeros() }
    }
}

/// Partial derivatives of one quantity with respect to the states it can depend on, then the
/// damper velocity: the columns [`G_P_A`] … [`G_DV`]. The spool velocity and the coil current reach
/// only the spool's own row of the Jacobian, written there directly; a gradient over every state
/// would carry two zero columns through every operation of the linearisation.
type Grad = SVector<f64, 6>;
const G_P_A: usize = 0;
const G_P_B: usize = 1;
const G_V_GAS: usize = 2;
const G_X_SPOOL: usize = 3;
const G_X_DAMPER: usize = 4;
/// The damper velocity's column.
const G_DV: usize = 5;
/// The state of each gradient column but the velocity's.
const GRAD_STATES: [usize; 5] = [idx::P_A, idx::P_B, idx::V_GAS, idx::X_SPOOL, idx::X_DAMPER];

/// The gradient with `value` in column `i` and zeros elsewhere. Built, not multiplied out: IEEE
/// arithmetic cannot drop a product 0·x or a sum x + 0 (x may be infinite, or −0), so a unit
/// vector times `value`, or added to a gradient, cost an operation per column.
fn basis(i: usize, value: f64) -> Grad {
    let mut g = Grad::zeros();
    g[i] = value;
    g
}

/// `g` with `value` added to its column `i` alone (see [`basis`]).
fn plus(mut g: Grad, i: usize, value: f64) -> Grad {
    g[i] += value;
    g
}

impl Plant<'_> {
    /// Derivatives and outputs at state `y`.
    pub fn evaluate(&self, y: &State) -> PlantOutputs {
        self.evaluate_with::<false>(y, None)
    }

    /// The load-cell force (N) at state `y`: [`PlantOutputs::force`] alone, which the hydraulic
    /// pressures and the effects' forces give without the rest of the evaluation.
    pub fn force(&self, y: &State) -> f64 {
        let (p, d) = (self.p, self.d);
        let hydraulic = y[idx::P_A] * d.cylinder.a_annulus - y[idx::P_B] * d.cylinder.a_piston;
        if !d.effects.adds_force() {
            return hydraulic;
        }
        let thermal = self.thermal();
        let p_r = self.reservoir(y[idx::V_GAS], thermal.gas_ratio).0;
        hydraulic + d.effects.force(p, &self.signals(y, p_r, thermal.viscosity_ratio))
    }

    /// What the effects see at state `y` with the reservoir at `p_r` (Pa) and the oil's viscosity
    /// `viscosity_ratio` times its reference's.
    fn signals(&self, y: &State, p_r: f64, viscosity_ratio: f64) -> PlantSignals {
        use idx::*;
        PlantSignals {
            v_damper: self.v_damper,
            x_damper: y[X_DAMPER],
            p_ext: y[P_A],
            p_comp: y[P_B],
            p_reservoir: p_r,
            x_spool: y[X_SPOOL],
            temperature: self.t_oil,
            viscosity_ratio,
        }
    }

    /// The oil's temperature as it acts (docs/physics.md §3.9): the viscosity over its reference
    /// value, and the gas's absolute temperature over its reference; both 1 unless
    /// `oil_temperature` is on.
    #[inline]
    fn thermal(&self) -> Thermal {
        if self.d.oil_temperature {
            Thermal {
                viscosity_ratio: viscosity_ratio(self.p.visc_temp_coeff, self.t_oil, self.p.t_ref),
                gas_ratio: self.t_oil / self.p.t_ref,
            }
        } else {
            Thermal { viscosity_ratio: 1.0, gas_ratio: 1.0 }
        }
    }

    /// The reservoir's gauge pressure (Pa) at gas volume `v_gas` (m³) and its slope (Pa/m³), the
    /// gas at `gas_ratio` times its reference absolute temperature.
    #[inline]
    fn reservoir(&self, v_gas: f64, gas_ratio: f64) -> (f64, f64) {
        // without the gas spring (effect gas_charge off) the pressure stays at the pre-charge
        let (p_r, slope) = if self.d.gas_spring {
            reservoir_pressure_and_slope(&self.d.gas, v_gas)
        } else {
            (self.p.p_reservoir0, 0.0)
        };
        if gas_ratio == 1.0 {
            (p_r, slope)
        } else {
            ((p_r + P_ATM) * gas_ratio - P_ATM, slope * gas_ratio)
        }
    }

    /// Derivatives and outputs at state `y`, and the plant linearised there. The derivatives are
    /// written out with the values (chain rule through every intermediate), so the Jacobian costs
    /// about one more evaluation instead of five finite differences, and it is exact.
    pub fn evaluate_linearised(&self, y: &State) -> (PlantOutputs, Linearisation) {
        let mut lin = Linearisation::zeros();
        let out = self.linearise(y, &mut lin);
        (out, lin)
    }

    /// [`Plant::evaluate_linearised`] into the caller's `lin`: the integrator keeps one in place
    /// rather than move its 440 bytes at every step.
    pub fn linearise(&self, y: &State, lin: &mut Linearisation) -> PlantOutputs {
        self.evaluate_with::<true>(y, Some(lin))
    }

    /// The one body of [`Plant::evaluate`] and [`Plant::linearise`]: the equations
    /// ([`Plant::intermediates`]) give the derivatives and the outputs; when `JAC`, their
    /// gradients ([`Plant::write_linearisation`]) give the linearisation in `lin`. The gradients
    /// read the equations' values and change none, so that the two are written apart and the
    /// evaluation without `JAC` computes no gradient at all.
    #[inline(always)]
    fn evaluate_with<const JAC: bool>(&self, y: &State, lin: Option<&mut Linearisation>) -> PlantOutputs {
        let q = self.intermediates(y);
        let out = PlantOutputs {
            dydt: self.derivatives(y, &q),
            force: q.force,
            p_reservoir: q.p_r,
            q_valve: q.flows.q_valve,
            flow_force: q.spool.f_flow,
            delta_mount: q.delta,
        };
        if let Some(lin) = lin.filter(|_| JAC) {
            self.write_linearisation(y, &q, lin);
        }
        out
    }

    /// The plant's equations at state `y` (docs/physics.md §3): every intermediate quantity the
    /// derivatives, the outputs and the linearisation are made of. A quotient by a parameter or
    /// by a value known early (a volume, a denominator shared by several quotients) is a product
    /// by its reciprocal: the division then runs beside the chain of dependent operations instead
    /// of in it (3–4 % of the time, with the controller's).
    #[inline(always)]
    fn intermediates(&self, y: &State) -> Intermediates {
        use idx::*;
        let (p, d) = (self.p, self.d);
        let cyl = &d.cylinder;
        let (p_a, p_b, x_s) = (y[P_A], y[P_B], y[X_SPOOL]);
        let thermal = self.thermal();
        let (p_r, dpr_dvg) = self.reservoir(y[V_GAS], thermal.gas_ratio);
        let signals = self.signals(y, p_r, thermal.viscosity_ratio);

        let force = p_a * cyl.a_annulus - p_b * cyl.a_piston + d.effects.force(p, &signals);
        let (delta, mount_stiffness) = match d.mount {
            Some(m) => {
                let delta = m.deflection(force);
                (delta, m.stiffness(delta))
            }
            None => (0.0, f64::INFINITY),
        };
        let (vol_a, vol_b) = cyl.volumes(y[X_DAMPER] - delta);
        let flows = self.flows(x_s, p_a, p_b, p_r, &signals);
        let r_a = flows.q_cv1 - flows.q_valve - flows.q_relief - flows.q_leak;
        let r_b = -flows.q_cv1 + flows.q_cv2 + flows.q_leak - flows.q_base;

        let ch = self.chambers(p_a, p_b, vol_a, vol_b);
        let (a, b) = (ch.a, ch.b);
        let (aa, ap) = (cyl.a_annulus, cyl.a_piston);
        let k_h = a * aa * aa + b * ap * ap;
        let s_flow = a * aa * r_a - b * ap * r_b;
        // the effects' forces change as the stroke and the velocity move (an end stop, friction):
        // the mount carries that rate too, Ḟ_e = ∂F_e/∂x·v + ∂F_e/∂v·a
        let effects_rate = if d.mount.is_some() && d.effects.adds_force() { self.effects_rate(&signals) } else { 0.0 };
        let (delta_rate, per_denominator) = if d.mount.is_some() {
            let per_denominator = 1.0 / (mount_stiffness + k_h);
            ((k_h * self.v_damper + s_flow + effects_rate) * per_denominator, per_denominator)
        } else {
            (0.0, 0.0)
        };
        Intermediates {
            dpr_dvg,
            p_r,
            signals,
            force,
            delta,
            mount_stiffness,
            vol_a,
            vol_b,
            r_a,
            r_b,
            ch,
            k_h,
            delta_rate,
            per_denominator,
            v_piston: self.v_damper - delta_rate,
            spool: self.spool_forces(y, &flows),
            flows,
        }
    }

    /// Each chamber's stiffness β/V at pressures `p_a`, `p_b` (Pa) and volumes `vol_a`, `vol_b`
    /// (m³), with what its gradient needs.
    #[inline(always)]
    fn chambers(&self, p_a: f64, p_b: f64, vol_a: f64, vol_b: f64) -> Chambers {
        let oil = &self.d.oil;
        let (beta_a, dbeta_a) = effective_bulk_modulus_and_slope(p_a, oil);
        let (beta_b, dbeta_b) = effective_bulk_modulus_and_slope(p_b, oil);
        let (per_vol_a, per_vol_b) = (1.0 / vol_a, 1.0 / vol_b);
        Chambers { dbeta_a, dbeta_b, per_vol_a, per_vol_b, a: beta_a * per_vol_a, b: beta_b * per_vol_b }
    }

    /// The forces on the spool at state `y` (N) but its spring's and damping's, with the flows
    /// `flows` through the valve.
    #[inline(always)]
    fn spool_forces(&self, y: &State, flows: &Flows) -> SpoolForces {
        use idx::*;
        let (p, d) = (self.p, self.d);
        let x_s = y[X_SPOOL];
        let flow_force_on = p.effect_flow_forces && flows.dp_valve > 0.0;
        let f_flow = if flow_force_on { flow_force(d.flow_force_gain, flows.a_valve, flows.dp_valve) } else { 0.0 };
        let (f_stop, k_stop, c_stop) = self.stop_force(x_s, y[V_SPOOL]);
        let f_sol = solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, y[I_COIL], x_s);
        SpoolForces { flow_force_on, f_flow, f_stop, k_stop, c_stop, f_sol }
    }

    /// The flows (m³/s) at spool position `x_s` (m), chamber pressures `p_a`, `p_b` and reservoir
    /// pressure `p_r` (Pa): the proportional valve, the check valves, the relief valve and the
    /// effects' bypass and base flows, with the partial derivatives their gradients need.
    #[inline(always)]
    fn flows(&self, x_s: f64, p_a: f64, p_b: f64, p_r: f64, signals: &PlantSignals) -> Flows {
        let (p, d) = (self.p, self.d);
        let orifice = |cd: f64, area: f64, dp: f64| orifice_flow_partials(cd, area, dp, p.rho, p.p_transition);
        let a_valve = d.ports.area(x_s);
        let dp_valve = p_a - p_r;
        let (q_valve, dqv_da, dqv_ddp) = orifice(p.cd_valve, a_valve + p.a_valve_leak, dp_valve);
        let check_valve = |dp: f64| {
            let (q, dq_da, dq_ddp) =
                orifice(p.cd_cv, check_valve_area(p.a_cv_leak, p.a_cv_max, d.p_cv_crack, p.p_cv_full, dp), dp);
            (q, dq_ddp + dq_da * check_valve_area_slope(p.a_cv_max, d.p_cv_crack, p.p_cv_full, dp))
        };
        let (q_cv1, dq1) = check_valve(p_b - p_a);
        let (q_cv2, dq2) = check_valve(p_r - p_b);
        let (q_relief, relief) = if dp_valve > p.p_relief {
            let per_range = 1.0 / p.dp_relief;
            let u = (dp_valve - p.p_relief) * per_range;
            let (q, dq_da, dq_ddp) = orifice(p.cd_valve, p.a_relief * smoothstep(u), dp_valve);
            (q, Some(Relief { per_range, u, dq_da, dq_ddp }))
        } else {
            (0.0, None)
        };
        let q_leak = d.effects.bypass_flow(p, signals);
        let q_base = if d.effects.adds_base_flow() { d.effects.base_flow(p, signals) } else { 0.0 };
        Flows { a_valve, dp_valve, q_valve, dqv_da, dqv_ddp, q_cv1, dq1, q_cv2, dq2, q_relief, relief, q_leak, q_base }
    }

    /// The rate of the effects' force (N/s) at `s` as the stroke and the velocity move:
    /// Ḟ_e = ∂F_e/∂x·v + ∂F_e/∂v·a.
    #[inline(always)]
    fn effects_rate(&self, s: &PlantSignals) -> f64 {
        let g = self.d.effects.force_gradient(self.p, s);
        g.x_damper * s.v_damper + g.v_damper * self.a_damper
    }

    /// dy/dt at state `y` from the plant's intermediate quantities `q`.
    #[inline(always)]
    fn derivatives(&self, y: &State, q: &Intermediates) -> State {
        use idx::*;
        let (p, d) = (self.p, self.d);
        let (aa, ap) = (d.cylinder.a_annulus, d.cylinder.a_piston);
        let (x_s, v_s) = (y[X_SPOOL], y[V_SPOOL]);
        let mut dydt = State::zeros();
        dydt[P_A] = q.ch.a * (aa * q.v_piston + q.r_a);
        dydt[P_B] = q.ch.b * (-ap * q.v_piston + q.r_b);
        dydt[V_GAS] = q.flows.q_cv2 - q.flows.q_valve - q.flows.q_relief - q.flows.q_base;
        dydt[X_SPOOL] = v_s;
        dydt[V_SPOOL] = if d.valve_held {
            0.0
        } else {
            (q.spool.f_sol - p.k_spool * x_s - p.c_spool * v_s - q.spool.f_flow - q.spool.f_stop) * (1.0 / p.m_spool)
        };
        dydt[I_COIL] = self.evaluate_coil(y);
        dydt[X_DAMPER] = self.v_damper;
        dydt
    }

    /// The linearisation at state `y` into `lin`: each intermediate quantity's gradient (a
    /// [`Grad`], `d_` and its name), by the chain rule through the equations of
    /// [`Plant::intermediates`], whose values `q` holds.
    #[inline(always)]
    fn write_linearisation(&self, y: &State, q: &Intermediates, lin: &mut Linearisation) {
        use idx::*;
        let (p, d) = (self.p, self.d);
        let cyl = &d.cylinder;
        let (aa, ap) = (cyl.a_annulus, cyl.a_piston);
        let d_force = plus(
            plus(self.signal_gradient(q.dpr_dvg, d.effects.force_gradient(p, &q.signals)), G_P_A, cyl.a_annulus),
            G_P_B,
            -cyl.a_piston,
        );
        let d_delta = if d.mount.is_some() { d_force * (1.0 / q.mount_stiffness) } else { Grad::zeros() };
        let d_xp = plus(-d_delta, G_X_DAMPER, 1.0);
        // the volumes' floor has no slope
        let d_vol_a = if q.vol_a > VOLUME_FLOOR { -d_xp * cyl.a_annulus } else { Grad::zeros() };
        let d_vol_b = if q.vol_b > VOLUME_FLOOR { d_xp * cyl.a_piston } else { Grad::zeros() };
        let f = self.flow_gradients(y[X_SPOOL], q);
        let d_r_a = f.d_q_cv1 - f.d_q_valve - f.d_q_relief - f.d_q_leak;
        let d_r_b = -f.d_q_cv1 + f.d_q_cv2 + f.d_q_leak - f.d_q_base;
        let ch = &q.ch;
        let d_a = plus(d_vol_a * -(ch.a * ch.per_vol_a), G_P_A, ch.dbeta_a * ch.per_vol_a);
        let d_b = plus(d_vol_b * -(ch.b * ch.per_vol_b), G_P_B, ch.dbeta_b * ch.per_vol_b);
        let d_delta_rate = if d.mount.is_some() {
            let d_effects_rate = if d.effects.adds_force() {
                self.signal_gradient(q.dpr_dvg, numeric_gradient(&q.signals, |s| self.effects_rate(s)))
            } else {
                Grad::zeros()
            };
            let k3 = d.mount.map_or(0.0, |m| m.k3);
            let d_k_h = d_a * (aa * aa) + d_b * (ap * ap);
            let d_s = (d_a * q.r_a + d_r_a * ch.a) * aa - (d_b * q.r_b + d_r_b * ch.b) * ap;
            let d_stiffness = d_delta * (6.0 * k3 * q.delta);
            (plus(d_k_h * self.v_damper, G_DV, q.k_h) + d_s + d_effects_rate - (d_stiffness + d_k_h) * q.delta_rate)
                * q.per_denominator
        } else {
            Grad::zeros()
        };
        let d_v_piston = plus(-d_delta_rate, G_DV, 1.0);
        let d_f_flow = if q.spool.flow_force_on {
            (f.d_a_valve * q.flows.dp_valve + f.d_dp_valve * q.flows.a_valve) * d.flow_force_gain
        } else {
            Grad::zeros()
        };

        // the rows over the gradient's columns; x_s's and x's rows, and the spool's entries for
        // v_s and i, are written into the Jacobian by `write_rows`
        let rows: [(usize, Grad); 4] = [
            (P_A, d_a * (aa * q.v_piston + q.r_a) + (d_v_piston * aa + d_r_a) * ch.a),
            (P_B, d_b * (-ap * q.v_piston + q.r_b) + (-d_v_piston * ap + d_r_b) * ch.b),
            (V_GAS, f.d_q_cv2 - f.d_q_valve - f.d_q_relief - f.d_q_base),
            (V_SPOOL, {
                let mut g = -d_f_flow;
                g[G_X_SPOOL] += p.k_sol * y[I_COIL] * p.kappa_sol / p.x_spool_max - p.k_spool - q.spool.k_stop;
                if d.valve_held {
                    Grad::zeros()
                } else {
                    g * (1.0 / p.m_spool)
                }
            }),
        ];
        self.write_rows(y[X_SPOOL], q.spool.c_stop, rows, lin);
    }

    /// A gradient over the effects' signals (∂/∂ each signal) as a gradient over the states and
    /// the velocity, the reservoir pressure's slope being `dpr_dvg` (Pa/m³).
    #[inline(always)]
    fn signal_gradient(&self, dpr_dvg: f64, g: PlantSignals) -> Grad {
        // the reservoir pressure's gradient has its V_gas column alone
        let mut out = basis(G_DV, g.v_damper);
        out[G_V_GAS] += dpr_dvg * g.p_reservoir;
        out[G_X_DAMPER] += g.x_damper;
        out[G_P_A] += g.p_ext;
        out[G_P_B] += g.p_comp;
        out[G_X_SPOOL] += g.x_spool;
        out
    }

    /// The flows' gradients at spool position `x_s` (m), from the flows' partial derivatives in
    /// `q`.
    #[inline(always)]
    fn flow_gradients(&self, x_s: f64, q: &Intermediates) -> FlowGradients {
        let (p, d) = (self.p, self.d);
        let fl = &q.flows;
        let d_pr = basis(G_V_GAS, q.dpr_dvg);
        let d_a_valve = basis(G_X_SPOOL, d.ports.area_slope(x_s));
        let d_dp_valve = plus(-d_pr, G_P_A, 1.0);
        let d_q_relief = match fl.relief {
            Some(r) => d_dp_valve * (r.dq_ddp + r.dq_da * p.a_relief * smoothstep_slope(r.u) * r.per_range),
            None => Grad::zeros(),
        };
        FlowGradients {
            d_a_valve,
            d_dp_valve,
            d_q_valve: d_a_valve * fl.dqv_da + d_dp_valve * fl.dqv_ddp,
            d_q_cv1: plus(basis(G_P_B, fl.dq1), G_P_A, -fl.dq1),
            d_q_cv2: plus(basis(G_V_GAS, q.dpr_dvg * fl.dq2), G_P_B, -fl.dq2),
            d_q_relief,
            d_q_leak: self.signal_gradient(q.dpr_dvg, d.effects.bypass_flow_gradient(p, &q.signals)),
            d_q_base: if d.effects.adds_base_flow() {
                self.signal_gradient(q.dpr_dvg, d.effects.base_flow_gradient(p, &q.signals))
            } else {
                Grad::zeros()
            },
        }
    }

    /// Writes the Jacobian and ∂f/∂v into `lin`: the `rows` over the gradient's columns, then the
    /// entries the gradients do not carry (the spool's velocity and coil current at spool
    /// position `x_s`, m, with the end stops' damping `c_stop`, N·s/m; the coil; the stroke).
    #[inline(always)]
    fn write_rows(&self, x_s: f64, c_stop: f64, rows: [(usize, Grad); 4], lin: &mut Linearisation) {
        use idx::*;
        let p = self.p;
        let Linearisation { jacobian, df_dv } = lin;
        // (assigned: nalgebra's `fill` goes element by element through an iterator)
        *jacobian = SMatrix::zeros();
        *df_dv = State::zeros();
        for (r, g) in rows {
            for (k, &c) in GRAD_STATES.iter().enumerate() {
                jacobian[(r, c)] = g[k];
            }
            df_dv[r] = g[G_DV];
        }
        if !self.d.valve_held {
            jacobian[(V_SPOOL, V_SPOOL)] = -(p.c_spool + c_stop) / p.m_spool;
            jacobian[(V_SPOOL, I_COIL)] = solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, 1.0, x_s) / p.m_spool;
        }
        jacobian[(X_SPOOL, V_SPOOL)] = 1.0;
        jacobian[(I_COIL, I_COIL)] = -1.0 / p.tau_coil;
        df_dv[X_DAMPER] = 1.0;
    }

    /// The coil current's derivative (A/s) at `y`: the one component that depends on the coil
    /// command.
    fn evaluate_coil(&self, y: &State) -> f64 {
        (self.i_command - y[idx::I_COIL]) * (1.0 / self.p.tau_coil)
    }

    /// Contact force (N) of the spool end stops (spring-damper beyond the travel), with the
    /// stiffness (N/m) and damping (N·s/m) in effect.
    fn stop_force(&self, x_s: f64, v_s: f64) -> (f64, f64, f64) {
        let p = self.p;
        let limit = if x_s < p.x_spool_min {
            p.x_spool_min
        } else if x_s > p.x_spool_max {
            p.x_spool_max
        } else {
            return (0.0, 0.0, 0.0);
        };
        (p.k_stop * (x_s - limit) + p.c_stop * v_s, p.k_stop, p.c_stop)
    }

    /// Static equilibrium at rest: both chambers at the reservoir pressure of stroke `x` and this
    /// plant's oil temperature, spool at `x_spool` held by the coil current that balances the
    /// centring spring.
    pub fn rest_state(&self, x: f64, x_spool: f64) -> State {
        let (p, d) = (self.p, self.d);
        let v_gas = p.v_gas0 + d.cylinder.a_rod * x;
        let p_r = self.reservoir(v_gas, self.thermal().gas_ratio).0;
        let i0 = rest_current(p, x_spool);
        State::from([p_r, p_r, v_gas, x_spool, 0.0, i0, x])
    }
}

/// The plant's intermediate quantities at one state ([`Plant::intermediates`]): what the
/// derivatives and the outputs are made of, and the values the linearisation's chain rule reads.
#[derive(Clone, Copy, Debug)]
struct Intermediates {
    /// The reservoir pressure's slope with the gas volume (Pa/m³).
    dpr_dvg: f64,
    /// Reservoir gauge pressure (Pa).
    p_r: f64,
    /// What the effects see.
    signals: PlantSignals,
    /// Load-cell force (N).
    force: f64,
    /// Mount deflection (m) and the mount's tangent stiffness there (N/m; infinite when rigid).
    delta: f64,
    mount_stiffness: f64,
    /// Chamber volumes (m³).
    vol_a: f64,
    vol_b: f64,
    flows: Flows,
    /// Net flows into the annulus and the full-bore chambers but for the piston's (m³/s).
    r_a: f64,
    r_b: f64,
    ch: Chambers,
    /// Hydraulic stiffness seen by the mount, a·A_a² + b·A_p² (N/m).
    k_h: f64,
    /// Mount deflection rate (m/s) and 1/(g'(δ) + K_h) (m/N; 0 without a mount).
    delta_rate: f64,
    per_denominator: f64,
    /// Piston velocity relative to the cylinder (m/s).
    v_piston: f64,
    spool: SpoolForces,
}

/// The chambers' stiffness ([`Plant::chambers`]).
#[derive(Clone, Copy, Debug)]
struct Chambers {
    /// The effective bulk moduli's slopes with pressure (-).
    dbeta_a: f64,
    dbeta_b: f64,
    /// Reciprocal chamber volumes (1/m³).
    per_vol_a: f64,
    per_vol_b: f64,
    /// β/V of each chamber (Pa/m³).
    a: f64,
    b: f64,
}

/// The forces on the spool ([`Plant::spool_forces`]).
#[derive(Clone, Copy, Debug)]
struct SpoolForces {
    /// Whether the flow force acts (on, and flow out of the annulus).
    flow_force_on: bool,
    /// Flow force on the spool (N).
    f_flow: f64,
    /// End-stop force (N), stiffness (N/m) and damping (N·s/m).
    f_stop: f64,
    k_stop: f64,
    c_stop: f64,
    /// Solenoid force (N).
    f_sol: f64,
}

/// The flows at one state ([`Plant::flows`]), with the partial derivatives their gradients need.
#[derive(Clone, Copy, Debug)]
struct Flows {
    /// Proportional valve's open area (m²) and pressure drop (Pa).
    a_valve: f64,
    dp_valve: f64,
    /// Flow through the proportional valve (m³/s) and its partials by area (m/s) and by pressure
    /// drop (m³/(s·Pa)).
    q_valve: f64,
    dqv_da: f64,
    dqv_ddp: f64,
    /// Flows through the piston's and the foot's check valves (m³/s), and their slopes with
    /// their pressure drops (m³/(s·Pa)).
    q_cv1: f64,
    dq1: f64,
    q_cv2: f64,
    dq2: f64,
    /// Flow through the relief valve (m³/s); where it is open, what its gradient needs.
    q_relief: f64,
    relief: Option<Relief>,
    /// The effects' bypass flow across the piston and base flow out of the full-bore chamber
    /// (m³/s).
    q_leak: f64,
    q_base: f64,
}

/// An open relief valve: what its flow's gradient needs.
#[derive(Clone, Copy, Debug)]
struct Relief {
    /// 1 / the pressure range over which it opens (1/Pa).
    per_range: f64,
    /// How far open, over that range (-).
    u: f64,
    /// The flow's partials by area (m/s) and by pressure drop (m³/(s·Pa)).
    dq_da: f64,
    dq_ddp: f64,
}

/// The flows' gradients ([`Plant::flow_gradients`]).
struct FlowGradients {
    d_a_valve: Grad,
    d_dp_valve: Grad,
    d_q_valve: Grad,
    d_q_cv1: Grad,
    d_q_cv2: Grad,
    d_q_relief: Grad,
    d_q_leak: Grad,
    d_q_base: Grad,
}

/// The oil temperature's action (see [`Plant::thermal`]).
#[derive(Clone, Copy, Debug)]
struct Thermal {
    /// Viscosity over its value at `T_ref` (-).
    viscosity_ratio: f64,
    /// Absolute temperature over `T_ref` (-), for the reservoir's gas.
    gas_ratio: f64,
}

impl Plant<'_> {}

/// Coil current (A) that holds the spool at `x_spool` against its centring spring.
pub fn rest_current(p: &Parameters, x_spool: f64) -> f64 {
    (p.k_spool * x_spool / solenoid_force(p.k_sol, p.kappa_sol, p.x_spool_max, 1.0, x_spool)).clamp(0.0, p.i_max)
}

/// Switches on every effect of the catalog, with the end stops within the strokes that
/// [`random_state`] draws, for the tests that must cover every effect.
#[cfg(test)]
pub(crate) fn every_effect_on(p: &mut Parameters) {
    for e in crate::effects::CATALOG {
        let switch = format!("effect_{}", e.info().key);
        let var = crate::model_description::BooleanVar::ALL.into_iter().find(|v| v.name() == switch);
        *p.boolean_mut(var.expect("every effect has a switch")).expect("a parameter") = true;
    }
    p.x_end_stop = 0.02;
}

/// A random state across the plant's regimes, drawn around `rest` with `uniform` (numbers in
/// [0, 1)): check valves shut, cracking and open, the relief valve, the valve shut and open, the
/// spool on its stops, chambers above and below the reservoir. `chambers_near_equal` puts p_B
/// within ±1 bar of p_A, where the piston's check valve cracks. For the tests that sweep states.
#[cfg(test)]
pub(crate) fn random_state(rest: &State, uniform: &mut impl FnMut() -> f64, chambers_near_equal: bool) -> State {
    use idx::*;
    let mut y = *rest;
    y[P_A] = -0.5e5 + 150e5 * uniform();
    y[P_B] = if chambers_near_equal { y[P_A] + 2e5 * (uniform() - 0.5) } else { -0.5e5 + 60e5 * uniform() };
    y[V_GAS] = rest[V_GAS] * (0.8 + 0.4 * uniform());
    y[X_SPOOL] = -0.5e-3 + 7e-3 * uniform();
    y[V_SPOOL] = 0.2 * (uniform() - 0.5);
    y[I_COIL] = 2.0 * uniform();
    y[X_DAMPER] = 0.08 * (uniform() - 0.5);
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The written-out Jacobian and ∂f/∂v against central differences of `evaluate`, over states
    /// that cross every regime: check valves shut, cracking and open, the relief valve, the valve
    /// shut and open, the spool on its stops, chambers above and below the reservoir, with every
    /// effect on and off.
    #[test]
    fn linearisation_matches_central_differences() {
        const SCALE: [f64; N_STATES + 1] = [1e5, 1e5, 1e-5, 1e-4, 1e-2, 1e-1, 1e-2, 1e-2];
        let mut uniform = crate::test_rng::uniform(0x2545_f491_4f6c_dd1d);
        for (all_on, held) in [(false, false), (true, false), (true, true)] {
            let mut p = Parameters::default();
            if all_on {
                every_effect_on(&mut p);
            }
            if held {
                p.control_mode = 2;
            }
            let d = p.derive();
            let t_oil = if all_on { 335.0 } else { 293.15 };
            for case in 0..400 {
                let rest =
                    Plant { p: &p, d: &d, v_damper: 0.0, i_command: 0.7, t_oil, a_damper: 0.0 }.rest_state(0.0, 1e-3);
                let y = random_state(&rest, &mut uniform, case % 3 == 0);
                let v = 1.5 * (uniform() - 0.5);
                let plant = |v: f64| Plant { p: &p, d: &d, v_damper: v, i_command: 0.7, t_oil, a_damper: 3.0 };
                let (out, lin) = plant(v).evaluate_linearised(&y);
                assert_eq!(out.dydt, plant(v).evaluate(&y).dydt);
                for col in 0..=N_STATES {
                    // 1e-5 of the scale balances truncation against rounding: at 1e-6 the rounding
                    // of a pressure's rate (terms of 1e13 Pa/m³ times flows that nearly cancel)
                    // reached the tolerance, and twice as many entries were skipped as noisy
                    let h = 1e-5 * SCALE[col];
                    let f = |s: f64| {
                        let mut yp = y;
                        if col < N_STATES {
                            yp[col] += s * h;
                            plant(v).evaluate(&yp).dydt
                        } else {
                            plant(v + s * h).evaluate(&yp).dydt
                        }
                    };
                    let fd = (f(1.0) - f(-1.0)) / (2.0 * h);
                    // a kink (check valve or stop edge) within ±h makes the difference meaningless
                    let one_sided = (f(1.0) - f(0.0)) / h - (f(0.0) - f(-1.0)) / h;
                    for row in 0..N_STATES {
                        let exact = if col < N_STATES { lin.jacobian[(row, col)] } else { lin.df_dv[row] };
                        let size = fd[row].abs().max(exact.abs());
                        if one_sided[row].abs() > 1e-4 * size {
                            continue;
                        }
                        let tol = 1e-5 * size + 1e-9 * out.dydt[row].abs().max(1e-12) / SCALE[col];
                        assert!(
                            (exact - fd[row]).abs() <= tol,
                            "case {case} (effects on: {all_on}, held: {held}), ∂f{row}/∂y{col}: written {exact:e}, differences {:e}",
                            fd[row]
                        );
                    }
                }
            }
        }
    }
}
