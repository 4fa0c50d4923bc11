//! The co-simulation slave without FMI types: variable access by the generated enums, range
//! checks from the XML's min/max, initialisation, stepping and state save/restore. `fmi2` adds
//! only the C boundary and the FMI state machine on top.

use crate::damper::{Damper, DamperState, Inputs, Outputs, StepStats};
use crate::model_description::{BooleanVar, Causality, IntegerVar, RealVar};
use crate::physics::params::Parameters;
use crate::snapshot::{self, Visit, Visitor};
use crate::solver::SolverError;
use crate::variables::{
    boolean_parameter, default_inputs, default_parameters, integer_parameter, real_input, real_output, real_parameter,
};

/// Everything that defines a slave's present condition (the FMU state).
#[derive(Clone, Copy, Debug)]
pub struct SlaveState {
    pub params: Parameters,
    pub inputs: Inputs,
    /// `Some` once initialised.
    pub damper: Option<DamperState>,
}

/// A damper seen through its variables.
#[derive(Clone, Debug)]
pub struct Slave {
    params: Parameters,
    inputs: Inputs,
    damper: Option<Damper>,
}

impl Default for Slave {
    fn default() -> Self {
        Slave { params: default_parameters(), inputs: default_inputs(), damper: None }
    }
}

impl Slave {
    /// Sets a Real parameter or input, refusing non-finite values and values outside the XML's
    /// [min, max]. Whether the call is legal now is the caller's concern (FMI state machine).
    pub fn set_real(&mut self, v: RealVar, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err(format!("{} = {value} refused: not a finite number", v.name()));
        }
        let (lo, hi) = (v.min().unwrap_or(f64::NEG_INFINITY), v.max().unwrap_or(f64::INFINITY));
        if value < lo || value > hi {
            return Err(format!("{} = {value} refused: outside [{lo}, {hi}]", v.name()));
        }
        let field = match v.causality() {
            Causality::Parameter => real_parameter(&mut self.params, v),
            Causality::Input => real_input(&mut self.inputs, v),
            Causality::Output => None,
        };
        *field.ok_or_else(|| format!("{} is an output and cannot be set", v.name()))? = value;
        Ok(())
    }

    /// Sets an Integer parameter within the XML's [min, max].
    pub fn set_integer(&mut self, v: IntegerVar, value: i32) -> Result<(), String> {
        let (lo, hi) = (v.min().unwrap_or(i32::MIN), v.max().unwrap_or(i32::MAX));
        if value < lo || value > hi {
            return Err(format!("{} = {value} refused: outside [{lo}, {hi}]", v.name()));
        }
        *integer_parameter(&mut self.params, v).ok_or_else(|| format!("{} cannot be set", v.name()))? = value;
        Ok(())
    }

    /// Sets a Boolean parameter.
    pub fn set_boolean(&mut self, v: BooleanVar, value: bool) -> Result<(), String> {
        *boolean_parameter(&mut self.params, v).ok_or_else(|| format!("{} cannot be set", v.name()))? = value;
        Ok(())
    }

    /// Value of a Real variable. Outputs before initialisation are those of the damper at rest
    /// with the present parameters (initial values of the "calculated" outputs).
    pub fn get_real(&self, v: RealVar) -> Result<f64, String> {
        let mut params = self.params;
        let mut inputs = self.inputs;
        if let Some(x) = real_parameter(&mut params, v).or(real_input(&mut inputs, v)) {
            return Ok(*x);
        }
        let outputs = self.outputs()?;
        Ok(real_output(&outputs, v).expect("every output is mapped (tested)"))
    }

    /// Value of an Integer variable.
    pub fn get_integer(&self, v: IntegerVar) -> i32 {
        let mut params = self.params;
        *integer_parameter(&mut params, v).expect("every Integer is a parameter")
    }

    /// Value of a Boolean variable.
    pub fn get_boolean(&self, v: BooleanVar) -> bool {
        let mut params = self.params;
        *boolean_parameter(&mut params, v).expect("every Boolean is a parameter")
    }

    fn outputs(&self) -> Result<Outputs, String> {
        match &self.damper {
            Some(d) => Ok(d.outputs()),
            None => Ok(Damper::new(self.params, self.inputs, 0.0)?.outputs()),
        }
    }

    /// Checks the parameters and puts the damper at rest at `start_time` [s].
    pub fn initialize(&mut self, start_time: f64) -> Result<(), String> {
        self.damper = Some(Damper::new(self.params, self.inputs, start_time)?);
        Ok(())
    }

    pub fn is_initialized(&self) -> bool {
        self.damper.is_some()
    }

    /// Time of the damper's state [s] (None before initialisation).
    pub fn time(&self) -> Option<f64> {
        self.damper.as_ref().map(|d| d.state.time)
    }

    /// Sets the damper's clock to the master's communication point `t` [s] (equal to within
    /// rounding), so the master's time grid, not the sum of step sizes, is the reference.
    pub fn align_time(&mut self, t: f64) {
        if let Some(d) = self.damper.as_mut() {
            d.state.time = t;
        }
    }

    /// Advances by `h` [s] with the present inputs held. The damper must be initialised.
    pub fn do_step(&mut self, h: f64) -> Result<StepStats, SolverError> {
        let damper = self.damper.as_mut().expect("do_step after initialisation");
        damper.inputs = self.inputs;
        damper.do_step(h)
    }

    /// Back to the condition of a new slave.
    pub fn reset(&mut self) {
        *self = Slave::default();
    }

    pub fn state(&self) -> SlaveState {
        SlaveState { params: self.params, inputs: self.inputs, damper: self.damper.as_ref().map(|d| d.state) }
    }

    pub fn set_state(&mut self, s: &SlaveState) -> Result<(), String> {
        self.damper = match s.damper {
            Some(state) => Some(Damper::from_state(s.params, s.inputs, state)?),
            None => None,
        };
        self.params = s.params;
        self.inputs = s.inputs;
        Ok(())
    }
}

impl Visit for SlaveState {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        self.params.visit(v);
        self.inputs.visit(v);
        let mut initialized = self.damper.is_some() as i64;
        v.int(&mut initialized);
        let mut state = self.damper.unwrap_or_else(|| {
            let d = Damper::new(default_parameters(), default_inputs(), 0.0).expect("defaults are valid");
            d.state
        });
        state.visit(v);
        self.damper = (initialized != 0).then_some(state);
    }
}

impl SlaveState {
    /// Serialised bytes (see [`crate::snapshot`]).
    pub fn to_bytes(&self) -> Vec<u8> {
        snapshot::to_bytes(self)
    }

    /// Reads a serialised state and checks it is one this model could have made.
    pub fn from_bytes(bytes: &[u8]) -> Result<SlaveState, String> {
        let mut s = Slave::default().state();
        snapshot::from_bytes(bytes, &mut s)?;
        s.params.validate()?;
        if let Some(d) = &s.damper {
            let expected = s.params.derive().delay_samples;
            if !d.controller.delay.is_consistent(expected) || !d.y.iter().all(|x| x.is_finite()) {
                return Err("serialized FMU state rejected: inconsistent damper state".into());
            }
        }
        Ok(s)
    }
}
