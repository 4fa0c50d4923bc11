//! The FMI 2.0 Co-Simulation C API: the only module with `unsafe` and C types.
//!
//! Every exported function is a few lines: null and length checks turn raw pointers into slices,
//! then a safe [`Instance`] method does the work, all inside a panic guard (a panic becomes
//! fmi2Fatal and the instance refuses further calls; it never unwinds into the host).
//! Memory comes from Rust's allocator (`canNotUseMemoryManagementFunctions="true"`).
#![allow(non_snake_case)]

mod guard;
mod instance;
mod logger;
mod state_machine;

use crate::model_description::GUID;
use crate::slave::SlaveState;
use fmi_sys::fmi2::*;
use guard::{ffi_guard, slice, slice_mut};
use instance::{status, Outcome};
pub use instance::{Failure, Instance};
use logger::Logger;
use state_machine::{Api, Phase};
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// Runs `f` on the instance behind `c`, turning a null instance into fmi2Error and a panic into
/// fmi2Fatal (logged, instance marked unusable).
fn with_instance(c: fmi2Component, function: &str, f: impl FnOnce(&mut Instance) -> Outcome) -> fmi2Status {
    // SAFETY: a non-null component is a pointer returned by fmi2Instantiate and not yet freed
    // (the importer's obligation); the FMI standard forbids concurrent calls on one instance.
    let Some(inst) = (unsafe { (c as *mut Instance).as_mut() }) else {
        return fmi2Status_fmi2Error;
    };
    if inst.phase == Phase::Fatal {
        return fmi2Status_fmi2Error;
    }
    match catch_unwind(AssertUnwindSafe(|| f(&mut *inst))) {
        Ok(outcome) => status(outcome),
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("unknown");
            let _ = catch_unwind(AssertUnwindSafe(|| inst.fatal(function, message)));
            fmi2Status_fmi2Fatal
        }
    }
}

/// A C string argument, or an error naming it.
///
/// # Safety
/// A non-null `p` must point to a NUL-terminated string valid for the call.
unsafe fn c_str<'a>(p: fmi2String) -> Option<&'a CStr> {
    // SAFETY: the caller guarantees a NUL-terminated string when non-null.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) })
}

/// Logs and returns the error for a NULL pointer argument.
fn null_arg(inst: &Instance, function: &str, what: &str) -> Failure {
    inst.error(format_args!("{function}: {what} is NULL"))
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    fmi2TypesPlatform.as_ptr() as *const c_char
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    fmi2Version.as_ptr() as *const c_char
}

/// # Safety
/// `categories` must hold `nCategories` valid C strings (or be NULL when `nCategories` is 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    with_instance(c, "fmi2SetDebugLogging", |inst| {
        inst.check(Api::SetDebugLogging, "fmi2SetDebugLogging")?;
        // SAFETY: importer supplies nCategories pointers.
        let names = unsafe { slice(categories, nCategories) }
            .ok_or_else(|| null_arg(inst, "fmi2SetDebugLogging", "categories"))?;
        let mut list = [c""; logger::CATEGORIES.len()];
        if names.len() > list.len() {
            return Err(inst.error(format_args!(
                "fmi2SetDebugLogging: {} categories given, {} exist",
                names.len(),
                list.len()
            )));
        }
        for (slot, &name) in list.iter_mut().zip(names) {
            // SAFETY: each entry is a C string from the importer.
            *slot = unsafe { c_str(name) }.ok_or_else(|| null_arg(inst, "fmi2SetDebugLogging", "a category"))?;
        }
        inst.logger
            .set_debug_logging(loggingOn != 0, &list[..names.len()])
            .map_err(|e| inst.error(format_args!("fmi2SetDebugLogging: {e}")))
    })
}

/// # Safety
/// String arguments must be NULL or NUL-terminated; `functions` must be NULL or point to a valid
/// `fmi2CallbackFunctions` whose logger, if set, stays callable while the instance lives.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: fmi2Type,
    fmuGUID: fmi2String,
    _fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    ffi_guard(ptr::null_mut(), || {
        // SAFETY: see the function's safety section.
        let callbacks = unsafe { functions.as_ref() }.copied();
        let name = unsafe { c_str(instanceName) };
        let logger = Logger::new(
            callbacks.and_then(|f| f.logger),
            callbacks.map_or(ptr::null_mut(), |f| f.componentEnvironment),
            CString::from(name.unwrap_or(c"(null)")),
            loggingOn != 0,
        );
        let instance = Instance::new(logger);
        let refuse = |why: std::fmt::Arguments| {
            instance.error(format_args!("fmi2Instantiate: {why}"));
            ptr::null_mut()
        };
        if name.is_none_or(|n| n.is_empty()) {
            return refuse(format_args!("instanceName must be a non-empty string"));
        }
        if fmuType != fmi2Type_fmi2CoSimulation {
            return refuse(format_args!("this FMU supports Co-Simulation only (fmuType {fmuType})"));
        }
        // SAFETY: as above.
        let guid = unsafe { c_str(fmuGUID) };
        if guid.and_then(|g| g.to_str().ok()) != Some(GUID) {
            return refuse(format_args!("GUID {guid:?} does not match this FMU's {GUID}"));
        }
        Box::into_raw(Box::new(instance)) as fmi2Component
    })
}

/// # Safety
/// `c` must be NULL or an instance from fmi2Instantiate, not used again afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    ffi_guard((), || {
        if !c.is_null() {
            // SAFETY: `c` came from Box::into_raw in fmi2Instantiate and is freed once.
            drop(unsafe { Box::from_raw(c as *mut Instance) });
        }
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    toleranceDefined: fmi2Boolean,
    tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    with_instance(c, "fmi2SetupExperiment", |inst| {
        inst.setup_experiment(
            (toleranceDefined != 0).then_some(tolerance),
            startTime,
            (stopTimeDefined != 0).then_some(stopTime),
        )
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2EnterInitializationMode", Instance::enter_initialization_mode)
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2ExitInitializationMode", Instance::exit_initialization_mode)
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Terminate", Instance::terminate)
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    with_instance(c, "fmi2Reset", Instance::reset)
}

/// Generates fmi2Get<Type>/fmi2Set<Type> from an Instance method taking slices.
macro_rules! get_set {
    ($get:ident, $set:ident, $ty:ty, $get_method:ident, $set_method:ident) => {
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $get(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut $ty,
        ) -> fmi2Status {
            with_instance(c, stringify!($get), |inst| {
                // SAFETY: the importer supplies nvr elements in each array.
                let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, stringify!($get), "vr"))?;
                let values =
                    unsafe { slice_mut(value, nvr) }.ok_or_else(|| null_arg(inst, stringify!($get), "value"))?;
                inst.$get_method(vrs, values)
            })
        }

        /// # Safety
        /// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $set(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const $ty,
        ) -> fmi2Status {
            with_instance(c, stringify!($set), |inst| {
                // SAFETY: the importer supplies nvr elements in each array.
                let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, stringify!($set), "vr"))?;
                let values = unsafe { slice(value, nvr) }.ok_or_else(|| null_arg(inst, stringify!($set), "value"))?;
                inst.$set_method(vrs, values)
            })
        }
    };
}

get_set!(fmi2GetReal, fmi2SetReal, fmi2Real, get_real, set_real);
get_set!(fmi2GetInteger, fmi2SetInteger, fmi2Integer, get_integer, set_integer);
get_set!(fmi2GetBoolean, fmi2SetBoolean, fmi2Boolean, get_boolean, set_boolean);

/// This FMU has no String variables: any value reference is unknown.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *mut fmi2String,
) -> fmi2Status {
    no_strings(c, "fmi2GetString", vr, nvr)
}

/// This FMU has no String variables: any value reference is unknown.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    _value: *const fmi2String,
) -> fmi2Status {
    no_strings(c, "fmi2SetString", vr, nvr)
}

fn no_strings(c: fmi2Component, function: &'static str, vr: *const fmi2ValueReference, nvr: usize) -> fmi2Status {
    with_instance(c, function, |inst| {
        if nvr == 0 {
            return Ok(());
        }
        // SAFETY: the importer supplies nvr value references.
        let first = unsafe { slice(vr, nvr) }.and_then(|v| v.first().copied());
        Err(inst.error(format_args!("{function}: unknown value reference {first:?}: this FMU has no String variables")))
    })
}

/// Boxed FMU state; the tag lets a foreign pointer be refused rather than misread.
struct StateBox {
    tag: u64,
    state: SlaveState,
}

const STATE_TAG: u64 = 0x5341_4453_5441_5445; // "SADSTATE"

/// # Safety
/// `s` must be NULL or a pointer returned by this library's fmi2GetFMUstate/fmi2DeSerializeFMUstate.
unsafe fn state_ref<'a>(s: fmi2FMUstate) -> Option<&'a mut StateBox> {
    // SAFETY: see above.
    unsafe { (s as *mut StateBox).as_mut() }.filter(|b| b.tag == STATE_TAG)
}

/// # Safety
/// `FMUstate` must point to writable storage for one pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2GetFMUstate", |inst| {
        let state = inst.get_fmu_state()?;
        // SAFETY: see the function's safety section.
        unsafe { store_state(inst, "fmi2GetFMUstate", FMUstate, state) }
    })
}

/// Stores `state` in the importer's slot: a new box when `*slot` is NULL, else the state it points
/// to is overwritten (FMI 2.0 §2.1.8).
///
/// # Safety
/// `slot` must be NULL or writable; a non-null `*slot` must be a state this library returned.
unsafe fn store_state(inst: &Instance, function: &str, slot: *mut fmi2FMUstate, state: SlaveState) -> Outcome {
    // SAFETY: see above.
    let slot = unsafe { slot.as_mut() }.ok_or_else(|| null_arg(inst, function, "FMUstate"))?;
    match unsafe { state_ref(*slot) } {
        Some(existing) => existing.state = state,
        None if slot.is_null() => *slot = Box::into_raw(Box::new(StateBox { tag: STATE_TAG, state })) as fmi2FMUstate,
        None => return Err(inst.error(format_args!("{function}: *FMUstate is not a state of this FMU"))),
    }
    Ok(())
}

/// # Safety
/// `FMUstate` must be a state returned by this library and not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2SetFMUstate", |inst| {
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref(FMUstate) }
            .ok_or_else(|| inst.error(format_args!("fmi2SetFMUstate: FMUstate is NULL or not a state of this FMU")))?;
        let state = b.state;
        inst.set_fmu_state(&state)
    })
}

/// # Safety
/// `FMUstate` must point to NULL or to a state returned by this library; it is set to NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    with_instance(c, "fmi2FreeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2FreeFMUstate")?;
        // SAFETY: the importer supplies a pointer slot (or NULL).
        let Some(slot) = (unsafe { FMUstate.as_mut() }) else { return Ok(()) };
        if slot.is_null() {
            return Ok(());
        }
        // SAFETY: checked by tag; the box came from Box::into_raw and is freed once.
        if unsafe { state_ref(*slot) }.is_none() {
            return Err(inst.error(format_args!("fmi2FreeFMUstate: not a state of this FMU")));
        }
        let mut b = unsafe { Box::from_raw(*slot as *mut StateBox) };
        b.tag = 0;
        *slot = ptr::null_mut();
        Ok(())
    })
}

/// # Safety
/// `FMUstate` must be a state of this library; `size` must be writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with_instance(c, "fmi2SerializedFMUstateSize", |inst| {
        inst.check(Api::FmuState, "fmi2SerializedFMUstateSize")?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref(FMUstate) }
            .ok_or_else(|| inst.error(format_args!("fmi2SerializedFMUstateSize: FMUstate is NULL or foreign")))?;
        let out = unsafe { size.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2SerializedFMUstateSize", "size"))?;
        *out = b.state.to_bytes().len();
        Ok(())
    })
}

/// # Safety
/// `FMUstate` must be a state of this library; `serializedState` must hold `size` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with_instance(c, "fmi2SerializeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2SerializeFMUstate")?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref(FMUstate) }
            .ok_or_else(|| inst.error(format_args!("fmi2SerializeFMUstate: FMUstate is NULL or foreign")))?;
        let bytes = b.state.to_bytes();
        if size < bytes.len() {
            return Err(
                inst.error(format_args!("fmi2SerializeFMUstate: buffer of {size} bytes, {} needed", bytes.len()))
            );
        }
        let out = unsafe { slice_mut(serializedState as *mut u8, bytes.len()) }
            .ok_or_else(|| null_arg(inst, "fmi2SerializeFMUstate", "serializedState"))?;
        out.copy_from_slice(&bytes);
        Ok(())
    })
}

/// # Safety
/// `serializedState` must hold `size` bytes; `FMUstate` must point to NULL or a state of this library.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    with_instance(c, "fmi2DeSerializeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2DeSerializeFMUstate")?;
        // SAFETY: see the function's safety section.
        let bytes = unsafe { slice(serializedState as *const u8, size) }
            .ok_or_else(|| null_arg(inst, "fmi2DeSerializeFMUstate", "serializedState"))?;
        let state =
            SlaveState::from_bytes(bytes).map_err(|e| inst.error(format_args!("fmi2DeSerializeFMUstate: {e}")))?;
        unsafe { store_state(inst, "fmi2DeSerializeFMUstate", FMUstate, state) }
    })
}

/// Not provided (`providesDirectionalDerivative` is false).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _vUnknown_ref: *const fmi2ValueReference,
    _nUnknown: usize,
    _vKnown_ref: *const fmi2ValueReference,
    _nKnown: usize,
    _dvKnown: *const fmi2Real,
    _dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetDirectionalDerivative", "providesDirectionalDerivative is false")
}

/// Not provided (`canInterpolateInputs` is false).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *const fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2SetRealInputDerivatives", "canInterpolateInputs is false")
}

/// Not provided (`maxOutputDerivativeOrder` is 0).
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _nvr: usize,
    _order: *const fmi2Integer,
    _value: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder is 0")
}

fn unsupported(c: fmi2Component, function: &'static str, why: &'static str) -> fmi2Status {
    with_instance(c, function, |inst| Err(inst.error(format_args!("{function}: not supported: {why}"))))
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2DoStep", |inst| inst.do_step(currentCommunicationPoint, communicationStepSize))
}

/// fmi2DoStep always completes synchronously, so there is never a step to cancel.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsupported(c, "fmi2CancelStep", "fmi2DoStep is synchronous, no step is ever pending")
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStatus(c: fmi2Component, s: fmi2StatusKind, _value: *mut fmi2Status) -> fmi2Status {
    with_instance(c, "fmi2GetStatus", |inst| {
        Err(inst.error(format_args!("fmi2GetStatus: status kind {s} not available: fmi2DoStep is synchronous")))
    })
}

/// # Safety
/// `value` must be writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: fmi2Component, s: fmi2StatusKind, value: *mut fmi2Real) -> fmi2Status {
    with_instance(c, "fmi2GetRealStatus", |inst| {
        if s != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(inst.error(format_args!("fmi2GetRealStatus: only fmi2LastSuccessfulTime is available")));
        }
        let t = inst.last_successful_time()?;
        // SAFETY: the importer supplies a writable value.
        *unsafe { value.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2GetRealStatus", "value"))? = t;
        Ok(())
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetIntegerStatus(c: fmi2Component, _s: fmi2StatusKind, _value: *mut fmi2Integer) -> fmi2Status {
    unsupported(c, "fmi2GetIntegerStatus", "no Integer status is defined for FMI 2.0 Co-Simulation")
}

/// # Safety
/// `value` must be writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    with_instance(c, "fmi2GetBooleanStatus", |inst| {
        inst.check(Api::GetStatus, "fmi2GetBooleanStatus")?;
        if s != fmi2StatusKind_fmi2Terminated {
            return Err(inst.error(format_args!("fmi2GetBooleanStatus: only fmi2Terminated is available")));
        }
        // The slave never asks to end the simulation: a discarded step can be retried or restored.
        *unsafe { value.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2GetBooleanStatus", "value"))? = fmi2False as i32;
        Ok(())
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStringStatus(c: fmi2Component, _s: fmi2StatusKind, _value: *mut fmi2String) -> fmi2Status {
    unsupported(c, "fmi2GetStringStatus", "fmi2DoStep is synchronous, no status message is pending")
}
