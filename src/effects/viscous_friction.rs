//! Viscous friction of the seals: the oil film's shear, linear in velocity. The worked example of
//! a user-written effect (docs/effects.md, "Writing a new effect"); together with
//! `seal_friction` it makes the Coulomb + viscous seal friction of the catalog.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;

pub struct ViscousFriction;

static INFO: EffectInfo = EffectInfo {
    key: "viscous_friction",
    meaning: "viscous seal friction c_viscous·v (off: none)",
    equation: "F = c_viscous·μ_r·v_damper in the load path (μ_r: the viscosity over its value at T_ref, 1 unless oil_temperature is on)",
    code: CodeRef { file: "src/effects/viscous_friction.rs", function: "ViscousFriction::force" },
    fitted: &[FittedParameter {
        name: "c_viscous",
        search: (0.0, 20_000.0),
        log: false,
        plausible: (200.0, 3000.0),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[],
    other: &[],
    hidden_range: (800.0, 2500.0),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "an error growing smoothly with velocity and no jump at reversals; in force control the loop removes most of it in steady motion, so it shows after demand steps, at high force rates and as two branches of the mean error against velocity",
};

impl Effect for ViscousFriction {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::FORCE
    }
    /// F = c·μ_r·v, opposing the motion (in tension when extending); the oil film's shear grows
    /// with its viscosity.
    fn force(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        p.c_viscous * s.viscosity_ratio * s.v_damper
    }
    fn force_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        PlantSignals { v_damper: p.c_viscous * s.viscosity_ratio, ..PlantSignals::ZERO }
    }
}
