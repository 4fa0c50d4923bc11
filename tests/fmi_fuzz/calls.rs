//! The fuzzer's calls on one instance: lifecycle, values and steps.

use super::library::{Api, Standard, H, S};
use super::mirror::{may_succeed, Call, Phase};
use super::model_info::{Type, Var};
use super::sequence::{Fuzzer, DISCARD, OK};
use std::ptr::{null, null_mut};

/// A value-reference no variable has.
const UNKNOWN_VR: u32 = 987_654;

impl Fuzzer<'_> {
    /// Whether `call` may return OK now on instance `k`.
    fn may(&self, k: usize, call: Call) -> bool {
        may_succeed(self.standard, self.live[k].phase, call)
    }

    /// The phase a successful lifecycle call leads to.
    fn after(&mut self, k: usize, call: Call) {
        let i = &mut self.live[k];
        match call {
            Call::EnterInitializationMode => i.phase = Phase::InitializationMode,
            Call::ExitInitializationMode => (i.phase, i.time) = (Phase::StepComplete, i.start),
            Call::Terminate => i.phase = Phase::Terminated,
            _ => (i.phase, i.start, i.stop) = (Phase::Instantiated, 0.0, None),
        }
    }

    fn lifecycle(&mut self, k: usize, what: &'static str, call: Call, f: unsafe extern "C" fn(H) -> S) {
        let c = self.live[k].c;
        let may = self.may(k, call);
        // SAFETY: c is a live instance of the FMU whose function f is.
        let status = self.dog.call(what, || unsafe { f(c) });
        self.check(what, status, may, false);
        if status == OK {
            self.after(k, call);
        }
    }

    /// FMI 2.0: after fmi2SetupExperiment; FMI 3.0: with the experiment drawn for it, whose start
    /// and stop must be valid for OK.
    pub(super) fn enter_initialization(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let (tol, start, stop) = self.live[k].experiment;
        let f = self.api(fmu);
        let what = f.name("fmi2EnterInitializationMode", "fmi3EnterInitializationMode");
        // SAFETY: c is a live instance of this FMU; the rest are plain values.
        let status = self.dog.call(what, || unsafe { f.enter_initialization_mode(c, tol, start, stop) });
        let valid =
            f.standard == Standard::Fmi2 || (start.is_finite() && stop.is_none_or(|s| s.is_finite() && s >= start));
        let may = self.may(k, Call::EnterInitializationMode) && valid;
        self.check(what, status, may, false);
        if status == OK {
            self.after(k, Call::EnterInitializationMode);
            if f.standard == Standard::Fmi3 {
                (self.live[k].start, self.live[k].stop) = (start, stop);
            }
        }
    }

    pub(super) fn exit_initialization(&mut self, k: usize) {
        let f = self.api(self.live[k].fmu);
        let what = f.name("fmi2ExitInitializationMode", "fmi3ExitInitializationMode");
        self.lifecycle(k, what, Call::ExitInitializationMode, f.common.exit_initialization_mode);
    }

    pub(super) fn terminate(&mut self, k: usize) {
        let f = self.api(self.live[k].fmu);
        self.lifecycle(k, f.name("fmi2Terminate", "fmi3Terminate"), Call::Terminate, f.common.terminate);
    }

    pub(super) fn reset(&mut self, k: usize) {
        let f = self.api(self.live[k].fmu);
        self.lifecycle(k, f.name("fmi2Reset", "fmi3Reset"), Call::Reset, f.common.reset);
    }

    /// nValues for `n` value references: mostly `n`; now and then one off, which FMI 3.0 refuses
    /// (its variables are scalars) and FMI 2.0 does not have.
    fn n_values(&mut self, n: usize) -> (usize, bool) {
        if self.standard == Standard::Fmi3 && self.rng.chance(0.05) {
            (n + 1, false)
        } else {
            (n, true)
        }
    }

    /// A value for `v`: mostly in its range, else its bounds, just outside, or special numbers.
    fn real_value(&mut self, v: &Var) -> f64 {
        let (lo, hi) = (v.min.unwrap_or(-1e3), v.max.unwrap_or(1e3));
        match self.rng.below(24) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => f64::MAX,
            4 => 5e-324,
            5 => -0.0,
            6 => -1e300,
            7 => lo,
            8 => hi,
            9 => lo - lo.abs().max(1.0) * 1e-3,
            10 => hi + hi.abs().max(1.0) * 1e-3,
            11..=15 if lo > 0.0 && hi / lo > 100.0 => lo * (hi / lo).powf(self.rng.unit()),
            _ => lo + (hi - lo) * self.rng.unit(),
        }
    }

    /// Variables of type `ty` to set or get: known ones, now and then an unknown reference.
    fn pick_vars(&mut self, fmu: usize, ty: Type) -> Vec<Option<Var>> {
        let vars: Vec<&Var> = self.api(fmu).info.of(ty).collect();
        let n = *self.rng.pick(&[0, 1, 1, 1, 2, 3, 5]);
        (0..n)
            .map(
                |_| if self.rng.chance(0.04) || vars.is_empty() { None } else { Some((*self.rng.pick(&vars)).clone()) },
            )
            .collect()
    }

    /// Whether setting `vars` may succeed now (each known, settable in this state).
    fn may_set(&self, k: usize, vars: &[Option<Var>]) -> bool {
        self.may(k, Call::SetInput)
            && vars.iter().all(|v| match v {
                None => false,
                Some(v) if v.causality == "parameter" => self.may(k, Call::SetParameter),
                Some(v) => v.causality == "input",
            })
    }

    pub(super) fn set_real(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let vars = self.pick_vars(fmu, Type::Real);
        let vrs: Vec<u32> = vars.iter().map(|v| v.as_ref().map_or(UNKNOWN_VR, |v| v.vr)).collect();
        let values: Vec<f64> = vars.iter().map(|v| v.as_ref().map_or(1.0, |v| self.real_value(v))).collect();
        let in_range = vars.iter().zip(&values).all(|(v, x)| {
            v.as_ref().is_some_and(|v| x.is_finite() && v.min.is_none_or(|m| *x >= m) && v.max.is_none_or(|m| *x <= m))
        });
        let (vp, xp) =
            if vrs.is_empty() && self.rng.chance(0.5) { (null(), null()) } else { (vrs.as_ptr(), values.as_ptr()) };
        let (n_values, scalar) = self.n_values(vrs.len());
        let f = self.api(fmu);
        let what = f.name("fmi2SetReal", "fmi3SetFloat64");
        // SAFETY: c is live; vp and xp hold vrs.len() elements (NULL only when there are none).
        let status = self.dog.call(what, || unsafe { f.set_real(c, vp, vrs.len(), xp, n_values) });
        let may = self.may_set(k, &vars) && in_range && scalar;
        self.check(what, status, may, false);
    }

    /// One parameter set to a value in its range (uniform, or log-uniform over decades).
    pub(super) fn set_legal_parameter(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let f = self.api(fmu);
        let params: Vec<&Var> = f
            .info
            .of(Type::Real)
            .filter(|v| v.causality == "parameter" && v.min.is_some() && v.max.is_some())
            .collect();
        let v = (*self.rng.pick(&params)).clone();
        let (lo, hi) = (v.min.unwrap(), v.max.unwrap());
        let x = if lo > 0.0 && hi / lo > 100.0 && self.rng.chance(0.7) {
            lo * (hi / lo).powf(self.rng.unit())
        } else {
            lo + (hi - lo) * self.rng.unit()
        };
        let what = f.name("fmi2SetReal", "fmi3SetFloat64");
        // SAFETY: c is live; one value reference and one value.
        let status = self.dog.call(what, || unsafe { f.set_real(c, &v.vr, 1, &x, 1) });
        let may = self.may(k, Call::SetParameter);
        self.check(what, status, may, false);
    }

    pub(super) fn set_integer_or_boolean(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let boolean = self.rng.chance(0.5);
        let vars = self.pick_vars(fmu, if boolean { Type::Boolean } else { Type::Integer });
        let vrs: Vec<u32> = vars.iter().map(|v| v.as_ref().map_or(UNKNOWN_VR, |v| v.vr)).collect();
        let values: Vec<i32> =
            vars.iter().map(|_| *self.rng.pick(&[0, 1, 2, -1, 3, 16, 17, 255, i32::MIN, i32::MAX])).collect();
        let in_range = boolean
            || vars.iter().zip(&values).all(|(v, x)| {
                let x = *x as f64;
                v.as_ref().is_some_and(|v| v.min.is_none_or(|m| x >= m) && v.max.is_none_or(|m| x <= m))
            });
        let (n_values, scalar) = self.n_values(vrs.len());
        let f = self.api(fmu);
        let what = f.name("fmi2SetInteger/Boolean", "fmi3SetInt32/Boolean");
        // SAFETY: c is live; vrs and values hold the same number of elements.
        let status = self.dog.call(what, || unsafe { f.set_integer_or_boolean(c, boolean, &vrs, &values, n_values) });
        let may = self.may_set(k, &vars) && in_range && scalar;
        self.check(what, status, may, false);
    }

    /// Types without variables (FMI 2.0 Strings; FMI 3.0 Float32, Int64, UInt16, String): nvr = 0
    /// may succeed where the call is legal, anything else fails. For FMI 3.0 also the functions
    /// these FMUs refuse in every state (Event Mode, Model Exchange, configuration).
    pub(super) fn strings(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let n = self.rng.below(2);
        let vr = [UNKNOWN_VR];
        let vp = if n == 0 { null() } else { vr.as_ptr() };
        let mut buffer = [0u64; 2];
        let out = buffer.as_mut_ptr() as *mut std::ffi::c_void;
        let (status, what, may) = match &self.api(fmu).api {
            Api::Fmi2(f) if self.rng.chance(0.5) => {
                // SAFETY: c is live; vp and out hold n elements (NULL when n = 0).
                let s = self.dog.call("fmi2GetString", || unsafe { (f.get_string)(c, vp, n, out as *mut _) });
                (s, "fmi2GetString", n == 0 && self.may(k, Call::Get))
            }
            Api::Fmi2(f) => {
                let values = [c"x".as_ptr()];
                // SAFETY: as above, values holds one string.
                let s = self.dog.call("fmi2SetString", || unsafe { (f.set_string)(c, vp, n, values.as_ptr()) });
                (s, "fmi2SetString", n == 0 && self.may(k, Call::SetInput))
            }
            Api::Fmi3(f) if self.rng.chance(0.7) => {
                let (name, g) = *self.rng.pick(&f.no_variables);
                let call = if name.starts_with("Get") { Call::Get } else { Call::SetInput };
                // SAFETY: c is live; vp and out hold n elements (NULL when n = 0), out 16 bytes.
                let s = self.dog.call(name, || unsafe { g(c, vp, n, out, n) });
                (s, name, n == 0 && self.may(k, call))
            }
            Api::Fmi3(f) => {
                let (name, g) = *self.rng.pick(&f.refused);
                // SAFETY: c is live.
                (self.dog.call(name, || unsafe { g(c) }), name, false)
            }
        };
        self.check(what, status, may, false);
    }

    /// Gets every variable (or, now and then, none through NULL arrays); OK values must be finite.
    pub(super) fn get_all(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let f = self.api(fmu);
        let none = self.rng.chance(0.1);
        let real: Vec<u32> = if none { vec![] } else { f.info.of(Type::Real).map(|v| v.vr).collect() };
        let mut values = vec![f64::NAN; real.len()];
        let (vp, xp) = if none { (null(), null_mut()) } else { (real.as_ptr(), values.as_mut_ptr()) };
        let (n_values, scalar) = self.n_values(real.len());
        let what = f.name("fmi2GetReal", "fmi3GetFloat64");
        // SAFETY: c is live; vp and xp hold real.len() elements (NULL when there are none).
        let status = self.dog.call(what, || unsafe { f.get_real(c, vp, real.len(), xp, n_values) });
        let may = self.may(k, Call::Get) && scalar;
        self.check(what, status, may, false);
        self.check_finite(what, status, &real, &values);
        for (ty, what) in [
            (Type::Integer, f.name("fmi2GetInteger", "fmi3GetInt32")),
            (Type::Boolean, f.name("fmi2GetBoolean", "fmi3GetBoolean")),
        ] {
            let vrs: Vec<u32> = f.info.of(ty).map(|v| v.vr).collect();
            let (n_values, scalar) = self.n_values(vrs.len());
            // SAFETY: c is live.
            let status = self.dog.call(what, || unsafe {
                if ty == Type::Integer {
                    f.get_integer(c, &vrs, n_values)
                } else {
                    f.get_boolean(c, &vrs, n_values)
                }
            });
            let may = self.may(k, Call::Get) && scalar;
            self.check(what, status, may, false);
        }
    }

    fn check_finite(&mut self, what: &str, status: S, vrs: &[u32], values: &[f64]) {
        if status != OK {
            return;
        }
        if let Some((vr, x)) = vrs.iter().zip(values).find(|(_, x)| !x.is_finite()) {
            self.report.non_finite += 1;
            let (seed, seq) = (self.seed, self.sequence);
            self.report.fail(format!("seed {seed} sequence {seq}: {what} gave vr {vr} = {x} with OK"));
        }
    }

    /// A communication step: mostly a few ms, else zero, negative, NaN, infinite, huge, tiny.
    fn step_size(&mut self) -> f64 {
        match self.rng.below(24) {
            0 => 0.0,
            1 => -1e-3,
            2 => f64::NAN,
            3 => f64::INFINITY,
            4 => 1e10,
            5 => 1e100,
            6 => f64::MAX,
            7 => 5e-324,
            8 => 1e-12,
            9 => 1e6,
            10..=13 => *self.rng.pick(&[1e-4, 5e-4, 1e-3, 2e-3]),
            _ => 5e-3 * self.rng.unit(),
        }
    }

    pub(super) fn do_step(&mut self, k: usize) {
        let (c, fmu, now, stop) = {
            let i = &self.live[k];
            (i.c, i.fmu, i.time, i.stop)
        };
        let h = self.step_size();
        let t = if self.rng.chance(0.95) { now } else { *self.rng.pick(&[now + 1.0, f64::NAN, -now - 1.0]) };
        let f = self.api(fmu);
        let what = f.name("fmi2DoStep", "fmi3DoStep");
        // SAFETY: c is live; the rest are plain values.
        let (status, out) = self.dog.call(what, || unsafe { f.do_step(c, t, h) });
        let slack = 1e-6 * (1.0 + now.abs());
        let valid = h > 0.0 && h.is_finite() && (t - now).abs() <= slack && stop.is_none_or(|s| t + h <= s + slack);
        let may = self.may(k, Call::DoStep) && valid;
        self.check(what, status, may, true);
        if let (Some((last, flagged)), OK | DISCARD) = (out, status) {
            let expected = if status == OK { t + h } else { t };
            if flagged || last != expected {
                self.report.non_conforming += 1;
                let (seed, seq) = (self.seed, self.sequence);
                self.report.fail(format!("seed {seed} sequence {seq}: fmi3DoStep said lastSuccessfulTime {last} (expected {expected}), events/termination/early return {flagged}"));
            }
        }
        match status {
            OK => {
                self.report.steps += 1;
                self.live[k].time = t + h;
                self.outputs_after_step(k);
            }
            // FMI 3.0: a discarded step leaves the FMU as it was, in Step Mode
            DISCARD if self.standard == Standard::Fmi2 => self.live[k].phase = Phase::StepFailed,
            _ => {}
        }
    }

    /// The outputs of an accepted step are finite, and FMI 3.0's time is where the step ended.
    fn outputs_after_step(&mut self, k: usize) {
        let (c, fmu, time) = (self.live[k].c, self.live[k].fmu, self.live[k].time);
        let f = self.api(fmu);
        let mut outputs = f.info.outputs();
        outputs.extend(f.info.independent());
        let mut values = vec![f64::NAN; outputs.len()];
        let what = f.name("fmi2GetReal after an OK step", "fmi3GetFloat64 after an OK step");
        // SAFETY: c is live; outputs and values hold the same number of elements.
        let s = self.dog.call(what, || unsafe {
            f.get_real(c, outputs.as_ptr(), outputs.len(), values.as_mut_ptr(), outputs.len())
        });
        self.check(what, s, true, false);
        if s != OK {
            self.report.non_finite += 1;
            let (seed, seq) = (self.seed, self.sequence);
            self.report.fail(format!("seed {seed} sequence {seq}: outputs refused after an OK step"));
        }
        self.check_finite(what, s, &outputs, &values);
        if s == OK
            && f.info.independent().is_some()
            && (values[values.len() - 1] - time).abs() > 1e-9 * (1.0 + time.abs())
        {
            self.report.non_conforming += 1;
            let (seed, seq) = (self.seed, self.sequence);
            self.report
                .fail(format!("seed {seed} sequence {seq}: time {} after a step to {time}", values[values.len() - 1]));
        }
    }

    /// FMI 2.0's status functions and fmi2CancelStep; for FMI 3.0, which has neither, the
    /// functions these FMUs refuse whatever the state.
    pub(super) fn status(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let f = match &self.api(fmu).api {
            Api::Fmi2(f) => f,
            Api::Fmi3(_) => return self.strings(k),
        };
        let kinds = [2u32, 3, 0, 99];
        let kind = *self.rng.pick(&kinds);
        let (mut real, mut boolean, mut status) = (f64::NAN, 7, 9);
        let which = self.rng.below(4);
        let what = ["fmi2GetRealStatus", "fmi2GetBooleanStatus", "fmi2GetStatus", "fmi2CancelStep"][which];
        // SAFETY: c is live; the out-pointers are valid locals.
        let result = self.dog.call(what, || unsafe {
            match which {
                0 => (f.get_real_status)(c, kind, &mut real),
                1 => (f.get_boolean_status)(c, kind, &mut boolean),
                2 => (f.get_status)(c, kind, &mut status),
                _ => (f.cancel_step)(c),
            }
        });
        // fmi2StatusKind: 2 fmi2LastSuccessfulTime, 3 fmi2Terminated
        let may_ok = match which {
            0 => kind == 2,
            1 => kind == 3,
            _ => false,
        };
        let call = if what == "fmi2CancelStep" { Call::CancelStep } else { Call::GetStatus };
        let may = may_ok && self.may(k, call);
        self.check(what, result, may, false);
        if result == OK && what == "fmi2GetRealStatus" && !real.is_finite() {
            self.report.non_finite += 1;
            self.report.fail(format!("seed {} sequence {}: last successful time {real}", self.seed, self.sequence));
        }
    }

    pub(super) fn debug_logging(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let all = [c"logEvents".as_ptr(), c"logStatusError".as_ptr(), c"logNonsense".as_ptr()];
        let n = self.rng.below(4);
        let known = n < 3;
        let on = self.rng.chance(0.5);
        let p = if n == 0 && self.rng.chance(0.5) { null() } else { all.as_ptr() };
        let f = self.api(fmu);
        let what = f.name("fmi2SetDebugLogging", "fmi3SetDebugLogging");
        // SAFETY: c is live; p holds n C strings (NULL only when n = 0).
        let status = self.dog.call(what, || unsafe { f.set_debug_logging(c, on, n, p) });
        self.check(what, status, known, false);
    }
}
