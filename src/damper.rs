//! The damper as a co-simulation unit, with no FMI types. The controller is sampled every
//! `T_sample` on the grid `t_start + k·T_sample`, whatever the communication steps are; between
//! samples the plant is integrated by a Rosenbrock method of order 3 (two evaluations a step) with
//! step-size control (embedded error estimate, steps ≤ `h_max`), so a smooth stretch costs one step
//! per sample and a check valve switching gets small steps. The step sequence depends only on the
//! sample grid and the inputs, so results are deterministic and do not depend on the communication
//! step when it is a multiple of `T_sample`. A communication step may be any positive length;
//! sample instants inside it split it. All state is plain `Copy` data.

use crate::control::{Controller, Demands, Measurements};
use crate::physics::iteration_matrix::PlantIterationMatrix;
use crate::physics::params::{Derived, ParameterError, Parameters};
use crate::physics::plant::{idx, rest_current, Linearisation, Plant, PlantOutputs, State, N_STATES};
use crate::solver::{cube_root_estimate, rosenbrock_step_from, SolverError, StepStart};
use crate::step_error::{StepError, GRID_RESOLUTION, MAX_SAMPLES_PER_STEP, MAX_STEPS_PER_SAMPLE, MIN_STEP};
use std::cell::Cell;

/// The states whose local error the step-size control bounds, each with its typical magnitude
/// (for the error weights rtol·(scale + |y|)): p_A, p_B (Pa), V_g (m³), x_s (m), x (m). The spool
/// velocity and the coil current are left out: they reach the force only through the spool
/// position (ẋ_s = v_s, and the current drives v_s), whose error estimate carries their errors
/// over the step, and an error in the current dies out with τ_coil (0.3 ms) within a sample. In
/// the norm (at 1 m/s and 1 A) they set 95 % of the steps at rtol 5e-5 (the current 87 %, after
/// every sample's new command), for no gain in the force: the same 1.5 N RMS force error
/// against a converged run now costs a third fewer instructions (`cargo bench --bench realtime`,
/// docs/performance.md).
const ERROR_CONTROLLED: [(usize, f64); 5] =
    [(idx::P_A, 1e6), (idx::P_B, 1e6), (idx::V_GAS, 1e-4), (idx::X_SPOOL, 1e-3), (idx::X_DAMPER, 1e-3)];

/// Inputs from the master, held over a communication step (the velocity along a ramp of slope
/// `a_damper`): the struct generated from `modelDescription.xml`'s inputs, a field each.
pub use crate::model_description::Inputs;

/// The slopes of the two demands over a step (N/s, m/s), as `a_damper` is the velocity's: a
/// master's input derivatives (fmi2SetRealInputDerivatives); 0 holds them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DemandRates {
    /// d`F_demand`/dt (N/s).
    pub f_demand: f64,
    /// d`x_spool_demand`/dt (m/s).
    pub x_spool_demand: f64,
}

/// The start value of the input `T_oil` (K).
pub const T_OIL_START: f64 = Inputs::START.t_oil;

impl Inputs {
    /// The damper velocity (m/s) `elapsed` (s) along its ramp.
    pub fn velocity_at(&self, elapsed: f64) -> f64 {
        self.v_damper + self.a_damper * elapsed
    }

    /// The inputs `elapsed` (s) along their ramps, the demands' slopes `rates`.
    pub fn moved(&self, rates: &DemandRates, elapsed: f64) -> Inputs {
        Inputs {
            v_damper: self.velocity_at(elapsed),
            f_demand: self.f_demand + rates.f_demand * elapsed,
            x_spool_demand: self.x_spool_demand + rates.x_spool_demand * elapsed,
            ..*self
        }
    }
}

/// The evolving state of a damper (everything but the parameters).
#[derive(Clone, Copy, Debug)]
pub struct DamperState {
    /// Plant states, see [`crate::physics::plant::idx`].
    pub y: State,
    pub controller: Controller,
    /// Amplifier output reaching the coil, held between samples (A).
    pub i_command: f64,
    /// Time of the state (s).
    pub time: f64,
    /// Start of the controller's sample grid (s).
    pub start_time: f64,
    /// Index of the next controller sample on that grid.
    pub next_sample: u64,
    /// Step size proposed by the step-size control for the next integration step (s).
    pub h_next: f64,
}

impl DamperState {
    /// Makes this state equal to `from`, as `*self = *from` would, copying only the controller's
    /// live delay-line entries: a step saves its starting state this way for the rollback.
    pub fn assign(&mut self, from: &DamperState) {
        let DamperState { y, controller, i_command, time, start_time, next_sample, h_next } = from;
        self.controller.assign(controller);
        (self.y, self.i_command, self.time, self.start_time) = (*y, *i_command, *time, *start_time);
        (self.next_sample, self.h_next) = (*next_sample, *h_next);
    }
}

/// The stroke left the cylinder's travel in a step: there are no end stops, so the results are not
/// physical until it is back.
#[derive(Clone, Copy, Debug)]
pub struct BeyondStroke {
    /// Stroke at the step's end (m).
    pub x_damper: f64,
    /// Half stroke (m).
    pub l_half_stroke: f64,
}

impl std::fmt::Display for BeyondStroke {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "x_damper = {} m is beyond the half stroke L_half_stroke = {} m; no end stops are modelled and the \
             chamber volumes are floored, so the results are not physical until the stroke is back within it",
            self.x_damper, self.l_half_stroke
        )
    }
}

/// Work done by one communication step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Controller samples taken.
    pub samples: u32,
    /// Rosenbrock steps taken.
    pub substeps: u32,
}

/// The outputs of the damper at its present state.
#[derive(Clone, Copy, Debug)]
pub struct Outputs {
    pub plant: PlantOutputs,
    /// Load-cell reading (N): the plant's force less the tare (see `tare_load_cell`).
    pub load_cell: f64,
    pub y: State,
    /// Spool demand of the last controller sample (m).
    pub x_spool_ref: f64,
    /// Force demand after the semi-active clip (N).
    pub force_demand_clipped: f64,
}

impl Outputs {
    /// Whether every output of the FMU is a finite number.
    pub fn all_finite(&self) -> bool {
        let p = &self.plant;
        [
            self.load_cell,
            p.p_reservoir,
            p.q_valve,
            p.flow_force,
            p.delta_mount,
            self.x_spool_ref,
            self.force_demand_clipped,
        ]
        .iter()
        .chain(self.y.iter())
        .all(|x| x.is_finite())
    }
}

/// A damper with validated parameters.
#[derive(Clone, Debug)]
pub struct Damper {
    params: Parameters,
    derived: Derived,
    pub state: DamperState,
    pub inputs: Inputs,
    /// The demands' slopes over the present step.
    pub rates: DemandRates,
    /// The plant's outputs at the present state, once a master has asked for one, with what they
    /// were computed from: a master reads several outputs after a step, and each would evaluate
    /// the plant again. Not computed by the step itself: a master that reads only the force
    /// (the load cell, [`Damper::load_cell`]) does not pay for an evaluation per step.
    last: Cell<Option<Evaluated>>,
    /// The state at the start of the present step, restored if the step fails.
    saved: DamperState,
    /// The plant evaluated and linearised at the start of the next Rosenbrock step. It is made
    /// here, in place, and `advance` tracks whether it is current: moving its 544 bytes cost a
    /// copy per sample.
    start: (PlantOutputs, Linearisation),
}

/// The plant evaluated at `y` with the velocity `v_damper` and the coil command `i_command`.
#[derive(Clone, Copy, Debug)]
struct Evaluated {
    y: State,
    v_damper: f64,
    t_oil: f64,
    i_command: f64,
    plant: PlantOutputs,
}

impl Damper {
    /// A damper at rest at `x_damper_start`, its spool at `x_spool_start`, at time `start_time` (s).
    pub fn new(params: Parameters, inputs: Inputs, start_time: f64) -> Result<Self, ParameterError> {
        params.validate()?;
        let derived = params.derive();
        let i0 = rest_current(&params, params.x_spool_start);
        let at_rest =
            Plant { p: &params, d: &derived, v_damper: 0.0, i_command: i0, t_oil: inputs.t_oil, a_damper: 0.0 };
        let y = at_rest.rest_state(params.x_damper_start, params.x_spool_start);
        let mut controller = Controller::at_rest(&derived, params.x_spool_start, i0);
        controller.x_spool_demand = params.x_spool_start;
        if params.tare_load_cell {
            controller.force_tare = at_rest.evaluate(&y).force;
        }
        let h_next = params.h_max.min(params.t_sample);
        let state = DamperState { y, controller, i_command: i0, time: start_time, start_time, next_sample: 0, h_next };
        Ok(Damper::assemble(params, derived, state, inputs))
    }

    /// Rebuilds a damper from a saved state (for FMU state restore).
    pub fn from_state(params: Parameters, inputs: Inputs, state: DamperState) -> Result<Self, ParameterError> {
        params.validate()?;
        Ok(Damper::assemble(params, params.derive(), state, inputs))
    }

    fn assemble(params: Parameters, derived: Derived, state: DamperState, inputs: Inputs) -> Self {
        let start = (PlantOutputs::default(), Linearisation::zeros());
        let rates = DemandRates::default();
        Damper { params, derived, state, inputs, rates, last: Cell::new(None), saved: state, start }
    }

    pub fn params(&self) -> &Parameters {
        &self.params
    }

    fn plant(&self) -> Plant<'_> {
        Plant {
            p: &self.params,
            d: &self.derived,
            v_damper: self.inputs.v_damper,
            i_command: self.state.i_command,
            t_oil: self.inputs.t_oil,
            a_damper: self.inputs.a_damper,
        }
    }

    /// Outputs at the present state.
    pub fn outputs(&self) -> Outputs {
        self.outputs_with(&self.inputs)
    }

    /// Outputs at the present state with `inputs` applied. The load-cell force (and the mount
    /// deflection) depend on the velocity directly where an effect adds a velocity-dependent
    /// force (seal and viscous friction): the model's one direct feedthrough.
    pub fn outputs_with(&self, inputs: &Inputs) -> Outputs {
        let (y, i_command) = (self.state.y, self.state.i_command);
        let plant = match self.last.get() {
            Some(e)
                if e.y == y
                    && e.v_damper.to_bits() == inputs.v_damper.to_bits()
                    && e.t_oil.to_bits() == inputs.t_oil.to_bits()
                    && e.i_command == i_command =>
            {
                e.plant
            }
            _ => {
                let plant = Plant { v_damper: inputs.v_damper, t_oil: inputs.t_oil, ..self.plant() }.evaluate(&y);
                self.last.set(Some(Evaluated { y, v_damper: inputs.v_damper, t_oil: inputs.t_oil, i_command, plant }));
                plant
            }
        };
        Outputs {
            plant,
            load_cell: plant.force - self.state.controller.force_tare,
            y,
            x_spool_ref: self.state.controller.x_spool_demand,
            force_demand_clipped: self.state.controller.force_demand_clipped,
        }
    }

    /// The load-cell reading (N) at the present state: [`Outputs::load_cell`] without the rest of
    /// the plant's evaluation.
    pub fn load_cell(&self) -> f64 {
        self.load_cell_with(&self.inputs)
    }

    /// [`Damper::load_cell`] with `inputs` applied (see [`Damper::outputs_with`]).
    pub fn load_cell_with(&self, inputs: &Inputs) -> f64 {
        Plant { v_damper: inputs.v_damper, t_oil: inputs.t_oil, ..self.plant() }.force(&self.state.y)
            - self.state.controller.force_tare
    }

    /// The stroke and the half stroke where the stroke is beyond the cylinder's travel
    /// (|x_damper| > `l_half_stroke`), which has no end stops.
    pub fn beyond_stroke(&self) -> Option<BeyondStroke> {
        let x_damper = self.state.y[idx::X_DAMPER];
        let l_half_stroke = self.params.l_half_stroke;
        (x_damper.abs() > l_half_stroke).then_some(BeyondStroke { x_damper, l_half_stroke })
    }

    /// Refuses a step of `h` (s) that spans more than [`MAX_SAMPLES_PER_STEP`] samples or whose
    /// times cannot resolve the sample grid; nothing is computed.
    pub fn check_step(&self, h: f64) -> Result<(), StepError> {
        let s = &self.state;
        let t_end = s.time + h;
        let samples = (t_end - s.start_time) / self.params.t_sample - s.next_sample as f64 + 1.0;
        if samples.is_nan() || samples > MAX_SAMPLES_PER_STEP as f64 {
            return Err(StepError::TooManySamples);
        }
        let scale = s.time.abs().max(t_end.abs()).max(s.start_time.abs());
        if scale.is_nan() || scale * f64::EPSILON > GRID_RESOLUTION * self.params.t_sample {
            return Err(StepError::TimeResolution);
        }
        Ok(())
    }

    /// Advances from the present time by `h` (s) > 0. On failure, including a state or a force
    /// that is not finite at the new time, the state is left as it was. (With a finite state
    /// and force every other output is finite: the gas volume is floored, the rest follows from
    /// the force and the pressures.)
    pub fn do_step(&mut self, h: f64) -> Result<StepStats, StepError> {
        self.saved.assign(&self.state);
        let inputs = self.inputs;
        let result = self.check_step(h).and_then(|()| self.advance(h)).and_then(|stats| {
            if self.state.y.iter().all(|x| x.is_finite()) && self.load_cell().is_finite() {
                Ok(stats)
            } else {
                Err(StepError::NonFiniteOutput)
            }
        });
        if result.is_err() {
            self.state.assign(&self.saved);
            self.inputs = inputs;
        }
        result
    }

    fn advance(&mut self, h: f64) -> Result<StepStats, StepError> {
        let ts = self.params.t_sample;
        let tol = 1e-6 * ts;
        let t_start = self.state.time;
        let t_end = t_start + h;
        let start = self.inputs;
        let mut t = t_start;
        let mut stats = StepStats::default();
        // whether `self.start` holds the plant linearised at the present state (by the controller
        // sample), for the next step
        let mut linearised = false;
        loop {
            let t_sample = self.state.start_time + self.state.next_sample as f64 * ts;
            if t_sample <= t + tol {
                // check_step bounds the samples; this bounds them whatever rounding does
                if stats.samples >= MAX_SAMPLES_PER_STEP {
                    return Err(StepError::TooManySamples);
                }
                self.sample_controller();
                linearised = true;
                stats.samples += 1;
                continue;
            }
            let t_next = if t_sample < t_end - tol { t_sample } else { t_end };
            // a whole sample interval is exactly T_sample, whatever the communication grid
            let span = if (t_next - t - ts).abs() <= tol { ts } else { t_next - t };
            stats.substeps += self.integrate(span, std::mem::take(&mut linearised))?;
            t = t_next;
            // the inputs at the new time: on their ramps from the step's start
            self.inputs = start.moved(&self.rates, t - t_start);
            if t >= t_end - tol {
                break;
            }
        }
        self.inputs = start.moved(&self.rates, h);
        self.state.time = t_end;
        Ok(stats)
    }

    /// The plant at the velocity `from` (s) into the present ramp.
    fn plant_at(&self, from: f64) -> Plant<'_> {
        Plant { v_damper: self.inputs.velocity_at(from), ..self.plant() }
    }

    /// Evaluates and linearises the plant at the present state, `from` (s) into the velocity's
    /// ramp, into `self.start`.
    fn linearise(&mut self, from: f64) {
        let plant = Plant {
            p: &self.params,
            d: &self.derived,
            v_damper: self.inputs.velocity_at(from),
            i_command: self.state.i_command,
            t_oil: self.inputs.t_oil,
            a_damper: self.inputs.a_damper,
        };
        self.start.0 = plant.linearise(&self.state.y, &mut self.start.1);
    }

    /// One Rosenbrock step of `step` (s) from the present state, `from` (s) into the velocity's ramp,
    /// from the plant linearised there (`self.start`).
    fn rosenbrock(&self, step: f64, from: f64) -> Result<(State, State), SolverError> {
        let (out, lin) = &self.start;
        let a = self.inputs.a_damper;
        // ∂f/∂t = ∂f/∂v · a
        let f_t = (a != 0.0).then(|| lin.df_dv * a);
        let start = StepStart { f0: &out.dydt, jacobian: &lin.jacobian, f_t };
        let at_end = self.plant_at(from + step);
        rosenbrock_step_from::<N_STATES, PlantIterationMatrix>(&start, |y| at_end.evaluate(y).dydt, &self.state.y, step)
    }

    /// Integrates over `span` (s) with step-size control; returns the number of steps taken.
    /// `linearised`: whether `self.start` holds the plant linearised at the present state.
    fn integrate(&mut self, span: f64, mut linearised: bool) -> Result<u32, StepError> {
        let (mut done, mut steps, mut attempts) = (0.0, 0u32, 0u32);
        let mut h = self.state.h_next.min(self.params.h_max);
        while done < span {
            if attempts >= MAX_STEPS_PER_SAMPLE {
                return Err(StepError::TooManySteps);
            }
            let last = h >= (span - done) * (1.0 - 1e-9);
            let step = if last { span - done } else { h };
            // a rejected step is tried again from the same state: its linearisation stands
            if !linearised {
                self.linearise(done);
                linearised = true;
            }
            let (y, error) = self.rosenbrock(step, done)?;
            let p = &self.params;
            let norm = (ERROR_CONTROLLED
                .iter()
                .map(|&(i, scale)| {
                    let r = error[i] / (p.rtol * (scale + self.state.y[i].abs().max(y[i].abs())));
                    r * r
                })
                .sum::<f64>()
                / ERROR_CONTROLLED.len() as f64)
                .sqrt();
            // 0.9/∛norm ≥ 4 below 0.0113: the growth limit, without the cube root
            let factor = if norm >= 0.0113 { (0.9 / cube_root_estimate(norm)).clamp(0.2, 4.0) } else { 4.0 };
            attempts += 1;
            if norm <= 1.0 {
                if !last && step < MIN_STEP {
                    return Err(SolverError::StepSizeTooSmall.into());
                }
                self.state.y = y;
                linearised = false;
                done = if last { span } else { done + step };
                steps += 1;
                // a short last step to land on the sample does not shrink the next proposal
                if !last || factor < 1.0 {
                    h = (step * factor).min(p.h_max);
                }
            } else {
                h = step * factor;
                if h < MIN_STEP {
                    return Err(SolverError::StepSizeTooSmall.into());
                }
            }
        }
        self.state.h_next = h;
        Ok(steps)
    }

    /// Samples the controller at the present state (the load cell's force from the pressures, as
    /// [`Plant::force`]); leaves in `self.start` the plant linearised there with the new coil
    /// command, for the integration step that follows.
    fn sample_controller(&mut self) {
        let m = Measurements {
            force: self.plant().force(&self.state.y),
            x_spool: self.state.y[idx::X_SPOOL],
            v_damper: self.inputs.v_damper,
        };
        let demands = Demands { force: self.inputs.f_demand, x_spool: self.inputs.x_spool_demand };
        self.state.i_command = self.state.controller.sample(&self.params, &self.derived, m, demands);
        self.state.next_sample += 1;
        // after the sample, not before it: the controller's chain of dependent operations (the
        // inverse valve law) then overlaps with the linearisation's work instead of waiting for it
        self.linearise(0.0);
    }
}
