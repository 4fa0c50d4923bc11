//! The full truck's FMU state for the byte format of `fmi_slave::snapshot`: every field of the
//! parameters (their generated layout), inputs and states is visited in a fixed order
//! (destructuring makes a new field of the others a compile error until it is visited here).

use crate::body::Inputs;
use crate::slave::Slave;
use fmi_slave::snapshot::{boolean, uint, Visit, Visitor};
use suspension::tracking::DemandHistory;

/// Tag of a serialised full-truck state.
pub const MAGIC: &[u8; 8] = b"FTRUCK01";

impl Visit for Slave {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let Slave { params, inputs, y, past, time, initialized, road: () } = self;
        params.visit(v);
        let Inputs { z_road, v_road, f_damper } = inputs;
        for x in z_road.iter_mut().chain(v_road.iter_mut()).chain(f_damper.iter_mut()).chain(y.iter_mut()) {
            v.real(x);
        }
        for history in past.iter_mut() {
            let DemandHistory { time: past_time, demand, newest, len } = history;
            for x in past_time.iter_mut().chain(demand.iter_mut()) {
                v.real(x);
            }
            uint(v, newest);
            uint(v, len);
        }
        v.real(time);
        boolean(v, initialized);
    }
}
