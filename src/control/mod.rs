//! The digital cascade controller of the paper's Fig. 3, sampled every `T_sample`:
//! outer force loop → spool demand → inner spool-position loop (+ flow-force compensation) →
//! amplifier delay → coil command.
mod amplifier;
mod force_controller;
mod spool_loop;

pub use amplifier::DelayLine;
pub use force_controller::{clip_to_dissipative, ForceController, A_FEEDFORWARD_MIN};
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

/// Anti-windup by clamping the integrator, for a loop whose output saturates: called when
/// `candidate` (the integral plus this sample's increment) would take the output past a bound,
/// with `at_bound`, the integral that puts the output exactly on that bound for this sample's
/// other terms. The integral moves towards the candidate only as far as the bound, and does not
/// move further out if it is beyond already. Freezing the integral while the output is clamped
/// (conditional integration) made the loop's state jump on a sub-newton difference in the
/// measured force, one integrator increment at a time, and the offset lasted 50–100 ms
/// (docs/physics.md §4); this law is continuous in the measurements, and the same as freezing
/// wherever the output stays inside its bounds.
pub fn integral_at_saturation(integral: f64, candidate: f64, at_bound: f64) -> f64 {
    // max/min rather than clamp: no panic on a NaN bound
    candidate.max(integral.min(at_bound)).min(integral.max(at_bound))
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
        self.value = (1.0 - a) * self.value + (a / ts) * (x - self.previous);
        self.previous = x;
        self.value
    }
}

/// State of the whole controller (plain data: part of the FMU state).
#[derive(Clone, Copy, Debug)]
pub struct Controller {
    pub force_controller: ForceController,
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
            force_controller: ForceController::default(),
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
        let Controller { force_controller, spool_loop, delay, x_spool_demand, force_demand_clipped, force_tare } = from;
        self.delay.assign(delay);
        (self.force_controller, self.spool_loop) = (*force_controller, *spool_loop);
        (self.x_spool_demand, self.force_demand_clipped, self.force_tare) =
            (*x_spool_demand, *force_demand_clipped, *force_tare);
    }

    /// One controller sample: returns the (delayed) current command reaching the coil (A).
    /// The demand is relative to the tared load cell; the force loop works in the raw load-cell
    /// frame (demand + tare against the raw force), where its inverse valve law holds.
    pub fn sample(&mut self, p: &Parameters, d: &Derived, m: Measurements, demands: Demands) -> f64 {
        if d.control_mode == ControlMode::ValveHeld {
            // no controller: the coil keeps the current it started with (the spool is held)
            return self.spool_loop.integral;
        }
        self.force_demand_clipped = clip_to_dissipative(demands.force, m.v_damper);
        let raw_demand = self.force_demand_clipped + self.force_tare;
        self.x_spool_demand = match d.control_mode {
            ControlMode::Force => self.force_controller.step(p, d, raw_demand, m),
            ControlMode::SpoolPosition | ControlMode::ValveHeld => demands.x_spool,
        };
        let i_cmd = self.spool_loop.step(p, d, self.x_spool_demand, m);
        self.delay.push(i_cmd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_integral_stops_on_the_bound() {
        // moving up past the bound 1.0 from 0.8: it stops on the bound
        assert_eq!(integral_at_saturation(0.8, 1.3, 1.0), 1.0);
        // beyond it already (the other terms moved): no further out, but back in freely
        assert_eq!(integral_at_saturation(1.2, 1.3, 1.0), 1.2);
        assert_eq!(integral_at_saturation(1.2, 1.1, 1.0), 1.1);
        // the same downwards
        assert_eq!(integral_at_saturation(-0.8, -1.3, -1.0), -1.0);
        assert_eq!(integral_at_saturation(-1.2, -1.3, -1.0), -1.2);
        assert_eq!(integral_at_saturation(-1.2, -1.1, -1.0), -1.1);
        // a NaN bound freezes it, without a panic
        assert_eq!(integral_at_saturation(0.8, 1.3, f64::NAN), 0.8);
    }

    /// One force-loop sample from the same state, swept over the measured force across the clip of
    /// the demanded area: the integral after it moves continuously with the force. (Freezing it
    /// while the demand is clipped made it jump by a whole increment, Ki·e·T, at the clip.)
    #[test]
    fn the_force_controller_integral_is_continuous_across_the_clip() {
        let p = Parameters::default();
        let d = p.derive();
        let (v, demand) = (0.3, 2e3);
        let after = |force: f64| {
            let mut force_controller = ForceController { integral: -1.0, ..ForceController::default() };
            let x = force_controller.step(&p, &d, demand, Measurements { force, x_spool: 1e-3, v_damper: v });
            (force_controller.integral, x)
        };
        let forces: Vec<f64> = (0..=20_000).map(|k| 4e3 * k as f64 / 20_000.0).collect();
        let samples: Vec<(f64, f64)> = forces.iter().map(|&f| after(f)).collect();
        // the sweep crosses the clip: the demand is clipped at one end and free at the other
        let clipped = samples.iter().filter(|s| s.1 >= d.x_demand_max * (1.0 - 1e-12)).count();
        assert!(clipped > 100 && clipped < samples.len() - 100, "{clipped} of {} clipped", samples.len());
        // where the clip begins, the increment a frozen integral would have jumped by
        let first = samples.iter().position(|s| s.1 >= d.x_demand_max * (1.0 - 1e-12)).unwrap();
        let error = (demand - forces[first]) / demand.abs().max(p.f_ref_min);
        let increment = (p.ki_f * error * p.t_sample).abs();
        // the largest change between neighbours, 0.2 N apart
        let largest = samples.windows(2).map(|w| (w[1].0 - w[0].0).abs()).fold(0.0, f64::max);
        assert!(
            largest < 0.05 * increment,
            "the integral moves {largest:e} between neighbours ({increment:e} a sample)"
        );
    }
}
