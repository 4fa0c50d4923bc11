//! The FMI 3.0 C entry points, generic over the [`Model`]: each checks its pointers (null,
//! length) and hands Rust values to a safe [`Instance`] method, inside the panic guard of
//! `with_instance`. What FMI 3.0 adds over FMI 2.0 is handled here: the instantiation token and
//! the Co-Simulation options of `fmi3InstantiateCoSimulation`, the experiment's times given to
//! `fmi3EnterInitializationMode`, `nValues` beside `nValueReferences`, one-byte Booleans, the
//! independent variable `time`, and `fmi3DoStep`'s out-arguments.

use super::*;
use crate::boundary::{c_str, get_values, into_handle, out_arg, set_values, with_instance, Handle};
use crate::guard::ffi_guard;
use crate::instance::{Instance, Standard};
use crate::logger::{Callback, Logger};
use crate::state_machine::Api;
use crate::{Model, Status};
use std::ffi::{c_char, CString};
use std::fmt;
use std::ptr;

pub use crate::boundary::{
    deserialize_fmu_state, free_fmu_state, free_instance, get_fmu_state, serialize_fmu_state,
    serialized_fmu_state_size, set_debug_logging, set_fmu_state, unsupported,
};

pub fn get_version() -> *const c_char {
    fmi3Version.as_ptr() as *const c_char
}

/// The Co-Simulation options an importer asks for at instantiation.
pub struct CoSimulationOptions {
    pub logging_on: bool,
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
    pub n_required_intermediate_variables: usize,
}

/// # Safety
/// String arguments must be NULL or NUL-terminated; `log_message`, if set, must stay callable with
/// `environment` while the instance lives.
pub unsafe fn instantiate_co_simulation<M: Model>(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    time_vr: u32,
    options: CoSimulationOptions,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    const NAME: &str = "fmi3InstantiateCoSimulation";
    ffi_guard(ptr::null_mut(), || {
        // SAFETY: instance_name is NULL or NUL-terminated (the function's safety section).
        let name = unsafe { c_str(instance_name) };
        let logger = Logger::new(
            Callback::Fmi3 { log_message, environment },
            CString::from(name.unwrap_or(c"(null)")),
            options.logging_on,
        );
        let instance = Instance::<M>::new(logger, Standard::Fmi3 { time_vr });
        let refuse = |why: fmt::Arguments| {
            instance.error(format_args!("{NAME}: {why}"));
            ptr::null_mut()
        };
        if name.is_none_or(|n| n.to_bytes().iter().all(u8::is_ascii_whitespace)) {
            return refuse(format_args!("instanceName must be a non-empty string"));
        }
        // SAFETY: as above.
        let token = unsafe { c_str(instantiation_token) };
        if token.and_then(|g| g.to_str().ok()) != Some(M::GUID) {
            return refuse(format_args!("instantiationToken {token:?} does not match this FMU's {}", M::GUID));
        }
        if options.event_mode_used {
            return refuse(format_args!(
                "eventModeUsed is true, but this FMU has no Event Mode (hasEventMode = false)"
            ));
        }
        if options.n_required_intermediate_variables > 0 {
            return refuse(format_args!(
                "{} requiredIntermediateVariables given: no variable of this FMU has intermediateUpdate = true",
                options.n_required_intermediate_variables
            ));
        }
        // earlyReturnAllowed needs nothing: this FMU never returns early (mightReturnEarlyFromDoStep false)
        let _ = options.early_return_allowed;
        into_handle(instance)
    })
}

/// fmi3InstantiateModelExchange and fmi3InstantiateScheduledExecution: this FMU is Co-Simulation
/// only. The refusal is logged through the importer's callback, then NULL returned.
pub fn refuse_instantiation(
    function: &'static str,
    environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    ffi_guard(ptr::null_mut(), || {
        let logger = Logger::new(Callback::Fmi3 { log_message, environment }, CString::from(c"(none)"), false);
        logger.log(
            Status::Error,
            3,
            format_args!("{function}: this FMU supports Co-Simulation only (fmi3InstantiateCoSimulation)"),
        );
        ptr::null_mut()
    })
}

pub fn enter_initialization_mode<M: Model>(
    c: fmi3Instance,
    tolerance: Option<f64>,
    start: f64,
    stop: Option<f64>,
) -> fmi3Status {
    const NAME: &str = "fmi3EnterInitializationMode";
    with_instance::<M>(c, NAME, |inst| {
        inst.check(Api::EnterInitializationMode, NAME)?;
        inst.setup_experiment(NAME, tolerance, start, stop)?;
        inst.enter_initialization_mode(NAME)
    })
}

pub fn exit_initialization_mode<M: Model>(c: fmi3Instance) -> fmi3Status {
    const NAME: &str = "fmi3ExitInitializationMode";
    with_instance::<M>(c, NAME, |inst| inst.exit_initialization_mode(NAME))
}

pub fn terminate<M: Model>(c: fmi3Instance) -> fmi3Status {
    with_instance::<M>(c, "fmi3Terminate", |inst| inst.terminate("fmi3Terminate"))
}

pub fn reset<M: Model>(c: fmi3Instance) -> fmi3Status {
    with_instance::<M>(c, "fmi3Reset", |inst| inst.reset("fmi3Reset"))
}

/// Refuses an `nValues` other than `nValueReferences`: every variable of these FMUs is a scalar.
fn scalars<M: Model>(inst: &Instance<M>, function: &str, nvr: usize, n_values: usize) -> Result<(), crate::Failure> {
    if n_values == nvr {
        Ok(())
    } else {
        Err(inst.error(format_args!(
            "{function}: nValues {n_values} must equal nValueReferences {nvr}: every variable is a scalar"
        )))
    }
}

/// # Safety
/// (For the getters and setters below.)
/// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn get_float64<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *mut f64,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3GetFloat64";
    let get = |inst: &mut Instance<M>, vrs: &[u32], values: &mut [f64]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.get_real(NAME, vrs, values)
    };
    // SAFETY: the function's safety section is get_values's.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, get) }
}

/// # Safety
/// As [`get_float64`].
pub unsafe fn get_int32<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *mut i32,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3GetInt32";
    let get = |inst: &mut Instance<M>, vrs: &[u32], values: &mut [i32]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.get_integer(NAME, vrs, values)
    };
    // SAFETY: as above.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, get) }
}

/// # Safety
/// As [`get_float64`]; `value` is an array of C `bool`, written as bytes 0 and 1.
pub unsafe fn get_boolean<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *mut u8,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3GetBoolean";
    let get = |inst: &mut Instance<M>, vrs: &[u32], values: &mut [u8]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.get_boolean(NAME, vrs, values, u8::from)
    };
    // SAFETY: as above.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, get) }
}

/// # Safety
/// As [`get_float64`].
pub unsafe fn set_float64<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *const f64,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3SetFloat64";
    let set = |inst: &mut Instance<M>, vrs: &[u32], values: &[f64]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.set_real(NAME, vrs, values)
    };
    // SAFETY: the function's safety section is set_values's.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, set) }
}

/// # Safety
/// As [`get_float64`].
pub unsafe fn set_int32<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *const i32,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3SetInt32";
    let set = |inst: &mut Instance<M>, vrs: &[u32], values: &[i32]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.set_integer(NAME, vrs, values)
    };
    // SAFETY: as above.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, set) }
}

/// # Safety
/// As [`get_float64`]; `value` is an array of C `bool`, read as bytes (any non-zero byte is true,
/// so a foreign byte is no undefined behaviour).
pub unsafe fn set_boolean<M: Model>(
    c: Handle,
    vr: *const u32,
    nvr: usize,
    value: *const u8,
    n_values: usize,
) -> fmi3Status {
    const NAME: &str = "fmi3SetBoolean";
    let set = |inst: &mut Instance<M>, vrs: &[u32], values: &[u8]| {
        scalars(inst, NAME, vrs.len(), n_values)?;
        inst.set_boolean(NAME, vrs, values, |x| x != 0)
    };
    // SAFETY: as above.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, set) }
}

/// A getter or setter of a type these FMUs have no variables of.
///
/// # Safety
/// `vr` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn no_variables<M: Model>(
    c: Handle,
    function: &'static str,
    ty: &str,
    vr: *const u32,
    nvr: usize,
) -> fmi3Status {
    // the state table holds for nvr = 0 too: Get as any getter, Set where inputs may be set
    let api = if function.starts_with("fmi3Get") { Api::Get } else { Api::SetInput };
    // SAFETY: see the function's safety section.
    unsafe { crate::boundary::no_variables::<M>(c, function, api, ty, vr, nvr) }
}

/// What `fmi3DoStep` tells the importer besides its status.
pub struct StepOut {
    pub event_handling_needed: *mut fmi3Boolean,
    pub terminate_simulation: *mut fmi3Boolean,
    pub early_return: *mut fmi3Boolean,
    pub last_successful_time: *mut f64,
}

/// # Safety
/// Every pointer of `out` must be writable (a NULL one is refused).
pub unsafe fn do_step<M: Model>(c: Handle, t: f64, h: f64, out: StepOut) -> fmi3Status {
    const NAME: &str = "fmi3DoStep";
    with_instance::<M>(c, NAME, |inst| {
        // SAFETY: each is NULL or writable (the function's safety section).
        let (event, terminate, early, last) = unsafe {
            (
                out_arg(inst, NAME, "eventHandlingNeeded", out.event_handling_needed)?,
                out_arg(inst, NAME, "terminateSimulation", out.terminate_simulation)?,
                out_arg(inst, NAME, "earlyReturn", out.early_return)?,
                out_arg(inst, NAME, "lastSuccessfulTime", out.last_successful_time)?,
            )
        };
        // no events, no wish to stop (a discarded step can be retried from the same state), never
        // early
        (*event, *terminate, *early) = (false, false, false);
        let outcome = inst.do_step(NAME, t, h);
        *last = inst.last_successful_time();
        outcome
    })
}
