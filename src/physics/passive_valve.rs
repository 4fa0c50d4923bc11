//! A passive damper valve (docs/physics.md §3.8): a bleed, laminar and orifice in parallel, beside
//! a preloaded blow-off (a shim stack or a spring-loaded disc) that opens above its preload.
//!
//! ```text
//! Q(Δp) = G_bleed·Δp/μ_r + Q_or(C_d, A_bleed, Δp) + Q_or(C_d, A_open·s(u), Δp),   u = k_open (Δp − p_open)/A_open
//! s(u)  = ramp(u) − ramp(u − 1),  ramp(u) = 0 (u ≤ −e/2), (u + e/2)²/(2e) (|u| < e/2), u (u ≥ e/2),  e = 0.1
//! ```
//! Q_or is the sharp-edged orifice law of [`orifice_flow_partials`]; μ_r the oil's viscosity over
//! its viscosity at the reference temperature (1 unless `oil_temperature` is on). The laminar
//! bleed gives a force linear in velocity at low speed, the orifice bleed a quadratic one; above
//! the preload the blow-off's area grows with the pressure (k_open), so the force grows more
//! slowly than the velocity (a degressive valve), until the blow-off is fully open (A_open) and
//! the law is an orifice's again. s(u) is continuously differentiable: the disc lifts gradually
//! over a tenth of its travel centred on the preload, and settles on its stop likewise, so that
//! the straight part of the law passes through p_open exactly (s = u there).

use super::fluid::orifice_flow_partials;
use super::params::Parameters;

/// Share of the blow-off's travel over which it lifts off and settles on its stop (the rounding
/// of the ramp s(u)) [A]: a shim stack opens gradually, not at one pressure.
const ROUNDING: f64 = 0.1;

/// One passive valve's data (SI).
#[derive(Clone, Copy, Debug)]
pub struct PassiveValve {
    /// Laminar bleed conductance at the reference temperature (m³/(s·Pa)).
    pub g_bleed: f64,
    /// Orifice bleed area (the adjuster's needle or the fixed bleed holes) (m²).
    pub a_bleed: f64,
    /// Blow-off preload pressure (Pa).
    pub p_open: f64,
    /// Blow-off area per pressure above the preload (m²/Pa).
    pub k_open: f64,
    /// Blow-off area when fully open (m²).
    pub a_open: f64,
    /// Discharge coefficient of the orifices (-).
    pub cd: f64,
}

/// The rounded ramp and its slope: u beyond ±e/2, a parabola between.
fn ramp(u: f64) -> (f64, f64) {
    let half = 0.5 * ROUNDING;
    if u <= -half {
        (0.0, 0.0)
    } else if u < half {
        let w = u + half;
        (w * w * (0.5 / ROUNDING), w * (1.0 / ROUNDING))
    } else {
        (u, 1.0)
    }
}

/// The blow-off's open fraction s(u) (0–1) and its slope ds/du.
pub fn open_fraction(u: f64) -> (f64, f64) {
    let ((a, da), (b, db)) = (ramp(u), ramp(u - 1.0));
    (a - b, da - db)
}

impl PassiveValve {
    /// The rebound valve of `p` (in the piston, annulus → full bore).
    pub fn rebound(p: &Parameters) -> PassiveValve {
        PassiveValve {
            g_bleed: p.g_bleed_reb,
            a_bleed: p.a_bleed_reb,
            p_open: p.p_open_reb,
            k_open: p.k_open_reb,
            a_open: p.a_open_reb,
            cd: p.cd_passive,
        }
    }

    /// The compression valve of `p` (at the base, full bore → reservoir).
    pub fn compression(p: &Parameters) -> PassiveValve {
        PassiveValve {
            g_bleed: p.g_bleed_comp,
            a_bleed: p.a_bleed_comp,
            p_open: p.p_open_comp,
            k_open: p.k_open_comp,
            a_open: p.a_open_comp,
            cd: p.cd_passive,
        }
    }

    /// Flow (m³/s) through the valve under the drop `dp` (Pa), in the direction of the drop, and
    /// its slope dQ/dΔp (m³/(s·Pa)), for oil of density `rho` (kg/m³) whose viscosity is
    /// `viscosity_ratio` times the reference's; `p_transition` (Pa) is the orifice law's laminar
    /// region. The bleed passes both ways; the blow-off opens only forwards (p_open ≥ 0).
    pub fn flow(&self, dp: f64, viscosity_ratio: f64, rho: f64, p_transition: f64) -> (f64, f64) {
        let g = self.g_bleed / viscosity_ratio;
        let (q_bleed, _, dq_bleed) = orifice_flow_partials(self.cd, self.a_bleed, dp, rho, p_transition);
        let mut q = g * dp + q_bleed;
        let mut slope = g + dq_bleed;
        let per_area = if self.a_open > 0.0 { self.k_open / self.a_open } else { 0.0 };
        let u = (dp - self.p_open) * per_area;
        if per_area > 0.0 && dp > 0.0 && u > -0.5 * ROUNDING {
            let (s, ds) = open_fraction(u);
            let (q_open, dq_da, dq_ddp) = orifice_flow_partials(self.cd, self.a_open * s, dp, rho, p_transition);
            q += q_open;
            slope += dq_ddp + dq_da * self.a_open * ds * per_area;
        }
        (q, slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RHO: f64 = 870.0;
    const P_TR: f64 = 5e3;

    fn valve() -> PassiveValve {
        PassiveValve { g_bleed: 2e-11, a_bleed: 1e-6, p_open: 20e5, k_open: 2e-12, a_open: 2e-5, cd: 0.7 }
    }

    /// The slope against central differences, across the bleed, the lift-off, the opening and
    /// the stop.
    #[test]
    fn slope_matches_differences() {
        let v = valve();
        for dp in [-30e5, -1e5, 0.0, 3e3, 1e5, 15e5, 19.9e5, 20.1e5, 21e5, 25e5, 30e5, 40e5, 80e5, 200e5] {
            let h = 1.0;
            let fd = (v.flow(dp + h, 1.3, RHO, P_TR).0 - v.flow(dp - h, 1.3, RHO, P_TR).0) / (2.0 * h);
            let exact = v.flow(dp, 1.3, RHO, P_TR).1;
            assert!((exact - fd).abs() <= 1e-6 * fd.abs().max(1e-15), "Δp {dp}: {exact:e} against {fd:e}");
        }
    }

    /// Hand values: below the preload the bleed alone (laminar + orifice); fully open the orifice
    /// of A_bleed + A_open; the blow-off never opens backwards; the laminar part scales with 1/μ.
    /// The orifice law's laminar region (p_transition) moves the turbulent flow by
    /// p_tr²/(4Δp²) relative: 6e-6 at 10 bar, hence the tolerance.
    #[test]
    fn bleed_and_blow_off_by_hand() {
        let v = valve();
        let orifice = |area: f64, dp: f64| 0.7 * area * (2.0 * dp / RHO).sqrt();
        let dp = 10e5;
        let q = v.flow(dp, 1.0, RHO, P_TR).0;
        assert!((q - (2e-11 * dp + orifice(1e-6, dp))).abs() < 1e-5 * q);
        // fully open beyond p_open + (1 + e/2)·A_open/k_open = 20 bar + 102.5 bar
        let dp = 150e5;
        let q = v.flow(dp, 1.0, RHO, P_TR).0;
        assert!((q - (2e-11 * dp + orifice(1e-6 + 2e-5, dp))).abs() < 1e-5 * q);
        // backwards: the bleed only
        let dp = -30e5;
        let q = v.flow(dp, 1.0, RHO, P_TR).0;
        assert!((q - (2e-11 * dp - orifice(1e-6, -dp))).abs() < 1e-5 * q.abs());
        // twice as viscous: half the laminar flow
        let laminar = |mu: f64| {
            let w = PassiveValve { a_bleed: 0.0, a_open: 0.0, ..v };
            w.flow(5e5, mu, RHO, P_TR).0
        };
        assert!((laminar(2.0) - 0.5 * laminar(1.0)).abs() < 1e-12 * laminar(1.0));
    }

    #[test]
    fn the_blow_off_lifts_and_settles_smoothly() {
        assert_eq!(open_fraction(-0.5), (0.0, 0.0));
        // the straight part passes through the preload: s = u
        assert_eq!(open_fraction(0.5), (0.5, 1.0));
        assert_eq!(open_fraction(0.1), (0.1, 1.0));
        assert_eq!(open_fraction(2.0), (1.0, 0.0));
        // continuous value and slope at the four joints
        let half = 0.5 * ROUNDING;
        for u in [-half, half, 1.0 - half, 1.0 + half] {
            let (below, above) = (open_fraction(u - 1e-12), open_fraction(u + 1e-12));
            assert!((below.0 - above.0).abs() < 1e-11 && (below.1 - above.1).abs() < 1e-10, "u = {u}");
        }
    }
}
