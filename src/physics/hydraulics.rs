//! The check-valve ("uniflow") circuit: annulus chamber A, full-bore chamber B, piston check valve
//! CV1 (B→A), replenishing check valve CV2 (reservoir→B), proportional valve and relief valve
//! A→reservoir, gas-charged reservoir (docs/physics.md §2–3).
//!
//! ```text
//! A_p = πD_p²/4, A_r = πD_r²/4, A_a = A_p − A_r
//! V_A = A_a (L_half + L_dead − x_p) + V_hose,   V_B = A_p (L_half + L_dead + x_p)
//! check valve: A_cv(Δp) = A_leak + A_max · smoothstep((Δp − p_crack)/(p_full − p_crack))
//! reservoir:   p_r = (p_r0 + p_atm)(V_g0/V_g)^n − p_atm
//! ```
//! Extension squeezes A only (force ≈ p_A A_a − p_r A_p); compression squeezes A and B together
//! through CV1 (force ≈ −p A_r) with about three times the oil volume.

use super::fixed_power::FixedPower;
use super::fluid::{smoothstep, smoothstep_slope, P_ATM};
use std::f64::consts::PI;

/// The chambers' smallest volume (m³), 0.1 cm³: a run beyond the stroke stays finite. The volume
/// has no slope there.
pub const VOLUME_FLOOR: f64 = 1e-7;

/// Cylinder geometry.
#[derive(Clone, Copy, Debug)]
pub struct Cylinder {
    /// Piston (bore) area (m²).
    pub a_piston: f64,
    /// Rod area (m²).
    pub a_rod: f64,
    /// Annulus area A_p − A_r (m²).
    pub a_annulus: f64,
    /// Annulus-side volume at mid-stroke, hose included (m³).
    pub v_a0: f64,
    /// Piston-side volume at mid-stroke (m³).
    pub v_b0: f64,
}

impl Cylinder {
    /// Geometry from bore `d_piston`, rod `d_rod`, half stroke `l_half`, dead length `l_dead` (m)
    /// and the hose volume `v_hose` (m³).
    pub fn new(d_piston: f64, d_rod: f64, l_half: f64, l_dead: f64, v_hose: f64) -> Self {
        let a_piston = PI / 4.0 * d_piston * d_piston;
        let a_rod = PI / 4.0 * d_rod * d_rod;
        let a_annulus = a_piston - a_rod;
        Cylinder {
            a_piston,
            a_rod,
            a_annulus,
            v_a0: a_annulus * (l_half + l_dead) + v_hose,
            v_b0: a_piston * (l_half + l_dead),
        }
    }

    /// Chamber volumes (V_A, V_B) (m³) at piston stroke `x_piston` (m) (extension positive),
    /// floored at [`VOLUME_FLOOR`] so a run beyond the stroke stays finite.
    pub fn volumes(&self, x_piston: f64) -> (f64, f64) {
        (
            (self.v_a0 - self.a_annulus * x_piston).max(VOLUME_FLOOR),
            (self.v_b0 + self.a_piston * x_piston).max(VOLUME_FLOOR),
        )
    }
}

/// Open area (m²) of a check valve with leakage area `a_leak`, full area `a_max` (m²), cracking
/// pressure `p_crack` and full-opening pressure `p_full` (Pa), under the forward drop `dp` (Pa).
pub fn check_valve_area(a_leak: f64, a_max: f64, p_crack: f64, p_full: f64, dp: f64) -> f64 {
    a_leak + a_max * smoothstep((dp - p_crack) * (1.0 / (p_full - p_crack)))
}

/// The slope d[`check_valve_area`]/dΔp (m²/Pa).
#[inline]
pub fn check_valve_area_slope(a_max: f64, p_crack: f64, p_full: f64, dp: f64) -> f64 {
    let per_range = 1.0 / (p_full - p_crack);
    a_max * smoothstep_slope((dp - p_crack) * per_range) * per_range
}

/// The reservoir's gas charge: pre-charge `p_r0` (Pa, gauge) at volume `v_g0` (m³), polytropic
/// index `n` (-), with its law tabulated for the fixed exponent ([`FixedPower`]).
#[derive(Clone, Copy, Debug)]
pub struct GasCharge {
    pub n: f64,
    /// (p_r0 + p_atm)(V_g0/V_g)^n = [(p_r0 + p_atm) V_g0^n]·V_g^(−n), tabulated from 2^−40 m³ up.
    absolute_pressure: FixedPower,
}

impl GasCharge {
    pub fn new(p_r0: f64, v_g0: f64, n: f64) -> Self {
        GasCharge { n, absolute_pressure: FixedPower::new((p_r0 + P_ATM) * libm::pow(v_g0, n), -n, -40) }
    }
}

/// Gauge pressure (Pa) of the reservoir's gas `charge` at gas volume `v_gas` (m³).
pub fn reservoir_pressure(charge: &GasCharge, v_gas: f64) -> f64 {
    reservoir_pressure_and_slope(charge, v_gas).0
}

/// [`reservoir_pressure`] (Pa) and its slope dp_r/dV_g = −n (p_r + p_atm)/V_g (Pa/m³).
#[inline]
pub fn reservoir_pressure_and_slope(charge: &GasCharge, v_gas: f64) -> (f64, f64) {
    let v = v_gas.max(1e-9);
    let absolute = charge.absolute_pressure.of(v);
    (absolute - P_ATM, if v_gas > 1e-9 { -charge.n * absolute / v } else { 0.0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_geometry_gives_the_papers_three_to_one_volume_ratio() {
        let c = Cylinder::new(0.070, 0.050, 0.100, 0.005, 1e-5);
        assert!((c.a_piston - 3.848e-3).abs() < 1e-6);
        assert!((c.a_rod - 1.963e-3).abs() < 1e-6);
        let (va, vb) = c.volumes(0.0);
        assert!((va - 208e-6).abs() < 1e-6 && ((va + vb) - 612e-6).abs() < 1e-6);
        assert!(((va + vb) / va - 2.94).abs() < 0.01);
    }

    #[test]
    fn check_valve_opens_between_crack_and_full() {
        let a = |dp| check_valve_area(1e-9, 2e-4, 0.3e5, 1e5, dp);
        assert_eq!(a(0.0), 1e-9);
        assert_eq!(a(0.3e5), 1e-9);
        assert!((a(0.65e5) - (1e-9 + 1e-4)).abs() < 1e-15);
        assert_eq!(a(2e5), 1e-9 + 2e-4);
    }

    #[test]
    fn reservoir_follows_the_gas_law() {
        assert!((reservoir_pressure(&GasCharge::new(5e5, 1e-3, 1.4), 1e-3) - 5e5).abs() < 1e-6);
        // half the volume: (6.01325 bar)·2^1.4 − 1.01325 bar
        let p = reservoir_pressure(&GasCharge::new(5e5, 1e-3, 1.0), 0.5e-3);
        assert!((p - (2.0 * (5e5 + P_ATM) - P_ATM)).abs() < 1e-6);
    }
}
