//! The binding between `modelDescription.xml` and the truck. Every match below is exhaustive over
//! the enums that `build.rs` generates from the XML, so a variable added to the XML, or removed
//! from it, does not compile until it is mapped here.

use crate::model_description::{IntegerVar, RealVar};
use crate::truck::{Evaluation, Inputs, Params, State};

impl Default for Params {
    fn default() -> Self {
        let mut p = Params::default_zero();
        for v in RealVar::ALL {
            if let (Some(field), Some(start)) = (real_parameter(&mut p, v), v.start()) {
                *field = start;
            }
        }
        p.damper_mode = IntegerVar::DamperMode.start().expect("start value");
        p
    }
}

/// The field of a Real parameter (None for inputs and outputs).
pub fn real_parameter(p: &mut Params, v: RealVar) -> Option<&mut f64> {
    use RealVar::*;
    Some(match v {
        ZRoad | VRoad | FDamper | VDamper | FDemand | XDamper | VBody | ABody | AAxle | ZBody | ZAxle | FTyre
        | FSuspension => return None,
        MBody => &mut p.m_body,
        MAxle => &mut p.m_axle,
        KSusp => &mut p.k_susp,
        KTyre => &mut p.k_tyre,
        CSusp => &mut p.c_susp,
        CTyre => &mut p.c_tyre,
        CPassive => &mut p.c_passive,
        Cm => &mut p.cm,
        Alpha => &mut p.alpha,
        Gravity => &mut p.gravity,
        HMax => &mut p.h_max,
        ZBodyStart => &mut p.z_body_start,
        ZAxleStart => &mut p.z_axle_start,
        VBodyStart => &mut p.v_body_start,
        VAxleStart => &mut p.v_axle_start,
    })
}

pub fn real_input(u: &mut Inputs, v: RealVar) -> Option<&mut f64> {
    match v {
        RealVar::ZRoad => Some(&mut u.z_road),
        RealVar::VRoad => Some(&mut u.v_road),
        RealVar::FDamper => Some(&mut u.f_damper),
        _ => None,
    }
}

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
    fn default_zero() -> Self {
        Params {
            damper_mode: 0,
            m_body: 0.0,
            m_axle: 0.0,
            k_susp: 0.0,
            k_tyre: 0.0,
            c_susp: 0.0,
            c_tyre: 0.0,
            c_passive: 0.0,
            cm: 0.0,
            alpha: 0.0,
            gravity: 0.0,
            h_max: 0.0,
            z_body_start: 0.0,
            z_axle_start: 0.0,
            v_body_start: 0.0,
            v_axle_start: 0.0,
        }
    }

    /// The state at initialisation, from the `*_start` parameters.
    pub fn start_state(&self) -> State {
        [self.z_body_start, self.v_body_start, self.z_axle_start, self.v_axle_start]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_real_variable_is_mapped_once() {
        let (mut p, mut u) = (Params::default(), Inputs::default());
        let y = p.start_state();
        let e = p.evaluate(&u, &y, 0.0);
        for v in RealVar::ALL {
            let n = real_parameter(&mut p, v).is_some() as u8
                + real_input(&mut u, v).is_some() as u8
                + real_output(&y, &e, v).is_some() as u8;
            assert_eq!(n, 1, "{}", v.name());
        }
        assert_eq!(Params::default().m_body, 4450.0);
    }
}
