//! The power amplifier's pure delay on the coil command, in whole controller samples. Off: no
//! delay.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, Start};

pub struct AmplifierDelay;

static INFO: EffectInfo = EffectInfo {
    key: "amplifier_delay",
    meaning: "pure delay of the power amplifier (off: none)",
    equation: "the coil command delayed by round(tau_amp/T_sample) controller samples",
    code: CodeRef { file: "src/control/amplifier.rs", function: "DelayLine::push" },
    fitted: &[FittedParameter {
        name: "tau_amp",
        search: (0.0, 0.01),
        log: false,
        plausible: (0.001, 0.006),
        grid: Some(0.5e-3),
        start: Start::Model,
    }],
    secondary: &[],
    other: &[],
    // 7–8 ms makes the force loop oscillate (a 25 Hz limit cycle at 20 kN demands)
    hidden_range: (0.004, 0.005),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Controlled,
    signature:
        "a constant time shift between model and measurement, the same in both directions, largest after demand steps",
};

impl Effect for AmplifierDelay {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
}
