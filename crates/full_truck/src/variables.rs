//! The binding between `modelDescription.xml`'s outputs and the truck (the parameters and the inputs
//! are generated fields of `Params` and `Inputs`). A corner's variables have value references 100·(k + 1) + j, k
//! the corner (0 front left … 5 second drive axle right) and j the quantity ([`CornerQuantity`]),
//! so one table serves all six; the body's outputs are matched by name. The test checks that every
//! variable is mapped once and that each corner's names and value references agree.

use crate::body::{Evaluation, Params, State, CORNERS, DOF};
use crate::model_description::RealVar;

/// What a corner's variable is, by the last two digits of its value reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CornerQuantity {
    ZRoad,
    VRoad,
    FDamper,
    VDamper,
    FDemand,
    XDamper,
    VBody,
    ABody,
    FTyre,
    FSuspension,
}

impl CornerQuantity {
    /// The quantity and its name's suffix, by the last two digits of the value reference.
    pub const ALL: [(u32, CornerQuantity, &'static str); 10] = [
        (1, Self::ZRoad, "z_road"),
        (2, Self::VRoad, "v_road"),
        (3, Self::FDamper, "F_damper"),
        (10, Self::VDamper, "v_damper"),
        (11, Self::FDemand, "F_demand"),
        (12, Self::XDamper, "x_damper"),
        (13, Self::VBody, "v_body"),
        (14, Self::ABody, "a_body"),
        (18, Self::FTyre, "F_tyre"),
        (19, Self::FSuspension, "F_suspension"),
    ];
}

/// The names of the corners, in their order (the prefix of their variables).
pub const CORNER_NAMES: [&str; CORNERS] =
    ["front_left", "front_right", "drive1_left", "drive1_right", "drive2_left", "drive2_right"];

/// The corner and quantity of a corner's variable.
pub fn corner_of(v: RealVar) -> Option<(usize, CornerQuantity)> {
    let vr = v.vr();
    let k = (vr / 100).checked_sub(1)? as usize;
    let quantity = CornerQuantity::ALL.iter().find(|q| q.0 == vr % 100)?.1;
    (k < CORNERS).then_some((k, quantity))
}

/// Value of an output at state `y` with evaluation `e`.
pub fn real_output(p: &Params, y: &State, e: &Evaluation, v: RealVar) -> Option<f64> {
    use RealVar::*;
    let (q, rate, a) = (&y[..DOF], &y[DOF..2 * DOF], &e.dydt[DOF..2 * DOF]);
    Some(match v {
        ZBody => q[0],
        VBody => rate[0],
        ABody => a[0],
        Pitch => q[1],
        PitchRate => rate[1],
        APitch => a[1],
        Roll => q[2],
        RollRate => rate[2],
        ARoll => a[2],
        ASeat => Params::body_acceleration(a, p.x_cg - p.x_seat, p.y_seat),
        _ => corner_output(p, e, corner_of(v)?)?,
    })
}

/// A corner's output.
fn corner_output(p: &Params, e: &Evaluation, (k, quantity): (usize, CornerQuantity)) -> Option<f64> {
    let (d, f) = (e.at_damper[k], e.corners[k]);
    Some(match quantity {
        CornerQuantity::VDamper => d.v_rel(),
        CornerQuantity::FDemand => f.demand,
        CornerQuantity::XDamper => d.z_body - d.z_axle,
        CornerQuantity::VBody => d.v_body,
        CornerQuantity::ABody => {
            let arm = crate::body::side(k) * 0.5 * p.suspension_track;
            Params::body_acceleration(&e.dydt[DOF..2 * DOF], p.axle(k / 2).x, arm)
        }
        CornerQuantity::FTyre => f.tyre,
        CornerQuantity::FSuspension => f.suspension,
        CornerQuantity::ZRoad | CornerQuantity::VRoad | CornerQuantity::FDamper => return None,
    })
}

impl Params {
    /// The state at initialisation, from the `*_start` parameters.
    pub fn start_state(&self) -> State {
        let mut y = [0.0; crate::body::STATES];
        y[..3].copy_from_slice(&[self.z_body_start, self.pitch_start, self.roll_start]);
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::At;
    use crate::model_description::Inputs;
    use suspension::tracking::DemandHistory;

    #[test]
    fn every_real_variable_is_mapped_once() {
        let (mut p, mut u) = (Params::default(), Inputs::default());
        let y = p.start_state();
        let past = [DemandHistory::default(); CORNERS];
        let e = p.evaluate(&u, &y, At { step_start: 0.0, since_step: 0.0, past: &past });
        let p0 = p;
        for v in RealVar::ALL {
            let n = p.real_mut(v).is_some() as u8
                + u.real_mut(v).is_some() as u8
                + real_output(&p0, &y, &e, v).is_some() as u8;
            assert_eq!(n, 1, "{}", v.name());
            if let Some((k, q)) = corner_of(v) {
                let suffix = CornerQuantity::ALL.iter().find(|x| x.1 == q).unwrap().2;
                assert_eq!(v.name(), format!("{}.{suffix}", CORNER_NAMES[k]));
            }
        }
        let corners = RealVar::ALL.iter().filter(|v| corner_of(**v).is_some()).count();
        assert_eq!(corners, CORNERS * CornerQuantity::ALL.len());
    }
}
