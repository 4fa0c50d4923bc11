//! The co-simulation slave without FMI types: variable access by value reference through the
//! generated enums ([`crate::variables`]), range checks from the XML's min/max, initialisation,
//! stepping and state save/restore ([`crate::snapshot`]). `fmi2_slave` adds the C boundary and
//! the FMI state machine on top.

use crate::limits::MAX_SUBSTEPS;
use crate::model_description::{BooleanVar, Causality, IntegerVar, RealVar, CAN_INTERPOLATE_INPUTS, GUID};
use crate::snapshot::MAGIC;
use crate::tracking::DemandHistory;
use crate::truck::{At, Evaluation, Inputs, Params, State, MODE_TRACKING};
use crate::variables::{real_input, real_output};
use fmi2_slave::snapshot;
use fmi2_slave::{check_integer, check_real, Model, ToleranceNote};

/// The FMU state: parameters, inputs, and once initialised the states and time.
#[derive(Clone, Copy, Debug, Default)]
pub struct Slave {
    pub(crate) params: Params,
    pub(crate) inputs: Inputs,
    pub(crate) y: State,
    /// The clipped demand's past, for the tracking damper's delay.
    pub(crate) past: DemandHistory,
    pub(crate) time: f64,
    pub(crate) initialized: bool,
}

fn unknown(vr: u32) -> String {
    format!("unknown value reference {vr}")
}

impl Slave {
    /// State and evaluation for the outputs: the present state, or the start state before
    /// initialisation. The road is taken at the end of the last step (z_road + v_road·h is not
    /// stored: outputs use the held inputs).
    fn evaluation(&self) -> (State, Evaluation) {
        let y = if self.initialized { self.y } else { self.params.start_state() };
        let at = At { step_start: self.time, since_step: 0.0, past: &self.past };
        (y, self.params.evaluate(&self.inputs, &y, at))
    }

    /// Whether every output is a finite number.
    fn outputs_finite(&self) -> bool {
        let (y, e) = self.evaluation();
        RealVar::ALL.iter().filter_map(|&v| real_output(&y, &e, v)).all(f64::is_finite)
    }

    /// Checks that a restored state is one this FMU could have made: every parameter in its XML
    /// range (and, once initialised, stable), every number finite.
    fn check_restored(&self) -> Result<(), String> {
        let (mut p, mut u) = (self.params, self.inputs);
        for v in RealVar::ALL {
            if let Some(x) = p.real_mut(v) {
                check_real(v.name(), *x, v.min(), v.max())?;
            }
            if let Some(x) = real_input(&mut u, v) {
                check_real(v.name(), *x, None, None)?;
            }
        }
        let mode = IntegerVar::DamperMode;
        check_integer(mode.name(), self.params.damper_mode, mode.min(), mode.max())?;
        if !self.y.iter().chain([&self.time]).all(|x| x.is_finite()) {
            return Err("a state or the time is not finite".into());
        }
        self.past.check()?;
        if self.initialized {
            self.params.validate()?;
        }
        Ok(())
    }
}

impl Model for Slave {
    const GUID: &'static str = GUID;
    const CAN_INTERPOLATE_INPUTS: bool = CAN_INTERPOLATE_INPUTS;
    type State = Slave;
    type StepError = &'static str;
    type StepWarning = std::convert::Infallible;

    fmi2_slave::parameter_access!();

    fn get_real(&self, vr: u32) -> Result<f64, String> {
        let v = RealVar::from_vr(vr).ok_or_else(|| unknown(vr))?;
        let (mut p, mut u) = (self.params, self.inputs);
        if let Some(x) = p.real_mut(v).or(real_input(&mut u, v)) {
            return Ok(*x);
        }
        let (y, e) = self.evaluation();
        let x = real_output(&y, &e, v).ok_or_else(|| unknown(vr))?;
        if !x.is_finite() {
            return Err(format!("{} = {x} is not finite (inputs out of the model's reach)", v.name()));
        }
        Ok(x)
    }

    type Settable = (Params, Inputs);

    fn settable(&self) -> Self::Settable {
        (self.params, self.inputs)
    }

    fn restore_settable(&mut self, (params, inputs): Self::Settable) {
        (self.params, self.inputs) = (params, inputs);
    }

    fn set_real(&mut self, vr: u32, value: f64) -> Result<(), String> {
        let v = RealVar::from_vr(vr).ok_or_else(|| unknown(vr))?;
        check_real(v.name(), value, v.min(), v.max())?;
        let field = match v.causality() {
            Causality::Parameter => self.params.real_mut(v),
            Causality::Input => real_input(&mut self.inputs, v),
            Causality::Output => None,
        };
        *field.ok_or_else(|| format!("{} is an output and cannot be set", v.name()))? = value;
        Ok(())
    }

    /// The truck integrates with fixed RK4 steps: a tolerance has nothing to control.
    fn use_tolerance(&mut self, tolerance: f64) -> Result<ToleranceNote, String> {
        Ok(ToleranceNote::Event(format!(
            "tolerance {tolerance} not used: fixed RK4 steps no longer than the parameter h_max"
        )))
    }

    fn initialize(&mut self, start_time: f64) -> Result<(), String> {
        self.params.validate()?;
        self.y = self.params.start_state();
        self.past = DemandHistory::default();
        self.time = start_time;
        self.initialized = true;
        Ok(())
    }

    fn time(&self) -> Option<f64> {
        self.initialized.then_some(self.time)
    }

    fn align_time(&mut self, t: f64) {
        self.time = t;
    }

    fn check_step(&self, h: f64) -> Result<(), &'static str> {
        if self.params.substeps(h) > MAX_SUBSTEPS {
            return Err("more than 1e7 integration steps (h/h_max) in one step");
        }
        let dt = h / self.params.substeps(h);
        if self.params.damper_mode == MODE_TRACKING && self.params.tracking().longest_delay() > DemandHistory::span(dt)
        {
            return Err("a tracking delay longer than the demand's past holds (510 internal steps of the step \
                        divided by h_max): raise h_max or shorten tracking_delay_*");
        }
        Ok(())
    }

    fn do_step(&mut self, h: f64) -> Result<Option<Self::StepWarning>, &'static str> {
        // what a refused step puts back; the demand's past (4 kB a side) only where it moves
        let (y0, z_road0, time0) = (self.y, self.inputs.z_road, self.time);
        let past0 = (self.params.damper_mode == MODE_TRACKING).then_some(self.past);
        let mut y = self.y;
        self.params.advance(&self.inputs, &mut y, h, self.time, &mut self.past);
        let restore = |s: &mut Self| {
            (s.y, s.inputs.z_road, s.time) = (y0, z_road0, time0);
            if let Some(past) = past0 {
                s.past = past;
            }
        };
        if !y.iter().all(|x| x.is_finite()) {
            restore(self);
            return Err("non-finite state");
        }
        self.y = y;
        // the road input is extrapolated over the step; hold its end value for the outputs
        self.inputs.z_road += self.inputs.v_road * h;
        self.time += h;
        if !self.outputs_finite() || !self.inputs.z_road.is_finite() {
            restore(self);
            return Err("an output is not finite at the end of the step");
        }
        Ok(None)
    }

    fn state(&self) -> Slave {
        *self
    }

    fn set_state(&mut self, s: &Slave) -> Result<(), String> {
        *self = *s;
        Ok(())
    }

    fn state_time(s: &Slave) -> Option<f64> {
        s.time()
    }

    fn serialize(s: &Slave) -> Vec<u8> {
        snapshot::to_bytes(MAGIC, GUID, s)
    }

    fn deserialize(bytes: &[u8]) -> Result<Slave, String> {
        let mut s = Slave::default();
        snapshot::from_bytes(MAGIC, GUID, bytes, &mut s)?;
        s.check_restored().map_err(|e| format!("serialized FMU state rejected: {e}"))?;
        Ok(s)
    }
}
