//! FMU state as bytes: every field of the parameters, inputs and damper state is visited in a fixed
//! order (destructuring makes a new field a compile error until it is visited here) and written as
//! little-endian 8-byte words behind a header (magic, format version, GUID, length), so a blob from
//! another model, version or build of the interface is refused instead of misread.

use crate::control::{Controller, DelayLine, FilteredDerivative, ForceLoop, SpoolLoop};
use crate::damper::{DamperState, Inputs};
use crate::model_description::GUID;
use crate::physics::params::Parameters;

const MAGIC: &[u8; 8] = b"SADAMPER";
const FORMAT_VERSION: u64 = 1;

/// Walks over numeric fields; a writer reads them, a reader overwrites them.
pub trait Visitor {
    fn real(&mut self, x: &mut f64);
    fn int(&mut self, x: &mut i64);
}

/// Something whose fields can be visited.
pub trait Visit {
    fn visit<V: Visitor>(&mut self, v: &mut V);
}

fn int32<V: Visitor>(v: &mut V, x: &mut i32) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w as i32;
}

fn uint<V: Visitor>(v: &mut V, x: &mut usize) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w as usize;
}

fn boolean<V: Visitor>(v: &mut V, x: &mut bool) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w != 0;
}

/// Destructures `Parameters` with every field named once (a field missing here is a compile
/// error) and visits the Integer fields, then the Real fields, in the order given.
macro_rules! visit_parameters {
    ($params:expr, $v:expr, ints: [$($i:ident),* $(,)?], reals: [$($r:ident),* $(,)?]) => {{
        let Parameters { $($i,)* $($r,)* } = $params;
        $(int32($v, $i);)*
        $($v.real($r);)*
    }};
}

impl Visit for Parameters {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        visit_parameters!(
            self,
            v,
            ints: [control_mode, force_controller, fc_mode, n_ports],
            reals: [
                rho, beta_oil, air_fraction, n_polytropic, p_transition, d_piston, d_rod, l_half_stroke, l_dead,
                v_hose, p_reservoir0, v_gas0, a_cv_max, cd_cv, p_cv_crack, p_cv_full, a_cv_leak, p_relief, dp_relief,
                a_relief, r_port, x_lap, a_valve_leak, cd_valve, cv_valve, theta_jet, m_spool, k_spool, c_spool,
                x_spool_min, x_spool_max, k_stop, c_stop, k_sol, kappa_sol, i_max, tau_amp, tau_coil, k1_mount,
                k3_mount, f_coulomb, v_friction, g_leak, t_sample, kp_x, ki_x, kd_x, tau_dx, dp_fc_nominal, kp_f,
                ki_f, kd_f, tau_df, f_ref_min, kp_f_pid, ki_f_pid, kd_f_pid, x_spool_bias, h_max, rtol,
                x_damper_start, x_spool_start,
            ]
        );
    }
}

impl Visit for Inputs {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let Inputs { v_damper, force_demand, x_spool_demand } = self;
        for x in [v_damper, force_demand, x_spool_demand] {
            v.real(x);
        }
    }
}

impl Visit for FilteredDerivative {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let (previous, value, primed) = self.fields_mut();
        v.real(previous);
        v.real(value);
        boolean(v, primed);
    }
}

impl Visit for DelayLine {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let (buffer, len, head) = self.fields_mut();
        for x in buffer.iter_mut() {
            v.real(x);
        }
        uint(v, len);
        uint(v, head);
    }
}

impl Visit for DamperState {
    fn visit<V: Visitor>(&mut self, v: &mut V) {
        let DamperState { y, controller, i_command, time, start_time, next_sample, h_next } = self;
        for x in y.iter_mut() {
            v.real(x);
        }
        let Controller { force_loop, spool_loop, delay, x_spool_demand, force_demand_clipped } = controller;
        let ForceLoop { integral, error_rate } = force_loop;
        v.real(integral);
        error_rate.visit(v);
        let SpoolLoop { integral, velocity } = spool_loop;
        v.real(integral);
        velocity.visit(v);
        delay.visit(v);
        for x in [x_spool_demand, force_demand_clipped, i_command, time, start_time, h_next] {
            v.real(x);
        }
        let mut n = *next_sample as i64;
        v.int(&mut n);
        *next_sample = n as u64;
    }
}

struct Writer<'a>(&'a mut Vec<u8>);

impl Visitor for Writer<'_> {
    fn real(&mut self, x: &mut f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn int(&mut self, x: &mut i64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    short: bool,
}

impl Reader<'_> {
    fn word(&mut self) -> [u8; 8] {
        match self.bytes.split_first_chunk::<8>() {
            Some((w, rest)) => {
                self.bytes = rest;
                *w
            }
            None => {
                self.short = true;
                [0; 8]
            }
        }
    }
}

impl Visitor for Reader<'_> {
    fn real(&mut self, x: &mut f64) {
        *x = f64::from_le_bytes(self.word());
    }
    fn int(&mut self, x: &mut i64) {
        *x = i64::from_le_bytes(self.word());
    }
}

/// Serialises `item` with the header.
pub fn to_bytes<T: Visit + Clone>(item: &T) -> Vec<u8> {
    let mut payload = Vec::new();
    item.clone().visit(&mut Writer(&mut payload));
    let mut out = Vec::with_capacity(payload.len() + 64);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(GUID.len() as u64).to_le_bytes());
    out.extend_from_slice(GUID.as_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// Reads into `item` what `to_bytes` wrote; refuses a foreign or truncated blob.
pub fn from_bytes<T: Visit>(bytes: &[u8], item: &mut T) -> Result<(), String> {
    let err = |what: &str| Err(format!("serialized FMU state rejected: {what}"));
    let Some((magic, rest)) = bytes.split_first_chunk::<8>() else { return err("shorter than its header") };
    if magic != MAGIC {
        return err("not a SemiActiveDamper state (bad magic)");
    }
    let mut r = Reader { bytes: rest, short: false };
    if u64::from_le_bytes(r.word()) != FORMAT_VERSION {
        return err("unknown format version");
    }
    let guid_len = u64::from_le_bytes(r.word()) as usize;
    if r.bytes.len() < guid_len || &r.bytes[..guid_len] != GUID.as_bytes() {
        return err("made by a model with another GUID");
    }
    r.bytes = &r.bytes[guid_len..];
    let len = u64::from_le_bytes(r.word()) as usize;
    if r.short || r.bytes.len() != len {
        return err("payload length does not match");
    }
    item.visit(&mut r);
    if r.short || !r.bytes.is_empty() {
        return err("payload does not match this model's state layout");
    }
    Ok(())
}
