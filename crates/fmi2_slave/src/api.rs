//! The FMI 2.0 C entry points, generic over the [`Model`]: the only code here with `unsafe` and raw
//! pointers. Each function checks its pointers (null, length) and hands Rust values to a safe
//! [`Instance`] method, inside a panic guard: a panic becomes fmi2Fatal and the instance refuses
//! further calls; it never unwinds into the host. Memory comes from Rust's allocator
//! (`canNotUseMemoryManagementFunctions="true"`).

use crate::guard::{ffi_guard, slice, slice_mut};
use crate::instance::{status, Failure, Instance, Outcome};
use crate::logger::Logger;
use crate::state_machine::{Api, Phase};
use crate::Model;
use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// The C types, for the shims that [`crate::export_fmi2!`] emits.
pub use crate::fmi2;
use crate::fmi2::*;

/// Runs `f` on the instance behind `c`, turning a null instance into fmi2Error and a panic into
/// fmi2Fatal (logged, instance marked unusable).
fn with_instance<M: Model>(
    c: fmi2Component,
    function: &str,
    f: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> fmi2Status {
    // SAFETY: a non-null component is a pointer returned by fmi2Instantiate of this model and not
    // yet freed (the importer's obligation); the FMI standard forbids concurrent calls on one
    // instance.
    let Some(inst) = (unsafe { (c as *mut Instance<M>).as_mut() }) else {
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

/// A C string argument.
///
/// # Safety
/// A non-null `p` must point to a NUL-terminated string valid for the call.
unsafe fn c_str<'a>(p: fmi2String) -> Option<&'a CStr> {
    // SAFETY: the caller guarantees a NUL-terminated string when non-null.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) })
}

/// Logs and returns the error for a NULL pointer argument.
fn null_arg<M: Model>(inst: &Instance<M>, function: &str, what: &str) -> Failure {
    inst.error(format_args!("{function}: {what} is NULL"))
}

pub fn get_types_platform() -> *const c_char {
    fmi2TypesPlatform.as_ptr() as *const c_char
}

pub fn get_version() -> *const c_char {
    fmi2Version.as_ptr() as *const c_char
}

/// # Safety
/// `categories` must hold `n` valid C strings (or be NULL when `n` is 0).
pub unsafe fn set_debug_logging<M: Model>(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetDebugLogging", |inst| {
        inst.check(Api::SetDebugLogging, "fmi2SetDebugLogging")?;
        // SAFETY: the importer supplies n pointers.
        let names =
            unsafe { slice(categories, n) }.ok_or_else(|| null_arg(inst, "fmi2SetDebugLogging", "categories"))?;
        let mut list = [c""; crate::logger::CATEGORIES.len()];
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
            .set_debug_logging(logging_on != 0, &list[..names.len()])
            .map_err(|e| inst.error(format_args!("fmi2SetDebugLogging: {e}")))
    })
}

/// # Safety
/// String arguments must be NULL or NUL-terminated; `functions` must be NULL or point to a valid
/// `fmi2CallbackFunctions` whose logger, if set, stays callable while the instance lives.
pub unsafe fn instantiate<M: Model>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    _resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    ffi_guard(ptr::null_mut(), || {
        // SAFETY: see the function's safety section.
        let callbacks = unsafe { functions.as_ref() }.copied();
        // SAFETY: instance_name is NULL or NUL-terminated (the function's safety section).
        let name = unsafe { c_str(instance_name) };
        let logger = Logger::new(
            callbacks.and_then(|f| f.logger),
            callbacks.map_or(ptr::null_mut(), |f| f.componentEnvironment),
            CString::from(name.unwrap_or(c"(null)")),
            logging_on != 0,
        );
        let instance = Instance::<M>::new(logger);
        let refuse = |why: std::fmt::Arguments| {
            instance.error(format_args!("fmi2Instantiate: {why}"));
            ptr::null_mut()
        };
        if name.is_none_or(|n| n.is_empty()) {
            return refuse(format_args!("instanceName must be a non-empty string"));
        }
        if fmu_type != fmi2Type_fmi2CoSimulation {
            return refuse(format_args!("this FMU supports Co-Simulation only (fmuType {fmu_type})"));
        }
        // SAFETY: as above.
        let guid = unsafe { c_str(guid) };
        if guid.and_then(|g| g.to_str().ok()) != Some(M::GUID) {
            return refuse(format_args!("GUID {guid:?} does not match this FMU's {}", M::GUID));
        }
        Box::into_raw(Box::new(instance)) as fmi2Component
    })
}

/// # Safety
/// `c` must be NULL or an instance from [`instantiate`] of this model, not used again afterwards.
pub unsafe fn free_instance<M: Model>(c: fmi2Component) {
    ffi_guard((), || {
        if !c.is_null() {
            // SAFETY: `c` came from Box::into_raw in `instantiate` and is freed once.
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
        }
    })
}

pub fn setup_experiment<M: Model>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: f64,
    start: f64,
    stop_defined: fmi2Boolean,
    stop: f64,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetupExperiment", |inst| {
        inst.setup_experiment((tolerance_defined != 0).then_some(tolerance), start, (stop_defined != 0).then_some(stop))
    })
}

pub fn enter_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2EnterInitializationMode", Instance::enter_initialization_mode)
}

pub fn exit_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2ExitInitializationMode", Instance::exit_initialization_mode)
}

pub fn terminate<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Terminate", Instance::terminate)
}

pub fn reset<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Reset", Instance::reset)
}

/// Generates a generic getter and setter from Instance methods taking slices.
macro_rules! get_set {
    ($get:ident, $set:ident, $ty:ty, $cget:literal, $cset:literal) => {
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
        pub unsafe fn $get<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *mut $ty) -> fmi2Status {
            with_instance::<M>(c, $cget, |inst| {
                // SAFETY: the importer supplies nvr elements in each array.
                let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, $cget, "vr"))?;
                // SAFETY: as for vr: value holds nvr writable elements, and it is not vr's memory.
                let values = unsafe { slice_mut(value, nvr) }.ok_or_else(|| null_arg(inst, $cget, "value"))?;
                inst.$get(vrs, values)
            })
        }

        /// # Safety
        /// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
        pub unsafe fn $set<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *const $ty) -> fmi2Status {
            with_instance::<M>(c, $cset, |inst| {
                // SAFETY: the importer supplies nvr elements in each array.
                let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, $cset, "vr"))?;
                // SAFETY: as for vr: value holds nvr elements.
                let values = unsafe { slice(value, nvr) }.ok_or_else(|| null_arg(inst, $cset, "value"))?;
                inst.$set(vrs, values)
            })
        }
    };
}

get_set!(get_real, set_real, f64, "fmi2GetReal", "fmi2SetReal");
get_set!(get_integer, set_integer, i32, "fmi2GetInteger", "fmi2SetInteger");
get_set!(get_boolean, set_boolean, i32, "fmi2GetBoolean", "fmi2SetBoolean");

/// # Safety
/// `vr`, `order` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn set_real_input_derivatives<M: Model>(
    c: fmi2Component,
    vr: *const u32,
    nvr: usize,
    order: *const i32,
    value: *const f64,
) -> fmi2Status {
    const NAME: &str = "fmi2SetRealInputDerivatives";
    with_instance::<M>(c, NAME, |inst| {
        // SAFETY: the importer supplies nvr elements in each array.
        let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, NAME, "vr"))?;
        // SAFETY: as for vr.
        let orders = unsafe { slice(order, nvr) }.ok_or_else(|| null_arg(inst, NAME, "order"))?;
        // SAFETY: as for vr.
        let values = unsafe { slice(value, nvr) }.ok_or_else(|| null_arg(inst, NAME, "value"))?;
        inst.set_real_input_derivatives(vrs, orders, values)
    })
}

/// These FMUs have no String variables: any value reference is unknown.
///
/// # Safety
/// `vr` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn no_strings<M: Model>(c: fmi2Component, function: &'static str, vr: *const u32, nvr: usize) -> fmi2Status {
    with_instance::<M>(c, function, |inst| {
        // the state table holds for nvr = 0 too: Get as any getter, Set where inputs may be set
        let api = if function == "fmi2GetString" { Api::Get } else { Api::SetInput };
        inst.check(api, function)?;
        if nvr == 0 {
            return Ok(());
        }
        // SAFETY: the importer supplies nvr value references.
        let first = unsafe { slice(vr, nvr) }.and_then(|v| v.first().copied());
        Err(inst.error(format_args!("{function}: unknown value reference {first:?}: this FMU has no String variables")))
    })
}

/// Boxed FMU state. The header comes first (`repr(C)`) and is read on its own before the box is
/// used: a tag per model (from its GUID) and the box's size, so that a state of another FMU built
/// on this crate, which shares the header layout, is refused without reading past its allocation.
#[repr(C)]
struct StateBox<S> {
    tag: u64,
    size: u64,
    state: S,
}

impl<S> StateBox<S> {
    fn new<M: Model<State = S>>(state: S) -> Self {
        StateBox { tag: state_tag::<M>(), size: std::mem::size_of::<Self>() as u64, state }
    }
}

/// The model's state tag: FNV-1a of its GUID (never 0, the tag of a freed box).
fn state_tag<M: Model>() -> u64 {
    let hash = M::GUID.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3));
    hash | 1
}

/// # Safety
/// `s` must be NULL or a pointer returned by the state functions of this crate, for any model
/// (each such box starts with the 16-byte header of [`StateBox`]).
unsafe fn state_ref<'a, M: Model>(s: fmi2FMUstate) -> Option<&'a mut StateBox<M::State>> {
    if s.is_null() {
        return None;
    }
    let header = s as *const u64;
    // SAFETY: a non-null s is a StateBox of some model (see above): its first two words are its
    // tag and size, whatever the model; the rest is read only once both match this model's box.
    let (tag, size) = unsafe { (header.read(), header.add(1).read()) };
    if tag != state_tag::<M>() || size != std::mem::size_of::<StateBox<M::State>>() as u64 {
        return None;
    }
    // SAFETY: tag and size say this is a live box of model M.
    unsafe { (s as *mut StateBox<M::State>).as_mut() }
}

/// Stores `state` in the importer's slot: a new box when `*slot` is NULL, else the state it points
/// to is overwritten (FMI 2.0 §2.1.8).
///
/// # Safety
/// `slot` must be NULL or writable; a non-null `*slot` must be a state this library returned.
unsafe fn store_state<M: Model>(
    inst: &Instance<M>,
    function: &str,
    slot: *mut fmi2FMUstate,
    state: M::State,
) -> Outcome {
    // SAFETY: see above.
    let slot = unsafe { slot.as_mut() }.ok_or_else(|| null_arg(inst, function, "FMUstate"))?;
    // SAFETY: a non-null *slot is a state this library returned (the function's safety section).
    match unsafe { state_ref::<M>(*slot) } {
        Some(existing) => existing.state = state,
        None if slot.is_null() => *slot = Box::into_raw(Box::new(StateBox::new::<M>(state))) as fmi2FMUstate,
        None => return Err(inst.error(format_args!("{function}: *FMUstate is not a state of this FMU"))),
    }
    Ok(())
}

/// # Safety
/// `fmu_state` must point to writable storage for one pointer.
pub unsafe fn get_fmu_state<M: Model>(c: fmi2Component, fmu_state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetFMUstate", |inst| {
        let state = inst.get_fmu_state()?;
        // SAFETY: see the function's safety section.
        unsafe { store_state(inst, "fmi2GetFMUstate", fmu_state, state) }
    })
}

/// # Safety
/// `fmu_state` must be a state returned by this library and not yet freed.
pub unsafe fn set_fmu_state<M: Model>(c: fmi2Component, fmu_state: fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2SetFMUstate", |inst| {
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("fmi2SetFMUstate: FMUstate is NULL or not a state of this FMU")))?;
        let state = b.state.clone();
        inst.set_fmu_state(&state)
    })
}

/// # Safety
/// `fmu_state` must point to NULL or to a state returned by this library; it is set to NULL.
pub unsafe fn free_fmu_state<M: Model>(c: fmi2Component, fmu_state: *mut fmi2FMUstate) -> fmi2Status {
    with_instance::<M>(c, "fmi2FreeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2FreeFMUstate")?;
        // SAFETY: the importer supplies a pointer slot (or NULL).
        let Some(slot) = (unsafe { fmu_state.as_mut() }) else { return Ok(()) };
        if slot.is_null() {
            return Ok(());
        }
        // SAFETY: *slot is a state of this library or foreign (the function's safety section);
        // state_ref tells them apart by the tag.
        if unsafe { state_ref::<M>(*slot) }.is_none() {
            return Err(inst.error(format_args!("fmi2FreeFMUstate: not a state of this FMU")));
        }
        // SAFETY: the tag check above proved that *slot is a box of this library, and the slot is
        // cleared below, so it is freed once.
        let mut b = unsafe { Box::from_raw(*slot as *mut StateBox<M::State>) };
        b.tag = 0;
        *slot = ptr::null_mut();
        Ok(())
    })
}

/// # Safety
/// `fmu_state` must be a state of this library; `size` must be writable.
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: fmi2Component,
    fmu_state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SerializedFMUstateSize", |inst| {
        inst.check(Api::FmuState, "fmi2SerializedFMUstateSize")?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("fmi2SerializedFMUstateSize: FMUstate is NULL or foreign")))?;
        // SAFETY: size is NULL or writable (the function's safety section).
        let out = unsafe { size.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2SerializedFMUstateSize", "size"))?;
        *out = M::serialize(&b.state).len();
        Ok(())
    })
}

/// # Safety
/// `fmu_state` must be a state of this library; `bytes` must hold `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: fmi2Component,
    fmu_state: fmi2FMUstate,
    bytes: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2SerializeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2SerializeFMUstate")?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("fmi2SerializeFMUstate: FMUstate is NULL or foreign")))?;
        let serialized = M::serialize(&b.state);
        if size < serialized.len() {
            return Err(
                inst.error(format_args!("fmi2SerializeFMUstate: buffer of {size} bytes, {} needed", serialized.len()))
            );
        }
        // SAFETY: bytes holds size ≥ serialized.len() writable bytes (the function's safety section).
        let out = unsafe { slice_mut(bytes as *mut u8, serialized.len()) }
            .ok_or_else(|| null_arg(inst, "fmi2SerializeFMUstate", "serializedState"))?;
        out.copy_from_slice(&serialized);
        Ok(())
    })
}

/// # Safety
/// `bytes` must hold `size` bytes; `fmu_state` must point to NULL or a state of this library.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: fmi2Component,
    bytes: *const fmi2Byte,
    size: usize,
    fmu_state: *mut fmi2FMUstate,
) -> fmi2Status {
    with_instance::<M>(c, "fmi2DeSerializeFMUstate", |inst| {
        inst.check(Api::FmuState, "fmi2DeSerializeFMUstate")?;
        // SAFETY: see the function's safety section.
        let data = unsafe { slice(bytes as *const u8, size) }
            .ok_or_else(|| null_arg(inst, "fmi2DeSerializeFMUstate", "serializedState"))?;
        let state = M::deserialize(data).map_err(|e| inst.error(format_args!("fmi2DeSerializeFMUstate: {e}")))?;
        // SAFETY: fmu_state is NULL or writable, a non-null *fmu_state a state of this library (the
        // function's safety section).
        unsafe { store_state(inst, "fmi2DeSerializeFMUstate", fmu_state, state) }
    })
}

/// Refuses a function the FMU does not provide, with the reason.
pub fn unsupported<M: Model>(c: fmi2Component, function: &'static str, why: &'static str) -> fmi2Status {
    with_instance::<M>(c, function, |inst| Err(inst.error(format_args!("{function}: not supported: {why}"))))
}

pub fn do_step<M: Model>(c: fmi2Component, t: f64, h: f64) -> fmi2Status {
    with_instance::<M>(c, "fmi2DoStep", |inst| inst.do_step(t, h))
}

/// # Safety
/// `value` must be writable.
pub unsafe fn get_real_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut f64) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetRealStatus", |inst| {
        if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(inst.error(format_args!("fmi2GetRealStatus: only fmi2LastSuccessfulTime is available")));
        }
        let t = inst.last_successful_time()?;
        // SAFETY: the importer supplies a writable value.
        *unsafe { value.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2GetRealStatus", "value"))? = t;
        Ok(())
    })
}

/// # Safety
/// `value` must be writable.
pub unsafe fn get_boolean_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut i32) -> fmi2Status {
    with_instance::<M>(c, "fmi2GetBooleanStatus", |inst| {
        inst.check(Api::GetStatus, "fmi2GetBooleanStatus")?;
        if kind != fmi2StatusKind_fmi2Terminated {
            return Err(inst.error(format_args!("fmi2GetBooleanStatus: only fmi2Terminated is available")));
        }
        // The slave never asks to end the simulation: a discarded step can be retried or restored.
        // SAFETY: the importer supplies a writable value (the function's safety section).
        *unsafe { value.as_mut() }.ok_or_else(|| null_arg(inst, "fmi2GetBooleanStatus", "value"))? = fmi2False;
        Ok(())
    })
}
