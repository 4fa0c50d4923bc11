//! The Co-Simulation state machines of both standards: which function may be called in which
//! state. FMI 2.0.4 §4.2.4 ("Calling sequence", state chart and table); FMI 3.0 §2.3 (the common
//! states) and §4.2 (Step Mode). The two differ here in three places: FMI 3.0 allows getting
//! variables in Instantiated (their start values), has no fmi2SetupExperiment (its arguments come
//! with fmi3EnterInitializationMode) and no state of a discarded step (a discarded fmi3DoStep
//! leaves the FMU as it was, in Step Mode).

use crate::instance::Standard;

/// State of an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    /// FMI 2.0 stepComplete, FMI 3.0 Step Mode: ready for the next step.
    StepComplete,
    /// FMI 2.0 stepFailed: the last fmi2DoStep returned fmi2Discard.
    StepFailed,
    Terminated,
    /// A panic was caught: only freeing the instance is allowed.
    Fatal,
}

/// The API functions whose legality depends on the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Api {
    SetDebugLogging,
    /// fmi2SetupExperiment (FMI 2.0 only).
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    Get,
    /// Setting parameters with variability fixed (and inputs): before initialisation ends.
    SetFixed,
    /// Setting inputs.
    SetInput,
    FmuState,
    DoStep,
    /// fmi2Get*Status (FMI 2.0 only).
    GetStatus,
}

/// Whether `api` may be called in `phase` under `standard`.
pub fn allowed(standard: Standard, phase: Phase, api: Api) -> bool {
    use Api::*;
    use Phase::*;
    let fmi2 = matches!(standard, Standard::Fmi2);
    match (api, phase) {
        (_, Fatal) => false,
        (SetDebugLogging | Reset | FmuState, _) => true,
        (SetupExperiment | GetStatus, _) if !fmi2 => false,
        (SetupExperiment | EnterInitializationMode, Instantiated) => true,
        (ExitInitializationMode, InitializationMode) => true,
        (Terminate, StepComplete | StepFailed) => true,
        (Get, Instantiated) => !fmi2,
        (Get, InitializationMode | StepComplete | StepFailed | Terminated) => true,
        (SetFixed, Instantiated | InitializationMode) => true,
        (SetInput, Instantiated | InitializationMode | StepComplete) => true,
        (DoStep, StepComplete) => true,
        (GetStatus, StepComplete | StepFailed | Terminated) => true,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FMI3: Standard = Standard::Fmi3 { time_vr: 0 };

    #[test]
    fn lifecycle_table() {
        for standard in [Standard::Fmi2, FMI3] {
            let allowed = |phase, api| allowed(standard, phase, api);
            assert!(allowed(Phase::Instantiated, Api::EnterInitializationMode));
            assert!(!allowed(Phase::Instantiated, Api::DoStep));
            assert!(!allowed(Phase::InitializationMode, Api::DoStep));
            assert!(allowed(Phase::StepComplete, Api::DoStep));
            assert!(!allowed(Phase::StepComplete, Api::SetFixed));
            assert!(allowed(Phase::StepComplete, Api::SetInput));
            assert!(!allowed(Phase::StepFailed, Api::DoStep));
            assert!(!allowed(Phase::Terminated, Api::DoStep));
            assert!(!allowed(Phase::Fatal, Api::Reset));
        }
    }

    #[test]
    fn where_the_standards_differ() {
        assert!(allowed(Standard::Fmi2, Phase::Instantiated, Api::SetupExperiment));
        assert!(!allowed(FMI3, Phase::Instantiated, Api::SetupExperiment));
        assert!(!allowed(Standard::Fmi2, Phase::Instantiated, Api::Get));
        assert!(allowed(FMI3, Phase::Instantiated, Api::Get));
        assert!(allowed(Standard::Fmi2, Phase::StepComplete, Api::GetStatus));
        assert!(!allowed(FMI3, Phase::StepComplete, Api::GetStatus));
    }
}
