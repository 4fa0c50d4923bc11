//! The co-simulation slave without FMI types, from the macro both trucks share
//! ([`truck_slave::truck_slave!`]: variable access by value reference through the generated enums
//! ([`crate::variables`]), range checks from the XML's min/max, initialisation, stepping and state
//! save/restore ([`crate::fmu_state`])), and what is the full truck's own: six road inputs and six
//! demands' pasts. `fmi_slave` adds the C boundary and the FMI state machines on top.

use crate::body::{At, Evaluation, Inputs, Params, State, CORNERS, MODE_TRACKING};
use crate::fmu_state::MAGIC;
use crate::limits::MAX_SUBSTEPS;
use crate::model_description::{BooleanVar, IntegerVar, RealVar, CAN_INTERPOLATE_INPUTS, GUID};
use crate::variables::real_output;
use fmi_slave::snapshot;
use fmi_slave::{check_integer, check_real, Model, Refusal, ToleranceNote};
use suspension::tracking::DemandHistory;

truck_slave::truck_slave!([DemandHistory; CORNERS], ());

impl Slave {
    fn output_at(&self, y: &State, e: &Evaluation, v: RealVar) -> Option<f64> {
        real_output(&self.params, y, e, v)
    }

    /// Whether every output is a finite number: the state's and the evaluation's numbers are.
    fn outputs_finite(&self) -> bool {
        let (y, e) = self.evaluation();
        let forces = e.corners.iter().flat_map(|c| [c.suspension, c.tyre, c.demand]);
        y.iter().chain(&e.dydt).copied().chain(forces).all(f64::is_finite)
    }

    fn pasts(&self) -> &[DemandHistory] {
        &self.past
    }

    /// The road inputs are extrapolated over the step; their end values are held for the outputs.
    fn hold_road_end(&mut self, h: f64) {
        for (z, v) in self.inputs.z_road.iter_mut().zip(self.inputs.v_road) {
            *z += v * h;
        }
    }

    fn road_finite(&self) -> bool {
        self.inputs.z_road.iter().all(|z| z.is_finite())
    }

    /// The full truck's road is always its inputs (a master feeds the six wheels' roads).
    fn start_road(&mut self, _fresh: bool) -> Result<(), Refusal> {
        Ok(())
    }

    fn road_covers(&self, _h: f64) -> bool {
        true
    }

    fn feed_road(&mut self, _h: f64) {}
}
