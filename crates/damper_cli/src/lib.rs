//! `damper`: the damper model against measurements, the command line and its
//! presentation; the engine (reading, model runs, analysis, diagnosis, generated data) is
//! `damper_engine`.
//!
//! - [`cli`]: the command line;
//! - [`calibrate_cmd`]: `damper calibrate`'s table and files (parameters.ssv, calibration.json);
//! - [`compare`]: `damper compare`'s files and terminal summary, with [`report`] (the HTML report,
//!   its plots drawn by [`svg`]) and [`describe`] (one-line descriptions both share);
//! - [`description_cmd`]: `damper describe`, a damper description's parameters and its SSP set;
//! - [`diagnose_cmd`]: `damper diagnose`'s report section, terminal summary and files, with
//!   [`before_after_report`] (the model before and after the named effects);
//! - [`json_summary`]: `summary.json` from a comparison or a diagnosis.
pub mod before_after_report;
pub mod calibrate_cmd;
pub mod cli;
pub mod compare;
pub mod describe;
pub mod description_cmd;
pub mod diagnose_cmd;
pub mod effects_cmd;
pub mod json_summary;
pub mod report;
pub mod svg;
