//! The steady flow (jet) force that pushes the spool towards closing. Off: none. The controller's
//! compensation stays, computed with its own nominal `Cv_compensation`, as on the real controller.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct FlowForces;

static INFO: EffectInfo = EffectInfo {
    key: "flow_forces",
    meaning: "steady flow force on the spool (off: none)",
    equation: "F_flow = 2·Cd_valve·Cv_valve·cos(theta_jet)·A·max(Δp, 0) on the spool, closing",
    code: CodeRef { file: "src/physics/valve.rs", function: "flow_force" },
    fitted: &[FittedParameter { name: "Cv_valve", search: (0.5, 1.0), log: false, plausible: (0.85, 1.0), grid: None, start: Start::Model }],
    secondary: &[],
    other: &["theta_jet"],
    hidden_range: (0.9, 0.94),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Controlled,
    signature: "a force error growing with velocity and force: spool pushed towards closing by the jet",
};

impl Effect for FlowForces {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
