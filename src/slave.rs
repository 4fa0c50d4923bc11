//! The co-simulation slave without FMI types: variable access by value reference through the
//! generated enums, range checks from the XML's min/max, initialisation, stepping and state
//! save/restore. `fmi_slave` adds the C boundary and the FMI state machines on top.

use crate::damper::{BeyondStroke, Damper, DamperState, DemandRates, Inputs};
use crate::fmu_state::{check_restored, MAGIC};
use crate::model_description::{BooleanVar, IntegerVar, RealVar, CAN_INTERPOLATE_INPUTS, GUID};
use crate::physics::params::Parameters;
use crate::step_error::StepError;
use crate::variables::real_output;
use fmi_slave::snapshot::{self, Visit, Visitor};
use fmi_slave::{Model, Refusal, ToleranceNote};

/// Everything that defines a slave's present condition (the FMU state).
#[derive(Clone, Copy, Debug)]
pub struct SlaveState {
    pub params: Parameters,
    pub inputs: Inputs,
    pub rates: DemandRates,
    /// `Some` once initialised.
    pub damper: Option<DamperState>,
}

/// A damper seen through its variables.
#[derive(Clone, Debug)]
pub struct Slave {
    params: Parameters,
    inputs: Inputs,
    /// The demands' slopes a master sent (fmi2SetRealInputDerivatives), held until it sends others.
    rates: DemandRates,
    damper: Option<Damper>,
    /// Whether the master has set the parameter `rtol`: then the tolerance of
    /// `fmi2SetupExperiment` does not replace it, whichever call came first.
    rtol_set: bool,
}

impl Default for Slave {
    fn default() -> Self {
        Slave {
            params: Parameters::default(),
            inputs: Inputs::START,
            rates: DemandRates::default(),
            damper: None,
            rtol_set: false,
        }
    }
}

impl Slave {
    /// The value of output `v`; before initialisation, of the damper at rest with the present
    /// parameters.
    fn output(&self, v: RealVar) -> Result<f64, Refusal> {
        // with the inputs set last: the force feeds through from v_damper (friction effects)
        let value = |d: &Damper| real_output(d, &self.inputs, v).ok_or(Refusal::UnknownReference(v.vr()));
        match &self.damper {
            Some(d) => value(d),
            None => value(&Damper::new(self.params, self.inputs, 0.0).map_err(Refusal::model)?),
        }
    }

    /// The value of input `v`, if it is one.
    fn input(&self, v: RealVar) -> Option<f64> {
        self.inputs.real(v)
    }

    fn input_mut(&mut self, v: RealVar) -> Option<&mut f64> {
        self.inputs.real_mut(v)
    }

    /// A master that sets `rtol` keeps it: the tolerance of the experiment does not replace it,
    /// whichever call came first.
    fn real_set(&mut self, v: RealVar) {
        self.rtol_set |= v == RealVar::Rtol;
    }
}

impl Model for Slave {
    const GUID: &'static str = GUID;
    const CAN_INTERPOLATE_INPUTS: bool = CAN_INTERPOLATE_INPUTS;
    type State = SlaveState;
    type StepError = StepError;
    type StepWarning = BeyondStroke;

    fmi_slave::parameter_access!();

    // Outputs before initialisation are those of the damper at rest with the present parameters
    // (initial values of the "calculated" outputs).
    fmi_slave::real_access!();

    type Settable = (Parameters, Inputs, DemandRates, bool);

    fn settable(&self) -> Self::Settable {
        (self.params, self.inputs, self.rates, self.rtol_set)
    }

    fn restore_settable(&mut self, (params, inputs, rates, rtol_set): Self::Settable) {
        (self.params, self.inputs, self.rates, self.rtol_set) = (params, inputs, rates, rtol_set);
    }

    /// First derivatives of the inputs (the master's interpolation of a continuous signal): the
    /// velocity's is `a_damper`, the demands' move them along a ramp as `a_damper` moves the
    /// velocity. A master that sends higher orders gets an error, not a silent truncation.
    fn set_real_input_derivative(&mut self, vr: u32, order: i32, value: f64) -> Result<(), Refusal> {
        let v = RealVar::from_vr(vr).ok_or(Refusal::UnknownReference(vr))?;
        if order != 1 {
            return Err(Refusal::DerivativeOrder { name: v.name(), order });
        }
        if !value.is_finite() {
            return Err(Refusal::DerivativeNotFinite { name: v.name(), value });
        }
        let rate = match v {
            RealVar::VDamper => &mut self.inputs.a_damper,
            RealVar::FDemand => &mut self.rates.f_demand,
            RealVar::XSpoolDemand => &mut self.rates.x_spool_demand,
            _ => {
                return Err(Refusal::NoDerivative {
                    name: v.name(),
                    why: "a_damper is itself the velocity's derivative: leave it out of the interpolated inputs",
                })
            }
        };
        *rate = value;
        Ok(())
    }

    /// The master's tolerance becomes `rtol`, the relative tolerance of the step-size control (FMI
    /// 2.0 suggests that a slave with a variable-step integrator use it), unless the master set
    /// `rtol` itself. A positive tolerance outside rtol's range is moved to its nearer end, with a
    /// warning: refusing it would stop a simulation over a value with no effect on the result
    /// (rtol 0.1 and 0.5 both give one step per controller sample).
    fn use_tolerance(&mut self, tolerance: f64) -> Result<ToleranceNote, Refusal> {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(Refusal::Tolerance(tolerance));
        }
        if self.rtol_set {
            let note = format!("tolerance {tolerance:e} not used: the parameter rtol is set to {:e}", self.params.rtol);
            return Ok(ToleranceNote::Event(note));
        }
        let rtol = RealVar::Rtol;
        let (lo, hi) = (rtol.min().unwrap_or(0.0), rtol.max().unwrap_or(f64::INFINITY));
        self.params.rtol = tolerance.clamp(lo, hi);
        Ok(if self.params.rtol == tolerance {
            ToleranceNote::Event(format!("tolerance {tolerance:e} sets rtol, the internal step-size control's"))
        } else {
            ToleranceNote::Warning(format!(
                "tolerance {tolerance:e} is outside rtol's range [{lo:e}, {hi:e}]: rtol = {:e}",
                self.params.rtol
            ))
        })
    }

    fn initialize(&mut self, start_time: f64) -> Result<(), Refusal> {
        self.damper = Some(Damper::new(self.params, self.inputs, start_time).map_err(Refusal::model)?);
        Ok(())
    }

    fn time(&self) -> Option<f64> {
        self.damper.as_ref().map(|d| d.state.time)
    }

    fn align_time(&mut self, t: f64) {
        if let Some(d) = self.damper.as_mut() {
            d.state.time = t;
        }
    }

    fn check_step(&self, h: f64) -> Result<(), StepError> {
        self.damper.as_ref().expect("check_step after initialisation").check_step(h)
    }

    fn do_step(&mut self, h: f64) -> Result<Option<BeyondStroke>, StepError> {
        let damper = self.damper.as_mut().expect("do_step after initialisation");
        (damper.inputs, damper.rates) = (self.inputs, self.rates);
        let was_beyond = damper.beyond_stroke().is_some();
        damper.do_step(h)?;
        // the inputs moved along their ramps (a_damper, the input derivatives): they are the
        // values at the new time
        self.inputs = damper.inputs;
        // once per excursion: a master driving the damper through its end would drown in warnings
        Ok(damper.beyond_stroke().filter(|_| !was_beyond))
    }

    fn state(&self) -> SlaveState {
        SlaveState {
            params: self.params,
            inputs: self.inputs,
            rates: self.rates,
            damper: self.damper.as_ref().map(|d| d.state),
        }
    }

    fn set_state(&mut self, s: &SlaveState) -> Result<(), Refusal> {
        self.damper = match s.damper {
            Some(state) => Some(Damper::from_state(s.params, s.inputs, state).map_err(Refusal::model)?),
            None => None,
        };
        (self.params, self.inputs, self.rates) = (s.params, s.inputs, s.rates);
        Ok(())
    }

    fn state_time(s: &SlaveState) -> Option<f64> {
        s.damper.map(|d| d.time)
    }

    fn serialize(s: &SlaveState) -> Vec<u8> {
        snapshot::to_bytes(MAGIC, GUID, s)
    }

    /// Reads a serialised state and checks it is one this model could have made.
    fn deserialize(bytes: &[u8]) -> Result<SlaveState, Refusal> {
        let mut s = Slave::default().state();
        snapshot::from_bytes(MAGIC, GUID, bytes, &mut s)?;
        check_restored(&s).map_err(Refusal::restored)?;
        Ok(s)
    }
}

impl Visit for SlaveState {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        self.params.visit(v);
        self.inputs.visit(v);
        self.rates.visit(v);
        let mut initialized = self.damper.is_some() as i64;
        v.int(&mut initialized);
        let mut state = self.damper.unwrap_or_else(|| {
            Damper::new(Parameters::default(), Inputs::START, 0.0).expect("defaults are valid").state
        });
        state.visit(v);
        self.damper = (initialized != 0).then_some(state);
    }
}
