//! The passive compression (base) valve of a passive or adjustable damper: from the full bore to
//! the reservoir; a laminar and an orifice bleed beside a preloaded blow-off (docs/physics.md §3.8).

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;
use crate::physics::passive_valve::PassiveValve;

pub struct CompressionValve;

static INFO: EffectInfo = EffectInfo {
    key: "compression_valve",
    meaning: "passive compression (base) valve: bleeds beside a preloaded blow-off (off: none)",
    equation: "Q = G_bleed_comp·Δp/μ_r + Q_or(A_bleed_comp) + Q_or(A_open_comp·s(k_open_comp·(Δp − p_open_comp)/A_open_comp)), Δp = p_comp − p_reservoir, from the full bore to the reservoir",
    code: CodeRef { file: "src/physics/passive_valve.rs", function: "PassiveValve::flow" },
    fitted: &[
        FittedParameter {
            name: "A_bleed_comp",
            search: (1e-10, 1e-4),
            log: true,
            plausible: (1e-8, 5e-5),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "p_open_comp",
            search: (1e4, 5e7),
            log: true,
            plausible: (1e5, 2e7),
            grid: None,
            start: Start::Model,
        },
    ],
    secondary: &[
        FittedParameter {
            name: "G_bleed_comp",
            search: (1e-15, 1e-8),
            log: true,
            plausible: (1e-13, 1e-9),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "k_open_comp",
            search: (1e-16, 1e-9),
            log: true,
            plausible: (1e-14, 1e-10),
            grid: None,
            start: Start::Model,
        },
    ],
    other: &["A_open_comp", "Cd_passive"],
    hidden_range: (1e-6, 4e-6),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::WhenOn,
    signature: "a force error in compression only, growing with velocity: at low speed (the bleed: linear or quadratic in velocity) or above a knee force (the blow-off: degressive); a changed adjuster moves the low-speed part",
};

impl Effect for CompressionValve {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::BASE_FLOW
    }
    /// Q(p_comp − p_reservoir) from the full bore to the reservoir.
    fn base_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        PassiveValve::compression(p).flow(s.p_comp - s.p_reservoir, s.viscosity_ratio, p.rho, p.p_transition).0
    }
    fn base_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        let slope = PassiveValve::compression(p).flow(s.p_comp - s.p_reservoir, s.viscosity_ratio, p.rho, p.p_transition).1;
        PlantSignals { p_comp: slope, p_reservoir: -slope, ..PlantSignals::ZERO }
    }
}
