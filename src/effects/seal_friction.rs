//! Coulomb friction of the rod and piston seals, smoothed through zero velocity.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;

pub struct SealFriction;

static INFO: EffectInfo = EffectInfo {
    key: "seal_friction",
    meaning: "Coulomb seal friction F_coulomb·tanh(v/v_friction) (off: none)",
    equation: "F = F_coulomb·tanh(v_damper/v_friction) in the load path",
    code: CodeRef { file: "src/effects/seal_friction.rs", function: "SealFriction::force" },
    fitted: &[
        FittedParameter { name: "F_coulomb", search: (0.0, 2000.0), log: false, plausible: (50.0, 600.0), grid: None, start: Start::Model },
        FittedParameter { name: "v_friction", search: (1e-4, 0.1), log: true, plausible: (5e-4, 0.05), grid: None, start: Start::Model },
    ],
    secondary: &[],
    other: &[],
    hidden_range: (150.0, 400.0),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature:
        "an error jump of twice the friction force at every velocity reversal, independent of the valve and the demand",
};

impl Effect for SealFriction {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::FORCE
    }
    /// F = F_c·tanh(v/v_f): a friction that opposes the motion, so in tension when extending.
    fn force(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        p.f_coulomb * libm::tanh(s.v_damper / p.v_friction)
    }
    fn force_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        let tanh = libm::tanh(s.v_damper / p.v_friction);
        PlantSignals { v_damper: p.f_coulomb * (1.0 - tanh * tanh) / p.v_friction, ..PlantSignals::ZERO }
    }
}
