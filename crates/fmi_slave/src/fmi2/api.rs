//! The FMI 2.0 C entry points, generic over the [`Model`]: each checks its pointers (null,
//! length) and hands Rust values to a safe [`Instance`] method, inside the panic guard of
//! `with_instance`. Memory comes from Rust's allocator (`canNotUseMemoryManagementFunctions="true"`).

use super::*;
use crate::boundary::{c_str, get_values, into_handle, null_arg, out_arg, set_values, with_instance};
use crate::guard::{ffi_guard, slice};
use crate::instance::{Instance, Standard};
use crate::logger::{Callback, Logger};
use crate::state_machine::Api;
use crate::Model;
use std::ffi::{c_char, CString};
use std::ptr;

pub use crate::boundary::{
    deserialize_fmu_state, free_fmu_state, free_instance, get_fmu_state, serialize_fmu_state,
    serialized_fmu_state_size, set_debug_logging, set_fmu_state, unsupported,
};

pub fn get_types_platform() -> *const c_char {
    fmi2TypesPlatform.as_ptr() as *const c_char
}

pub fn get_version() -> *const c_char {
    fmi2Version.as_ptr() as *const c_char
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
        let callback = Callback::Fmi2 {
            logger: callbacks.and_then(|f| f.logger),
            environment: callbacks.map_or(ptr::null_mut(), |f| f.componentEnvironment),
        };
        let logger = Logger::new(callback, CString::from(name.unwrap_or(c"(null)")), logging_on != 0);
        let instance = Instance::<M>::new(logger, Standard::Fmi2);
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
        into_handle(instance)
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
    const NAME: &str = "fmi2SetupExperiment";
    with_instance::<M>(c, NAME, |inst| {
        inst.check(Api::SetupExperiment, NAME)?;
        inst.setup_experiment(
            NAME,
            (tolerance_defined != 0).then_some(tolerance),
            start,
            (stop_defined != 0).then_some(stop),
        )
    })
}

pub fn enter_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    const NAME: &str = "fmi2EnterInitializationMode";
    with_instance::<M>(c, NAME, |inst| inst.enter_initialization_mode(NAME))
}

pub fn exit_initialization_mode<M: Model>(c: fmi2Component) -> fmi2Status {
    const NAME: &str = "fmi2ExitInitializationMode";
    with_instance::<M>(c, NAME, |inst| inst.exit_initialization_mode(NAME))
}

pub fn terminate<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Terminate", |inst| inst.terminate("fmi2Terminate"))
}

pub fn reset<M: Model>(c: fmi2Component) -> fmi2Status {
    with_instance::<M>(c, "fmi2Reset", |inst| inst.reset("fmi2Reset"))
}

/// # Safety
/// (For the getters and setters below.)
/// `vr` and `value` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn get_real<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *mut f64) -> fmi2Status {
    const NAME: &str = "fmi2GetReal";
    // SAFETY: the function's safety section is get_values's.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, |inst, vrs, values| inst.get_real(NAME, vrs, values)) }
}

/// # Safety
/// As [`get_real`].
pub unsafe fn get_integer<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *mut i32) -> fmi2Status {
    const NAME: &str = "fmi2GetInteger";
    // SAFETY: as above.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, |inst, vrs, values| inst.get_integer(NAME, vrs, values)) }
}

/// # Safety
/// As [`get_real`].
pub unsafe fn get_boolean<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *mut i32) -> fmi2Status {
    const NAME: &str = "fmi2GetBoolean";
    let get = |inst: &mut Instance<M>, vrs: &[u32], values: &mut [i32]| {
        inst.get_boolean(NAME, vrs, values, |b| b as fmi2Boolean)
    };
    // SAFETY: as above.
    unsafe { get_values::<M, _>(c, NAME, vr, nvr, value, get) }
}

/// # Safety
/// As [`get_real`].
pub unsafe fn set_real<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *const f64) -> fmi2Status {
    const NAME: &str = "fmi2SetReal";
    // SAFETY: the function's safety section is set_values's.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, |inst, vrs, values| inst.set_real(NAME, vrs, values)) }
}

/// # Safety
/// As [`get_real`].
pub unsafe fn set_integer<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *const i32) -> fmi2Status {
    const NAME: &str = "fmi2SetInteger";
    // SAFETY: as above.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, |inst, vrs, values| inst.set_integer(NAME, vrs, values)) }
}

/// # Safety
/// As [`get_real`]. Any non-zero `int` is true.
pub unsafe fn set_boolean<M: Model>(c: fmi2Component, vr: *const u32, nvr: usize, value: *const i32) -> fmi2Status {
    const NAME: &str = "fmi2SetBoolean";
    let set = |inst: &mut Instance<M>, vrs: &[u32], values: &[i32]| inst.set_boolean(NAME, vrs, values, |x| x != 0);
    // SAFETY: as above.
    unsafe { set_values::<M, _>(c, NAME, vr, nvr, value, set) }
}

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
        inst.set_real_input_derivatives(NAME, vrs, orders, values)
    })
}

/// These FMUs have no String variables: any value reference is unknown.
///
/// # Safety
/// `vr` must hold `nvr` elements (or be NULL when `nvr` is 0).
pub unsafe fn no_strings<M: Model>(c: fmi2Component, function: &'static str, vr: *const u32, nvr: usize) -> fmi2Status {
    // the state table holds for nvr = 0 too: Get as any getter, Set where inputs may be set
    let api = if function == "fmi2GetString" { Api::Get } else { Api::SetInput };
    // SAFETY: see the function's safety section.
    unsafe { crate::boundary::no_variables::<M>(c, function, api, "String", vr, nvr) }
}

pub fn do_step<M: Model>(c: fmi2Component, t: f64, h: f64) -> fmi2Status {
    with_instance::<M>(c, "fmi2DoStep", |inst| inst.do_step("fmi2DoStep", t, h))
}

/// # Safety
/// `value` must be writable.
pub unsafe fn get_real_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut f64) -> fmi2Status {
    const NAME: &str = "fmi2GetRealStatus";
    with_instance::<M>(c, NAME, |inst| {
        if kind != fmi2StatusKind_fmi2LastSuccessfulTime {
            return Err(inst.error(format_args!("{NAME}: only fmi2LastSuccessfulTime is available")));
        }
        let t = inst.last_successful_time_status(NAME)?;
        // SAFETY: the importer supplies a writable value.
        *unsafe { out_arg(inst, NAME, "value", value) }? = t;
        Ok(())
    })
}

/// # Safety
/// `value` must be writable.
pub unsafe fn get_boolean_status<M: Model>(c: fmi2Component, kind: fmi2StatusKind, value: *mut i32) -> fmi2Status {
    const NAME: &str = "fmi2GetBooleanStatus";
    with_instance::<M>(c, NAME, |inst| {
        inst.check(Api::GetStatus, NAME)?;
        if kind != fmi2StatusKind_fmi2Terminated {
            return Err(inst.error(format_args!("{NAME}: only fmi2Terminated is available")));
        }
        // The slave never asks to end the simulation: a discarded step can be retried or restored.
        // SAFETY: the importer supplies a writable value (the function's safety section).
        *unsafe { out_arg(inst, NAME, "value", value) }? = fmi2False;
        Ok(())
    })
}
