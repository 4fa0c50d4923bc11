//! The compliant mount (bushes and frame) in series with the damper: a massless cubic spring,
//! eliminated algebraically. Off: a rigid mount.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct MountCompliance;

static INFO: EffectInfo = EffectInfo {
    key: "mount_compliance",
    meaning: "compliant mount in series (off: rigid mount)",
    equation: "F = k1_mount·δ + k3_mount·δ³ in series with the damper, the deflection δ solved from the force in closed form; off: δ = 0",
    code: CodeRef { file: "src/physics/mount.rs", function: "CubicMount::deflection" },
    fitted: &[FittedParameter { name: "k1_mount", search: (2e6, 1e10), log: true, plausible: (1e7, 2e8), grid: None, start: Start::Model }],
    secondary: &[FittedParameter { name: "k3_mount", search: (1e11, 1e16), log: true, plausible: (1e12, 2e14), grid: None, start: Start::Model }],
    other: &[],
    hidden_range: (2.0e7, 3.5e7),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature: "a phase lag growing with the force rate: a hysteresis loop of the error against velocity, the same in both directions",
};

impl Effect for MountCompliance {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
