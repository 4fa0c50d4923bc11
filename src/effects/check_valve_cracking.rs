//! The check valves' cracking pressure: their opening starts at p_cv_crack. Off: they open at zero
//! pressure drop.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct CheckValveCracking;

static INFO: EffectInfo = EffectInfo {
    key: "check_valve_cracking",
    meaning: "check-valve cracking pressure (off: they open at zero pressure drop)",
    equation:
        "A_cv(Δp) = A_cv_leak + A_cv_max·smoothstep((Δp − p_cv_crack)/(p_cv_full − p_cv_crack)); off: p_cv_crack = 0",
    code: CodeRef { file: "src/physics/hydraulics.rs", function: "check_valve_area" },
    fitted: &[FittedParameter {
        name: "p_cv_crack",
        search: (0.0, 0.95e5),
        log: false,
        plausible: (0.2e5, 0.85e5),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[],
    other: &[],
    // below p_cv_full (1 bar), where the valve is fully open
    hidden_range: (0.5e5, 0.8e5),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "a small offset with the sign of the direction of motion and a delayed force build-up after reversals",
};

impl Effect for CheckValveCracking {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
