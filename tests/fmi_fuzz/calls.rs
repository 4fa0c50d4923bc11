//! The fuzzer's calls on one instance: lifecycle, values and steps.

use super::mirror::{may_succeed, Call, Phase};
use super::model_info::{Type, Var};
use super::sequence::{api, Fuzzer};
use fmi2_slave::api::fmi2::*;
use std::ptr::{null, null_mut};

/// A value-reference no variable has.
const UNKNOWN_VR: u32 = 987_654;

impl Fuzzer<'_> {
    fn lifecycle(
        &mut self,
        k: usize,
        what: &'static str,
        call: Call,
        f: unsafe extern "C" fn(fmi2Component) -> fmi2Status,
    ) {
        let (c, phase) = (self.live[k].c, self.live[k].phase);
        // SAFETY: c is a live instance of the FMU whose function f is.
        let status = self.dog.call(what, || unsafe { f(c) });
        self.check(what, status, may_succeed(phase, call), false);
        if status != fmi2Status_fmi2OK {
            return;
        }
        let i = &mut self.live[k];
        match call {
            Call::EnterInitializationMode => i.phase = Phase::InitializationMode,
            Call::ExitInitializationMode => (i.phase, i.time) = (Phase::StepComplete, i.start),
            Call::Terminate => i.phase = Phase::Terminated,
            _ => (i.phase, i.start, i.stop) = (Phase::Instantiated, 0.0, None),
        }
    }

    pub(super) fn enter_initialization(&mut self, k: usize) {
        let f = api(self.live[k].fmu).api.enter_initialization_mode;
        self.lifecycle(k, "fmi2EnterInitializationMode", Call::EnterInitializationMode, f);
    }

    pub(super) fn exit_initialization(&mut self, k: usize) {
        let f = api(self.live[k].fmu).api.exit_initialization_mode;
        self.lifecycle(k, "fmi2ExitInitializationMode", Call::ExitInitializationMode, f);
    }

    pub(super) fn terminate(&mut self, k: usize) {
        let f = api(self.live[k].fmu).api.terminate;
        self.lifecycle(k, "fmi2Terminate", Call::Terminate, f);
    }

    pub(super) fn reset(&mut self, k: usize) {
        let f = api(self.live[k].fmu).api.reset;
        self.lifecycle(k, "fmi2Reset", Call::Reset, f);
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
        let vars: Vec<&Var> = api(fmu).info.of(ty).collect();
        let n = *self.rng.pick(&[0, 1, 1, 1, 2, 3, 5]);
        (0..n)
            .map(
                |_| if self.rng.chance(0.04) || vars.is_empty() { None } else { Some((*self.rng.pick(&vars)).clone()) },
            )
            .collect()
    }

    /// Whether setting `vars` may succeed now (each known, settable in this state).
    fn may_set(phase: Phase, vars: &[Option<Var>]) -> bool {
        may_succeed(phase, Call::SetInput)
            && vars.iter().all(|v| match v {
                None => false,
                Some(v) if v.causality == "parameter" => may_succeed(phase, Call::SetParameter),
                Some(v) => v.causality == "input",
            })
    }

    pub(super) fn set_real(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let vars = self.pick_vars(fmu, Type::Real);
        let vrs: Vec<u32> = vars.iter().map(|v| v.as_ref().map_or(UNKNOWN_VR, |v| v.vr)).collect();
        let values: Vec<f64> = vars.iter().map(|v| v.as_ref().map_or(1.0, |v| self.real_value(v))).collect();
        let in_range = vars.iter().zip(&values).all(|(v, x)| {
            v.as_ref().is_some_and(|v| x.is_finite() && v.min.is_none_or(|m| *x >= m) && v.max.is_none_or(|m| *x <= m))
        });
        let (vp, xp) =
            if vrs.is_empty() && self.rng.chance(0.5) { (null(), null()) } else { (vrs.as_ptr(), values.as_ptr()) };
        // SAFETY: c is live; vp and xp hold vrs.len() elements (NULL only when there are none).
        let status = self.dog.call("fmi2SetReal", || unsafe { (api(fmu).api.set_real)(c, vp, vrs.len(), xp) });
        self.check("fmi2SetReal", status, Self::may_set(phase, &vars) && in_range, false);
    }

    /// One parameter set to a value in its range (uniform, or log-uniform over decades).
    pub(super) fn set_legal_parameter(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let params: Vec<&Var> = api(fmu)
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
        // SAFETY: c is live; one value reference and one value.
        let status = self.dog.call("fmi2SetReal", || unsafe { (api(fmu).api.set_real)(c, &v.vr, 1, &x) });
        self.check("fmi2SetReal", status, may_succeed(phase, Call::SetParameter), false);
    }

    pub(super) fn set_integer_or_boolean(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let boolean = self.rng.chance(0.5);
        let vars = self.pick_vars(fmu, if boolean { Type::Boolean } else { Type::Integer });
        let vrs: Vec<u32> = vars.iter().map(|v| v.as_ref().map_or(UNKNOWN_VR, |v| v.vr)).collect();
        let values: Vec<i32> =
            vars.iter().map(|_| *self.rng.pick(&[0, 1, 2, -1, 3, 16, 17, i32::MIN, i32::MAX])).collect();
        let in_range = boolean
            || vars.iter().zip(&values).all(|(v, x)| {
                let x = *x as f64;
                v.as_ref().is_some_and(|v| v.min.is_none_or(|m| x >= m) && v.max.is_none_or(|m| x <= m))
            });
        let f = if boolean { api(fmu).api.set_boolean } else { api(fmu).api.set_integer };
        // SAFETY: c is live; vrs and values hold the same number of elements.
        let status =
            self.dog.call("fmi2SetInteger/Boolean", || unsafe { f(c, vrs.as_ptr(), vrs.len(), values.as_ptr()) });
        self.check("fmi2SetInteger/Boolean", status, Self::may_set(phase, &vars) && in_range, false);
    }

    /// No String variables: nvr = 0 may succeed where the call is legal, anything else fails.
    pub(super) fn strings(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let n = self.rng.below(2);
        let vr = [UNKNOWN_VR];
        let vp = if n == 0 { null() } else { vr.as_ptr() };
        let (status, call) = if self.rng.chance(0.5) {
            let mut out: [fmi2String; 1] = [null()];
            // SAFETY: c is live; vp and out hold n elements (NULL when n = 0).
            let s = self.dog.call("fmi2GetString", || unsafe { (api(fmu).api.get_string)(c, vp, n, out.as_mut_ptr()) });
            (s, Call::Get)
        } else {
            let values: [fmi2String; 1] = [c"x".as_ptr()];
            // SAFETY: as above, values holds one string.
            let s = self.dog.call("fmi2SetString", || unsafe { (api(fmu).api.set_string)(c, vp, n, values.as_ptr()) });
            (s, Call::SetInput)
        };
        self.check("fmi2Get/SetString", status, n == 0 && may_succeed(phase, call), false);
    }

    /// Gets every variable (or, now and then, none through NULL arrays); OK values must be finite.
    pub(super) fn get_all(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let info = &api(fmu).info;
        let none = self.rng.chance(0.1);
        let real: Vec<u32> = if none { vec![] } else { info.of(Type::Real).map(|v| v.vr).collect() };
        let mut values = vec![f64::NAN; real.len()];
        let (vp, xp) = if none { (null(), null_mut()) } else { (real.as_ptr(), values.as_mut_ptr()) };
        // SAFETY: c is live; vp and xp hold real.len() elements (NULL when there are none).
        let status = self.dog.call("fmi2GetReal", || unsafe { (api(fmu).api.get_real)(c, vp, real.len(), xp) });
        self.check("fmi2GetReal", status, may_succeed(phase, Call::Get), false);
        self.check_finite("fmi2GetReal", status, &real, &values);
        for (ty, what) in [(Type::Integer, "fmi2GetInteger"), (Type::Boolean, "fmi2GetBoolean")] {
            let vrs: Vec<u32> = info.of(ty).map(|v| v.vr).collect();
            let mut out = vec![0i32; vrs.len()];
            let f = if ty == Type::Integer { api(fmu).api.get_integer } else { api(fmu).api.get_boolean };
            // SAFETY: c is live; vrs and out hold the same number of elements.
            let status = self.dog.call(what, || unsafe { f(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) });
            self.check(what, status, may_succeed(phase, Call::Get), false);
        }
    }

    fn check_finite(&mut self, what: &str, status: fmi2Status, vrs: &[u32], values: &[f64]) {
        if status != fmi2Status_fmi2OK {
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
        let (c, fmu, phase, now, stop) = {
            let i = &self.live[k];
            (i.c, i.fmu, i.phase, i.time, i.stop)
        };
        let h = self.step_size();
        let t = if self.rng.chance(0.95) { now } else { *self.rng.pick(&[now + 1.0, f64::NAN, -now - 1.0]) };
        // SAFETY: c is live; the rest are plain values.
        let status = self.dog.call("fmi2DoStep", || unsafe { (api(fmu).api.do_step)(c, t, h, 0) });
        let slack = 1e-6 * (1.0 + now.abs());
        let valid = h > 0.0 && h.is_finite() && (t - now).abs() <= slack && stop.is_none_or(|s| t + h <= s + slack);
        self.check("fmi2DoStep", status, may_succeed(phase, Call::DoStep) && valid, true);
        match status {
            fmi2Status_fmi2OK => {
                self.report.steps += 1;
                self.live[k].time = t + h;
                // the outputs of an accepted step are finite
                let outputs = api(fmu).info.outputs();
                let mut values = vec![f64::NAN; outputs.len()];
                // SAFETY: c is live; outputs and values hold the same number of elements.
                let s = self.dog.call("fmi2GetReal", || unsafe {
                    (api(fmu).api.get_real)(c, outputs.as_ptr(), outputs.len(), values.as_mut_ptr())
                });
                self.check("fmi2GetReal after an OK step", s, true, false);
                if s != fmi2Status_fmi2OK {
                    self.report.non_finite += 1;
                    let (seed, seq) = (self.seed, self.sequence);
                    self.report.fail(format!("seed {seed} sequence {seq}: outputs refused after an OK step"));
                }
                self.check_finite("fmi2GetReal after an OK step", s, &outputs, &values);
            }
            fmi2Status_fmi2Discard => self.live[k].phase = Phase::StepFailed,
            _ => {}
        }
    }

    pub(super) fn status(&mut self, k: usize) {
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let f = &api(fmu).api;
        let kind = *self.rng.pick(&[
            fmi2StatusKind_fmi2LastSuccessfulTime,
            fmi2StatusKind_fmi2Terminated,
            fmi2StatusKind_fmi2DoStepStatus,
            99,
        ]);
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
        let may_ok = match which {
            0 => kind == fmi2StatusKind_fmi2LastSuccessfulTime,
            1 => kind == fmi2StatusKind_fmi2Terminated,
            _ => false,
        };
        let call = if what == "fmi2CancelStep" { Call::CancelStep } else { Call::GetStatus };
        self.check(what, result, may_ok && may_succeed(phase, call), false);
        if result == fmi2Status_fmi2OK && what == "fmi2GetRealStatus" && !real.is_finite() {
            self.report.non_finite += 1;
            self.report.fail(format!("seed {} sequence {}: last successful time {real}", self.seed, self.sequence));
        }
    }

    pub(super) fn debug_logging(&mut self, k: usize) {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let all = [c"logEvents".as_ptr(), c"logStatusError".as_ptr(), c"logNonsense".as_ptr()];
        let n = self.rng.below(4);
        let known = n < 3;
        let on = self.rng.below(2) as i32;
        let p = if n == 0 && self.rng.chance(0.5) { null() } else { all.as_ptr() };
        // SAFETY: c is live; p holds n C strings (NULL only when n = 0).
        let status = self.dog.call("fmi2SetDebugLogging", || unsafe { (api(fmu).api.set_debug_logging)(c, on, n, p) });
        self.check("fmi2SetDebugLogging", status, known, false);
    }
}
