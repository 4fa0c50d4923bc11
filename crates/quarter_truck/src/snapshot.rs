//! The truck's FMU state for the byte format of `fmi2_slave::snapshot`: every field of the
//! parameters, inputs and states is visited in a fixed order (destructuring makes a new field a
//! compile error until it is visited here).

use crate::slave::Slave;
use crate::truck::{Inputs, Params};
use fmi2_slave::snapshot::{boolean, int32, Visit, Visitor};

/// Tag of a serialised quarter-truck state.
pub const MAGIC: &[u8; 8] = b"QTRUCK01";

impl Visit for Slave {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let Slave { params, inputs, y, time, initialized } = self;
        // every field named once: a field missing here is a compile error
        macro_rules! visit_params {
            (ints: [$($i:ident),*], reals: [$($r:ident),*]) => {{
                let Params { $($i,)* $($r,)* } = params;
                $(int32(v, $i);)*
                $(v.real($r);)*
            }};
        }
        visit_params!(
            ints: [damper_mode],
            reals: [
                m_body, m_axle, k_susp, k_tyre, c_susp, c_tyre, c_passive, cm, alpha, gravity, h_max, z_body_start,
                z_axle_start, v_body_start, v_axle_start
            ]
        );
        let Inputs { z_road, v_road, f_damper } = inputs;
        for x in [z_road, v_road, f_damper].into_iter().chain(y.iter_mut()) {
            v.real(x);
        }
        v.real(time);
        boolean(v, initialized);
    }
}
