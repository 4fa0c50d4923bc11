//! The binding between `modelDescription.xml`'s outputs and the truck (the parameters and the inputs
//! are generated fields of `Params` and `Inputs`). The match below is over the enum that `build.rs`
//! generates from the XML; the test checks that every variable is mapped once.

use crate::model_description::RealVar;
#[cfg(test)]
use crate::truck::At;
use crate::truck::{Evaluation, Params, State};

/// Value of an output at state `y` with evaluation `e`.
pub fn real_output(y: &State, e: &Evaluation, v: RealVar) -> Option<f64> {
    use RealVar::*;
    Some(match v {
        VDamper => y[1] - y[3],
        FDemand => e.f_demand,
        XDamper => y[0] - y[2],
        VBody => y[1],
        ABody => e.dydt[1],
        AAxle => e.dydt[3],
        ZBody => y[0],
        ZAxle => y[2],
        FTyre => e.f_tyre,
        FSuspension => e.f_suspension,
        _ => return None,
    })
}

impl Params {
    /// The state at initialisation, from the `*_start` parameters.
    pub fn start_state(&self) -> State {
        [self.z_body_start, self.v_body_start, self.z_axle_start, self.v_axle_start, 0.0, 0.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model_description::Inputs;

    #[test]
    fn every_real_variable_is_mapped_once() {
        let (mut p, mut u) = (Params::default(), Inputs::default());
        let y = p.start_state();
        let past = crate::tracking::DemandHistory::default();
        let e = p.evaluate(&u, &y, At { step_start: 0.0, since_step: 0.0, past: &past });
        for v in RealVar::ALL {
            let n =
                p.real_mut(v).is_some() as u8 + u.real_mut(v).is_some() as u8 + real_output(&y, &e, v).is_some() as u8;
            assert_eq!(n, 1, "{}", v.name());
        }
        assert_eq!(Params::default().m_body, 4450.0);
    }
}
