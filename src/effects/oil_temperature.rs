//! The oil's temperature, measured (the input `T_oil`): the viscosity of the bleeds, the leakage
//! and the viscous friction, and the gas charge's pressure (docs/physics.md §3.9).

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct OilTemperature;

static INFO: EffectInfo = EffectInfo {
    key: "oil_temperature",
    meaning: "the measured oil temperature T_oil acts on viscosity and gas pressure (off: none)",
    equation: "μ_r = exp(−visc_temp_coeff·(T_oil − T_ref)) divides the laminar bleeds' and the leakage's conductance and multiplies the viscous friction; the gas's absolute pressure scales with T_oil/T_ref",
    code: CodeRef { file: "src/physics/fluid.rs", function: "viscosity_ratio" },
    fitted: &[FittedParameter {
        name: "visc_temp_coeff",
        search: (0.0, 0.15),
        log: false,
        plausible: (0.01, 0.07),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[],
    other: &["T_ref"],
    hidden_range: (0.025, 0.05),
    hide_with: HideWith { set: &[], temperature_rise: 40.0 },
    candidacy: Candidacy::WithTemperature,
    signature: "an error that follows the measured temperature: the gas force's offset grows with it (T/T_ref of the absolute pre-charge), the low-speed (bleed, leakage, viscous) damping falls as the oil heats",
};

impl Effect for OilTemperature {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
