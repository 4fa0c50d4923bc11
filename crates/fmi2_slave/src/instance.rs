//! One FMU instance behind the C API: the model, the FMI state, the experiment's times and the
//! logger. Methods take Rust types (slices, options); pointer handling is in `api.rs`.

use crate::fmi2::*;
use crate::logger::{Logger, LOG_EVENTS};
use crate::state_machine::{allowed, Api, Phase};
use crate::{Causality, Model, ToleranceNote, VarInfo};
use std::fmt;

/// Why a call did not succeed (fmi2Fatal only comes from caught panics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    Discard,
    Error,
}

pub type Outcome = Result<(), Failure>;

/// The C status of an outcome.
pub fn status(outcome: Outcome) -> fmi2Status {
    match outcome {
        Ok(()) => fmi2Status_fmi2OK,
        Err(Failure::Discard) => fmi2Status_fmi2Discard,
        Err(Failure::Error) => fmi2Status_fmi2Error,
    }
}

/// Largest relative error of the step length in `(t + h) - t` that fmi2DoStep accepts.
pub const TIME_RESOLUTION: f64 = 1e-6;

/// Log categories by status.
const CAT_WARNING: usize = 1;
const CAT_DISCARD: usize = 2;
const CAT_ERROR: usize = 3;
const CAT_FATAL: usize = 4;

pub struct Instance<M: Model> {
    pub logger: Logger,
    pub phase: Phase,
    slave: M,
    start_time: f64,
    stop_time: Option<f64>,
    last_successful_time: f64,
}

impl<M: Model> Instance<M> {
    pub fn new(logger: Logger) -> Self {
        Instance {
            logger,
            phase: Phase::Instantiated,
            slave: M::default(),
            start_time: 0.0,
            stop_time: None,
            last_successful_time: 0.0,
        }
    }

    /// Logs an error and returns it.
    pub fn error(&self, args: fmt::Arguments) -> Failure {
        self.logger.log(fmi2Status_fmi2Error, CAT_ERROR, args);
        Failure::Error
    }

    pub fn warning(&self, args: fmt::Arguments) {
        self.logger.log(fmi2Status_fmi2Warning, CAT_WARNING, args);
    }

    pub fn event(&self, args: fmt::Arguments) {
        self.logger.log(fmi2Status_fmi2OK, LOG_EVENTS, args);
    }

    /// Marks the instance unusable after a caught panic.
    pub fn fatal(&mut self, function: &str, message: &str) {
        self.phase = Phase::Fatal;
        self.logger.log(
            fmi2Status_fmi2Fatal,
            CAT_FATAL,
            format_args!("{function}: internal error (panic: {message}); only fmi2FreeInstance is possible now"),
        );
    }

    /// Refuses `function` when the state machine does not allow `api` now.
    pub fn check(&self, api: Api, function: &str) -> Outcome {
        if allowed(self.phase, api) {
            Ok(())
        } else {
            Err(self.error(format_args!("{function}: illegal call sequence: not allowed in state {:?}", self.phase)))
        }
    }

    pub fn setup_experiment(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Outcome {
        self.check(Api::SetupExperiment, "fmi2SetupExperiment")?;
        if !start.is_finite() || stop.is_some_and(|s| !s.is_finite() || s < start) {
            return Err(self.error(format_args!(
                "fmi2SetupExperiment: startTime {start} and stopTime {stop:?} must be finite with stopTime >= startTime"
            )));
        }
        if let Some(tol) = tolerance {
            match self.slave.use_tolerance(tol) {
                Ok(ToleranceNote::Event(note)) => self.event(format_args!("fmi2SetupExperiment: {note}")),
                Ok(ToleranceNote::Warning(note)) => self.warning(format_args!("fmi2SetupExperiment: {note}")),
                Err(e) => return Err(self.error(format_args!("fmi2SetupExperiment: {e}"))),
            }
        }
        self.start_time = start;
        self.stop_time = stop;
        Ok(())
    }

    pub fn enter_initialization_mode(&mut self) -> Outcome {
        self.check(Api::EnterInitializationMode, "fmi2EnterInitializationMode")?;
        self.phase = Phase::InitializationMode;
        Ok(())
    }

    pub fn exit_initialization_mode(&mut self) -> Outcome {
        self.check(Api::ExitInitializationMode, "fmi2ExitInitializationMode")?;
        if let Err(e) = self.slave.initialize(self.start_time) {
            return Err(self.error(format_args!("fmi2ExitInitializationMode: invalid parameters: {e}")));
        }
        self.last_successful_time = self.start_time;
        self.phase = Phase::StepComplete;
        self.event(format_args!("initialised at t = {} s", self.start_time));
        Ok(())
    }

    pub fn terminate(&mut self) -> Outcome {
        self.check(Api::Terminate, "fmi2Terminate")?;
        self.phase = Phase::Terminated;
        Ok(())
    }

    pub fn reset(&mut self) -> Outcome {
        self.check(Api::Reset, "fmi2Reset")?;
        self.slave = M::default();
        self.phase = Phase::Instantiated;
        self.start_time = 0.0;
        self.stop_time = None;
        Ok(())
    }

    fn unknown(&self, function: &str, vr: u32, ty: &str) -> Failure {
        self.error(format_args!("{function}: unknown value reference {vr} for type {ty}"))
    }

    /// The variable behind `vr`, or the logged error for an unknown value reference.
    fn lookup(&self, function: &str, vr: u32, ty: &str, info: fn(u32) -> Option<VarInfo>) -> Result<VarInfo, Failure> {
        info(vr).ok_or_else(|| self.unknown(function, vr, ty))
    }

    pub fn get_real(&self, vrs: &[u32], values: &mut [f64]) -> Outcome {
        self.check(Api::Get, "fmi2GetReal")?;
        for (vr, value) in vrs.iter().zip(values) {
            self.lookup("fmi2GetReal", *vr, "Real", M::real_info)?;
            *value = self.slave.get_real(*vr).map_err(|e| self.error(format_args!("fmi2GetReal: {e}")))?;
        }
        Ok(())
    }

    pub fn get_integer(&self, vrs: &[u32], values: &mut [i32]) -> Outcome {
        self.check(Api::Get, "fmi2GetInteger")?;
        for (vr, value) in vrs.iter().zip(values) {
            self.lookup("fmi2GetInteger", *vr, "Integer", M::integer_info)?;
            *value = self.slave.get_integer(*vr).map_err(|e| self.error(format_args!("fmi2GetInteger: {e}")))?;
        }
        Ok(())
    }

    pub fn get_boolean(&self, vrs: &[u32], values: &mut [i32]) -> Outcome {
        self.check(Api::Get, "fmi2GetBoolean")?;
        for (vr, value) in vrs.iter().zip(values) {
            self.lookup("fmi2GetBoolean", *vr, "Boolean", M::boolean_info)?;
            *value = self.slave.get_boolean(*vr).map_err(|e| self.error(format_args!("fmi2GetBoolean: {e}")))? as i32;
        }
        Ok(())
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
        if allowed(self.phase, api) {
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
        ty: &str,
        info: fn(u32) -> Option<VarInfo>,
        vrs: &[u32],
        values: &[T],
        set: impl Fn(&mut M, u32, T) -> Result<(), crate::Refusal>,
    ) -> Outcome {
        // with no variable (nvr = 0) the call is still subject to the state table
        if !allowed(self.phase, Api::SetFixed) && !allowed(self.phase, Api::SetInput) {
            return Err(
                self.error(format_args!("{function}: illegal call sequence: not allowed in state {:?}", self.phase))
            );
        }
        for vr in vrs {
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
        set: impl Fn(&mut M, u32, T) -> Result<(), crate::Refusal>,
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

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Outcome {
        self.set_all("fmi2SetReal", "Real", M::real_info, vrs, values, M::set_real)
    }

    /// Input derivatives (canInterpolateInputs): Real inputs only, set where inputs may be set, all
    /// or none.
    pub fn set_real_input_derivatives(&mut self, vrs: &[u32], orders: &[i32], values: &[f64]) -> Outcome {
        const NAME: &str = "fmi2SetRealInputDerivatives";
        self.check(Api::SetInput, NAME)?;
        for vr in vrs {
            let v = self.lookup(NAME, *vr, "Real", M::real_info)?;
            if v.causality != Causality::Input {
                return Err(self.error(format_args!("{NAME}: {} is not an input", v.name)));
            }
        }
        let derivatives = vrs.iter().copied().zip(orders.iter().copied().zip(values.iter().copied()));
        self.commit_all(NAME, derivatives, |m, vr, (order, value)| m.set_real_input_derivative(vr, order, value))
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Outcome {
        self.set_all("fmi2SetInteger", "Integer", M::integer_info, vrs, values, M::set_integer)
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[i32]) -> Outcome {
        self.set_all("fmi2SetBoolean", "Boolean", M::boolean_info, vrs, values, |m, vr, x| m.set_boolean(vr, x != 0))
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Outcome {
        self.check(Api::DoStep, "fmi2DoStep")?;
        let now = self.slave.time().expect("initialised in StepComplete");
        if !(h > 0.0 && h.is_finite() && t.is_finite()) {
            return Err(self.error(format_args!(
                "fmi2DoStep: communicationStepSize {h} must be positive and finite (currentCommunicationPoint {t})"
            )));
        }
        let tol = 1e-9 * (1.0 + now.abs());
        if (t - now).abs() > tol {
            return Err(self.error(format_args!(
                "fmi2DoStep: currentCommunicationPoint {t} s does not match the FMU's time {now} s"
            )));
        }
        if let Some(stop) = self.stop_time {
            if t + h > stop + tol {
                return Err(self.error(format_args!("fmi2DoStep: step to {} s passes stopTime {stop} s", t + h)));
            }
        }
        // t + h must move the clock by h: far from 0 a small step would round away (and the
        // model's time would stop while its loops wait for it)
        let end = t + h;
        if !end.is_finite() || ((end - t) - h).abs() > TIME_RESOLUTION * h {
            return Err(self.error(format_args!(
                "fmi2DoStep: step of {h} s at t = {t} s refused: t + h is not resolved to {TIME_RESOLUTION} of the step"
            )));
        }
        if let Err(e) = self.slave.check_step(h) {
            return Err(self.error(format_args!("fmi2DoStep: step from {t} s by {h} s refused: {e}")));
        }
        self.slave.align_time(t);
        match self.slave.do_step(h) {
            Ok(warning) => {
                self.last_successful_time = t + h;
                if let Some(w) = warning {
                    self.warning(format_args!("fmi2DoStep: step from {t} s by {h} s: {w}"));
                }
                Ok(())
            }
            Err(e) => {
                self.phase = Phase::StepFailed;
                self.last_successful_time = t;
                self.logger.log(
                    fmi2Status_fmi2Discard,
                    CAT_DISCARD,
                    format_args!("fmi2DoStep: step from {t} s by {h} s discarded: {e}; state kept at {t} s"),
                );
                Err(Failure::Discard)
            }
        }
    }

    pub fn get_fmu_state(&self) -> Result<M::State, Failure> {
        self.check(Api::FmuState, "fmi2GetFMUstate")?;
        Ok(self.slave.state())
    }

    pub fn set_fmu_state(&mut self, state: &M::State) -> Outcome {
        self.check(Api::FmuState, "fmi2SetFMUstate")?;
        self.slave.set_state(state).map_err(|e| self.error(format_args!("fmi2SetFMUstate: {e}")))?;
        if let Some(time) = M::state_time(state) {
            self.phase = Phase::StepComplete;
            self.last_successful_time = time;
        } else if !matches!(self.phase, Phase::Instantiated | Phase::InitializationMode) {
            self.phase = Phase::Instantiated;
        }
        Ok(())
    }

    pub fn last_successful_time(&self) -> Result<f64, Failure> {
        self.check(Api::GetStatus, "fmi2GetRealStatus")?;
        Ok(self.last_successful_time)
    }
}
