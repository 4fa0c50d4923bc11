//! The truck's FMU state for the byte format of `fmi_slave::snapshot`: every field of the
//! parameters and inputs (their generated layouts) and states is visited in a fixed order
//! (destructuring makes a new field of the others a compile error until it is visited here).

use crate::slave::{visit_history, Slave};
use fmi_slave::snapshot::{boolean, Visit, Visitor};

/// Tag of a serialised quarter-truck state.
pub const MAGIC: &[u8; 8] = b"QTRUCK02";

impl Visit for Slave {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        // the road is made again from the parameters (truck_slave's set_state)
        let Slave { params, inputs, y, past, time, initialized, road: _ } = self;
        params.visit(v);
        inputs.visit(v);
        for x in y.iter_mut() {
            v.real(x);
        }
        visit_history(past, v);
        v.real(time);
        boolean(v, initialized);
    }
}
