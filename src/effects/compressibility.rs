//! Entrained air in the oil: the effective bulk modulus β_e(p) of the chamber pressures. Off:
//! air-free oil, β_e = β_oil.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct Compressibility;

static INFO: EffectInfo = EffectInfo {
    key: "compressibility",
    meaning: "oil with entrained air (off: air-free oil)",
    equation: "r = (p_atm/(p + p_atm))^(1/n_polytropic), β_e(p) = (1 + air_fraction·r)/(1/beta_oil + air_fraction·r/(n_polytropic·(p + p_atm))), the bulk modulus of both chambers; off: β_e = beta_oil",
    code: CodeRef { file: "src/physics/fluid.rs", function: "effective_bulk_modulus_and_slope" },
    fitted: &[FittedParameter { name: "air_fraction", search: (1e-4, 0.2), log: true, plausible: (0.002, 0.1), grid: None, start: Start::Model }],
    secondary: &[FittedParameter { name: "n_polytropic", search: (1.0, 1.67), log: false, plausible: (1.0, 1.4), grid: None, start: Start::Model }],
    other: &[],
    hidden_range: (0.035, 0.05),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "error proportional to the force rate during transients, larger at low pressure and in compression, gone in steady state",
};

impl Effect for Compressibility {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
