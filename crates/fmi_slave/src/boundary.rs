//! What both standards' entry points do alike at the C boundary, generic over the [`Model`]: find
//! the instance behind the C pointer (a panic becomes Fatal and the instance refuses further
//! calls; it never unwinds into the host), read C strings, free instances, and keep FMU states in
//! boxes that carry their model's tag. Both standards' instance and state handles are `void*` and
//! their status enums number alike ([`Status`]), so one implementation serves both; the functions
//! take the C function's name for their messages.

use crate::guard::{ffi_guard, slice, slice_mut};
use crate::instance::{status, Failure, Instance, Outcome};
use crate::logger::CATEGORIES;
use crate::state_machine::{Api, Phase};
use crate::{Model, Status};
use std::ffi::{c_char, c_uint, c_void, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

/// An instance handle: `fmi2Component`, `fmi3Instance`.
pub type Handle = *mut c_void;
/// An FMU state handle: `fmi2FMUstate`, `fmi3FMUState`.
pub type StateHandle = *mut c_void;

/// Runs `f` on the instance behind `c`, turning a null instance into Error and a panic into Fatal
/// (logged, instance marked unusable).
pub fn with_instance<M: Model>(c: Handle, function: &str, f: impl FnOnce(&mut Instance<M>) -> Outcome) -> c_uint {
    // SAFETY: a non-null handle is a pointer returned by this model's instantiate function and not
    // yet freed (the importer's obligation); both standards forbid concurrent calls on one
    // instance.
    let Some(inst) = (unsafe { (c as *mut Instance<M>).as_mut() }) else {
        return Status::Error.code();
    };
    if inst.phase == Phase::Fatal {
        return Status::Error.code();
    }
    match catch_unwind(AssertUnwindSafe(|| f(&mut *inst))) {
        Ok(outcome) => status(outcome).code(),
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("unknown");
            let _ = catch_unwind(AssertUnwindSafe(|| inst.fatal(function, message)));
            Status::Fatal.code()
        }
    }
}

/// A C string argument.
///
/// # Safety
/// A non-null `p` must point to a NUL-terminated string valid for the call.
pub unsafe fn c_str<'a>(p: *const c_char) -> Option<&'a CStr> {
    // SAFETY: the caller guarantees a NUL-terminated string when non-null.
    (!p.is_null()).then(|| unsafe { CStr::from_ptr(p) })
}

/// Logs and returns the error for a NULL pointer argument.
pub fn null_arg<M: Model>(inst: &Instance<M>, function: &str, what: &str) -> Failure {
    inst.error(format_args!("{function}: {what} is NULL"))
}

/// Moves a new instance to the heap, as the handle the importer keeps.
pub fn into_handle<M: Model>(instance: Instance<M>) -> Handle {
    Box::into_raw(Box::new(instance)) as Handle
}

/// # Safety
/// `c` must be NULL or an instance handle of this model, not used again afterwards.
pub unsafe fn free_instance<M: Model>(c: Handle) {
    ffi_guard((), || {
        if !c.is_null() {
            // SAFETY: `c` came from Box::into_raw in `into_handle` and is freed once.
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
        }
    })
}

/// # Safety
/// `categories` must hold `n` valid C strings (or be NULL when `n` is 0).
pub unsafe fn set_debug_logging<M: Model>(
    c: Handle,
    function: &'static str,
    logging_on: bool,
    n: usize,
    categories: *const *const c_char,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(Api::SetDebugLogging, function)?;
        // SAFETY: the importer supplies n pointers.
        let names = unsafe { slice(categories, n) }.ok_or_else(|| null_arg(inst, function, "categories"))?;
        let mut list = [c""; CATEGORIES.len()];
        if names.len() > list.len() {
            return Err(inst.error(format_args!("{function}: {} categories given, {} exist", names.len(), list.len())));
        }
        for (slot, &name) in list.iter_mut().zip(names) {
            // SAFETY: each entry is a C string from the importer.
            *slot = unsafe { c_str(name) }.ok_or_else(|| null_arg(inst, function, "a category"))?;
        }
        inst.logger
            .set_debug_logging(logging_on, &list[..names.len()])
            .map_err(|e| inst.error(format_args!("{function}: {e}")))
    })
}

/// Refuses a function the FMU does not provide, with the reason.
pub fn unsupported<M: Model>(c: Handle, function: &'static str, why: &'static str) -> c_uint {
    with_instance::<M>(c, function, |inst| Err(inst.error(format_args!("{function}: not supported: {why}"))))
}

/// Refuses a function for variables of a type the FMU has none of (nvr = 0 is a legal no-op, subject
/// to the state table like any getter or setter).
///
/// # Safety
/// `vr` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn no_variables<M: Model>(
    c: Handle,
    function: &'static str,
    api: Api,
    ty: &str,
    vr: *const u32,
    nvr: usize,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(api, function)?;
        if nvr == 0 {
            return Ok(());
        }
        // SAFETY: the importer supplies nvr value references.
        let first = unsafe { slice(vr, nvr) }.and_then(|v| v.first().copied());
        Err(inst.error(format_args!("{function}: unknown value reference {first:?}: this FMU has no {ty} variables")))
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
unsafe fn state_ref<'a, M: Model>(s: StateHandle) -> Option<&'a mut StateBox<M::State>> {
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
/// to is overwritten (FMI 2.0 §2.1.8, FMI 3.0 §2.2.6.4).
///
/// # Safety
/// `slot` must be NULL or writable; a non-null `*slot` must be a state this library returned.
unsafe fn store_state<M: Model>(
    inst: &Instance<M>,
    function: &str,
    slot: *mut StateHandle,
    state: M::State,
) -> Outcome {
    // SAFETY: see above.
    let slot = unsafe { slot.as_mut() }.ok_or_else(|| null_arg(inst, function, "FMUstate"))?;
    // SAFETY: a non-null *slot is a state this library returned (the function's safety section).
    match unsafe { state_ref::<M>(*slot) } {
        Some(existing) => existing.state = state,
        None if slot.is_null() => *slot = Box::into_raw(Box::new(StateBox::new::<M>(state))) as StateHandle,
        None => return Err(inst.error(format_args!("{function}: *FMUstate is not a state of this FMU"))),
    }
    Ok(())
}

/// # Safety
/// `fmu_state` must point to writable storage for one pointer.
pub unsafe fn get_fmu_state<M: Model>(c: Handle, function: &'static str, fmu_state: *mut StateHandle) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        let state = inst.get_fmu_state(function)?;
        // SAFETY: see the function's safety section.
        unsafe { store_state(inst, function, fmu_state, state) }
    })
}

/// # Safety
/// `fmu_state` must be a state returned by this library and not yet freed.
pub unsafe fn set_fmu_state<M: Model>(c: Handle, function: &'static str, fmu_state: StateHandle) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("{function}: FMUstate is NULL or not a state of this FMU")))?;
        let state = b.state.clone();
        inst.set_fmu_state(function, &state)
    })
}

/// # Safety
/// `fmu_state` must point to NULL or to a state returned by this library; it is set to NULL.
pub unsafe fn free_fmu_state<M: Model>(c: Handle, function: &'static str, fmu_state: *mut StateHandle) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(Api::FmuState, function)?;
        // SAFETY: the importer supplies a pointer slot (or NULL).
        let Some(slot) = (unsafe { fmu_state.as_mut() }) else { return Ok(()) };
        if slot.is_null() {
            return Ok(());
        }
        // SAFETY: *slot is a state of this library or foreign (the function's safety section);
        // state_ref tells them apart by the tag.
        if unsafe { state_ref::<M>(*slot) }.is_none() {
            return Err(inst.error(format_args!("{function}: not a state of this FMU")));
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
    c: Handle,
    function: &'static str,
    fmu_state: StateHandle,
    size: *mut usize,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(Api::FmuState, function)?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("{function}: FMUstate is NULL or foreign")))?;
        // SAFETY: size is NULL or writable (the function's safety section).
        let out = unsafe { size.as_mut() }.ok_or_else(|| null_arg(inst, function, "size"))?;
        *out = M::serialize(&b.state).len();
        Ok(())
    })
}

/// # Safety
/// `fmu_state` must be a state of this library; `bytes` must hold `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: Handle,
    function: &'static str,
    fmu_state: StateHandle,
    bytes: *mut u8,
    size: usize,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(Api::FmuState, function)?;
        // SAFETY: see the function's safety section.
        let b = unsafe { state_ref::<M>(fmu_state) }
            .ok_or_else(|| inst.error(format_args!("{function}: FMUstate is NULL or foreign")))?;
        let serialized = M::serialize(&b.state);
        if size < serialized.len() {
            return Err(inst.error(format_args!("{function}: buffer of {size} bytes, {} needed", serialized.len())));
        }
        // SAFETY: bytes holds size ≥ serialized.len() writable bytes (the function's safety section).
        let out =
            unsafe { slice_mut(bytes, serialized.len()) }.ok_or_else(|| null_arg(inst, function, "serializedState"))?;
        out.copy_from_slice(&serialized);
        Ok(())
    })
}

/// # Safety
/// `bytes` must hold `size` bytes; `fmu_state` must point to NULL or a state of this library.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: Handle,
    function: &'static str,
    bytes: *const u8,
    size: usize,
    fmu_state: *mut StateHandle,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        inst.check(Api::FmuState, function)?;
        // SAFETY: see the function's safety section.
        let data = unsafe { slice(bytes, size) }.ok_or_else(|| null_arg(inst, function, "serializedState"))?;
        let state = M::deserialize(data).map_err(|e| inst.error(format_args!("{function}: {e}")))?;
        // SAFETY: fmu_state is NULL or writable, a non-null *fmu_state a state of this library (the
        // function's safety section).
        unsafe { store_state(inst, function, fmu_state, state) }
    })
}

/// A writable scalar out-argument, or the logged error for a NULL one.
///
/// # Safety
/// A non-null `p` must be writable for the call.
pub unsafe fn out_arg<'a, M: Model, T>(
    inst: &Instance<M>,
    function: &str,
    what: &str,
    p: *mut T,
) -> Result<&'a mut T, Failure> {
    // SAFETY: see the function's safety section.
    unsafe { p.as_mut() }.ok_or_else(|| null_arg(inst, function, what))
}

/// Reads the importer's `nvr` value references and hands them, with the `value` array to fill,
/// to `get` (a getter of [`Instance`]).
///
/// # Safety
/// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0), in different memory.
pub unsafe fn get_values<M: Model, T>(
    c: Handle,
    function: &'static str,
    vr: *const u32,
    nvr: usize,
    value: *mut T,
    get: impl FnOnce(&mut Instance<M>, &[u32], &mut [T]) -> Outcome,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        // SAFETY: the importer supplies nvr elements in each array.
        let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, function, "vr"))?;
        // SAFETY: as for vr: value holds nvr writable elements, and it is not vr's memory.
        let values = unsafe { slice_mut(value, nvr) }.ok_or_else(|| null_arg(inst, function, "value"))?;
        get(inst, vrs, values)
    })
}

/// Reads the importer's `nvr` value references and values and hands them to `set` (a setter of
/// [`Instance`]).
///
/// # Safety
/// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn set_values<M: Model, T>(
    c: Handle,
    function: &'static str,
    vr: *const u32,
    nvr: usize,
    value: *const T,
    set: impl FnOnce(&mut Instance<M>, &[u32], &[T]) -> Outcome,
) -> c_uint {
    with_instance::<M>(c, function, |inst| {
        // SAFETY: the importer supplies nvr elements in each array.
        let vrs = unsafe { slice(vr, nvr) }.ok_or_else(|| null_arg(inst, function, "vr"))?;
        // SAFETY: as for vr: value holds nvr elements.
        let values = unsafe { slice(value, nvr) }.ok_or_else(|| null_arg(inst, function, "value"))?;
        set(inst, vrs, values)
    })
}
