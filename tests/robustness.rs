//! One regression test per finding of the first randomized call-sequence run: each failed,
//! hung or panicked before its fix. The damper is driven in-process through its C API; the truck,
//! and the two FMUs together, through their binaries (dlopen, as in tests/call_sequences.rs).
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
// The FMUs' C API through raw pointers: the crate denies unsafe code (Cargo.toml), this file
// needs it.
#![allow(unsafe_code)]
use crate::common;
use crate::fmi_fuzz;

use common::*;
use fmi_fuzz::library::{fmus, Fmu as Binary, Instantiation, Standard};
use fmi_slave::fmi2::*;
use semi_active_damper::c_api::*;
use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::model_description::{IntegerVar, RealVar};
use semi_active_damper::physics::params::Parameters;
use semi_active_damper::step_error::StepError;
use std::ptr::{null, null_mut};

const DISCARD: fmi2Status = fmi2Status_fmi2Discard;

/// The damper's serialized state now.
fn serialized(f: &Fmu) -> Vec<fmi2Byte> {
    let mut s: fmi2FMUstate = null_mut();
    let mut size = 0;
    // SAFETY: s is a writable slot; the state is this instance's, serialized into a buffer of
    // its size, then freed once.
    unsafe {
        assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
        assert_eq!(fmi2SerializedFMUstateSize(f.c, s, &mut size), OK);
        let mut bytes = vec![0 as fmi2Byte; size];
        assert_eq!(fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), size), OK);
        assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
        bytes
    }
}

/// Deserializes `bytes` into the damper instance and sets the state; the first failing status.
fn restore(f: &Fmu, bytes: &[fmi2Byte]) -> fmi2Status {
    let mut s: fmi2FMUstate = null_mut();
    // SAFETY: bytes holds bytes.len() bytes; s is a writable slot, freed once if filled.
    unsafe {
        let status = fmi2DeSerializeFMUstate(f.c, bytes.as_ptr(), bytes.len(), &mut s);
        if status != OK {
            return status;
        }
        let status = fmi2SetFMUstate(f.c, s);
        assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
        status
    }
}

/// Overwrites the first payload word equal to `old` with `new` (the header is 70 bytes).
fn replace_word(bytes: &mut [fmi2Byte], old: f64, new: f64) {
    let at = (70..bytes.len() - 7)
        .step_by(8)
        .find(|&i| bytes[i..i + 8].iter().map(|&b| b as u8).eq(old.to_le_bytes()))
        .unwrap_or_else(|| panic!("no word {old} in the state"));
    for (b, x) in bytes[at..at + 8].iter_mut().zip(new.to_le_bytes()) {
        *b = x as fmi2Byte;
    }
}

#[test]
fn finding1_damper_refuses_absurd_steps_instead_of_hanging() {
    let f = Fmu::initialised("f1-steps", |_| {});
    for h in [1e10, 1e100, f64::MAX] {
        assert_eq!(f.step(0.0, h), ERROR, "step {h}");
    }
    assert_eq!(f.step(0.0, 1e-3), OK, "the instance is unchanged");
    assert!(logged("f1-steps").iter().any(|m| m.contains("controller samples")), "{:#?}", logged("f1-steps"));
}

#[test]
fn finding1_damper_refuses_a_start_time_it_cannot_resolve() {
    for (start, expected) in [(1e100, ERROR), (1e7, ERROR), (1e3, OK)] {
        let f = Fmu::new("f1-start");
        assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, start, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(f.c), OK);
        assert_eq!(fmi2ExitInitializationMode(f.c), OK);
        assert_eq!(f.step(start, 0.0036), expected, "start {start}");
    }
    let log = logged("f1-start");
    assert!(
        log.iter().any(|m| m.contains("not resolved")) && log.iter().any(|m| m.contains("sample grid")),
        "{log:#?}"
    );
}

#[test]
fn finding2_damper_refuses_corrupted_states() {
    let f = Fmu::initialised("f2-states", |f| {
        f.set(RealVar::HMax, 4.321e-4);
    });
    let mut t = 0.0;
    for _ in 0..17 {
        f.set(RealVar::VDamper, 0.3);
        assert_eq!(f.step(t, 1e-3), OK);
        t += 1e-3;
    }
    let good = serialized(&f);
    assert_eq!(restore(&f, &good), OK);
    let mut flipped = good.clone();
    replace_word(&mut flipped, 4.321e-4, f64::from_bits(4.321e-4f64.to_bits() ^ (1 << 61)));
    assert_eq!(restore(&f, &flipped), ERROR, "h_max ≈ 1e-158");
    let mut minus_inf = good.clone();
    replace_word(&mut minus_inf, t, f64::NEG_INFINITY);
    assert_eq!(restore(&f, &minus_inf), ERROR, "time -inf");
    let mut random = good.clone();
    let mut x = 0x2545_f491_4f6c_dd1du64;
    for b in random.iter_mut().skip(70) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        *b = x as fmi2Byte;
    }
    assert_eq!(restore(&f, &random), ERROR, "random payload");
    assert_eq!(f.step(t, 1e-3), OK, "the refused states changed nothing");
}

#[test]
fn finding2_accepted_integration_steps_are_bounded_and_floored() {
    let inputs = Inputs { v_damper: 0.3, f_demand: 5e3, ..Default::default() };
    // a step proposal below the floor used to loop over accepted steps without end
    let p = Parameters { h_max: 1e-158, ..Parameters::default() };
    let mut d = Damper::new(p, inputs, 0.0).unwrap();
    let before = d.state.y;
    assert!(matches!(d.do_step(1e-3), Err(StepError::Solver(_))));
    assert_eq!(d.state.y, before, "state kept at the step's start");
    // accepted steps count against the limit per sample: 1e-9 s steps would need 5e5 per sample
    let p = Parameters { h_max: 1e-9, ..Parameters::default() };
    let mut d = Damper::new(p, inputs, 0.0).unwrap();
    assert_eq!(d.do_step(1e-3), Err(StepError::TooManySteps));
    assert_eq!(d.state.time, 0.0);
}

#[test]
fn finding3_small_valves_are_refused_not_a_panic() {
    let f = Fmu::new("f3-valve");
    assert_eq!(f.set(RealVar::RPort, 1e-4), ERROR, "below the narrowed range");
    assert_eq!(f.set(RealVar::XSpoolMax, 0.00081), ERROR, "below the narrowed range");
    // each value in range, but the valve's largest demanded area is 1e-9 m²
    assert_eq!(f.set(RealVar::RPort, 5e-4), OK);
    assert_eq!(f.set(RealVar::XLap, 4.9e-4), OK);
    assert_eq!(f.set(RealVar::XSpoolMax, 1e-3), OK);
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), ERROR);
    assert!(logged("f3-valve").iter().any(|m| m.contains("r_port") && m.contains("x_spool_max")));
    // the smallest legal port, alone, works
    let g = Fmu::initialised("f3-smallest", |g| {
        g.set(RealVar::RPort, 5e-4);
        // SAFETY: one value reference and one value.
        assert_eq!(unsafe { fmi2SetInteger(g.c, &IntegerVar::NPorts.vr(), 1, &1) }, OK);
    });
    for k in 0..200 {
        g.set(RealVar::VDamper, 0.5);
        g.set(RealVar::FDemand, 5e3);
        assert_eq!(g.step(k as f64 * 1e-3, 1e-3), OK);
    }
}

#[test]
fn finding4_states_serialized_before_initialisation_are_accepted() {
    for (v, x) in [(RealVar::PCvFull, 1.0), (RealVar::XDamperStart, -0.91)] {
        let f = Fmu::new("f4-uninit");
        assert_eq!(f.set(v, x), OK, "in range, refused only at initialisation");
        let bytes = serialized(&f);
        assert_eq!(restore(&f, &bytes), OK, "{v:?} = {x}");
    }
}

#[test]
fn finding6_tiny_cubic_mount_stiffness_gives_finite_outputs() {
    let f = Fmu::initialised("f6-mount", |f| {
        f.set(RealVar::K3Mount, 2.2e-308);
    });
    for k in 0..50 {
        f.set(RealVar::VDamper, 0.3);
        f.set(RealVar::FDemand, 5e3);
        assert_eq!(f.step(k as f64 * 1e-3, 1e-3), OK);
        assert!(f.get(RealVar::DeltaMount).is_finite() && f.get(RealVar::FDamper).is_finite());
    }
}

#[test]
fn finding7_nvr_zero_and_get_string_follow_the_state_table() {
    let f = Fmu::new("f7-table");
    // SAFETY: NULL arrays with nvr = 0 are what the standard allows; the FMU reads nothing.
    unsafe {
        assert_eq!(fmi2GetString(f.c, null(), 0, null_mut()), ERROR, "no getter in Instantiated");
        assert_eq!(fmi2SetReal(f.c, null(), 0, null()), OK, "setters are legal in Instantiated");
    }
    // a step that takes 1e4 accepted integration steps in one sample is discarded
    f.set(RealVar::TSample, 0.01);
    f.set(RealVar::HMax, 1e-7);
    f.initialise();
    assert_eq!(f.step(0.0, 1e-3), DISCARD);
    let set_none = || {
        // SAFETY: NULL arrays with nvr = 0.
        unsafe {
            [
                fmi2SetReal(f.c, null(), 0, null()),
                fmi2SetInteger(f.c, null(), 0, null()),
                fmi2SetBoolean(f.c, null(), 0, null()),
                fmi2SetString(f.c, null(), 0, null()),
            ]
        }
    };
    assert_eq!(set_none(), [ERROR; 4], "in StepFailed");
    assert_eq!(fmi2Terminate(f.c), OK);
    assert_eq!(set_none(), [ERROR; 4], "in Terminated");
}

#[test]
fn finding8_dp_relief_at_its_minimum_is_not_stiff() {
    let f = Fmu::new("f8-relief");
    assert_eq!(f.set(RealVar::DpRelief, 1.0), ERROR, "below the narrowed range");
    let substeps = |dp_relief: f64, v: f64| {
        let p = Parameters { dp_relief, ..Parameters::default() };
        let mut d = Damper::new(p, Inputs { v_damper: v, f_demand: 1e5 * v, ..Default::default() }, 0.0).unwrap();
        (0..100).map(|_| d.do_step(0.01).unwrap().substeps).sum::<u32>()
    };
    let min = RealVar::DpRelief.min().unwrap();
    for v in [2.7, -2.7] {
        let (at_min, default) = (substeps(min, v), substeps(Parameters::default().dp_relief, v));
        assert!(at_min <= 2 * default, "{v} m/s: {at_min} integration steps against {default} by default");
    }
}

/// An instance of one of the FMI 2.0 binaries.
struct Instance(&'static Binary, fmi2Component);

impl Instance {
    fn new(fmu: &'static Binary) -> Self {
        // SAFETY: the instance is freed once, when dropped.
        let c = unsafe { fmu.instantiate(Instantiation::Valid, false, "") };
        assert!(!c.is_null());
        Instance(fmu, c)
    }

    fn vr(&self, name: &str) -> u32 {
        self.0.info.vars.iter().find(|v| v.name == name).unwrap_or_else(|| panic!("{name}")).vr
    }

    fn set(&self, name: &str, x: f64) -> fmi2Status {
        // SAFETY: a live instance; one value reference and one value.
        unsafe { self.0.set_real(self.1, &self.vr(name), 1, &x, 1) }
    }

    fn initialise(&self) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe {
            assert_eq!(self.0.setup_experiment(self.1, None, 0.0, None), Some(OK));
            assert_eq!(self.0.enter_initialization_mode(self.1, None, 0.0, None), OK);
            (self.0.common.exit_initialization_mode)(self.1)
        }
    }

    fn step(&self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: a live instance.
        unsafe { self.0.do_step(self.1, t, h).0 }
    }

    fn state(&self) -> fmi2FMUstate {
        let mut s = null_mut();
        // SAFETY: a live instance; s is a writable slot.
        assert_eq!(unsafe { (self.0.common.get_fmu_state)(self.1, &mut s) }, OK);
        s
    }

    fn serialized(&self) -> Vec<fmi2Byte> {
        let s = self.state();
        let mut size = 0;
        // SAFETY: a live instance and its state, serialized into a buffer of its size.
        unsafe {
            assert_eq!((self.0.common.serialized_size)(self.1, s, &mut size), OK);
            let mut bytes = vec![0 as fmi2Byte; size];
            assert_eq!((self.0.common.serialize)(self.1, s, bytes.as_mut_ptr() as *mut u8, size), OK);
            bytes
        }
    }

    fn deserialize(&self, bytes: &[fmi2Byte]) -> fmi2Status {
        let mut s = null_mut();
        // SAFETY: a live instance; bytes holds bytes.len() bytes; s is a writable slot.
        unsafe { (self.0.common.deserialize)(self.1, bytes.as_ptr() as *const u8, bytes.len(), &mut s) }
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: a live instance, freed once (its states are leaked: a few per test).
        unsafe { (self.0.common.free_instance)(self.1) }
    }
}

fn truck() -> &'static Binary {
    &fmus(Standard::Fmi2)[1]
}

#[test]
fn finding1_truck_refuses_absurd_steps_instead_of_hanging() {
    let t = Instance::new(truck());
    assert_eq!(t.initialise(), OK);
    for h in [1e10, 1e100, f64::MAX] {
        assert_eq!(t.step(0.0, h), ERROR, "step {h}");
    }
    assert_eq!(t.step(0.0, 1e-3), OK);
}

#[test]
fn finding2_truck_refuses_corrupted_states() {
    let t = Instance::new(truck());
    assert_eq!(t.set("h_max", 4.321e-4), OK);
    assert_eq!(t.initialise(), OK);
    assert_eq!(t.step(0.0, 0.017), OK);
    let good = t.serialized();
    assert_eq!(t.deserialize(&good), OK);
    let mut flipped = good.clone();
    replace_word(&mut flipped, 4.321e-4, f64::from_bits(4.321e-4f64.to_bits() ^ (1 << 61)));
    assert_eq!(t.deserialize(&flipped), ERROR, "h_max ≈ 1e-158");
    let mut minus_inf = good.clone();
    replace_word(&mut minus_inf, 0.017, f64::NEG_INFINITY);
    assert_eq!(t.deserialize(&minus_inf), ERROR, "time -inf");
    let mut two = good.clone();
    let last = two.len() - 8;
    two[last] = 2; // the Boolean `initialised`
    assert_eq!(t.deserialize(&two), ERROR, "a Boolean word of 2");
}

#[test]
fn serialized_truck_states_are_accepted_whatever_the_inputs_did() {
    let t = Instance::new(truck());
    assert_eq!(t.initialise(), OK);
    assert_eq!(t.set("v_road", 50.0), OK);
    assert_eq!(t.step(0.0, 0.1), OK, "the road input ramps to z_road = 5 m, beyond its range");
    assert_eq!(t.deserialize(&t.serialized()), OK);
}

#[test]
fn finding5_a_state_of_one_fmu_is_refused_by_the_other() {
    let [damper, truck, _] = fmus(Standard::Fmi2);
    let (d, t) = (Instance::new(damper), Instance::new(truck));
    assert_eq!(d.initialise(), OK);
    assert_eq!(t.initialise(), OK);
    let (ds, ts) = (d.state(), t.state());
    let mut size = 0;
    // SAFETY: live instances and states; each FMU must refuse the other's state without using it.
    unsafe {
        assert_eq!((truck.common.set_fmu_state)(t.1, ds), ERROR);
        assert_eq!((damper.common.set_fmu_state)(d.1, ts), ERROR);
        assert_eq!((truck.common.serialized_size)(t.1, ds, &mut size), ERROR);
        let mut foreign = ts;
        assert_eq!((damper.common.free_fmu_state)(d.1, &mut foreign), ERROR);
        assert_eq!(foreign, ts, "not freed");
    }
    assert_eq!(t.deserialize(&d.serialized()), ERROR);
    assert_eq!(d.deserialize(&t.serialized()), ERROR);
}

#[test]
fn finding6_truck_refuses_rk4_unstable_parameters() {
    let t = Instance::new(truck());
    assert_eq!(t.set("m_body", 1.7), OK);
    assert_eq!(t.set("k_susp", 1e9), OK);
    assert_eq!(t.initialise(), ERROR, "h_max·|λ| ≈ 8.6: RK4 would diverge");
    assert!(fmi_fuzz::library::RECENT.lock().unwrap().iter().any(|m| m.contains("RK4") && m.contains("m_body")));
}
