//! When the diagnosis names an effect, and when the ladder keeps one: the thresholds both judge
//! by, and the share of the error above the noise floor that a change of model explains.

/// Least share of the validation error above the noise floor an effect must explain to be named.
pub const MIN_EXPLAINED: f64 = 0.5;
/// The best plausible runner-up must explain less than this fraction of what the best explains.
pub const MAX_RUNNER_UP_RATIO: f64 = 0.7;
/// A baseline within this factor of the noise floor has nothing to explain.
pub const FLOOR_FACTOR: f64 = 1.3;
/// Near the noise floor (a baseline within [`FLOOR_FACTOR`] of it) an effect is still named when
/// it cuts the validation mean-square error by at least this share of the noise variance. Over 20
/// records with nothing hidden (rig and HiL) no candidate cut more than 0.0014; a weak hidden piston
/// leakage on HiL data cuts 0.07–0.57 (`crates/damper_engine/examples/ranking_accuracy.rs`).
pub const MIN_GAIN: f64 = 0.02;
/// Share of the error above the floor `f` that going from NRMSE `b` to `c` explains.
pub fn share(b: f64, c: f64, f: f64) -> f64 {
    ((b * b - c * c) / (b * b - f * f).max(1e-300)).min(1.0)
}
