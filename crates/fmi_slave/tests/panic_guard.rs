//! A panic inside a model never unwinds into the host, through either standard's C API: the call
//! that panicked returns Fatal with a logged message, every later call on that instance but freeing
//! it is refused with Error, and other instances go on. A model that panics on demand stands in for
//! a bug. scripts/test.sh also runs this test as a Windows program under Wine, where unwinding takes
//! a different path (SEH). (A test program may export both standards' functions; an FMU's binary
//! exports one.)
#![allow(unsafe_code)]

use fmi_slave::fmi2::*;
use fmi_slave::fmi3::{fmi3Instance, fmi3InstanceEnvironment, fmi3Status, fmi3String};
use fmi_slave::{Causality, Model, Refusal, ToleranceNote, VarInfo};
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
        Err(Refusal::Unreadable(fmi_slave::Unreadable::ShorterThanHeader))
    }
}

fmi_slave::export_fmi2!(Fragile);
/// The FMI 3.0 independent variable's value reference.
const TIME_VR: u32 = 0;
fmi_slave::export_fmi3!(Fragile, time_vr = TIME_VR);

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

static LOG3: Mutex<Vec<(usize, fmi3Status, String)>> = Mutex::new(Vec::new());

/// FMI 3.0's logger: the instance environment (here the instance's number) names the instance.
unsafe extern "C" fn log_message(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the FMU passes a NUL-terminated message, valid for the call.
    let message = unsafe { CStr::from_ptr(message) }.to_string_lossy().into_owned();
    LOG3.lock().unwrap().push((env as usize, status, message));
}

fn instantiate3(number: usize) -> fmi3Instance {
    let (name, token) = (CString::new(format!("instance {number}")).unwrap(), CString::new(Fragile::GUID).unwrap());
    // SAFETY: NUL-terminated strings, no intermediate variables, a logger that lives for the test.
    let c = unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            false,
            false,
            std::ptr::null(),
            0,
            number as fmi3InstanceEnvironment,
            Some(log_message),
            None,
        )
    };
    assert!(!c.is_null());
    assert_eq!(fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0), 0);
    assert_eq!(fmi3ExitInitializationMode(c), 0);
    c
}

fn step3(c: fmi3Instance, t: f64) -> fmi3Status {
    let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
    // SAFETY: four writable out-arguments.
    let status = unsafe { fmi3DoStep(c, t, 0.1, true, &mut event, &mut terminate, &mut early, &mut last) };
    if status == 0 {
        assert!(!event && !terminate && !early);
        assert_eq!(last, t + 0.1);
    }
    status
}

#[test]
fn fmi3_a_panic_in_a_step_is_fatal_for_its_instance_only() {
    let (fragile, sound) = (instantiate3(1), instantiate3(2));
    assert_eq!(step3(fragile, 0.0), 0);
    // SAFETY: one value reference and one value.
    assert_eq!(unsafe { fmi3SetFloat64(fragile, &1, 1, &PANIC_ON_STEP, 1) }, 0);
    assert_eq!(step3(fragile, 0.1), 4, "fmi3Fatal");
    let fatal: Vec<_> = LOG3.lock().unwrap().iter().filter(|(_, s, _)| *s == 4).cloned().collect();
    assert_eq!(fatal.len(), 1, "{fatal:?}");
    assert_eq!(fatal[0].0, 1, "logged to the instance's own environment");
    assert!(
        fatal[0].2.contains("fmi3DoStep: internal error (panic: deliberate panic in do_step); only fmi3FreeInstance"),
        "{}",
        fatal[0].2
    );
    assert_eq!(step3(fragile, 0.1), 3, "fmi3Error from now on");
    assert_eq!(fmi3Reset(fragile), 3);

    assert_eq!(step3(sound, 0.0), 0);
    let (mut steps, mut time) = (f64::NAN, f64::NAN);
    // SAFETY: one value reference and room for one value, twice.
    unsafe {
        assert_eq!(fmi3GetFloat64(sound, &2, 1, &mut steps, 1), 0);
        assert_eq!(fmi3GetFloat64(sound, &TIME_VR, 1, &mut time, 1), 0);
    }
    assert_eq!((steps, time), (1.0, 0.1), "the step counter and the independent variable");
    // SAFETY: each instance freed once and not used afterwards.
    unsafe {
        fmi3FreeInstance(fragile);
        fmi3FreeInstance(sound);
    }
}
