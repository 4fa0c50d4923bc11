//! Viscous friction of the seals: the oil film's shear, linear in velocity. The worked example of
//! a user-written effect (docs/effects.md, "Writing a new effect"); together with
//! `seal_friction` it makes the Coulomb + viscous seal friction of the catalog.

use super::{CodeRef, Effect, EffectInfo, FittedParameter, PlantSignals, Terms};
use crate::physics::params::Parameters;

pub struct ViscousFriction;

static INFO: EffectInfo = EffectInfo {
    key: "viscous_friction",
    meaning: "viscous seal friction c_viscous·v (off: none)",
    equation: "F = c_viscous·v_damper in the load path",
    code: CodeRef { file: "src/effects/viscous_friction.rs", function: "ViscousFriction::force" },
    fitted: &[FittedParameter {
        name: "c_viscous",
        search: (0.0, 20_000.0),
        log: false,
        plausible: (200.0, 3000.0),
        grid: None,
    }],
    secondary: &[],
    other: &[],
    hidden_range: (800.0, 2500.0),
    signature: "an error growing smoothly with velocity and no jump at reversals; in force control the loop removes most of it in steady motion, so it shows after demand steps, at high force rates and as two branches of the mean error against velocity",
};

impl Effect for ViscousFriction {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::FORCE
    }
    /// F = c·v, opposing the motion: in tension when extending.
    fn force(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        p.c_viscous * s.v_damper
    }
    fn force_gradient(&self, p: &Parameters, _s: &PlantSignals) -> PlantSignals {
        PlantSignals { v_damper: p.c_viscous, ..PlantSignals::ZERO }
    }
}
