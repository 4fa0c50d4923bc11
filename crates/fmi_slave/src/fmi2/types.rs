//! The FMI 2.0 C types, transcribed from the standard's `fmi2TypesPlatform.h` and
//! `fmi2FunctionTypes.h` (FMI 2.0.4, "default" platform). Their licence (2-Clause BSD, Modelica
//! Association Project "FMI") is in `crates/fmi_slave/FMI-HEADERS-LICENSE.txt`; every FMU ships it.
//!
//! Carried here rather than taken from `fmi-sys` because an exporting FMU needs only these few
//! dozen names: `fmi-sys` generates them with bindgen (so building the FMU would need libclang)
//! and links a C logger whose `callback_log` symbol would be exported beside the fmi2 functions.
//! The names follow bindgen's spelling of the C enums (`fmi2Status_fmi2OK`), so tests that drive
//! the C API read like C.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2Char = c_char;
pub type fmi2String = *const fmi2Char;
pub type fmi2Byte = c_char;

pub const fmi2True: fmi2Boolean = 1;
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2GetTypesPlatform()` returns this (NUL-terminated).
pub const fmi2TypesPlatform: &[u8; 8] = b"default\0";
/// `fmi2GetVersion()` returns this (NUL-terminated).
pub const fmi2Version: &[u8; 4] = b"2.0\0";

/// C enums are `int`-sized on every platform FMI 2.0 supports.
pub type fmi2Status = c_uint;
pub const fmi2Status_fmi2OK: fmi2Status = 0;
pub const fmi2Status_fmi2Warning: fmi2Status = 1;
pub const fmi2Status_fmi2Discard: fmi2Status = 2;
pub const fmi2Status_fmi2Error: fmi2Status = 3;
pub const fmi2Status_fmi2Fatal: fmi2Status = 4;
pub const fmi2Status_fmi2Pending: fmi2Status = 5;

pub type fmi2Type = c_uint;
pub const fmi2Type_fmi2ModelExchange: fmi2Type = 0;
pub const fmi2Type_fmi2CoSimulation: fmi2Type = 1;

pub type fmi2StatusKind = c_uint;
pub const fmi2StatusKind_fmi2DoStepStatus: fmi2StatusKind = 0;
pub const fmi2StatusKind_fmi2PendingStatus: fmi2StatusKind = 1;
pub const fmi2StatusKind_fmi2LastSuccessfulTime: fmi2StatusKind = 2;
pub const fmi2StatusKind_fmi2Terminated: fmi2StatusKind = 3;

/// The importer's logger: `message` is a printf format string, hence the variadic tail.
pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        componentEnvironment: fmi2ComponentEnvironment,
        instanceName: fmi2String,
        status: fmi2Status,
        category: fmi2String,
        message: fmi2String,
        ...
    ),
>;
pub type fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void>;
pub type fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(obj: *mut c_void)>;
pub type fmi2StepFinished =
    Option<unsafe extern "C" fn(componentEnvironment: fmi2ComponentEnvironment, status: fmi2Status)>;

#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct fmi2CallbackFunctions {
    pub logger: fmi2CallbackLogger,
    pub allocateMemory: fmi2CallbackAllocateMemory,
    pub freeMemory: fmi2CallbackFreeMemory,
    pub stepFinished: fmi2StepFinished,
    pub componentEnvironment: fmi2ComponentEnvironment,
}
