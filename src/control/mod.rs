//! The digital cascade controller of the paper's Fig. 3, sampled every `T_sample`:
//! outer force loop → spool demand → inner spool-position loop (+ flow-force compensation) →
//! amplifier delay → coil command.
mod amplifier;
mod force_loop;
mod spool_loop;

pub use amplifier::DelayLine;
pub use force_loop::{clip_to_dissipative, ForceLoop, A_FEEDFORWARD_MIN};
pub use spool_loop::SpoolLoop;

use crate::physics::params::{ControlMode, Derived, Parameters};

/// What the controller measures at a sample.
#[derive(Clone, Copy, Debug)]
pub struct Measurements {
    /// Load-cell force (N).
    pub force: f64,
    /// Spool position from the displacement transducer (m).
    pub x_spool: f64,
    /// Damper velocity (m/s).
    pub v_damper: f64,
}

/// Demands from outside (the vehicle controller or the test rig).
#[derive(Clone, Copy, Debug, Default)]
pub struct Demands {
    /// Force demand (N) (control_mode 0).
    pub force: f64,
    /// Spool position demand (m) (control_mode 1).
    pub x_spool: f64,
}

/// Backward difference through a first-order low-pass: the derivative estimate of a sampled
/// signal. The first sample primes it (no derivative kick at start).
#[derive(Clone, Copy, Debug, Default)]
pub struct FilteredDerivative {
    previous: f64,
    /// Present estimate (unit of the signal per second).
    pub value: f64,
    primed: bool,
}

impl FilteredDerivative {
    /// Mutable access to every field, for FMU-state serialisation.
    pub fn fields_mut(&mut self) -> (&mut f64, &mut f64, &mut bool) {
        (&mut self.previous, &mut self.value, &mut self.primed)
    }

    /// Feeds sample `x`, taken `ts` (s) after the previous one, with filter time constant `tau` (s).
    pub fn update(&mut self, x: f64, ts: f64, tau: f64) -> f64 {
        if !self.primed {
            self.previous = x;
            self.primed = true;
        }
        let a = ts / (tau + ts);
        self.value = (1.0 - a) * self.value + a * (x - self.previous) / ts;
        self.previous = x;
        self.value
    }
}

/// State of the whole controller (plain data: part of the FMU state).
#[derive(Clone, Copy, Debug)]
pub struct Controller {
    pub force_loop: ForceLoop,
    pub spool_loop: SpoolLoop,
    pub delay: DelayLine,
    /// Spool demand of the last sample (m).
    pub x_spool_demand: f64,
    /// Force demand pursued at the last sample, after the semi-active clip (N).
    pub force_demand_clipped: f64,
    /// Load-cell reading at rest subtracted from every force measurement (0 unless the load cell
    /// is zeroed at initialisation) (N).
    pub force_tare: f64,
}

impl Controller {
    /// A controller at rest with the coil current `i0` (A) holding the spool at `x_spool0` (m).
    pub fn at_rest(d: &Derived, x_spool0: f64, i0: f64) -> Self {
        Controller {
            force_loop: ForceLoop::default(),
            spool_loop: SpoolLoop::at_rest(i0),
            delay: DelayLine::filled(d.delay_samples, i0),
            x_spool_demand: x_spool0,
            force_demand_clipped: 0.0,
            force_tare: 0.0,
        }
    }

    /// Makes this controller equal to `from`, as `*self = *from` would, copying only the delay
    /// line's live entries (see [`DelayLine::assign`]).
    pub fn assign(&mut self, from: &Controller) {
        let Controller { force_loop, spool_loop, delay, x_spool_demand, force_demand_clipped, force_tare } = from;
        self.delay.assign(delay);
        (self.force_loop, self.spool_loop) = (*force_loop, *spool_loop);
        (self.x_spool_demand, self.force_demand_clipped, self.force_tare) =
            (*x_spool_demand, *force_demand_clipped, *force_tare);
    }

    /// One controller sample: returns the (delayed) current command reaching the coil (A).
    /// The demand is relative to the tared load cell; the force loop works in the raw load-cell
    /// frame (demand + tare against the raw force), where its inverse valve law holds.
    pub fn sample(&mut self, p: &Parameters, d: &Derived, m: Measurements, demands: Demands) -> f64 {
        self.force_demand_clipped = clip_to_dissipative(demands.force, m.v_damper);
        let raw_demand = self.force_demand_clipped + self.force_tare;
        self.x_spool_demand = match d.control_mode {
            ControlMode::Force => self.force_loop.step(p, d, raw_demand, m),
            ControlMode::SpoolPosition => demands.x_spool,
        };
        let i_cmd = self.spool_loop.step(p, d, self.x_spool_demand, m);
        self.delay.push(i_cmd)
    }
}
