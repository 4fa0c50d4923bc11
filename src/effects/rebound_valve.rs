//! The passive rebound valve of a passive or adjustable damper: in the piston, from the annulus to
//! the full bore; a laminar and an orifice bleed beside a preloaded blow-off (docs/physics.md §3.8).

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;
use crate::physics::passive_valve::PassiveValve;

pub struct ReboundValve;

static INFO: EffectInfo = EffectInfo {
    key: "rebound_valve",
    meaning: "passive rebound valve in the piston: bleeds beside a preloaded blow-off (off: none)",
    equation: "Q = G_bleed_reb·Δp/μ_r + Q_or(A_bleed_reb) + Q_or(A_open_reb·s(k_open_reb·(Δp − p_open_reb)/A_open_reb)), Δp = p_ext − p_comp, from the annulus to the full bore",
    code: CodeRef { file: "src/physics/passive_valve.rs", function: "PassiveValve::flow" },
    fitted: &[
        FittedParameter {
            name: "A_bleed_reb",
            search: (1e-10, 1e-4),
            log: true,
            plausible: (1e-8, 5e-5),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "p_open_reb",
            search: (1e4, 5e7),
            log: true,
            plausible: (1e5, 2e7),
            grid: None,
            start: Start::Model,
        },
    ],
    secondary: &[
        FittedParameter {
            name: "G_bleed_reb",
            search: (1e-15, 1e-8),
            log: true,
            plausible: (1e-13, 1e-9),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "k_open_reb",
            search: (1e-16, 1e-9),
            log: true,
            plausible: (1e-14, 1e-10),
            grid: None,
            start: Start::Model,
        },
    ],
    other: &["A_open_reb", "Cd_passive"],
    hidden_range: (1e-6, 4e-6),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::WhenOn,
    signature: "a force error in extension only, growing with velocity: at low speed (the bleed: linear or quadratic in velocity) or above a knee force (the blow-off: degressive); a changed adjuster moves the low-speed part",
};

impl Effect for ReboundValve {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::BYPASS_FLOW
    }
    /// Q(p_ext − p_comp) from the annulus to the full bore.
    fn bypass_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        PassiveValve::rebound(p).flow(s.p_ext - s.p_comp, s.viscosity_ratio, p.rho, p.p_transition).0
    }
    fn bypass_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        let slope = PassiveValve::rebound(p).flow(s.p_ext - s.p_comp, s.viscosity_ratio, p.rho, p.p_transition).1;
        PlantSignals { p_ext: slope, p_comp: -slope, ..PlantSignals::ZERO }
    }
}
