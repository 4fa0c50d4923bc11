//! The damper model against measurements, as data: nothing here prints or writes HTML
//! or SVG; the `damper` command line (crates/damper_cli) presents the results.
//!
//! - [`measurement`], [`units`]: reading a measurement CSV (column mapping, units, errors with
//!   file, line and column); [`motion`]: the model's motion from the velocity and displacement
//!   columns ([`velocity_noise`]: a velocity made from the displacement; [`stroke`]: the two fused);
//! - [`model`]: the model driven by measured inputs ([`model::Model::run`], thread-safe), behind
//!   the trait [`model::Backend`]: in-process or through a packaged FMU ([`fmu_model`]);
//! - [`parameters`]: parameters by FMU name and the effect catalog's switches; [`description`]: a
//!   damper described from its datasheet (TOML, values with units read by [`quantity`]);
//! - [`dsp`]: error metrics, spectra, correlations, the load-cell filter, the noise estimate;
//! - [`analysis`]: fit per signal and where the error lives; [`comparison`]: read, run, analyse;
//! - [`floor`]: what no effect can explain (sensor noise, numerics, the velocity's noise carried
//!   through the model), [`sensitivity`]: the samples that inform nothing;
//! - [`missing_effect`]: which catalog effect is missing, by the thresholds of [`criteria`], from the
//!   [`candidate`] fits ([`lm`]: bounded Levenberg–Marquardt, parameter uncertainty), with [`ladder`]
//!   (the effects added in turn) and [`before_after`] (the model with the named effects);
//!   [`propagation`]: the uncertainty a named effect's size inherits from the calibration;
//!   [`diagnose_measurement`] runs it all on a measurement;
//! - [`summary`]: the typed `summary.json` and the JSON writing shared with the truth file;
//! - [`calibrate`]: nominal parameters fitted on calibration records ([`lm`]: bounded
//!   Levenberg–Marquardt with covariance), written as an SSP parameter set ([`ssv`]) and
//!   `calibration.json` ([`calibration_file`]); [`settings`]: several settings of an adjustable
//!   damper in one calibration;
//! - [`generate`]: measurement-like data with hidden effects ([`rng`]), and their truth;
//! - [`error`]: the crate's one error type, [`Error`].
pub mod analysis;
pub mod before_after;
pub mod bounds;
pub mod calibrate;
pub mod calibration_file;
pub mod candidate;
pub mod comparison;
pub mod criteria;
pub mod description;
pub mod diagnose_measurement;
pub mod dsp;
pub mod error;
pub mod floor;
pub mod fmu_model;
pub mod force_velocity;
pub mod generate;
pub mod ladder;
pub mod lm;
pub mod measurement;
pub mod missing_effect;
pub mod model;
pub mod motion;
pub mod parameters;
pub mod propagation;
pub mod quantity;
pub mod record_checks;
pub mod record_parts;
pub mod record_traps;
pub mod residual_signature;
pub mod rng;
pub mod sensitivity;
pub mod settings;
pub mod ssv;
pub mod steady;
pub mod stroke;
pub mod summary;
pub mod units;
pub mod velocity_noise;
pub mod verdict;

pub use error::Error;
