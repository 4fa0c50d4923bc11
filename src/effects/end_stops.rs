//! End stops: the bump and rebound rubbers that take the load beyond a stroke, progressive
//! (quadratic in the compression of the rubber), the same in both directions.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;

pub struct EndStops;

static INFO: EffectInfo = EffectInfo {
    key: "end_stops",
    meaning: "end stops beyond x_end_stop: F = sign(x)·k_end_stop·(|x| − x_end_stop)² (off: none)",
    equation: "F = sign(x_damper)·k_end_stop·max(|x_damper| − x_end_stop, 0)² in the load path",
    code: CodeRef { file: "src/effects/end_stops.rs", function: "EndStops::force" },
    fitted: &[
        FittedParameter {
            name: "k_end_stop",
            search: (1e4, 1e12),
            log: true,
            plausible: (1e6, 1e11),
            grid: None,
            start: Start::Model,
        },
        FittedParameter {
            name: "x_end_stop",
            search: (0.0, 1.0),
            log: false,
            plausible: (0.002, 0.5),
            grid: None,
            start: Start::OfLargestStroke(0.8),
        },
    ],
    secondary: &[],
    other: &[],
    hidden_range: (2e8, 2e9),
    hide_with: HideWith { set: &[("x_end_stop", 0.012)], temperature_rise: 0.0 },
    candidacy: Candidacy::Always,
    signature: "an error only where the stroke is beyond a position, growing with it, the same sign as the stroke (the model too weak there); against velocity it looks like friction at standstill, against stroke it is a dead band",
};

impl Effect for EndStops {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::FORCE
    }
    /// The rubber beyond the stop pushes back towards mid-stroke: in tension when extended.
    fn force(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        let depth = (s.x_damper.abs() - p.x_end_stop).max(0.0);
        p.k_end_stop * depth * depth * s.x_damper.signum()
    }
    fn force_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        let depth = (s.x_damper.abs() - p.x_end_stop).max(0.0);
        PlantSignals { x_damper: 2.0 * p.k_end_stop * depth, ..PlantSignals::ZERO }
    }
}
