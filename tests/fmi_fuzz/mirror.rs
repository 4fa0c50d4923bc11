//! The importer's own copy of the FMI 2.0 Co-Simulation state table (FMI 2.0.4, §4.2.4), written
//! from the standard rather than from the FMU's code: which calls may succeed in which state.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
}

/// The calls whose legality depends on the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    Get,
    /// fmi2Set* of a parameter (variability fixed).
    SetParameter,
    /// fmi2Set* of an input, or of nothing (nvr = 0).
    SetInput,
    FmuState,
    DoStep,
    /// fmi2CancelStep: only while a step is pending, which never happens with a synchronous step.
    CancelStep,
    GetStatus,
    SetDebugLogging,
}

/// Whether `call` may return fmi2OK in `phase`.
pub fn may_succeed(phase: Phase, call: Call) -> bool {
    use Call::*;
    use Phase::*;
    match call {
        SetDebugLogging | Reset | FmuState => true,
        SetupExperiment | EnterInitializationMode => phase == Instantiated,
        ExitInitializationMode => phase == InitializationMode,
        Terminate => matches!(phase, StepComplete | StepFailed),
        Get => phase != Instantiated,
        SetParameter => matches!(phase, Instantiated | InitializationMode),
        SetInput => matches!(phase, Instantiated | InitializationMode | StepComplete),
        DoStep => phase == StepComplete,
        CancelStep => false,
        GetStatus => matches!(phase, StepComplete | StepFailed | Terminated),
    }
}
