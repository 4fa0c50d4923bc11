//! The FMI 2.0 C API in-process: lifecycle, the state machine, bad arguments, FMU state.
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
// Calls the FMU's C API as an importer does, through raw pointers: the crate denies unsafe code
// (Cargo.toml), this file needs it.
#![allow(unsafe_code)]
use crate::common;

use common::*;
use fmi_slave::fmi2::*;
use semi_active_damper::c_api::*;
use semi_active_damper::model_description::{IntegerVar, RealVar};
use std::ffi::CString;

#[test]
fn version_and_platform() {
    // SAFETY: fmi2GetVersion returns a pointer to a static NUL-terminated string.
    assert_eq!(unsafe { std::ffi::CStr::from_ptr(fmi2GetVersion()) }, c"2.0");
    // SAFETY: as fmi2GetVersion.
    assert_eq!(unsafe { std::ffi::CStr::from_ptr(fmi2GetTypesPlatform()) }, c"default");
}

#[test]
fn instantiate_refuses_wrong_guid_type_and_name() {
    let name = CString::new("bad").unwrap();
    let guid = c"{00000000-0000-0000-0000-000000000000}";
    let null = std::ptr::null();
    let no_callbacks: *const fmi2CallbackFunctions = std::ptr::null();
    // SAFETY: the strings are NUL-terminated CStrings and literals that outlive the calls; NULL
    // callbacks, names and instances are what the FMU must refuse, and it reads nothing through
    // them.
    unsafe {
        assert!(fmi2Instantiate(name.as_ptr(), fmi2Type_fmi2CoSimulation, guid.as_ptr(), null, no_callbacks, 0, 0)
            .is_null());
        let good = CString::new(semi_active_damper::model_description::GUID).unwrap();
        assert!(fmi2Instantiate(name.as_ptr(), fmi2Type_fmi2ModelExchange, good.as_ptr(), null, no_callbacks, 0, 0)
            .is_null());
        assert!(fmi2Instantiate(null, fmi2Type_fmi2CoSimulation, good.as_ptr(), null, no_callbacks, 0, 0).is_null());
        // a null instance is an error, not a crash
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 1e-3, 0), ERROR);
        fmi2FreeInstance(std::ptr::null_mut());
    }
}

#[test]
fn illegal_call_sequences_are_refused_and_logged() {
    let f = Fmu::new("sequence");
    assert_eq!(f.step(0.0, 1e-3), ERROR, "doStep before initialisation");
    let mut x = 0.0;
    // SAFETY: vr and value point to one element each.
    assert_eq!(unsafe { fmi2GetReal(f.c, &RealVar::FDamper.vr(), 1, &mut x) }, ERROR, "get in Instantiated");
    assert_eq!(fmi2ExitInitializationMode(f.c), ERROR);
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), ERROR);
    assert_eq!(fmi2ExitInitializationMode(f.c), OK);
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), ERROR);
    assert_eq!(f.set(RealVar::AirFraction, 0.03), ERROR, "fixed parameter after initialisation");
    assert_eq!(f.step(0.0, 1e-3), OK);
    assert_eq!(fmi2Terminate(f.c), OK);
    assert_eq!(f.step(1e-3, 1e-3), ERROR, "doStep after terminate");
    assert_eq!(fmi2Reset(f.c), OK);
    assert_eq!(f.set(RealVar::AirFraction, 0.03), OK, "parameters settable again after reset");
    let log = logged("sequence");
    assert!(log.iter().filter(|m| m.contains("illegal call sequence")).count() >= 5, "{log:#?}");
    assert!(log.iter().any(|m| m.contains("air_fraction") && m.contains("cannot be set")), "{log:#?}");
}

#[test]
fn bad_values_are_refused_and_change_nothing() {
    let f = Fmu::initialised("values", |_| {});
    assert_eq!(f.set(RealVar::VDamper, 0.1), OK);
    assert_eq!(f.set(RealVar::VDamper, f64::NAN), ERROR);
    assert_eq!(f.set(RealVar::VDamper, f64::INFINITY), ERROR);
    assert_eq!(f.get(RealVar::VDamper), 0.1, "a refused value leaves the old one");
    assert_eq!(f.set(RealVar::FDamper, 1.0), ERROR, "outputs cannot be set");
    // all-or-nothing: a batch with one bad value changes none
    let vrs = [RealVar::VDamper.vr(), RealVar::FDemand.vr()];
    // SAFETY: vrs and the value array hold two elements each.
    assert_eq!(unsafe { fmi2SetReal(f.c, vrs.as_ptr(), 2, [0.2, f64::NAN].as_ptr()) }, ERROR);
    assert_eq!(f.get(RealVar::VDamper), 0.1);
    let mut x = 0.0;
    // SAFETY: vr and value point to one element each.
    assert_eq!(unsafe { fmi2GetReal(f.c, &9999, 1, &mut x) }, ERROR, "unknown value reference");
    // SAFETY: value points to one element; the NULL vr array is what the FMU must refuse.
    assert_eq!(unsafe { fmi2GetReal(f.c, std::ptr::null(), 1, &mut x) }, ERROR, "null vr array");
    assert_eq!(f.step(0.0, 0.0), ERROR, "zero step");
    assert_eq!(f.step(0.0, -1e-3), ERROR, "negative step");
    assert_eq!(f.step(0.0, f64::NAN), ERROR, "NaN step");
    assert_eq!(f.step(0.5, 1e-3), ERROR, "wrong communication point");
    assert_eq!(f.step(0.0, 1e-3), OK, "still usable after refused calls");
    let log = logged("values");
    for needle in
        ["not a finite number", "unknown value reference 9999", "does not match the FMU's time", "must be positive"]
    {
        assert!(log.iter().any(|m| m.contains(needle)), "no message with {needle:?}: {log:#?}");
    }
}

#[test]
fn out_of_range_and_inconsistent_parameters_are_refused() {
    let f = Fmu::new("ranges");
    assert_eq!(f.set(RealVar::AirFraction, -1.0), ERROR);
    let mode = IntegerVar::ControlMode.vr();
    // SAFETY: vr and value point to one element each.
    assert_eq!(unsafe { fmi2SetInteger(f.c, &mode, 1, &7) }, ERROR);
    // each value in range, but the rod would be wider than the bore
    assert_eq!(f.set(RealVar::DRod, 0.08), OK);
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), ERROR);
    assert!(logged("ranges").iter().any(|m| m.contains("D_rod must be smaller than D_piston")));
}

/// FMI 2.0: with toleranceDefined a variable-step slave uses the master's tolerance. It
/// becomes `rtol` unless the master set `rtol` itself, before or after; out of rtol's range it is
/// moved into it with a warning, and a tolerance that is not a positive number is refused.
#[test]
fn the_masters_tolerance_sets_rtol_unless_rtol_was_set() {
    let rtol_after = |name: &str, calls: &dyn Fn(&Fmu)| {
        let f = Fmu::new(name);
        calls(&f);
        assert_eq!(fmi2EnterInitializationMode(f.c), OK);
        f.get(RealVar::Rtol)
    };
    let no_tolerance = rtol_after("tol_none", &|f| assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK));
    assert_eq!(no_tolerance, 3e-4, "the parameter's start value");
    let from_master = rtol_after("tol_master", &|f| assert_eq!(fmi2SetupExperiment(f.c, 1, 2e-5, 0.0, 0, 0.0), OK));
    assert_eq!(from_master, 2e-5);
    let set_before = rtol_after("tol_before", &|f| {
        assert_eq!(f.set(RealVar::Rtol, 1e-4), OK);
        assert_eq!(fmi2SetupExperiment(f.c, 1, 2e-5, 0.0, 0, 0.0), OK);
    });
    assert_eq!(set_before, 1e-4);
    let set_after = rtol_after("tol_after", &|f| {
        assert_eq!(fmi2SetupExperiment(f.c, 1, 2e-5, 0.0, 0, 0.0), OK);
        assert_eq!(f.set(RealVar::Rtol, 1e-4), OK);
    });
    assert_eq!(set_after, 1e-4);

    let loose = rtol_after("tol_loose", &|f| assert_eq!(fmi2SetupExperiment(f.c, 1, 0.5, 0.0, 0, 0.0), OK));
    assert_eq!(loose, 0.1);
    let warning = "[1] fmi2SetupExperiment: tolerance 5e-1 is outside rtol's range [1e-10, 1e-1]: rtol = 1e-1";
    assert!(logged("tol_loose").iter().any(|m| m.contains(warning)));
    let tight = rtol_after("tol_tight", &|f| assert_eq!(fmi2SetupExperiment(f.c, 1, 1e-14, 0.0, 0, 0.0), OK));
    assert_eq!(tight, 1e-10);

    let f = Fmu::new("tol_bad");
    for bad in [0.0, -1e-4, f64::NAN, f64::INFINITY] {
        assert_eq!(fmi2SetupExperiment(f.c, 1, bad, 0.0, 0, 0.0), ERROR, "tolerance {bad}");
    }
    let refusal = "tolerance 0 refused: a relative tolerance must be a positive number";
    assert!(logged("tol_bad").iter().any(|m| m.contains(refusal)));
    assert_eq!(fmi2SetupExperiment(f.c, 1, 1e-6, 0.0, 0, 0.0), OK, "a refused tolerance leaves the instance usable");
}

fn set_derivatives(f: &Fmu, vars: &[RealVar], orders: &[i32], values: &[f64]) -> fmi2Status {
    let vrs: Vec<u32> = vars.iter().map(|v| v.vr()).collect();
    // SAFETY: the three arrays hold vars.len() elements each.
    unsafe { fmi2SetRealInputDerivatives(f.c, vrs.as_ptr(), vrs.len(), orders.as_ptr(), values.as_ptr()) }
}

/// canInterpolateInputs: first derivatives move the inputs along ramps over a step. The velocity's
/// is `a_damper`; a demand's ramp is what setting the demand at every controller sample gives.
#[test]
fn input_derivatives_move_the_inputs_along_ramps() {
    let f = Fmu::initialised("deriv", |_| ());
    assert_eq!(set_derivatives(&f, &[RealVar::VDamper], &[1], &[2.0]), OK);
    assert_eq!(f.get(RealVar::ADamper), 2.0);
    for (var, order, why) in [
        (RealVar::VDamper, 2, "v_damper: derivative of order 2 refused"),
        (RealVar::ADamper, 1, "a_damper: no derivative taken"),
        (RealVar::FDamper, 1, "F_damper is not an input"),
        (RealVar::Rtol, 1, "rtol is not an input"),
    ] {
        // with a good one first: all or none
        let status = set_derivatives(&f, &[RealVar::VDamper, var], &[1, order], &[3.0, 1.0]);
        assert_eq!(status, ERROR, "{why}");
        assert!(logged("deriv").iter().any(|m| m.contains(why)), "{why}");
    }
    assert_eq!(f.get(RealVar::ADamper), 2.0, "nothing set by a refused call");

    // F_demand from 2 kN rising at 1 MN/s for 20 ms at 0.15 m/s: 1 ms steps with the derivative,
    // against 0.5 ms steps (the controller's sample time) with the demand set at each
    let (f0, rate, h) = (2e3, 1e6, 1e-3);
    let ramped = Fmu::initialised("ramped", |f| assert_eq!(f.set(RealVar::XDamperStart, -0.03), OK));
    let sampled = Fmu::initialised("sampled", |f| assert_eq!(f.set(RealVar::XDamperStart, -0.03), OK));
    let held = Fmu::initialised("held", |f| assert_eq!(f.set(RealVar::XDamperStart, -0.03), OK));
    let (mut largest_rounding, mut largest_hold) = (0.0f64, 0.0f64);
    for k in 0..20 {
        let t = k as f64 * h;
        for g in [&ramped, &sampled, &held] {
            assert_eq!(g.set(RealVar::VDamper, 0.15), OK);
            assert_eq!(g.set(RealVar::FDemand, f0 + rate * t), OK);
        }
        assert_eq!(set_derivatives(&ramped, &[RealVar::FDemand], &[1], &[rate]), OK);
        assert_eq!(ramped.step(t, h), OK);
        assert_eq!(held.step(t, h), OK);
        assert_eq!(sampled.step(t, 0.5 * h), OK);
        assert_eq!(sampled.set(RealVar::FDemand, f0 + rate * (t + 0.5 * h)), OK);
        assert_eq!(sampled.step(t + 0.5 * h, 0.5 * h), OK);
        let force = ramped.get(RealVar::FDamper);
        largest_rounding = largest_rounding.max((force - sampled.get(RealVar::FDamper)).abs());
        largest_hold = largest_hold.max((force - held.get(RealVar::FDamper)).abs());
        // the demand moved to the step's end
        assert!((ramped.get(RealVar::FDemand) - (f0 + rate * (t + h))).abs() < 1e-9);
    }
    assert!(largest_rounding < 1e-6, "ramp against demands set at the samples: {largest_rounding} N");
    assert!(largest_hold > 10.0, "a held demand is not the ramp: {largest_hold} N");
}

#[test]
fn stop_time_is_respected() {
    let f = Fmu::new("stop");
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 1, 2e-3), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), OK);
    assert_eq!(f.step(0.0, 1e-3), OK);
    assert_eq!(f.step(1e-3, 1e-3), OK);
    assert_eq!(f.step(2e-3, 1e-3), ERROR);
}

fn run(f: &Fmu, t0: f64, n: usize) -> Vec<u64> {
    (0..n)
        .map(|k| {
            let t = t0 + k as f64 * 1e-3;
            f.set(RealVar::VDamper, 0.3 * (20.0 * t).sin());
            f.set(RealVar::FDemand, 8e3 * (7.0 * t).cos());
            assert_eq!(f.step(t, 1e-3), OK);
            f.get(RealVar::FDamper).to_bits()
        })
        .collect()
}

#[test]
fn fmu_state_round_trip_is_bitwise() {
    let f = Fmu::initialised("state", |_| {});
    run(&f, 0.0, 100);
    let mut s: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: s is a writable slot for one state pointer.
    assert_eq!(unsafe { fmi2GetFMUstate(f.c, &mut s) }, OK);
    let first = run(&f, 0.1, 100);
    // SAFETY: s is a state this instance returned and has not freed.
    assert_eq!(unsafe { fmi2SetFMUstate(f.c, s) }, OK);
    assert_eq!(run(&f, 0.1, 100), first, "get/set state");

    // serialise, restore into a fresh instance
    let mut size = 0usize;
    // SAFETY: s is a state of this library; size is writable.
    assert_eq!(unsafe { fmi2SerializedFMUstateSize(f.c, s, &mut size) }, OK);
    let mut bytes = vec![0 as fmi2Byte; size];
    // SAFETY: bytes holds size writable bytes.
    assert_eq!(unsafe { fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), size) }, OK);
    let g = Fmu::new("state-copy");
    let mut s2: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: bytes holds size bytes; s2 is a writable slot holding NULL.
    assert_eq!(unsafe { fmi2DeSerializeFMUstate(g.c, bytes.as_ptr(), size, &mut s2) }, OK);
    // SAFETY: s2 is a state this library returned and has not freed.
    assert_eq!(unsafe { fmi2SetFMUstate(g.c, s2) }, OK);
    assert_eq!(run(&g, 0.1, 100), first, "serialised state in a fresh instance");

    // corrupted or truncated blobs are refused
    bytes[0] ^= 1;
    let mut s3: fmi2FMUstate = std::ptr::null_mut();
    // SAFETY: bytes holds size bytes; s3 is a writable slot holding NULL.
    assert_eq!(unsafe { fmi2DeSerializeFMUstate(g.c, bytes.as_ptr(), size, &mut s3) }, ERROR);
    bytes[0] ^= 1;
    // SAFETY: bytes holds more than size - 8 bytes; s3 is a writable slot holding NULL.
    assert_eq!(unsafe { fmi2DeSerializeFMUstate(g.c, bytes.as_ptr(), size - 8, &mut s3) }, ERROR);
    assert!(s3.is_null());
    // SAFETY: s and s2 are states of this library, each freed once (the FMU sets the slots to NULL).
    unsafe {
        assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
        assert_eq!(fmi2FreeFMUstate(g.c, &mut s2), OK);
    }
    assert!(s.is_null());
}

#[test]
fn instances_are_independent() {
    let a = Fmu::initialised("a", |_| {});
    let b = Fmu::initialised("b", |f| {
        f.set(RealVar::AirFraction, 0.05);
    });
    let alone = Fmu::initialised("alone", |_| {});
    let reference = run(&alone, 0.0, 200);
    // interleave a and b step by step; b has other parameters and inputs
    let mut out_a = Vec::new();
    for k in 0..200 {
        let t = k as f64 * 1e-3;
        b.set(RealVar::VDamper, -0.5);
        assert_eq!(b.step(t, 1e-3), OK);
        out_a.extend(run(&a, t, 1));
    }
    assert_eq!(out_a, reference);
}

#[test]
fn debug_logging_categories() {
    let f = Fmu::new("categories");
    let cats = [c"logEvents".as_ptr()];
    // SAFETY: cats holds one pointer to a NUL-terminated literal.
    assert_eq!(unsafe { fmi2SetDebugLogging(f.c, 1, 1, cats.as_ptr()) }, OK);
    let bad = [c"logNonsense".as_ptr()];
    // SAFETY: bad holds one pointer to a NUL-terminated literal.
    assert_eq!(unsafe { fmi2SetDebugLogging(f.c, 1, 1, bad.as_ptr()) }, ERROR);
    assert_eq!(fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(f.c), OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), OK);
    assert!(logged("categories").iter().any(|m| m.contains("initialised at t = 0 s")));
}

/// There are no end stops: a stroke beyond `L_half_stroke` is logged as a warning, once per
/// excursion, and the simulation goes on.
#[test]
fn a_stroke_beyond_the_travel_is_warned_about_once_per_excursion() {
    const NAME: &str = "beyond_stroke";
    let f = Fmu::initialised(NAME, |f| assert_eq!(f.set(RealVar::XDamperStart, 0.095), OK));
    let warnings = || {
        logged(NAME)
            .into_iter()
            .filter(|m| m.contains("[1]") && m.contains("beyond the half stroke"))
            .collect::<Vec<_>>()
    };
    let mut t = 0.0;
    let mut drive = |v: f64, steps: usize| {
        for _ in 0..steps {
            assert_eq!(f.set(RealVar::VDamper, v), OK);
            assert_eq!(f.step(t, 1e-3), OK, "a warning, not a failed step");
            t += 1e-3;
        }
    };
    drive(0.5, 9); // to 99.5 mm
    assert!(warnings().is_empty(), "{:?}", warnings());
    drive(0.5, 20); // out to 109.5 mm
    let logged = warnings();
    assert_eq!(logged.len(), 1, "{logged:?}");
    assert!(logged[0].contains("x_damper = 0.1") && logged[0].contains("L_half_stroke = 0.1 m"), "{}", logged[0]);
    drive(-0.5, 40); // back to 89.5 mm
    assert_eq!(warnings().len(), 1);
    drive(0.5, 40); // and out again
    assert_eq!(warnings().len(), 2);
}
