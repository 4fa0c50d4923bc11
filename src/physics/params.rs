//! Model parameters in SI units: the struct is generated from `modelDescription.xml`, where every
//! value carries its unit, description and source, and its defaults are the XML's start values;
//! here are the checks across parameters and the quantities derived from them.

use super::fluid::{GasRelease, Oil};
use super::hydraulics::{Cylinder, GasCharge};
use super::mount::CubicMount;
use super::valve::{flow_force_gain, ValvePorts};
use crate::control::A_FEEDFORWARD_MIN;
use crate::effects::ActiveEffects;

/// Longest amplifier delay line, in controller samples.
pub const MAX_DELAY_SAMPLES: usize = 200;

/// Outer force-loop law.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ForceLaw {
    /// Inverse-valve feedforward + PI on ln(valve area) (docs/physics.md §4.3).
    FeedforwardLogArea,
    /// The paper's plain PID from relative force error to spool position.
    PaperPid,
}

/// Flow-force compensation current of the inner loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlowForceCompensation {
    None,
    /// Proportional to the estimated flow at a fixed pressure drop (the paper's wording).
    FixedGain,
    /// Proportional to flow × sqrt(estimated pressure drop): cancels the flow-force stiffness.
    Scheduled,
}

/// What the digital controller regulates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ControlMode {
    /// Outer force loop + inner spool loop.
    Force,
    /// Inner spool loop only; the spool demand is an input.
    SpoolPosition,
    /// No controller: the valve held at `x_spool_start`, as a passive or adjustable damper's
    /// valve is (docs/physics.md §4.6). The demands are not used.
    ValveHeld,
}

/// All parameters: generated from `modelDescription.xml`, one field per parameter (the variable's
/// name in lower case), `Default` from its start values.
pub use crate::model_description::Parameters;

/// Quantities derived once from the parameters.
#[derive(Clone, Copy, Debug)]
pub struct Derived {
    pub cylinder: Cylinder,
    pub ports: ValvePorts,
    /// The series mount, `None` when `effect_mount_compliance` is off (rigid mount).
    pub mount: Option<CubicMount>,
    /// The oil, with the entrained air fraction in effect (0 when `effect_compressibility` is off)
    /// and the gas it releases at low pressure (none when `effect_gas_release` is off).
    pub oil: Oil,
    /// The reservoir's gas charge.
    pub gas: GasCharge,
    /// Check-valve cracking pressure in effect (0 when `effect_check_valve_cracking` is off) (Pa).
    pub p_cv_crack: f64,
    /// Upper spool demand: 0.5 mm short of the end stop (m).
    pub x_demand_max: f64,
    /// Valve area at `x_demand_max` (m²).
    pub a_demand_max: f64,
    /// Amplifier delay in controller samples.
    pub delay_samples: usize,
    /// Flow-force gain 2 C_d C_v cos θ (-), see [`crate::physics::valve::flow_force`].
    pub flow_force_gain: f64,
    /// The flow-force compensation's current per unit of √Δp̂·Q̂ (A/(m³/s·√Pa)):
    /// C_v,nom cos θ sqrt(2ρ)/K_sol, for the spool loop's flow-force compensation.
    pub compensation_gain: f64,
    pub control_mode: ControlMode,
    /// The valve held at its start position (`control_mode` 2): the spool does not move.
    pub valve_held: bool,
    /// Whether the measured oil temperature acts (`effect_oil_temperature`).
    pub oil_temperature: bool,
    /// Whether the reservoir's gas is a spring (`effect_gas_charge`); off: its pressure stays at
    /// the pre-charge.
    pub gas_spring: bool,
    pub force_law: ForceLaw,
    pub flow_force_compensation: FlowForceCompensation,
    /// The switched-on effects that add a force or a bypass flow to the plant.
    pub effects: ActiveEffects,
}

/// Parameters that do not go together (each is in its own range): the message names them and
/// says what to change.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum ParameterError {
    /// A relation between parameters, in words.
    #[error("{0}")]
    Relation(&'static str),
    /// The valve's largest demanded area `a_max` (m²) is below `least` (m²).
    #[error(
        "the valve's largest demanded area ({a_max:.3e} m² from n_ports, r_port, x_lap and x_spool_max - 0.5 mm) \
         must be at least {least:.1e} m²: raise r_port, n_ports or x_spool_max, or lower x_lap"
    )]
    ValveTooSmall { a_max: f64, least: f64 },
    /// |x_damper_start| is not below L_half_stroke + L_dead = `limit` (m).
    #[error("|x_damper_start| must be below L_half_stroke + L_dead = {limit} m")]
    StartBeyondStroke { limit: f64 },
}

/// How far below its stop `x_spool_max` the force loops' spool demand ends (m; docs/physics.md
/// §4.3): the largest demanded opening is one the spool loop can hold off the stop.
pub const DEMAND_MARGIN_BELOW_STOP: f64 = 0.5e-3;

impl Parameters {
    /// Checks the relations between parameters that single-variable ranges cannot express.
    pub fn validate(&self) -> Result<(), ParameterError> {
        let checks: [(bool, &'static str); 8] = [
            (self.d_rod < self.d_piston, "D_rod must be smaller than D_piston"),
            (self.p_cv_full > self.p_cv_crack, "p_cv_full must exceed p_cv_crack"),
            (self.x_spool_max > self.x_spool_min, "x_spool_max must exceed x_spool_min"),
            (
                self.x_spool_max - DEMAND_MARGIN_BELOW_STOP > self.x_lap,
                "x_spool_max - 0.5 mm must exceed x_lap (the valve must be able to open)",
            ),
            (
                self.tau_amp / self.t_sample <= MAX_DELAY_SAMPLES as f64,
                "tau_amp/T_sample exceeds the 200-sample delay line",
            ),
            ((0..=2).contains(&self.control_mode), "control_mode must be 0, 1 or 2"),
            (self.force_controller == 0 || self.force_controller == 1, "force_controller must be 0 or 1"),
            ((0..=2).contains(&self.flow_force_compensation), "flow_force_compensation must be 0, 1 or 2"),
        ];
        for (ok, msg) in checks {
            if !ok {
                return Err(ParameterError::Relation(msg));
            }
        }
        // the force loop works between a floor and the largest demanded area: both must fit
        let a_max = ValvePorts { n_ports: self.n_ports as f64, r_port: self.r_port, x_lap: self.x_lap }
            .area(self.x_spool_max - DEMAND_MARGIN_BELOW_STOP);
        if a_max.is_nan() || a_max < 2.0 * A_FEEDFORWARD_MIN {
            return Err(ParameterError::ValveTooSmall { a_max, least: 2.0 * A_FEEDFORWARD_MIN });
        }
        let l = self.l_half_stroke + self.l_dead;
        if self.x_damper_start.abs() >= l {
            return Err(ParameterError::StartBeyondStroke { limit: l });
        }
        Ok(())
    }

    /// Derived quantities; call after `validate`.
    pub fn derive(&self) -> Derived {
        let cylinder = Cylinder::new(self.d_piston, self.d_rod, self.l_half_stroke, self.l_dead, self.v_hose);
        let ports = ValvePorts { n_ports: self.n_ports as f64, r_port: self.r_port, x_lap: self.x_lap };
        let x_demand_max = self.x_spool_max - DEMAND_MARGIN_BELOW_STOP;
        Derived {
            cylinder,
            ports,
            mount: self.effect_mount_compliance.then_some(CubicMount::new(self.k1_mount, self.k3_mount)),
            oil: Oil::new(
                self.beta_oil,
                if self.effect_compressibility { self.air_fraction } else { 0.0 },
                self.n_polytropic,
                self.effect_gas_release.then(|| GasRelease::new(self.gas_solubility, self.p_saturation)),
            ),
            gas: GasCharge::new(self.p_reservoir0, self.v_gas0, self.n_polytropic),
            p_cv_crack: if self.effect_check_valve_cracking { self.p_cv_crack } else { 0.0 },
            x_demand_max,
            a_demand_max: ports.area(x_demand_max),
            flow_force_gain: flow_force_gain(self.cd_valve, self.cv_valve, self.theta_jet),
            compensation_gain: self.cv_compensation * libm::cos(self.theta_jet) * (2.0 * self.rho).sqrt() / self.k_sol,
            delay_samples: if self.effect_amplifier_delay {
                (self.tau_amp / self.t_sample).round() as usize
            } else {
                0
            },
            control_mode: match self.control_mode {
                1 => ControlMode::SpoolPosition,
                2 => ControlMode::ValveHeld,
                _ => ControlMode::Force,
            },
            valve_held: self.control_mode == 2,
            oil_temperature: self.effect_oil_temperature,
            gas_spring: self.effect_gas_charge,
            force_law: if self.force_controller == 1 { ForceLaw::PaperPid } else { ForceLaw::FeedforwardLogArea },
            flow_force_compensation: match self.flow_force_compensation {
                0 => FlowForceCompensation::None,
                1 => FlowForceCompensation::FixedGain,
                _ => FlowForceCompensation::Scheduled,
            },
            effects: ActiveEffects::of(self),
        }
    }
}
