//! Why a run did not complete.

use std::path::PathBuf;

/// A run that could not start or did not finish; each names the instance, variable or time.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The job's JSON is malformed or inconsistent.
    #[error("job: {0}")]
    Job(String),
    /// An FMU could not be imported (unzipped, its model description read).
    #[error("{}: {problem}", path.display())]
    Import { path: PathBuf, problem: String },
    /// A variable the job names is not in the instance's FMU, or not of a usable type.
    #[error("{instance}.{variable}: {problem}")]
    Variable { instance: String, variable: String, problem: String },
    /// The caller's input series do not match the job's inputs.
    #[error("inputs: {0}")]
    Inputs(String),
    /// The tracking fit's buffers do not match their shapes, or an index is out of range.
    #[error("tracking fit: {0}")]
    TrackingFit(String),
    /// The record buffer has another size than (n_steps + 1) × recorded variables.
    #[error("record: a buffer of {given} values for {needed}")]
    RecordSize { given: usize, needed: usize },
    /// An FMU refused a call (fmi2Error, fmi2Fatal, or a step it discarded): the run stops there,
    /// as a master stops at an FMU's first error. `message` is the FMU's last logged error.
    #[error("{instance} refused {call} at t = {time} s: {message}")]
    Refused { instance: String, call: &'static str, time: f64, message: String },
}
