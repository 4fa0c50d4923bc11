//! The truck's FMU state for the byte format of `fmi_slave::snapshot`: every field of the
//! parameters (their generated layout), inputs and states is visited in a fixed order
//! (destructuring makes a new field of the others a compile error until it is visited here).

use crate::slave::Slave;
use crate::tracking::DemandHistory;
use crate::truck::Inputs;
use fmi_slave::snapshot::{boolean, uint, Visit, Visitor};

/// Tag of a serialised quarter-truck state.
pub const MAGIC: &[u8; 8] = b"QTRUCK02";

impl Visit for Slave {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        // the road is made again from the parameters (truck_slave's set_state)
        let Slave { params, inputs, y, past, time, initialized, road: _ } = self;
        params.visit(v);
        let Inputs { z_road, v_road, f_damper } = inputs;
        for x in [z_road, v_road, f_damper].into_iter().chain(y.iter_mut()) {
            v.real(x);
        }
        let DemandHistory { time: past_time, demand, newest, len } = past;
        for x in past_time.iter_mut().chain(demand.iter_mut()) {
            v.real(x);
        }
        uint(v, newest);
        uint(v, len);
        v.real(time);
        boolean(v, initialized);
    }
}
