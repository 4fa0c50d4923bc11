//! The reservoir's gas charge: the pre-charge sets the gas force −p_r·A_r, the gas volume how it
//! grows as the rod enters (a polytropic spring, docs/physics.md §3.5). Part of every damper's
//! build: refitted where it has moved (a damper re-charged, or losing gas), not switched on.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct GasCharge;

static INFO: EffectInfo = EffectInfo {
    key: "gas_charge",
    meaning: "the reservoir's gas pre-charge and spring (off: the pressure stays at p_reservoir0)",
    equation: "p_r = (p_reservoir0 + p_atm)·(V_gas0/V_g)^n_polytropic − p_atm, the gas force −p_r·A_r in the load cell; off: p_r = p_reservoir0",
    code: CodeRef { file: "src/physics/hydraulics.rs", function: "reservoir_pressure_and_slope" },
    fitted: &[FittedParameter {
        name: "p_reservoir0",
        search: (1e4, 1e7),
        log: true,
        plausible: (1e5, 5e6),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[FittedParameter {
        name: "V_gas0",
        search: (1e-6, 1e-1),
        log: true,
        plausible: (5e-6, 1e-2),
        grid: None,
        start: Start::Model,
    }],
    other: &["n_polytropic"],
    hidden_range: (6e5, 7.5e5),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::WhenOn,
    signature: "a force offset the same in both directions and at every velocity (the gas force, pre-charge times rod area), growing with the compression stroke as the gas is squeezed",
};

impl Effect for GasCharge {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
