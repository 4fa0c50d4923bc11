//! The importer's own copy of the Co-Simulation state tables, written from the standards rather
//! than from the FMU's code: which calls may succeed in which state. FMI 2.0.4 §4.2.4; FMI 3.0
//! §2.3 and §4.2 differ in that variables may be read in Instantiated (their start values), the
//! experiment comes with fmi3EnterInitializationMode, and a discarded fmi3DoStep leaves the FMU in
//! Step Mode, as it was.

use super::library::Standard;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    InitializationMode,
    /// FMI 2.0 stepComplete, FMI 3.0 Step Mode.
    StepComplete,
    /// FMI 2.0 only.
    StepFailed,
    Terminated,
}

/// The calls whose legality depends on the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// fmi2SetupExperiment.
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Reset,
    Get,
    /// Setting a parameter (variability fixed).
    SetParameter,
    /// Setting an input, or nothing (nvr = 0).
    SetInput,
    FmuState,
    DoStep,
    /// fmi2CancelStep: only while a step is pending, which never happens with a synchronous step.
    CancelStep,
    /// fmi2Get*Status.
    GetStatus,
    SetDebugLogging,
}

/// Whether `call` may return OK in `phase` under `standard`.
pub fn may_succeed(standard: Standard, phase: Phase, call: Call) -> bool {
    use Call::*;
    use Phase::*;
    let fmi3 = standard == Standard::Fmi3;
    match call {
        SetDebugLogging | Reset | FmuState => true,
        SetupExperiment => !fmi3 && phase == Instantiated,
        EnterInitializationMode => phase == Instantiated,
        ExitInitializationMode => phase == InitializationMode,
        Terminate => matches!(phase, StepComplete | StepFailed),
        Get => fmi3 || phase != Instantiated,
        SetParameter => matches!(phase, Instantiated | InitializationMode),
        SetInput => matches!(phase, Instantiated | InitializationMode | StepComplete),
        DoStep => phase == StepComplete,
        CancelStep => false,
        GetStatus => !fmi3 && matches!(phase, StepComplete | StepFailed | Terminated),
    }
}
