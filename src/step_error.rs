//! Why a damper step fails, and the limits that keep every step's work bounded whatever the
//! arguments, parameters or restored state (docs/robustness.md). The limits are far above what a
//! sane run needs: they turn a would-be hang into a refusal or a discarded step.

use crate::solver::SolverError;
use std::fmt;

/// Most controller samples in one step: 5000 s at the default T_sample of 0.5 ms.
pub const MAX_SAMPLES_PER_STEP: u32 = 10_000_000;
/// Most integration steps, accepted or rejected, in one controller sample.
pub const MAX_STEPS_PER_SAMPLE: u32 = 5000;
/// Smallest integration step (s) short of the one that lands on a sample: below it the step is
/// given up (the tolerance cannot be met, or time would stop advancing).
pub const MIN_STEP: f64 = 1e-10;
/// Resolution of the sample grid that the clock must keep, relative to T_sample: a tenth of the
/// grid's matching tolerance (1e-6 T_sample), so ≈ 62 h from t = 0 at T_sample 0.5 ms.
pub const GRID_RESOLUTION: f64 = 1e-7;

/// Why a step failed or was refused; the state is left as it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepError {
    /// The integrator failed.
    Solver(SolverError),
    /// More integration steps in one controller sample than [`MAX_STEPS_PER_SAMPLE`].
    TooManySteps,
    /// The step spans more controller samples than [`MAX_SAMPLES_PER_STEP`].
    TooManySamples,
    /// The clock is too far from 0 to resolve the sample grid ([`GRID_RESOLUTION`]).
    TimeResolution,
    /// An output is NaN or infinite at the end of the step.
    NonFiniteOutput,
}

impl From<SolverError> for StepError {
    fn from(e: SolverError) -> Self {
        StepError::Solver(e)
    }
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepError::Solver(e) => e.fmt(f),
            StepError::TooManySteps => {
                write!(f, "more than {MAX_STEPS_PER_SAMPLE} integration steps in one controller sample")
            }
            StepError::TooManySamples => write!(f, "more than {MAX_SAMPLES_PER_STEP} controller samples in one step"),
            StepError::TimeResolution => {
                write!(f, "time too far from 0 to resolve the controller's sample grid to {GRID_RESOLUTION} T_sample")
            }
            StepError::NonFiniteOutput => write!(f, "an output is not finite at the end of the step"),
        }
    }
}
