//! One FMU instance behind either C API: the model, the state machine, the experiment's times and
//! the logger. Methods take Rust types (slices, options) and the name of the C function being
//! served, for its messages; pointer handling is in the standards' `api` modules.

use crate::logger::{Logger, LOG_EVENTS};
use crate::state_machine::{allowed, Api, Phase};
use crate::{Causality, Model, Refusal, Status, ToleranceNote, VarInfo};
use std::fmt;

/// Why a call did not succeed (Fatal only comes from caught panics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    Discard,
    Error,
}

pub type Outcome = Result<(), Failure>;

/// The C status of an outcome.
pub fn status(outcome: Outcome) -> Status {
    match outcome {
        Ok(()) => Status::Ok,
        Err(Failure::Discard) => Status::Discard,
        Err(Failure::Error) => Status::Error,
    }
}

/// The standard whose C API serves an instance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    Fmi2,
    /// With the value reference of the independent variable `time`, which FMI 3.0 model
    /// descriptions declare and FMI 2.0 ones do not.
    Fmi3 {
        time_vr: u32,
    },
}

/// Largest relative error of the step length in `(t + h) - t` that a step accepts.
pub const TIME_RESOLUTION: f64 = 1e-6;

/// Log categories by status.
const CAT_WARNING: usize = 1;
const CAT_DISCARD: usize = 2;
const CAT_ERROR: usize = 3;
const CAT_FATAL: usize = 4;

pub struct Instance<M: Model> {
    pub logger: Logger,
    pub phase: Phase,
    standard: Standard,
    slave: M,
    start_time: f64,
    stop_time: Option<f64>,
    last_successful_time: f64,
}

impl<M: Model> Instance<M> {
    pub fn new(logger: Logger, standard: Standard) -> Self {
        Instance {
            logger,
            phase: Phase::Instantiated,
            standard,
            slave: M::default(),
            start_time: 0.0,
            stop_time: None,
            last_successful_time: 0.0,
        }
    }

    /// Logs an error and returns it.
    pub fn error(&self, args: fmt::Arguments) -> Failure {
        self.logger.log(Status::Error, CAT_ERROR, args);
        Failure::Error
    }

    pub fn warning(&self, args: fmt::Arguments) {
        self.logger.log(Status::Warning, CAT_WARNING, args);
    }

    pub fn event(&self, args: fmt::Arguments) {
        self.logger.log(Status::Ok, LOG_EVENTS, args);
    }

    /// Marks the instance unusable after a caught panic.
    pub fn fatal(&mut self, function: &str, message: &str) {
        self.phase = Phase::Fatal;
        let free = match self.standard {
            Standard::Fmi2 => "fmi2FreeInstance",
            Standard::Fmi3 { .. } => "fmi3FreeInstance",
        };
        self.logger.log(
            Status::Fatal,
            CAT_FATAL,
            format_args!("{function}: internal error (panic: {message}); only {free} is possible now"),
        );
    }

    /// Refuses `function` when the state machine does not allow `api` now.
    pub fn check(&self, api: Api, function: &str) -> Outcome {
        if allowed(self.standard, self.phase, api) {
            Ok(())
        } else {
            Err(self.error(format_args!("{function}: illegal call sequence: not allowed in state {:?}", self.phase)))
        }
    }

    /// The experiment's tolerance, start and stop time: fmi2SetupExperiment, or the arguments of
    /// fmi3EnterInitializationMode (`function`).
    pub fn setup_experiment(
        &mut self,
        function: &str,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Outcome {
        if !start.is_finite() || stop.is_some_and(|s| !s.is_finite() || s < start) {
            return Err(self.error(format_args!(
                "{function}: startTime {start} and stopTime {stop:?} must be finite with stopTime >= startTime"
            )));
        }
        if let Some(tol) = tolerance {
            match self.slave.use_tolerance(tol) {
                Ok(ToleranceNote::Event(note)) => self.event(format_args!("{function}: {note}")),
                Ok(ToleranceNote::Warning(note)) => self.warning(format_args!("{function}: {note}")),
                Err(e) => return Err(self.error(format_args!("{function}: {e}"))),
            }
        }
        self.start_time = start;
        self.stop_time = stop;
        Ok(())
    }

    pub fn enter_initialization_mode(&mut self, function: &str) -> Outcome {
        self.check(Api::EnterInitializationMode, function)?;
        self.phase = Phase::InitializationMode;
        Ok(())
    }

    pub fn exit_initialization_mode(&mut self, function: &str) -> Outcome {
        self.check(Api::ExitInitializationMode, function)?;
        if let Err(e) = self.slave.initialize(self.start_time) {
            return Err(self.error(format_args!("{function}: invalid parameters: {e}")));
        }
        self.last_successful_time = self.start_time;
        self.phase = Phase::StepComplete;
        self.event(format_args!("initialised at t = {} s", self.start_time));
        Ok(())
    }

    pub fn terminate(&mut self, function: &str) -> Outcome {
        self.check(Api::Terminate, function)?;
        self.phase = Phase::Terminated;
        Ok(())
    }

    pub fn reset(&mut self, function: &str) -> Outcome {
        self.check(Api::Reset, function)?;
        self.slave = M::default();
        self.phase = Phase::Instantiated;
        self.start_time = 0.0;
        self.stop_time = None;
        Ok(())
    }

    /// The variable behind `vr`, or the logged error for an unknown value reference.
    fn lookup(&self, function: &str, vr: u32, ty: &str, info: fn(u32) -> Option<VarInfo>) -> Result<VarInfo, Failure> {
        info(vr).ok_or_else(|| self.error(format_args!("{function}: unknown value reference {vr} for type {ty}")))
    }

    /// FMI 3.0's independent variable, if `vr` is its value reference: the model's time, or the
    /// start time before initialisation.
    fn independent(&self, vr: u32) -> Option<f64> {
        match self.standard {
            Standard::Fmi3 { time_vr } if vr == time_vr => Some(self.slave.time().unwrap_or(self.start_time)),
            _ => None,
        }
    }

    /// Reads the variables `vrs` of one type into `values`, converted by `to`.
    fn get_all<T, C>(
        &self,
        function: &str,
        (ty, info): (&str, fn(u32) -> Option<VarInfo>),
        vrs: &[u32],
        values: &mut [C],
        get: impl Fn(&M, u32) -> Result<T, Refusal>,
        to: impl Fn(T) -> C,
    ) -> Outcome {
        self.check(Api::Get, function)?;
        for (vr, value) in vrs.iter().zip(values) {
            self.lookup(function, *vr, ty, info)?;
            *value = to(get(&self.slave, *vr).map_err(|e| self.error(format_args!("{function}: {e}")))?);
        }
        Ok(())
    }

    pub fn get_real(&self, function: &str, vrs: &[u32], values: &mut [f64]) -> Outcome {
        self.check(Api::Get, function)?;
        for (vr, value) in vrs.iter().zip(values.iter_mut()) {
            if let Some(t) = self.independent(*vr) {
                *value = t;
            } else {
                self.lookup(function, *vr, "Real", M::real_info)?;
            }
        }
        let independent = |i: usize| self.independent(vrs[i]).is_some();
        self.slave.get_reals(vrs, values, &independent).map_err(|(_, e)| self.error(format_args!("{function}: {e}")))
    }

    pub fn get_integer(&self, function: &str, vrs: &[u32], values: &mut [i32]) -> Outcome {
        self.get_all(function, ("Integer", M::integer_info), vrs, values, M::get_integer, |x| x)
    }

    /// Booleans as the standard's C type: `to` makes one of a `bool`.
    pub fn get_boolean<C>(&self, function: &str, vrs: &[u32], values: &mut [C], to: impl Fn(bool) -> C) -> Outcome {
        self.get_all(function, ("Boolean", M::boolean_info), vrs, values, M::get_boolean, to)
    }

    /// May a variable of `causality` be set now?
    fn check_set(&self, function: &str, name: &str, causality: Causality) -> Outcome {
        let api = match causality {
            Causality::Parameter => Api::SetFixed,
            Causality::Input => Api::SetInput,
            Causality::Output => {
                return Err(self.error(format_args!("{function}: {name} is an output and cannot be set")))
            }
        };
        if allowed(self.standard, self.phase, api) {
            Ok(())
        } else {
            Err(self.error(format_args!("{function}: {name} ({causality:?}) cannot be set in state {:?}", self.phase)))
        }
    }

    /// Applies all values or none: each variable must be known and settable now, then the values
    /// are set on a copy that replaces the model only if every one is accepted.
    fn set_all<T: Copy>(
        &mut self,
        function: &str,
        (ty, info): (&str, fn(u32) -> Option<VarInfo>),
        vrs: &[u32],
        values: &[T],
        set: impl Fn(&mut M, u32, T) -> Result<(), Refusal>,
    ) -> Outcome {
        // with no variable (nvr = 0) the call is still subject to the state table
        if !allowed(self.standard, self.phase, Api::SetFixed) && !allowed(self.standard, self.phase, Api::SetInput) {
            return Err(
                self.error(format_args!("{function}: illegal call sequence: not allowed in state {:?}", self.phase))
            );
        }
        for vr in vrs {
            if self.independent(*vr).is_some() {
                return Err(self.error(format_args!("{function}: time is the independent variable and cannot be set")));
            }
            let v = self.lookup(function, *vr, ty, info)?;
            self.check_set(function, v.name, v.causality)?;
        }
        self.commit_all(function, vrs.iter().copied().zip(values.iter().copied()), set)
    }

    /// Applies the values, all or nothing: if one is refused, the model's settable part
    /// ([`Model::settable`]) is put back as it was before the first.
    fn commit_all<T>(
        &mut self,
        function: &str,
        values: impl Iterator<Item = (u32, T)>,
        set: impl Fn(&mut M, u32, T) -> Result<(), Refusal>,
    ) -> Outcome {
        let before = self.slave.settable();
        for (vr, value) in values {
            if let Err(e) = set(&mut self.slave, vr, value) {
                self.slave.restore_settable(before);
                return Err(self.error(format_args!("{function}: {e}")));
            }
        }
        Ok(())
    }

    pub fn set_real(&mut self, function: &str, vrs: &[u32], values: &[f64]) -> Outcome {
        self.set_all(function, ("Real", M::real_info), vrs, values, M::set_real)
    }

    /// Input derivatives (FMI 2.0 canInterpolateInputs): Real inputs only, set where inputs may
    /// be set, all or none.
    pub fn set_real_input_derivatives(
        &mut self,
        function: &str,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Outcome {
        self.check(Api::SetInput, function)?;
        for vr in vrs {
            let v = self.lookup(function, *vr, "Real", M::real_info)?;
            if v.causality != Causality::Input {
                return Err(self.error(format_args!("{function}: {} is not an input", v.name)));
            }
        }
        let derivatives = vrs.iter().copied().zip(orders.iter().copied().zip(values.iter().copied()));
        self.commit_all(function, derivatives, |m, vr, (order, value)| m.set_real_input_derivative(vr, order, value))
    }

    pub fn set_integer(&mut self, function: &str, vrs: &[u32], values: &[i32]) -> Outcome {
        self.set_all(function, ("Integer", M::integer_info), vrs, values, M::set_integer)
    }

    /// Booleans as the standard's C type: `from` reads one as a `bool`.
    pub fn set_boolean<C: Copy>(
        &mut self,
        function: &str,
        vrs: &[u32],
        values: &[C],
        from: impl Fn(C) -> bool,
    ) -> Outcome {
        self.set_all(function, ("Boolean", M::boolean_info), vrs, values, |m, vr, x| m.set_boolean(vr, from(x)))
    }

    /// Refuses a step the model should not start: not at its time, past the stop time, too short
    /// for the clock to resolve, or beyond the model's own limits.
    fn check_step(&self, function: &str, t: f64, h: f64) -> Outcome {
        let now = self.slave.time().expect("initialised in StepComplete");
        if !(h > 0.0 && h.is_finite() && t.is_finite()) {
            return Err(self.error(format_args!(
                "{function}: communicationStepSize {h} must be positive and finite (currentCommunicationPoint {t})"
            )));
        }
        let tol = 1e-9 * (1.0 + now.abs());
        if (t - now).abs() > tol {
            return Err(self.error(format_args!(
                "{function}: currentCommunicationPoint {t} s does not match the FMU's time {now} s"
            )));
        }
        if let Some(stop) = self.stop_time {
            if t + h > stop + tol {
                return Err(self.error(format_args!("{function}: step to {} s passes stopTime {stop} s", t + h)));
            }
        }
        // t + h must move the clock by h: far from 0 a small step would round away (and the
        // model's time would stop while its loops wait for it)
        let end = t + h;
        if !end.is_finite() || ((end - t) - h).abs() > TIME_RESOLUTION * h {
            return Err(self.error(format_args!(
                "{function}: step of {h} s at t = {t} s refused: t + h is not resolved to {TIME_RESOLUTION} of the step"
            )));
        }
        if let Err(e) = self.slave.check_step(h) {
            return Err(self.error(format_args!("{function}: step from {t} s by {h} s refused: {e}")));
        }
        Ok(())
    }

    /// One communication step from `t` by `h`. A step the model cannot complete leaves its state
    /// at `t` and is discarded: FMI 2.0 then enters stepFailed; FMI 3.0 stays in Step Mode, since
    /// the FMU is as it was before the call.
    pub fn do_step(&mut self, function: &str, t: f64, h: f64) -> Outcome {
        self.check(Api::DoStep, function)?;
        self.check_step(function, t, h)?;
        self.slave.align_time(t);
        match self.slave.do_step(h) {
            Ok(warning) => {
                self.last_successful_time = t + h;
                if let Some(w) = warning {
                    self.warning(format_args!("{function}: step from {t} s by {h} s: {w}"));
                }
                Ok(())
            }
            Err(e) => {
                if self.standard == Standard::Fmi2 {
                    self.phase = Phase::StepFailed;
                }
                self.last_successful_time = t;
                self.logger.log(
                    Status::Discard,
                    CAT_DISCARD,
                    format_args!("{function}: step from {t} s by {h} s discarded: {e}; state kept at {t} s"),
                );
                Err(Failure::Discard)
            }
        }
    }

    pub fn get_fmu_state(&self, function: &str) -> Result<M::State, Failure> {
        self.check(Api::FmuState, function)?;
        Ok(self.slave.state())
    }

    pub fn set_fmu_state(&mut self, function: &str, state: &M::State) -> Outcome {
        self.check(Api::FmuState, function)?;
        self.slave.set_state(state).map_err(|e| self.error(format_args!("{function}: {e}")))?;
        if let Some(time) = M::state_time(state) {
            self.phase = Phase::StepComplete;
            self.last_successful_time = time;
        } else if !matches!(self.phase, Phase::Instantiated | Phase::InitializationMode) {
            self.phase = Phase::Instantiated;
        }
        Ok(())
    }

    /// The end of the last step that succeeded (s).
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }

    /// fmi2GetRealStatus's check, then [`Instance::last_successful_time`].
    pub fn last_successful_time_status(&self, function: &str) -> Result<f64, Failure> {
        self.check(Api::GetStatus, function)?;
        Ok(self.last_successful_time)
    }
}
