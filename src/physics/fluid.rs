//! Oil with entrained air, and the sharp-edged orifice law shared by every restriction.
//!
//! ```text
//! effective bulk modulus (polytropic air in oil, Merritt; MathWorks "Hydraulic Fluid"):
//!   r(p)   = (p_atm / (p + p_atm))^(1/n)
//!   β_e(p) = (1 + α₀ r) / (1/β_L + α₀ r / (n (p + p_atm)))          p gauge (Pa)
//! with gas released below the saturation pressure (effect gas_release, Henry's law at equilibrium):
//!   α(p)   = α₀ + L h(p_sat − p_abs)/p_atm,   h a smooth max(u, 0)
//!   β_e(p) = (1 + α r) / (1/β_L + α r/(n p_abs) + L h'(p_sat − p_abs) r/p_atm)
//! orifice with a laminar region (MathWorks Fixed Orifice form):
//!   Q(A, Δp) = C_d A sqrt(2/ρ) Δp / (Δp² + p_tr²)^(1/4)
//! ```
//! For |Δp| ≫ p_tr the orifice law is the turbulent `C_d A sqrt(2|Δp|/ρ)`; at Δp = 0 its slope is
//! finite, `C_d A sqrt(2/ρ)/sqrt(p_tr)`, which keeps the Jacobian bounded at flow reversals.

use super::fixed_power::FixedPower;

/// Standard atmospheric pressure (Pa).
pub const P_ATM: f64 = 101_325.0;

/// Oil (bulk modulus `beta_oil` (Pa)) carrying `air_fraction` (air volume per oil volume at
/// atmospheric pressure, -) of air with polytropic index `n` (-), with the air's volume ratio r(p)
/// tabulated for its fixed exponent ([`FixedPower`]).
#[derive(Clone, Copy, Debug)]
pub struct Oil {
    pub beta_oil: f64,
    pub air_fraction: f64,
    /// The gas that comes out of solution at low pressure (`None` when `effect_gas_release` is
    /// off).
    pub release: Option<GasRelease>,
    /// r = (p_atm/p_abs)^(1/n) = p_atm^(1/n)·p_abs^(−1/n), tabulated from 1 kPa absolute upwards.
    volume_ratio: FixedPower,
    /// 1/β_L (1/Pa), α₀/n (-) and 1 + 1/n (-): the law's constants, so that an evaluation
    /// divides only where its inputs make it.
    oil_compliance: f64,
    air_per_index: f64,
    slope_factor: f64,
    /// 1/n (-), for the released gas.
    per_index: f64,
}

impl Oil {
    pub fn new(beta_oil: f64, air_fraction: f64, n: f64, release: Option<GasRelease>) -> Self {
        Oil {
            beta_oil,
            air_fraction,
            release,
            volume_ratio: FixedPower::new(libm::pow(P_ATM, 1.0 / n), -1.0 / n, 10),
            oil_compliance: 1.0 / beta_oil,
            air_per_index: air_fraction / n,
            slope_factor: 1.0 + 1.0 / n,
            per_index: 1.0 / n,
        }
    }
}

/// Effective bulk modulus (Pa) of `oil` at gauge pressure `p` (Pa). Below 2 % of an atmosphere
/// absolute the air law is frozen (cavitation region) so that β_e stays positive.
pub fn effective_bulk_modulus(p: f64, oil: &Oil) -> f64 {
    effective_bulk_modulus_and_slope(p, oil).0
}

/// [`effective_bulk_modulus`] (Pa) and its slope dβ_e/dp (-).
#[inline]
pub fn effective_bulk_modulus_and_slope(p: f64, oil: &Oil) -> (f64, f64) {
    match oil.release {
        None => entrained_air_modulus_and_slope(p, oil),
        Some(release) => released_gas_modulus_and_slope(p, oil, &release),
    }
}

/// Absolute pressure (Pa) below which the gas law is frozen (cavitation region), so that β_e stays
/// positive: 2 % of an atmosphere.
const FROZEN_BELOW: f64 = 0.02 * P_ATM;

/// Gauge pressure `p` as the gas laws take it: absolute, floored at [`FROZEN_BELOW`] (`frozen`
/// below it, where the slope is 0), its reciprocal, and the air's volume ratio r there.
struct Absolute {
    frozen: bool,
    p_abs: f64,
    per_p_abs: f64,
    r: f64,
}

#[inline(always)]
fn absolute(p: f64, oil: &Oil) -> Absolute {
    let p_abs = (p + P_ATM).max(FROZEN_BELOW);
    // the reciprocal while the table reads r: the rest then multiplies
    Absolute { frozen: p + P_ATM < FROZEN_BELOW, p_abs, per_p_abs: 1.0 / p_abs, r: oil.volume_ratio.of(p_abs) }
}

/// The bulk modulus (Pa) and its slope (-) of oil with entrained air alone.
#[inline]
fn entrained_air_modulus_and_slope(p: f64, oil: &Oil) -> (f64, f64) {
    let Oil { beta_oil, air_fraction, .. } = *oil;
    if air_fraction == 0.0 {
        return (beta_oil, 0.0);
    }
    let Absolute { frozen, per_p_abs, r, .. } = absolute(p, oil);
    let num = 1.0 + air_fraction * r;
    // α₀ r/(n p_abs), the air's compliance
    let air = oil.air_per_index * r * per_p_abs;
    let per_den = 1.0 / (oil.oil_compliance + air);
    let beta = num * per_den;
    if frozen {
        return (beta, 0.0);
    }
    // dr/dp = −r/(n p_abs): d(num)/dp = −air, d(den)/dp = −air (1 + 1/n)/p_abs
    let d_den = -air * oil.slope_factor * per_p_abs;
    (beta, (-air - beta * d_den) * per_den)
}

/// Half the pressure band (Pa) over which gas starts to come out of solution around the
/// saturation pressure: h(u) blends 0 into u over |u| < RELEASE_BAND, so that the bulk modulus
/// and its slope stay continuous and the integrator sees no kink (\[A\]: 0.1 bar, a third of the
/// check valves' 0.3 bar cracking pressure, small beside the drops that draw a chamber below
/// saturation).
pub const RELEASE_BAND: f64 = 1e4;

/// Gas dissolved in the oil that comes out of solution below the saturation pressure (effect
/// `gas_release`, docs/physics.md §3.2). At equilibrium (Henry's law) oil holds `solubility`
/// volumes of gas (at p_atm) per volume and per atmosphere of the gas's pressure; oil saturated at
/// p_sat has released, at p_abs below it, α_rel = solubility·(p_sat − p_abs)/p_atm of them, which
/// then expand polytropically as the entrained air does. Release and dissolution are taken as
/// instantaneous (as the air dissolution of the MathWorks isothermal liquid, \[S\]): what this
/// leaves out is the seconds a real oil takes to dissolve the gas again.
#[derive(Clone, Copy, Debug)]
pub struct GasRelease {
    /// solubility/p_atm (1/Pa).
    per_pressure: f64,
    /// Saturation pressure, absolute (Pa).
    p_saturation_abs: f64,
}

impl GasRelease {
    /// Oil of Bunsen coefficient `solubility` (-) saturated at gauge pressure `p_saturation` (Pa).
    pub fn new(solubility: f64, p_saturation: f64) -> Self {
        GasRelease { per_pressure: solubility / P_ATM, p_saturation_abs: p_saturation + P_ATM }
    }

    /// At absolute pressure `p_abs` (Pa): the released gas α_rel (volume at p_atm per oil volume,
    /// -), its rate of release −dα_rel/dp (1/Pa) and that rate's slope with pressure (1/Pa²).
    #[inline]
    pub fn released(&self, p_abs: f64) -> (f64, f64, f64) {
        // t runs over the band: h(u) = 2δ(t³ − t⁴/2), h' = smoothstep(t), h'' = smoothstep'(t)/(2δ)
        let u = self.p_saturation_abs - p_abs;
        let t = (u + RELEASE_BAND) * (0.5 / RELEASE_BAND);
        let h = if t <= 0.0 {
            0.0
        } else if t >= 1.0 {
            u
        } else {
            2.0 * RELEASE_BAND * t * t * t * (1.0 - 0.5 * t)
        };
        let rate = self.per_pressure * smoothstep(t);
        (self.per_pressure * h, rate, -self.per_pressure * smoothstep_slope(t) * (0.5 / RELEASE_BAND))
    }
}

/// The bulk modulus (Pa) and its slope (-) of oil with entrained air and the gas `release` has
/// let out at gauge pressure `p` (Pa): the air law of [`effective_bulk_modulus`] with the free gas
/// α = α₀ + α_rel(p), plus the compliance of the gas released per pressure drop, (−dα_rel/dp)·r.
#[inline]
fn released_gas_modulus_and_slope(p: f64, oil: &Oil, release: &GasRelease) -> (f64, f64) {
    let Absolute { frozen, p_abs, per_p_abs, r } = absolute(p, oil);
    let (released, rate, rate_slope) = release.released(p_abs);
    let alpha = oil.air_fraction + released;
    let num = 1.0 + alpha * r;
    // the free gas's compliance α r/(n p_abs), and the release's (−dα/dp)·r; written so that
    // above the band (nothing released) every operation is the entrained air's alone, bit for bit
    let air = (oil.air_per_index + released * oil.per_index) * r * per_p_abs;
    let freed = rate * r;
    let per_den = 1.0 / (oil.oil_compliance + air + freed);
    let beta = num * per_den;
    if frozen {
        return (beta, 0.0);
    }
    // dr/dp = −r/(n p_abs), dα/dp = −rate: d(num)/dp = −freed − air,
    // d(den)/dp = −air (1 + 1/n)/p_abs − 2 freed/(n p_abs) + (d rate/dp)·r
    let d_den = -air * oil.slope_factor * per_p_abs - 2.0 * freed * oil.per_index * per_p_abs + rate_slope * r;
    (beta, (-freed - air - beta * d_den) * per_den)
}

/// Flow (m³/s) through a sharp-edged orifice of area `area` (m²) with discharge coefficient `cd`
/// under the pressure drop `dp` (Pa), for oil of density `rho` (kg/m³); `p_transition` (Pa) sets
/// the laminar region around Δp = 0.
#[inline]
pub fn orifice_flow(cd: f64, area: f64, dp: f64, rho: f64, p_transition: f64) -> f64 {
    orifice_flow_partials(cd, area, dp, rho, p_transition).0
}

/// [`orifice_flow`] Q (m³/s) and its partial derivatives ∂Q/∂A (m/s) and ∂Q/∂Δp (m³/(s·Pa)):
/// ∂Q/∂Δp = C_d A sqrt(2/ρ) (Δp²/2 + p_tr²) / (Δp² + p_tr²)^(5/4).
#[inline]
pub fn orifice_flow_partials(cd: f64, area: f64, dp: f64, rho: f64, p_transition: f64) -> (f64, f64, f64) {
    let s2 = dp * dp + p_transition * p_transition;
    let per_area = cd * (2.0 / rho).sqrt() / s2.sqrt().sqrt();
    let dq_darea = per_area * dp;
    (area * dq_darea, dq_darea, area * per_area * (0.5 * dp * dp + p_transition * p_transition) / s2)
}

/// The oil's viscosity at `t` (K) over its viscosity at `t_ref` (K): exp(−b (t − t_ref)), with
/// `b` = `visc_temp_coeff` (1/K), Reynolds' exponential law (docs/physics.md §3.9). Over the
/// 20–100 °C of a damper's oil it stays within a few per cent of Walther's ASTM D341 law for
/// b fitted at the range's middle.
#[inline]
pub fn viscosity_ratio(b: f64, t: f64, t_ref: f64) -> f64 {
    libm::exp(-b * (t - t_ref))
}

/// C¹ ramp from 0 (u ≤ 0) to 1 (u ≥ 1): 3u² − 2u³. Used for valve openings so the right-hand side
/// stays continuously differentiable.
#[inline]
pub fn smoothstep(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// The slope of [`smoothstep`]: 6u(1 − u) inside the ramp, 0 outside.
#[inline]
pub fn smoothstep_slope(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    6.0 * u * (1.0 - u)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bulk_modulus_matches_the_table_of_docs_physics() {
        // docs/physics.md §3.2: α₀ 2.5 %, n 1.4, β_L 1.5 GPa.
        for (bar, mpa) in [(5.0, 112.0), (10.0, 277.8), (20.0, 611.1), (50.0, 1138.5), (100.0, 1366.1), (150.0, 1430.0)]
        {
            let b = effective_bulk_modulus(bar * 1e5, &Oil::new(1.5e9, 0.025, 1.4, None)) / 1e6;
            assert!((b - mpa).abs() < 0.1, "{bar} bar: {b} MPa, expected {mpa}");
        }
    }

    #[test]
    fn bulk_modulus_limits() {
        // Without air it is the oil's; with air it rises monotonically towards it with pressure.
        assert_eq!(effective_bulk_modulus(1e6, &Oil::new(1.5e9, 0.0, 1.4, None)), 1.5e9);
        let oil = Oil::new(1.5e9, 0.025, 1.4, None);
        let mut last = 0.0;
        for k in 0..200 {
            let b = effective_bulk_modulus(-1e5 + k as f64 * 1e5, &oil);
            assert!(b > last && b < 1.5e9);
            last = b;
        }
        // At atmospheric pressure a 2.5 % air fraction is soft: β ≈ n·p_atm·(1+α)/α.
        let b0 = effective_bulk_modulus(0.0, &oil);
        let hand = (1.025) / (1.0 / 1.5e9 + 0.025 / (1.4 * P_ATM));
        assert!((b0 - hand).abs() < 1e-6 * hand);
    }

    #[test]
    fn orifice_is_turbulent_far_from_zero_and_finite_slope_at_zero() {
        // Q = Cd A sqrt(2 Δp/ρ): 0.65 · 10 mm² · sqrt(2 · 50 bar / 870 kg/m³) = 6.969e-4 m³/s.
        let q = orifice_flow(0.65, 10e-6, 50e5, 870.0, 5e3);
        let hand = 0.65 * 10e-6 * (2.0 * 50e5 / 870.0f64).sqrt();
        assert!((q - hand).abs() < 1e-6 * hand, "{q} vs {hand}");
        assert_eq!(orifice_flow(0.65, 10e-6, -50e5, 870.0, 5e3), -q);
        let slope = orifice_flow(0.65, 10e-6, 1e-3, 870.0, 5e3) / 1e-3;
        let hand_slope = 0.65 * 10e-6 * (2.0 / 870.0f64).sqrt() / 5e3f64.sqrt();
        assert!((slope - hand_slope).abs() < 1e-6 * hand_slope);
    }

    #[test]
    fn slopes_are_the_derivatives() {
        let central = |f: &dyn Fn(f64) -> f64, x: f64, h: f64| (f(x + h) - f(x - h)) / (2.0 * h);
        let oil = Oil::new(1.5e9, 0.025, 1.4, None);
        for bar in [-0.9, -0.5, 0.0, 1.0, 5.0, 20.0, 100.0, 300.0] {
            let p = bar * 1e5;
            let (_, slope) = effective_bulk_modulus_and_slope(p, &oil);
            let fd = central(&|p| effective_bulk_modulus(p, &oil), p, 10.0);
            assert!((slope - fd).abs() < 1e-6 * fd.abs().max(1.0), "{bar} bar: {slope} vs {fd}");
        }
        for dp in [-50e5, -1e4, -1e3, 0.0, 2e3, 5e3, 1e5, 80e5] {
            let (q, dq_da, dq_ddp) = orifice_flow_partials(0.65, 10e-6, dp, 870.0, 5e3);
            assert_eq!(q, orifice_flow(0.65, 10e-6, dp, 870.0, 5e3));
            assert!((dq_da - q / 10e-6).abs() <= 1e-12 * dq_da.abs());
            let fd = central(&|dp| orifice_flow(0.65, 10e-6, dp, 870.0, 5e3), dp, 1.0);
            assert!((dq_ddp - fd).abs() < 1e-6 * fd.abs(), "Δp {dp}: {dq_ddp} vs {fd}");
        }
        for u in [0.1, 0.3, 0.5, 0.9] {
            assert!((smoothstep_slope(u) - central(&smoothstep, u, 1e-6)).abs() < 1e-8);
        }
        assert_eq!(smoothstep_slope(-0.5) + smoothstep_slope(1.5), 0.0);
    }

    /// Oil saturated at the truck's 5 bar pre-charge, with mineral oil's solubility of air.
    fn releasing_oil() -> Oil {
        Oil::new(1.5e9, 0.025, 1.4, Some(GasRelease::new(0.09, 5e5)))
    }

    #[test]
    fn released_gas_matches_the_hand_formula() {
        // 0.5 bar below saturation (beyond the band): α = α₀ + L·Δp/p_atm, and the release adds
        // L·r/p_atm to the compliance.
        let (p, p_abs) = (4.5e5, 4.5e5 + P_ATM);
        let r = libm::pow(P_ATM / p_abs, 1.0 / 1.4);
        let alpha = 0.025 + 0.09 * 0.5e5 / P_ATM;
        let hand = (1.0 + alpha * r) / (1.0 / 1.5e9 + alpha * r / (1.4 * p_abs) + 0.09 * r / P_ATM);
        let b = effective_bulk_modulus(p, &releasing_oil());
        assert!((b - hand).abs() < 1e-12 * hand, "{b} vs {hand}");
        // 3.49 MPa: the released gas makes the oil 28× softer than its air alone (97.6 MPa)
        assert!((b / 1e6 - 3.491).abs() < 0.001, "{b}");
        let air_only = effective_bulk_modulus(p, &Oil::new(1.5e9, 0.025, 1.4, None));
        assert!((air_only / 1e6 - 97.57).abs() < 0.01, "{air_only}");
    }

    #[test]
    fn nothing_is_released_above_saturation() {
        // above the band the law is the entrained air's, bit for bit; without entrained air the
        // oil's own modulus
        let (with, without) = (releasing_oil(), Oil::new(1.5e9, 0.025, 1.4, None));
        for p in [5e5 + RELEASE_BAND, 6e5, 20e5, 150e5] {
            assert_eq!(effective_bulk_modulus_and_slope(p, &with), effective_bulk_modulus_and_slope(p, &without));
        }
        let air_free = Oil::new(1.5e9, 0.0, 1.4, Some(GasRelease::new(0.09, 0.0)));
        assert!((effective_bulk_modulus(1e5, &air_free) - 1.5e9).abs() < 1e-6);
        assert!(effective_bulk_modulus(-0.5e5, &air_free) < 1e6);
    }

    #[test]
    fn the_compliance_is_the_released_volume_s_slope() {
        // dV/V = −dp/β: integrating 1/β from 6 bar down to p gives the volume the gas takes,
        // ln(1 + α(p) r(p)) − ln(1 + α₀ r(6 bar)), up to the oil's own compression (p/β_L)
        let oil = releasing_oil();
        let volume = |p: f64| {
            let p_abs = p + P_ATM;
            let released = 0.09 * (5e5 + P_ATM - p_abs).max(0.0) / P_ATM;
            libm::log(1.0 + (0.025 + released) * libm::pow(P_ATM / p_abs, 1.0 / 1.4)) - p / 1.5e9
        };
        for p_end in [4.8e5, 3e5, 1e5, 0.0, -0.5e5] {
            let n = 200_000;
            let h = (6e5 - p_end) / n as f64;
            // the midpoint rule, fine enough that its error is far below the tolerance
            let integral: f64 = (0..n).map(|k| h / effective_bulk_modulus(p_end + (k as f64 + 0.5) * h, &oil)).sum();
            let hand = volume(p_end) - volume(6e5);
            assert!((integral - hand).abs() < 2e-3 * hand.abs() + 1e-6, "down to {p_end} Pa: {integral} vs {hand}");
        }
    }

    #[test]
    fn released_gas_slopes_are_the_derivatives() {
        let central = |f: &dyn Fn(f64) -> f64, x: f64, h: f64| (f(x + h) - f(x - h)) / (2.0 * h);
        for oil in [releasing_oil(), Oil::new(1.5e9, 0.0, 1.4, Some(GasRelease::new(0.05, 0.0)))] {
            // beyond, at the edges of and inside the band, far below, near vacuum
            for p in [6e5, 5.1e5, 5.05e5, 5e5, 4.95e5, 4.9e5, 4e5, 1e5, 0.0, -0.9e5] {
                let (_, slope) = effective_bulk_modulus_and_slope(p, &oil);
                // a small step: the band's curvature is large (the compliance grows 28-fold
                // over 0.2 bar) and its third derivative jumps at the edges
                let fd = central(&|p| effective_bulk_modulus(p, &oil), p, 1e-3);
                assert!((slope - fd).abs() < 2e-4 * fd.abs().max(1.0), "{p} Pa: {slope} vs {fd}");
            }
            // continuous across the band's edges (h is C²): over 2 mPa no more than the slope moves it
            for edge in [5e5 - RELEASE_BAND, 5e5 + RELEASE_BAND, -RELEASE_BAND, RELEASE_BAND] {
                let (below, above) =
                    (effective_bulk_modulus(edge - 1e-3, &oil), effective_bulk_modulus(edge + 1e-3, &oil));
                assert!((below - above).abs() < 1e-7 * above, "{edge}: {below} vs {above}");
            }
        }
    }

    #[test]
    fn smoothstep_ends_and_middle() {
        assert_eq!(smoothstep(-1.0), 0.0);
        assert_eq!(smoothstep(2.0), 1.0);
        assert_eq!(smoothstep(0.5), 0.5);
    }
}
