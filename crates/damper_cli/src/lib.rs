//! `damper`: the damper model against measurements (issue 4).
//!
//! - [`measurement`]: reading a measurement CSV (column mapping, units, errors with file, line
//!   and column);
//! - [`model`]: the model driven by measured inputs ([`model::Model::run`], thread-safe), in-process
//!   or through a packaged FMU ([`model::Backend`], [`fmu_model`]);
//! - [`parameters`]: parameters by FMU name and the effect catalog's switches;
//! - [`analysis`]: fit per signal and where the error lives; [`report`] and [`compare`] turn it
//!   into `report.html`, `summary.json` (typed in [`summary`]) and the terminal summary;
//! - [`diagnose`]: which catalog effect is missing (fit on train, score on validation, rank),
//!   with [`fit`] (bounded Nelder–Mead, parameter uncertainty), [`ladder`] (the effects added in
//!   turn), [`before_after`] (the model with the named effects against the baseline, by regime)
//!   and [`diagnose_cmd`] (the command: report, summary);
//! - [`generate`]: measurement-like data with hidden effects, and their truth;
//! - [`cli`]: the command line.
pub mod analysis;
pub mod before_after;
pub mod cli;
pub mod compare;
pub mod diagnose;
pub mod diagnose_cmd;
pub mod dsp;
pub mod fit;
pub mod fmu_model;
pub mod generate;
pub mod ladder;
pub mod measurement;
pub mod model;
pub mod parameters;
pub mod report;
pub mod rng;
pub mod summary;
pub mod svg;
pub mod units;
