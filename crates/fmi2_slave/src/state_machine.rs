//! The FMI 2.0 Co-Simulation state machine (FMI 2.0.4 specification §4.2.4, "Calling sequence"
//! state chart and table): which function may be called in which state.

/// State of a slave instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    StepComplete,
    /// The last fmi2DoStep returned fmi2Discard.
    StepFailed,
    Terminated,
    /// A panic was caught: only fmi2FreeInstance is allowed.
    Fatal,
}

/// The API functions whose legality depends on the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Api {
    SetDebugLogging,
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
    GetStatus,
}

/// Whether `api` may be called in `phase`.
pub fn allowed(phase: Phase, api: Api) -> bool {
    use Api::*;
    use Phase::*;
    match (api, phase) {
        (_, Fatal) => false,
        (SetDebugLogging | Reset | FmuState, _) => true,
        (SetupExperiment | EnterInitializationMode, Instantiated) => true,
        (ExitInitializationMode, InitializationMode) => true,
        (Terminate, StepComplete | StepFailed) => true,
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

    #[test]
    fn lifecycle_table() {
        assert!(allowed(Phase::Instantiated, Api::SetupExperiment));
        assert!(!allowed(Phase::Instantiated, Api::DoStep));
        assert!(!allowed(Phase::Instantiated, Api::Get));
        assert!(!allowed(Phase::InitializationMode, Api::DoStep));
        assert!(allowed(Phase::StepComplete, Api::DoStep));
        assert!(!allowed(Phase::StepComplete, Api::SetFixed));
        assert!(allowed(Phase::StepComplete, Api::SetInput));
        assert!(!allowed(Phase::StepFailed, Api::DoStep));
        assert!(!allowed(Phase::Terminated, Api::DoStep));
        assert!(!allowed(Phase::Fatal, Api::Reset));
    }
}
