//! Gas released from the oil at low pressure (gaseous cavitation): oil saturated with gas at
//! `p_saturation` lets it out of solution where a chamber's pressure falls below that, and takes
//! it back as the pressure rises (Henry's law at equilibrium). The free gas adds to the entrained
//! air's compliance, so a chamber that has been below saturation must be compressed through its
//! released gas before it carries load again: lost motion after the reversal.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct GasRelease;

static INFO: EffectInfo = EffectInfo {
    key: "gas_release",
    meaning: "gas coming out of solution below the saturation pressure (off: none)",
    equation: "α(p) = air_fraction + gas_solubility·h(p_saturation − p)/p_atm, β_e(p) = (1 + α·r)/(1/beta_oil + α·r/(n_polytropic·(p + p_atm)) + gas_solubility·h′(p_saturation − p)·r/p_atm), h a smooth max(u, 0) over ±0.1 bar; both chambers",
    code: CodeRef { file: "src/physics/fluid.rs", function: "GasRelease::released" },
    fitted: &[FittedParameter {
        name: "gas_solubility",
        search: (1e-4, 0.5),
        log: true,
        plausible: (0.005, 0.12),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[FittedParameter {
        name: "p_saturation",
        search: (-0.9e5, 5e6),
        log: false,
        plausible: (-0.9e5, 5e6),
        grid: None,
        start: Start::SameAs("p_reservoir0"),
    }],
    other: &[],
    hidden_range: (0.02, 0.09),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "lost motion after a reversal out of a stroke that drew a chamber below the saturation pressure (in this circuit the full bore, refilled through the foot valve in extension): the model's force builds too early at the turn into compression, more after fast extensions; nothing while both chambers stay above saturation",
};

impl Effect for GasRelease {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
