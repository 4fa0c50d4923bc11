//! The co-simulation slave without FMI types, from the macro both trucks share
//! ([`truck_slave::truck_slave!`]: variable access by value reference through the generated enums
//! ([`crate::variables`]), range checks from the XML's min/max, initialisation, stepping and state
//! save/restore ([`crate::fmu_state`])), and what is the quarter truck's own: one road input (or its
//! own road, [`crate::road_source`]) and one demand's past. `fmi_slave` adds the C boundary and the FMI state machines on top.

use crate::fmu_state::MAGIC;
use crate::limits::MAX_SUBSTEPS;
use crate::model_description::{BooleanVar, IntegerVar, RealVar, CAN_INTERPOLATE_INPUTS, GUID};
use crate::road_source::RoadSource;
use crate::tracking::DemandHistory;
use crate::truck::{At, Evaluation, Inputs, Params, State, MODE_TRACKING};
use crate::variables::real_output;
use fmi_slave::snapshot;
use fmi_slave::{check_integer, check_real, Model, Refusal, ToleranceNote};

truck_slave::truck_slave!(DemandHistory, RoadSource);

impl Slave {
    fn output_at(&self, y: &State, e: &Evaluation, v: RealVar) -> Option<f64> {
        real_output(y, e, v)
    }

    /// Whether every output is a finite number.
    fn outputs_finite(&self) -> bool {
        let (y, e) = self.evaluation();
        RealVar::ALL.iter().filter_map(|&v| real_output(&y, &e, v)).all(f64::is_finite)
    }

    fn pasts(&self) -> &[DemandHistory] {
        std::slice::from_ref(&self.past)
    }

    /// The road input is extrapolated over the step; its end value is held for the outputs.
    fn hold_road_end(&mut self, h: f64) {
        self.inputs.z_road += self.inputs.v_road * h;
    }

    fn road_finite(&self) -> bool {
        self.inputs.z_road.is_finite()
    }
}
