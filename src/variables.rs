//! The binding between `modelDescription.xml` and the model. Every match below is exhaustive over
//! the enums that `build.rs` generates from the XML, so a variable added to the XML, or removed
//! from it, does not compile until it is mapped here.

use crate::damper::{Damper, Inputs};
use crate::model_description::{BooleanVar, Causality, IntegerVar, RealVar};
use crate::physics::params::Parameters;
use crate::physics::plant::idx;

/// The parameters with the start values of `modelDescription.xml`.
pub fn default_parameters() -> Parameters {
    let mut p = Parameters::default();
    for v in RealVar::ALL {
        if let (Some(field), Some(start)) = (real_parameter(&mut p, v), v.start()) {
            *field = start;
        }
    }
    for v in IntegerVar::ALL {
        if let (Some(field), Some(start)) = (integer_parameter(&mut p, v), v.start()) {
            *field = start;
        }
    }
    for v in BooleanVar::ALL {
        if let (Some(field), Some(start)) = (boolean_parameter(&mut p, v), v.start()) {
            *field = start;
        }
    }
    p
}

/// The inputs with the start values of `modelDescription.xml`.
pub fn default_inputs() -> Inputs {
    let mut inputs = Inputs::default();
    for v in RealVar::ALL {
        if let (Some(field), Some(start)) = (real_input(&mut inputs, v), v.start()) {
            *field = start;
        }
    }
    inputs
}

/// The field of a Real parameter (None for inputs and outputs).
pub fn real_parameter(p: &mut Parameters, v: RealVar) -> Option<&mut f64> {
    use RealVar::*;
    Some(match v {
        VDamper | ADamper | FDemand | XSpoolDemand | FDamper | XSpool | ISol | PExt | PComp | PReservoir | QValve
        | XSpoolRef | XDamper | FDemandClipped | FFlow | DeltaMount => return None,
        Rho => &mut p.rho,
        BetaOil => &mut p.beta_oil,
        AirFraction => &mut p.air_fraction,
        NPolytropic => &mut p.n_polytropic,
        PTransition => &mut p.p_transition,
        DPiston => &mut p.d_piston,
        DRod => &mut p.d_rod,
        LHalfStroke => &mut p.l_half_stroke,
        LDead => &mut p.l_dead,
        VHose => &mut p.v_hose,
        PReservoir0 => &mut p.p_reservoir0,
        VGas0 => &mut p.v_gas0,
        ACvMax => &mut p.a_cv_max,
        CdCv => &mut p.cd_cv,
        PCvCrack => &mut p.p_cv_crack,
        PCvFull => &mut p.p_cv_full,
        ACvLeak => &mut p.a_cv_leak,
        PRelief => &mut p.p_relief,
        DpRelief => &mut p.dp_relief,
        ARelief => &mut p.a_relief,
        RPort => &mut p.r_port,
        XLap => &mut p.x_lap,
        AValveLeak => &mut p.a_valve_leak,
        CdValve => &mut p.cd_valve,
        CvValve => &mut p.cv_valve,
        ThetaJet => &mut p.theta_jet,
        MSpool => &mut p.m_spool,
        KSpool => &mut p.k_spool,
        CSpool => &mut p.c_spool,
        XSpoolMin => &mut p.x_spool_min,
        XSpoolMax => &mut p.x_spool_max,
        KStop => &mut p.k_stop,
        CStop => &mut p.c_stop,
        KSol => &mut p.k_sol,
        KappaSol => &mut p.kappa_sol,
        IMax => &mut p.i_max,
        TauAmp => &mut p.tau_amp,
        TauCoil => &mut p.tau_coil,
        K1Mount => &mut p.k1_mount,
        K3Mount => &mut p.k3_mount,
        FCoulomb => &mut p.f_coulomb,
        VFriction => &mut p.v_friction,
        GLeak => &mut p.g_leak,
        CViscous => &mut p.c_viscous,
        TSample => &mut p.t_sample,
        KpX => &mut p.kp_x,
        KiX => &mut p.ki_x,
        KdX => &mut p.kd_x,
        TauDx => &mut p.tau_dx,
        DpFcNominal => &mut p.dp_fc_nominal,
        CvCompensation => &mut p.cv_compensation,
        KpF => &mut p.kp_f,
        KiF => &mut p.ki_f,
        KdF => &mut p.kd_f,
        TauDF => &mut p.tau_df,
        FRefMin => &mut p.f_ref_min,
        KpFPid => &mut p.kp_f_pid,
        KiFPid => &mut p.ki_f_pid,
        KdFPid => &mut p.kd_f_pid,
        XSpoolBias => &mut p.x_spool_bias,
        HMax => &mut p.h_max,
        Rtol => &mut p.rtol,
        XDamperStart => &mut p.x_damper_start,
        XSpoolStart => &mut p.x_spool_start,
    })
}

/// The field of an Integer parameter.
pub fn integer_parameter(p: &mut Parameters, v: IntegerVar) -> Option<&mut i32> {
    Some(match v {
        IntegerVar::ControlMode => &mut p.control_mode,
        IntegerVar::ForceController => &mut p.force_controller,
        IntegerVar::FcMode => &mut p.fc_mode,
        IntegerVar::NPorts => &mut p.n_ports,
    })
}

/// The field of a Boolean parameter.
pub fn boolean_parameter(p: &mut Parameters, v: BooleanVar) -> Option<&mut bool> {
    Some(match v {
        BooleanVar::TareLoadCell => &mut p.tare_load_cell,
        BooleanVar::EffectCompressibility => &mut p.effect_compressibility,
        BooleanVar::EffectMountCompliance => &mut p.effect_mount_compliance,
        BooleanVar::EffectAmplifierDelay => &mut p.effect_amplifier_delay,
        BooleanVar::EffectFlowForces => &mut p.effect_flow_forces,
        BooleanVar::EffectSealFriction => &mut p.effect_seal_friction,
        BooleanVar::EffectPistonLeakage => &mut p.effect_piston_leakage,
        BooleanVar::EffectCheckValveCracking => &mut p.effect_check_valve_cracking,
        BooleanVar::EffectViscousFriction => &mut p.effect_viscous_friction,
    })
}

/// The field of a Real input.
pub fn real_input(inputs: &mut Inputs, v: RealVar) -> Option<&mut f64> {
    match v {
        RealVar::VDamper => Some(&mut inputs.v_damper),
        RealVar::ADamper => Some(&mut inputs.a_damper),
        RealVar::FDemand => Some(&mut inputs.force_demand),
        RealVar::XSpoolDemand => Some(&mut inputs.x_spool_demand),
        _ if v.causality() == Causality::Input => unreachable!("input {} is not mapped", v.name()),
        _ => None,
    }
}

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

    #[test]
    fn every_variable_is_mapped_once() {
        let mut p = Parameters::default();
        let mut i = Inputs::default();
        for v in RealVar::ALL {
            let n = real_parameter(&mut p, v).is_some() as u8
                + real_input(&mut i, v).is_some() as u8
                + (v.causality() == Causality::Output) as u8;
            assert_eq!(n, 1, "{}", v.name());
            assert_eq!(real_parameter(&mut p, v).is_some(), v.causality() == Causality::Parameter);
        }
    }

    #[test]
    fn defaults_are_the_xml_start_values() {
        let p = default_parameters();
        assert_eq!(p.air_fraction, 0.025);
        assert_eq!(p.tau_amp, 3e-3);
        assert_eq!(p.n_ports, 2);
        assert!(p.validate().is_ok());
    }
}
