//! The damper's FMU state for the byte format of `fmi_slave::snapshot`: every field of the
//! parameters and inputs (their generated layouts), the demands' rates and the damper state is
//! visited in a fixed order
//! (destructuring makes a new field of the others a compile error until it is visited here).

use crate::control::{Controller, DelayLine, FilteredDerivative, ForceController, SpoolLoop};
use crate::damper::{DamperState, DemandRates};
use crate::model_description::{Causality, IntegerVar, RealVar};
use crate::slave::SlaveState;
use fmi_slave::snapshot::{all_finite, boolean, uint, uint64, Visit, Visitor};
use fmi_slave::{check_integer, check_real, Refusal};

/// Tag of a serialised damper state.
pub const MAGIC: &[u8; 8] = b"SADAMPER";

impl Visit for DemandRates {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let DemandRates { f_demand, x_spool_demand } = self;
        v.real(f_demand);
        v.real(x_spool_demand);
    }
}

impl Visit for FilteredDerivative {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let (previous, value, primed) = self.fields_mut();
        v.real(previous);
        v.real(value);
        boolean(v, primed);
    }
}

impl Visit for DelayLine {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let (buffer, len, head) = self.fields_mut();
        for x in buffer.iter_mut() {
            v.real(x);
        }
        uint(v, len);
        uint(v, head);
    }
}

impl Visit for DamperState {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let DamperState { y, controller, i_command, time, start_time, next_sample, h_next } = self;
        for x in y.iter_mut() {
            v.real(x);
        }
        let Controller { force_controller, spool_loop, delay, x_spool_demand, force_demand_clipped, force_tare } =
            controller;
        let ForceController { integral, error_rate } = force_controller;
        v.real(integral);
        error_rate.visit(v);
        let SpoolLoop { integral, velocity } = spool_loop;
        v.real(integral);
        velocity.visit(v);
        delay.visit(v);
        for x in [x_spool_demand, force_demand_clipped, force_tare, i_command, time, start_time, h_next] {
            v.real(x);
        }
        uint64(v, next_sample);
    }
}

/// Checks that a restored state is one this FMU could have made: every number finite, every
/// parameter in its XML range, and once initialised, parameters that pass initialisation's checks,
/// the delay line, step-size proposal and sample grid consistent with them and with the time.
/// Inputs are only required finite: the velocity moves along its ramp beyond its range's reach.
pub fn check_restored(s: &SlaveState) -> Result<(), Refusal> {
    if !all_finite(s) {
        return Err(Refusal::StateNotFinite("a number"));
    }
    let p = &s.params;
    for v in RealVar::ALL.into_iter().filter(|v| v.causality() == Causality::Parameter) {
        check_real(v.name(), p.real(v).expect("a parameter"), v.min(), v.max())?;
    }
    for v in IntegerVar::ALL {
        check_integer(v.name(), p.integer(v).expect("a parameter"), v.min(), v.max())?;
    }
    let Some(d) = &s.damper else { return Ok(()) };
    s.params.validate().map_err(Refusal::model)?;
    let ts = s.params.t_sample;
    let next_sample = d.start_time + d.next_sample as f64 * ts;
    let checks = [
        (d.controller.delay.is_consistent(s.params.derive().delay_samples), "the amplifier delay line"),
        (d.h_next > 0.0 && d.h_next <= s.params.h_max, "the step-size proposal h_next (0 < h_next <= h_max)"),
        (d.next_sample < 1 << 53 && (next_sample - d.time - 0.5 * ts).abs() <= ts, "the sample grid and the time"),
    ];
    match checks.iter().find(|(ok, _)| !ok) {
        Some((_, what)) => Err(Refusal::Inconsistent(what)),
        None => Ok(()),
    }
}
