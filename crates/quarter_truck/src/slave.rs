//! The quarter truck seen through its variables, without FMI types: the mapping of
//! `modelDescription.xml`'s variables (exhaustive matches over the generated enums), range checks,
//! stepping and the FMU state.

use crate::model_description::{BooleanVar, Causality, IntegerVar, RealVar, GUID};
use crate::truck::{Evaluation, Inputs, Params, State};
use fmi2_slave::snapshot::{self, int32, Visit, Visitor};
use fmi2_slave::{check_integer, check_real, Model, VarInfo};

const MAGIC: &[u8; 8] = b"QTRUCK01";

/// The FMU state: parameters, inputs, and once initialised the states and time.
#[derive(Clone, Copy, Debug, Default)]
pub struct Slave {
    params: Params,
    inputs: Inputs,
    y: State,
    time: f64,
    initialized: bool,
}

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
fn real_parameter(p: &mut Params, v: RealVar) -> Option<&mut f64> {
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

fn real_input(u: &mut Inputs, v: RealVar) -> Option<&mut f64> {
    match v {
        RealVar::ZRoad => Some(&mut u.z_road),
        RealVar::VRoad => Some(&mut u.v_road),
        RealVar::FDamper => Some(&mut u.f_damper),
        _ => None,
    }
}

/// Value of an output at state `y` with evaluation `e`.
fn real_output(y: &State, e: &Evaluation, v: RealVar) -> Option<f64> {
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

fn unknown(vr: u32) -> String {
    format!("unknown value reference {vr}")
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

    fn start_state(&self) -> State {
        [self.z_body_start, self.v_body_start, self.z_axle_start, self.v_axle_start]
    }
}

impl Slave {
    /// State and evaluation for the outputs: the present state, or the start state before
    /// initialisation. The road is taken at the end of the last step (z_road + v_road·h is not
    /// stored: outputs use the held inputs).
    fn evaluation(&self) -> (State, Evaluation) {
        let y = if self.initialized { self.y } else { self.params.start_state() };
        (y, self.params.evaluate(&self.inputs, &y, 0.0))
    }
}

impl Model for Slave {
    const GUID: &'static str = GUID;
    type State = Slave;
    type StepError = &'static str;

    fn real_info(vr: u32) -> Option<VarInfo> {
        RealVar::from_vr(vr).map(RealVar::info)
    }

    fn integer_info(vr: u32) -> Option<VarInfo> {
        IntegerVar::from_vr(vr).map(IntegerVar::info)
    }

    fn boolean_info(vr: u32) -> Option<VarInfo> {
        BooleanVar::from_vr(vr).map(BooleanVar::info)
    }

    fn get_real(&self, vr: u32) -> Result<f64, String> {
        let v = RealVar::from_vr(vr).ok_or_else(|| unknown(vr))?;
        let (mut p, mut u) = (self.params, self.inputs);
        if let Some(x) = real_parameter(&mut p, v).or(real_input(&mut u, v)) {
            return Ok(*x);
        }
        let (y, e) = self.evaluation();
        real_output(&y, &e, v).ok_or_else(|| unknown(vr))
    }

    fn get_integer(&self, vr: u32) -> Result<i32, String> {
        match IntegerVar::from_vr(vr).ok_or_else(|| unknown(vr))? {
            IntegerVar::DamperMode => Ok(self.params.damper_mode),
        }
    }

    fn get_boolean(&self, vr: u32) -> Result<bool, String> {
        Err(unknown(vr))
    }

    fn set_real(&mut self, vr: u32, value: f64) -> Result<(), String> {
        let v = RealVar::from_vr(vr).ok_or_else(|| unknown(vr))?;
        check_real(v.name(), value, v.min(), v.max())?;
        let field = match v.causality() {
            Causality::Parameter => real_parameter(&mut self.params, v),
            Causality::Input => real_input(&mut self.inputs, v),
            Causality::Output => None,
        };
        *field.ok_or_else(|| format!("{} is an output and cannot be set", v.name()))? = value;
        Ok(())
    }

    fn set_integer(&mut self, vr: u32, value: i32) -> Result<(), String> {
        let v = IntegerVar::from_vr(vr).ok_or_else(|| unknown(vr))?;
        check_integer(v.name(), value, v.min(), v.max())?;
        match v {
            IntegerVar::DamperMode => self.params.damper_mode = value,
        }
        Ok(())
    }

    fn set_boolean(&mut self, vr: u32, _value: bool) -> Result<(), String> {
        Err(unknown(vr))
    }

    fn initialize(&mut self, start_time: f64) -> Result<(), String> {
        self.y = self.params.start_state();
        self.time = start_time;
        self.initialized = true;
        Ok(())
    }

    fn time(&self) -> Option<f64> {
        self.initialized.then_some(self.time)
    }

    fn align_time(&mut self, t: f64) {
        self.time = t;
    }

    fn do_step(&mut self, h: f64) -> Result<(), &'static str> {
        let mut y = self.y;
        self.params.advance(&self.inputs, &mut y, h);
        if !y.iter().all(|x| x.is_finite()) {
            return Err("non-finite state");
        }
        self.y = y;
        // the road input is extrapolated over the step; hold its end value for the outputs
        self.inputs.z_road += self.inputs.v_road * h;
        self.time += h;
        Ok(())
    }

    fn state(&self) -> Slave {
        *self
    }

    fn set_state(&mut self, s: &Slave) -> Result<(), String> {
        *self = *s;
        Ok(())
    }

    fn state_time(s: &Slave) -> Option<f64> {
        s.time()
    }

    fn serialize(s: &Slave) -> Vec<u8> {
        snapshot::to_bytes(MAGIC, GUID, s)
    }

    fn deserialize(bytes: &[u8]) -> Result<Slave, String> {
        let mut s = Slave::default();
        snapshot::from_bytes(MAGIC, GUID, bytes, &mut s)?;
        Ok(s)
    }
}

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
        fmi2_slave::snapshot::boolean(v, initialized);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_real_variable_is_mapped_once() {
        let (mut p, mut u) = (Params::default(), Inputs::default());
        let (y, e) = Slave::default().evaluation();
        for v in RealVar::ALL {
            let n = real_parameter(&mut p, v).is_some() as u8
                + real_input(&mut u, v).is_some() as u8
                + real_output(&y, &e, v).is_some() as u8;
            assert_eq!(n, 1, "{}", v.name());
        }
        assert_eq!(Params::default().m_body, 4450.0);
    }
}
