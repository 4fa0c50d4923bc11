//! The binding between `modelDescription.xml`'s outputs and the model (the parameters and the
//! inputs are generated fields of `Parameters` and `Inputs`). The match below is exhaustive over
//! the enum that `build.rs` generates from the XML, so an output added to the XML, or removed from
//! it, is not served until it is computed here (the tests check that every variable is mapped).

use crate::damper::{Damper, Inputs};
use crate::model_description::{Causality, RealVar};
use crate::physics::plant::idx;

/// The value of a Real output of `d` with `inputs` applied: from the state, from the load cell
/// alone ([`Damper::load_cell_with`]), or, for four of them, from the plant's evaluation, which
/// the damper keeps for the next read.
pub fn real_output(d: &Damper, inputs: &Inputs, v: RealVar) -> Option<f64> {
    use RealVar::*;
    let y = &d.state.y;
    // the four outputs of the plant's full evaluation (cached for the others' reads)
    let plant = || d.outputs_with(inputs).plant;
    Some(match v {
        FDamper => d.load_cell_with(inputs),
        XSpool => y[idx::X_SPOOL],
        ISol => y[idx::I_COIL],
        PExt => y[idx::P_A],
        PComp => y[idx::P_B],
        PReservoir => plant().p_reservoir,
        QValve => plant().q_valve,
        XSpoolRef => d.state.controller.x_spool_demand,
        XDamper => y[idx::X_DAMPER],
        FDemandClipped => d.state.controller.force_demand_clipped,
        FFlow => plant().flow_force,
        DeltaMount => plant().delta_mount,
        _ if v.causality() == Causality::Output => unreachable!("output {} is not mapped", v.name()),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::params::Parameters;

    #[test]
    fn every_variable_is_mapped_once() {
        let mut p = Parameters::default();
        let mut i = Inputs::default();
        for v in RealVar::ALL {
            let n = p.real_mut(v).is_some() as u8
                + i.real_mut(v).is_some() as u8
                + (v.causality() == Causality::Output) as u8;
            assert_eq!(n, 1, "{}", v.name());
            assert_eq!(p.real_mut(v).is_some(), v.causality() == Causality::Parameter);
            assert_eq!(i.real_mut(v).is_some(), v.causality() == Causality::Input);
        }
    }

    #[test]
    fn defaults_are_the_xml_start_values() {
        let p = Parameters::default();
        assert_eq!(p.air_fraction, 0.025);
        assert_eq!(p.tau_amp, 3e-3);
        assert_eq!(p.n_ports, 2);
        assert!(p.validate().is_ok());
    }
}
