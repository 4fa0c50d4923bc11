//! When the diagnosis names an effect, and when the ladder keeps one: the thresholds both judge
//! by, and the share of the error above the noise floor that a change of model explains.

/// Least share of the validation error above the noise floor an effect must explain to be named.
pub const MIN_EXPLAINED: f64 = 0.5;
/// The best plausible runner-up must explain less than this fraction of what the best explains.
pub const MAX_RUNNER_UP_RATIO: f64 = 0.7;
/// A best candidate near the floor is also confident when every plausible rival leaves at least
/// this many times its mean-square error above the floor. Shares of the error explained compress
/// large differences: compressibility hidden on a rig record left 1.6× the floor, a refitted gas
/// pre-charge 18× (explaining 83 % against 100 %: "ambiguous"); the reverse with the gas
/// pre-charge hidden, 1.9× against 17×.
pub const RIVAL_LEFT_FACTOR: f64 = 10.0;
/// A baseline within this factor of the noise floor has nothing to explain.
pub const FLOOR_FACTOR: f64 = 1.3;
/// Effects "explain" the record only when they leave at most this factor of the noise floor;
/// more, and they are named as a partial explanation.
pub const EXPLAINED_FACTOR: f64 = 2.0;
/// A partial explanation explains at least this share of the error above the floor: with less,
/// an effect of the catalog with a similar signature absorbs part of an error it does not cause
/// (compressibility explains 52 % of a missing viscous friction).
pub const PARTIAL_MIN_EXPLAINED: f64 = 0.75;
/// The model does not fit the damper when even the best the diagnosis reaches leaves at least
/// this validation NRMSE (and [`DOES_NOT_FIT_FLOOR_FACTOR`] times the floor): a missing catalog
/// effect leaves less once it is added (0.005–0.03 in the tests), a damper of another kind or
/// nominal parameters far from the damper's leave more (0.6 on a magnetorheological damper).
pub const DOES_NOT_FIT_NRMSE: f64 = 0.15;
/// ... and at least this factor of the noise floor (a very noisy record is not a misfit).
pub const DOES_NOT_FIT_FLOOR_FACTOR: f64 = 10.0;
/// Near the noise floor (a baseline within [`FLOOR_FACTOR`] of it) an effect is still named when
/// it cuts the validation mean-square error by at least this share of the noise variance, and by
/// [`NUMERICS_MARGIN`] times the model's own numerical error variance. Over 20 records with
/// nothing hidden (rig and HiL) no candidate cut more than 0.0014; a weak hidden piston leakage on
/// HiL data cuts 0.07–0.57 (`crates/damper_engine/examples/ranking_accuracy.rs`).
pub const MIN_GAIN: f64 = 0.02;
/// A candidate can absorb the model's numerical error; a weak effect must cut this many times
/// more.
pub const NUMERICS_MARGIN: f64 = 4.0;
/// A refitted parameter that moved less than this many standard uncertainties from the model's
/// value has not moved: the refit is not an effect.
pub const MOVED_SIGMAS: f64 = 3.0;
/// The model's numerical error is measured against the same run at this fraction of the rtol. A
/// tenth is enough: the check's own error is then a fourteenth of the run's (0.11 N against 1.5 N
/// RMS at rtol 3e-5, `cargo bench --bench realtime`'s input), so the difference is the run's error
/// within 7 %; a hundredth made the check the diagnosis's longest run (38× against 77× real time).
pub const NUMERICS_CHECK_FACTOR: f64 = 0.1;
/// Share of the error above the floor `f` that going from NRMSE `b` to `c` explains.
pub fn share(b: f64, c: f64, f: f64) -> f64 {
    ((b * b - c * c) / (b * b - f * f).max(1e-300)).min(1.0)
}
