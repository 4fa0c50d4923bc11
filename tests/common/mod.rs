//! Calling the exported C API in-process, as an importer would.
#![allow(dead_code)]

pub mod cdylib;

use fmi_slave::fmi2::*;
use semi_active_damper::c_api::*;
use semi_active_damper::model_description::{RealVar, GUID};
use std::ffi::{c_char, CStr, CString};
use std::sync::Mutex;

/// Messages logged by every instance of this test binary (test name in the instance name).
pub static LOG: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// A logger callback without the variadic tail.
pub type FixedLogger = unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String);

/// The importer's logger; declared without the variadic tail (the FMU passes none: its message
/// is the format string with '%' escaped), which the x86-64 C ABI allows.
unsafe extern "C" fn logger(
    _env: fmi2ComponentEnvironment,
    name: fmi2String,
    status: fmi2Status,
    _cat: fmi2String,
    msg: fmi2String,
) {
    // SAFETY: the FMU passes NUL-terminated instance names and messages, valid for the call.
    let name = unsafe { CStr::from_ptr(name) }.to_string_lossy();
    // SAFETY: as name.
    let msg = unsafe { CStr::from_ptr(msg) }.to_string_lossy();
    LOG.lock().unwrap().push(format!("{name} [{status}] {msg}"));
}

pub fn logged(instance: &str) -> Vec<String> {
    LOG.lock().unwrap().iter().filter(|m| m.starts_with(instance)).cloned().collect()
}

pub const OK: fmi2Status = fmi2Status_fmi2OK;
pub const ERROR: fmi2Status = fmi2Status_fmi2Error;

pub struct Fmu {
    pub c: fmi2Component,
    pub name: String,
}

impl Fmu {
    pub fn new(name: &str) -> Fmu {
        Fmu::with_logger(name, logger)
    }

    pub fn with_logger(name: &str, logger: FixedLogger) -> Fmu {
        let callbacks = fmi2CallbackFunctions {
            // SAFETY: see `logger`.
            logger: unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(logger) },
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        };
        let cname = CString::new(name).unwrap();
        let guid = CString::new(GUID).unwrap();
        // SAFETY: the name and GUID are NUL-terminated CStrings and callbacks a valid struct, all alive for
        // the call (the FMU copies what it keeps).
        let c = unsafe {
            fmi2Instantiate(
                cname.as_ptr(),
                fmi2Type_fmi2CoSimulation,
                guid.as_ptr(),
                std::ptr::null(),
                &callbacks,
                0,
                0,
            )
        };
        assert!(!c.is_null());
        Fmu { c, name: name.into() }
    }

    pub fn initialised(name: &str, setup: impl FnOnce(&Fmu)) -> Fmu {
        let f = Fmu::new(name);
        setup(&f);
        f.initialise();
        f
    }

    /// setupExperiment at t = 0, enter and exit initialisation mode.
    pub fn initialise(&self) {
        assert_eq!(fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(self.c), OK);
        assert_eq!(fmi2ExitInitializationMode(self.c), OK);
    }

    pub fn set(&self, v: RealVar, x: f64) -> fmi2Status {
        // SAFETY: vr and value point to one element each.
        unsafe { fmi2SetReal(self.c, &v.vr(), 1, &x) }
    }

    pub fn get(&self, v: RealVar) -> f64 {
        let mut x = f64::NAN;
        // SAFETY: vr and value point to one element each.
        assert_eq!(unsafe { fmi2GetReal(self.c, &v.vr(), 1, &mut x) }, OK);
        x
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        fmi2DoStep(self.c, t, h, 1)
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        // SAFETY: c is this instance, freed once and not used afterwards.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

pub fn c_chars(s: &CStr) -> *const c_char {
    s.as_ptr()
}
