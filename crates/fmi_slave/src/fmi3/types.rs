//! The FMI 3.0 C types, transcribed from the standard's `fmi3PlatformTypes.h` and
//! `fmi3FunctionTypes.h` (FMI 3.0). Their licence (2-Clause BSD, Modelica Association Project
//! "FMI") is in `crates/fmi_slave/FMI-HEADERS-LICENSE.txt`; every FMU ships it.
//!
//! Carried here, as the FMI 2.0 types are, rather than taken from `fmi-sys`: an exporting FMU needs
//! only these names, and `fmi-sys` generates them with bindgen (building the FMU would need
//! libclang). The spelling follows the C headers, so tests that drive the C API read like C.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use std::ffi::{c_char, c_uint, c_void};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3FMUState = *mut c_void;
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C99 `bool`: one byte, 0 or 1.
pub type fmi3Boolean = bool;
pub type fmi3Char = c_char;
pub type fmi3String = *const fmi3Char;
pub type fmi3Byte = u8;
pub type fmi3Binary = *const fmi3Byte;
pub type fmi3Clock = bool;

pub const fmi3True: fmi3Boolean = true;
pub const fmi3False: fmi3Boolean = false;

/// `fmi3GetVersion()` returns this (NUL-terminated).
pub const fmi3Version: &[u8; 4] = b"3.0\0";

/// C enums are `int`-sized on every platform FMI 3.0 supports.
pub type fmi3Status = c_uint;
pub const fmi3OK: fmi3Status = 0;
pub const fmi3Warning: fmi3Status = 1;
pub const fmi3Discard: fmi3Status = 2;
pub const fmi3Error: fmi3Status = 3;
pub const fmi3Fatal: fmi3Status = 4;

pub type fmi3DependencyKind = c_uint;
pub type fmi3IntervalQualifier = c_uint;

/// The importer's logger. Unlike FMI 2.0's, `message` is plain text (no format string); `#` is
/// the escape character of value references (`#1365#`), so a literal `#` is written `##`.
pub type fmi3LogMessageCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ),
>;
pub type fmi3ClockUpdateCallback = Option<unsafe extern "C" fn(instanceEnvironment: fmi3InstanceEnvironment)>;
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        instanceEnvironment: fmi3InstanceEnvironment,
        intermediateUpdateTime: fmi3Float64,
        intermediateVariableSetRequested: fmi3Boolean,
        intermediateVariableGetAllowed: fmi3Boolean,
        intermediateStepFinished: fmi3Boolean,
        canReturnEarly: fmi3Boolean,
        earlyReturnRequested: *mut fmi3Boolean,
        earlyReturnTime: *mut fmi3Float64,
    ),
>;
pub type fmi3LockPreemptionCallback = Option<unsafe extern "C" fn()>;
pub type fmi3UnlockPreemptionCallback = Option<unsafe extern "C" fn()>;

/// The opaque pointer type of callbacks the FMU never calls (kept for the signatures).
pub type fmi3Opaque = *mut c_void;
