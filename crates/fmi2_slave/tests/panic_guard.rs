//! A panic inside a model never unwinds into the host: the call that panicked returns fmi2Fatal with a
//! logged message, every later call on that instance but fmi2FreeInstance is refused with fmi2Error,
//! and other instances go on. A model that panics on demand stands in for a bug. scripts/test.sh also
//! runs this test as a Windows program under Wine, where unwinding takes a different path (SEH).
#![allow(unsafe_code)]

use fmi2_slave::api::fmi2::*;
use fmi2_slave::{Causality, Model, Refusal, ToleranceNote, VarInfo};
use std::ffi::{CStr, CString};
use std::sync::Mutex;

/// Input 1 panics the next step when set to [`PANIC_ON_STEP`]; output 2 counts the steps.
#[derive(Clone, Default)]
struct Fragile {
    input: f64,
    steps: f64,
    time: Option<f64>,
}

const PANIC_ON_STEP: f64 = 13.0;

impl Model for Fragile {
    const GUID: &'static str = "{panic-guard-test}";
    type State = Fragile;
    type StepError = &'static str;
    type StepWarning = std::convert::Infallible;

    fn real_info(vr: u32) -> Option<VarInfo> {
        match vr {
            1 => Some(VarInfo { name: "input", causality: Causality::Input }),
            2 => Some(VarInfo { name: "steps", causality: Causality::Output }),
            _ => None,
        }
    }
    fn integer_info(_: u32) -> Option<VarInfo> {
        None
    }
    fn boolean_info(_: u32) -> Option<VarInfo> {
        None
    }
    fn get_real(&self, vr: u32) -> Result<f64, Refusal> {
        Ok(if vr == 1 { self.input } else { self.steps })
    }
    fn get_integer(&self, _: u32) -> Result<i32, Refusal> {
        unreachable!()
    }
    fn get_boolean(&self, _: u32) -> Result<bool, Refusal> {
        unreachable!()
    }
    type Settable = f64;
    fn settable(&self) -> f64 {
        self.input
    }
    fn restore_settable(&mut self, input: f64) {
        self.input = input;
    }
    fn set_real(&mut self, _: u32, value: f64) -> Result<(), Refusal> {
        self.input = value;
        Ok(())
    }
    fn set_integer(&mut self, _: u32, _: i32) -> Result<(), Refusal> {
        unreachable!()
    }
    fn set_boolean(&mut self, _: u32, _: bool) -> Result<(), Refusal> {
        unreachable!()
    }
    fn use_tolerance(&mut self, _: f64) -> Result<ToleranceNote, Refusal> {
        Ok(ToleranceNote::Event(String::new()))
    }
    fn initialize(&mut self, start_time: f64) -> Result<(), Refusal> {
        self.time = Some(start_time);
        Ok(())
    }
    fn time(&self) -> Option<f64> {
        self.time
    }
    fn align_time(&mut self, t: f64) {
        self.time = Some(t);
    }
    fn check_step(&self, _: f64) -> Result<(), Self::StepError> {
        Ok(())
    }
    fn do_step(&mut self, h: f64) -> Result<Option<Self::StepWarning>, Self::StepError> {
        assert!(self.input != PANIC_ON_STEP, "deliberate panic in do_step");
        self.steps += 1.0;
        self.time = self.time.map(|t| t + h);
        Ok(None)
    }
    fn state(&self) -> Self::State {
        self.clone()
    }
    fn set_state(&mut self, state: &Self::State) -> Result<(), Refusal> {
        *self = state.clone();
        Ok(())
    }
    fn state_time(state: &Self::State) -> Option<f64> {
        state.time
    }
    fn serialize(_: &Self::State) -> Vec<u8> {
        Vec::new()
    }
    fn deserialize(_: &[u8]) -> Result<Self::State, Refusal> {
        Err(Refusal::Unreadable(fmi2_slave::Unreadable::ShorterThanHeader))
    }
}

fmi2_slave::export_fmi2!(Fragile);

static LOG: Mutex<Vec<(String, fmi2Status, String)>> = Mutex::new(Vec::new());

type FixedLogger = unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String, fmi2String);

/// The importer's logger, declared without the variadic tail (the FMU passes none: its message is
/// the format string with '%' escaped), which the x86-64 C ABIs of Linux and Windows allow.
unsafe extern "C" fn logger(
    _env: fmi2ComponentEnvironment,
    name: fmi2String,
    status: fmi2Status,
    _category: fmi2String,
    message: fmi2String,
) {
    // SAFETY: the FMU passes NUL-terminated instance names and messages, valid for the call.
    let name = unsafe { CStr::from_ptr(name) }.to_string_lossy().into_owned();
    // SAFETY: as name.
    let message = unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned();
    LOG.lock().unwrap().push((name, status, message));
}

fn instantiate(name: &str) -> fmi2Component {
    let callbacks = fmi2CallbackFunctions {
        // SAFETY: see `logger`.
        logger: unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(logger) },
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    let (name, guid) = (CString::new(name).unwrap(), CString::new(Fragile::GUID).unwrap());
    // SAFETY: NUL-terminated strings and a valid callback struct, alive for the call.
    let c = unsafe {
        fmi2Instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, guid.as_ptr(), std::ptr::null(), &callbacks, 0, 0)
    };
    assert!(!c.is_null());
    assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), fmi2Status_fmi2OK);
    assert_eq!(fmi2EnterInitializationMode(c), fmi2Status_fmi2OK);
    assert_eq!(fmi2ExitInitializationMode(c), fmi2Status_fmi2OK);
    c
}

fn set_input(c: fmi2Component, value: f64) -> fmi2Status {
    // SAFETY: one value reference and one value.
    unsafe { fmi2SetReal(c, &1, 1, &value) }
}

fn steps(c: fmi2Component) -> (fmi2Status, f64) {
    let mut value = f64::NAN;
    // SAFETY: one value reference and room for one value.
    let status = unsafe { fmi2GetReal(c, &2, 1, &mut value) };
    (status, value)
}

#[test]
fn a_panic_in_a_step_is_fatal_for_its_instance_only_and_never_unwinds_into_the_host() {
    let (fragile, sound) = (instantiate("fragile"), instantiate("sound"));
    assert_eq!(fmi2DoStep(fragile, 0.0, 0.1, 1), fmi2Status_fmi2OK);

    assert_eq!(set_input(fragile, PANIC_ON_STEP), fmi2Status_fmi2OK);
    assert_eq!(fmi2DoStep(fragile, 0.1, 0.1, 1), fmi2Status_fmi2Fatal);
    let fatal: Vec<_> = LOG.lock().unwrap().iter().filter(|(_, s, _)| *s == fmi2Status_fmi2Fatal).cloned().collect();
    assert_eq!(fatal.len(), 1, "{fatal:?}");
    assert_eq!(fatal[0].0, "fragile");
    assert!(fatal[0].2.contains("fmi2DoStep: internal error (panic: deliberate panic in do_step)"), "{}", fatal[0].2);

    // the instance refuses everything but fmi2FreeInstance from now on
    assert_eq!(set_input(fragile, 0.0), fmi2Status_fmi2Error);
    assert_eq!(steps(fragile).0, fmi2Status_fmi2Error);
    assert_eq!(fmi2DoStep(fragile, 0.1, 0.1, 1), fmi2Status_fmi2Error);
    assert_eq!(fmi2Reset(fragile), fmi2Status_fmi2Error);

    // another instance of the same model is untouched
    assert_eq!(fmi2DoStep(sound, 0.0, 0.1, 1), fmi2Status_fmi2OK);
    assert_eq!(steps(sound), (fmi2Status_fmi2OK, 1.0));

    // SAFETY: each instance freed once and not used afterwards.
    unsafe {
        fmi2FreeInstance(fragile);
        fmi2FreeInstance(sound);
    }
}
