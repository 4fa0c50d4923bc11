//! Proportional valve: circular ports uncovered by a spool edge, the proportional solenoid and the
//! steady flow force on the spool.
//!
//! ```text
//! port area, opening h = x_spool − x_lap, n ports of radius r (circular segment):
//!   A(h)  = n [ r² acos((r−h)/r) − (r−h) sqrt(2rh − h²) ],  0 ≤ h ≤ 2r   (0 below, nπr² above)
//!   dA/dh = 2 n sqrt(h(2r − h))                                (chord length)
//! solenoid (proportional, flat force–stroke curve, linearised gain K):
//!   F_sol = K i (1 + κ (x/x_max − 0.5))
//! steady flow force (closing), jet angle θ, velocity coefficient C_v:
//!   F_flow = 2 C_d C_v cos θ · A · max(Δp, 0)
//! ```

use super::piecewise::octic;
use crate::solver::{cube_root_estimate, cube_root_halley_step};
use std::f64::consts::PI;

/// The inverse port law's table ([`ValvePorts::position_for_area`]): with φ the root of Kepler's
/// equation φ − sin φ = M (eccentricity 1) and t = (6M)^(2/3), the opening fraction
/// sin²(φ/4) = (t/16)·W(t), W smooth on 0 ≤ t ≤ (6π)^(2/3) (M ≤ π; the upper half by symmetry),
/// within 1.2e-14 relative: a table evaluation costs less than a starter, a Halley iteration and
/// a `sincos` (4 % of the whole damper's time). Its form, where it comes from and
/// what tests it: [`super::piecewise`]; here, `the_opening_table_is_within_its_bound`.
#[rustfmt::skip]
const KEPLER_OPENING: [[f64; 9]; 8] = [
    [1.0056318858522755, 0.005732722998360747, 0.00010323556933359022, 2.463822096474043e-06, 6.733298525562937e-08, 1.994515492681072e-09, 6.234487498446378e-11, 2.0299671747832032e-12, 6.370055664254952e-14],
    [1.017531130122818, 0.006177558308675384, 0.00011981050926690522, 3.093509304081895e-06, 9.167149451145163e-08, 2.9483089805616355e-09, 1.001363258317739e-10, 3.5466561431711377e-12, 1.252924481494468e-13],
    [1.0303918048381184, 0.0066971127629285076, 0.00014083420772312868, 3.963073460519358e-06, 1.283182359761885e-07, 4.515715815699434e-09, 1.679705047446446e-10, 6.520651797434305e-12, 2.53580080778128e-13],
    [1.0443832810310771, 0.007312509368672497, 0.00016809873985468594, 5.201289411060805e-06, 1.8571196894841785e-07, 7.218530159480204e-09, 2.968432189135302e-10, 1.2763804870985392e-11, 5.607394859690093e-13],
    [1.0597255282108884, 0.008053903394515786, 0.0002044219658654671, 7.0314989942131074e-06, 2.8001393912287444e-07, 1.2161258472441557e-08, 5.593727505769705e-10, 2.69578677358604e-11, 1.3440492447845514e-12],
    [1.0767121838516474, 0.008966023544353368, 0.00025445919915724203, 9.865374402426916e-06, 4.4450523638362104e-07, 2.1887908499520724e-08, 1.1429124637561529e-09, 6.267247660020114e-11, 3.519303983591449e-12],
    [1.0957488853614452, 0.010118471485712604, 0.00032639408873835963, 1.4522213617363033e-05, 7.543016560521048e-07, 4.291968296923519e-08, 2.5933381239923624e-09, 1.651167688866821e-10, 1.0764976842649257e-11],
    [1.1174212147433318, 0.011626469740436456, 0.00043581959213192097, 2.280377816344151e-05, 1.400505594833425e-06, 9.448757412928234e-08, 6.780591469573338e-09, 5.153890960286346e-10, 4.00005845060521e-11],
];
/// (6π)^(2/3): t at M = π.
const KEPLER_T_MAX: f64 = 7.082731016000907;

/// The port law's table ([`ValvePorts::area`]): with u = h/r ≤ 1 a port's open area is
/// r²·u^(3/2)·G(u), G smooth on 0 ≤ u ≤ 1, within 1.2e-15 relative (the other half by symmetry).
/// It replaced an arcsine's rational approximation, its division and a square root: 2 % faster.
/// Tested here by `the_segment_area_is_the_circle_segments`.
#[rustfmt::skip]
const SEGMENT_AREA: [[f64; 9]; 8] = [
    [1.8678405475617217, -0.01787863992757079, -0.00010236284388429582, -1.279170056242606e-06, -2.104442443752315e-08, -4.013101620878269e-10, -8.39709137547688e-12, -1.8383479250728114e-13, -9.887303978669186e-15],
    [1.8316632328550968, -0.018304148571797595, -0.00011057718579467256, -1.4650355516859606e-06, -2.5619524386987636e-08, -5.200886013665889e-10, -1.1614621292046668e-11, -2.8530336653634683e-13, -8.261632617666122e-16],
    [1.794600479348351, -0.018764901533841305, -0.000120026859786939, -1.6928206410984832e-06, -3.1602687580418565e-08, -6.86055993413986e-10, -1.638718373347887e-11, -4.2243738125898607e-13, -1.0308768779724624e-14],
    [1.7565764975741476, -0.019266392337316213, -0.0001310013683365246, -1.9759624283870063e-06, -3.9577468840159045e-08, -9.235241944115938e-10, -2.373386511729043e-11, -6.626396072190059e-13, -2.204684273227561e-14],
    [1.717503235326162, -0.019815454592542574, -0.0001438870573795543, -2.3337242479526196e-06, -5.0443457422354034e-08, -1.2729350239636244e-09, -3.5403843149576915e-11, -1.0521422025429847e-12, -4.350534285751791e-14],
    [1.6772772578772654, -0.020420730848907463, -0.00015921115621993787, -2.794513932444428e-06, -6.563573452145866e-08, -1.80401200619993e-09, -5.4793061121102255e-11, -1.7779809340652593e-12, -4.775454358782699e-14],
    [1.6357754837931664, -0.021093365686108794, -0.00017771227893974967, -3.401642129901918e-06, -8.753855538344998e-08, -2.6431858550383155e-09, -8.83224507034864e-11, -3.1718885962988314e-12, -1.0525810015582878e-13],
    [1.5928491988799853, -0.021848065700743123, -0.0002004580669076462, -4.223819066434548e-06, -1.2030920091145002e-07, -4.033063484843127e-09, -1.4985620150971235e-10, -6.0016808797846425e-12, -2.4891914415694027e-13],
];

/// The opening fraction sin²(φ/4) of a port at t = (6M)^(2/3) (see `KEPLER_OPENING`).
fn opening_fraction(t: f64) -> f64 {
    t * (1.0 / 16.0) * octic(&KEPLER_OPENING, t, KEPLER_T_MAX)
}

/// The open area of a port of unit radius at the opening u = h/r, 0 < u < 2: α(u) = acos(1 − u) −
/// (1 − u)·sqrt(u(2 − u)), from `SEGMENT_AREA` and α(u) = π − α(2 − u).
fn segment_area(u: f64) -> f64 {
    let upper = u > 1.0;
    let w = if upper { 2.0 - u } else { u };
    let area = w * w.sqrt() * octic(&SEGMENT_AREA, w, 1.0);
    if upper {
        PI - area
    } else {
        area
    }
}

/// Port geometry of the valve.
#[derive(Clone, Copy, Debug)]
pub struct ValvePorts {
    /// Number of circular ports (-).
    pub n_ports: f64,
    /// Port radius (m).
    pub r_port: f64,
    /// Spool overlap: ports start to open at this spool position (m).
    pub x_lap: f64,
}

impl ValvePorts {
    /// Open area (m²) at spool position `x_spool` (m).
    pub fn area(&self, x_spool: f64) -> f64 {
        let r = self.r_port;
        let h = x_spool - self.x_lap;
        let one = if h <= 0.0 {
            0.0
        } else if h >= 2.0 * r {
            PI * r * r
        } else {
            r * r * segment_area(h / r)
        };
        self.n_ports * one
    }

    /// dA/dx_spool (m²/m): the total chord length of the uncovered port edges.
    pub fn area_slope(&self, x_spool: f64) -> f64 {
        let r = self.r_port;
        let h = x_spool - self.x_lap;
        if h <= 0.0 || h >= 2.0 * r {
            0.0
        } else {
            2.0 * self.n_ports * (h * (2.0 * r - h)).sqrt()
        }
    }

    /// Spool position (m) that opens `area` (m²); `area` is clamped to [0, nπr²]. The controller
    /// inverts the port law at every sample, so this is written for speed: with φ = 2θ the law
    /// is A = (n r²/2)(φ − sin φ) and h = 2r sin²(φ/4), so φ solves Kepler's equation
    /// φ − sin φ = M = 2A/(n r²) (eccentricity 1), odd about M = π. The opening fraction
    /// sin²(φ/4) is a smooth function of t = (6M)^(2/3) (the root goes as M^(1/3) at 0), taken
    /// from a piecewise polynomial (`KEPLER_OPENING`) within 1.2e-14: a cube root and a
    /// polynomial, a fixed cost, and no iteration on the equation.
    pub fn position_for_area(&self, area: f64) -> f64 {
        let r = self.r_port;
        let scale = self.n_ports * r * r;
        let m = (area * (2.0 / scale)).clamp(0.0, 2.0 * PI);
        if m.is_nan() || m <= 0.0 {
            return self.x_lap;
        }
        // the upper half by symmetry: φ(2π − M) = 2π − φ(M)
        let upper = m > PI;
        let m_half = if upper { 2.0 * PI - m } else { m };
        // the opening goes as M^(2/3): below this M it is under 1e-20 of the port's radius (and
        // the cube root's products below would underflow)
        if m_half < 1e-30 {
            return self.x_lap + if upper { 2.0 * r } else { 0.0 };
        }
        // the estimate's 1e-4 would be the table's error: one more Halley step takes it to 1e-12
        let s = cube_root_halley_step(cube_root_estimate(6.0 * m_half), 6.0 * m_half);
        let opening = 2.0 * r * opening_fraction(s * s);
        self.x_lap + if upper { 2.0 * r - opening } else { opening }
    }
}

/// Force (N) of the proportional solenoid with force constant `k_sol` (N/A) at current `i` (A),
/// spool position `x_spool` (m); `kappa` is the relative force slope over the stroke `x_max` (m).
pub fn solenoid_force(k_sol: f64, kappa: f64, x_max: f64, i: f64, x_spool: f64) -> f64 {
    k_sol * i * (1.0 + kappa * (x_spool / x_max - 0.5))
}

/// Steady flow force (N) on the spool, acting to close the valve: jet momentum through the open
/// area `area` (m²) under the pressure drop `dp` (Pa) (only positive drops drive the jet), with
/// `gain` = [`flow_force_gain`] (computed once per parameter set: it holds a cosine).
pub fn flow_force(gain: f64, area: f64, dp: f64) -> f64 {
    gain * area * dp.max(0.0)
}

/// The flow-force gain 2 C_d C_v cos θ (-): [`flow_force`] = gain · A · max(Δp, 0).
pub fn flow_force_gain(cd: f64, cv: f64, theta_jet: f64) -> f64 {
    2.0 * cd * cv * libm::cos(theta_jet)
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    const PORTS: ValvePorts = ValvePorts { n_ports: 2.0, r_port: 3e-3, x_lap: 0.3e-3 };

    #[test]
    fn area_at_landmarks() {
        assert_eq!(PORTS.area(0.0), 0.0);
        assert_eq!(PORTS.area(0.3e-3), 0.0);
        // half open: two half circles = π r²
        let half = PORTS.area(0.3e-3 + 3e-3);
        assert!((half - PI * 9e-6).abs() < 1e-15);
        assert!((PORTS.area(10e-3) - 2.0 * PI * 9e-6).abs() < 1e-18);
        // small openings follow n (4/3) sqrt(2r) h^1.5
        let h: f64 = 1e-6;
        let small = 2.0 * 4.0 / 3.0 * (6e-3f64).sqrt() * h.powf(1.5);
        assert!((PORTS.area(0.3e-3 + h) - small).abs() < 1e-3 * small);
    }

    #[test]
    fn slope_is_the_derivative_of_area() {
        for k in 1..60 {
            let x = 0.3e-3 + k as f64 * 1e-4;
            let fd = (PORTS.area(x + 1e-9) - PORTS.area(x - 1e-9)) / 2e-9;
            assert!((fd - PORTS.area_slope(x)).abs() < 1e-6 * PORTS.area_slope(x).max(1e-6), "x {x}");
        }
    }

    #[test]
    fn inverse_area_round_trips() {
        // docs/physics.md §3.3 and §5.3 operating points: 3.76 mm² ↔ x_s 1.009 mm, 25.06 mm² ↔ 3.032 mm.
        assert!((PORTS.position_for_area(3.76e-6) - 1.009e-3).abs() < 2e-6);
        assert!((PORTS.position_for_area(25.06e-6) - 3.032e-3).abs() < 2e-6);
        for k in 1..100 {
            let a = k as f64 * 0.5e-6;
            let x = PORTS.position_for_area(a);
            assert!((PORTS.area(x) - a).abs() < 1e-12, "A {a}");
        }
        // over the whole range, from a micron of opening to the last micron before full open, on
        // the opening h (where A is flat, at the ends, the opening is the meaningful accuracy)
        let full = 2.0 * PI * 9e-6;
        for k in 0..=2000 {
            let h = 1e-6 + (6e-3 - 2e-6) * k as f64 / 2000.0;
            let a = PORTS.area(0.3e-3 + h);
            let x = PORTS.position_for_area(a);
            let slope = PORTS.area_slope(x).max(1e-12);
            // the area's own rounding (its two terms cancel at small openings) over its slope
            let resolution = 4.0 * f64::EPSILON * (PORTS.n_ports * 9e-6 * PI) / slope;
            assert!((x - (0.3e-3 + h)).abs() <= resolution.max(1e-15), "h {h}: x {x}, area {a} of {full}");
        }
        assert_eq!(PORTS.position_for_area(0.0), 0.3e-3);
        assert_eq!(PORTS.position_for_area(-1.0), 0.3e-3);
        assert!((PORTS.position_for_area(full) - 6.3e-3).abs() < 1e-15);
        assert!((PORTS.position_for_area(1.0) - 6.3e-3).abs() < 1e-15);
    }

    /// φ − sin φ without cancellation: its series below φ = 1 (terms to φ²⁵, under 1e-20).
    fn kepler(phi: f64) -> f64 {
        if phi >= 1.0 {
            return phi - phi.sin();
        }
        let x2 = phi * phi;
        let (mut term, mut total) = (phi * x2 / 6.0, 0.0);
        for k in 1..=12 {
            total += term;
            let n = 2.0 * k as f64 + 1.0;
            term *= -x2 / ((n + 1.0) * (n + 2.0));
        }
        total
    }

    #[test]
    fn the_segment_area_is_the_circle_segments() {
        // the segment's area acos(1 − u) − (1 − u)·sqrt(u(2 − u)) from the library's acos where its
        // two terms do not cancel, and below u = 1/2 as (φ − sin φ)/2 with φ = 4 asin(sqrt(u/2))
        let reference = |u: f64| {
            if u >= 0.5 {
                (1.0 - u).acos() - (1.0 - u) * (u * (2.0 - u)).sqrt()
            } else {
                0.5 * kepler(4.0 * (0.5 * u).sqrt().asin())
            }
        };
        let mut worst = 0.0f64;
        let openings = (1..40_000).map(|k| 2.0 * k as f64 / 40_000.0);
        // small openings down to 1e-15 of the radius, and the last ones before the port is open
        let ends = (0..=300).flat_map(|k| {
            let u = 10f64.powf(-15.0 + 14.0 * k as f64 / 300.0);
            [u, 2.0 - u]
        });
        for u in openings.chain(ends) {
            worst = worst.max((segment_area(u) / reference(u) - 1.0).abs());
        }
        assert!(worst < 4e-15, "worst relative error {worst:e}");
    }

    #[test]
    fn the_opening_table_is_within_its_bound() {
        let t_max = (6.0 * PI).powf(2.0 / 3.0);
        assert!((t_max / KEPLER_T_MAX - 1.0).abs() < 4.0 * f64::EPSILON);
        let mut worst = 0.0f64;
        for k in 1..=8000 {
            let t = t_max * k as f64 / 8000.0;
            let m = t.powf(1.5) / 6.0;
            // the root by bisection on the monotone φ − sin φ, to the last bit
            let (mut lo, mut hi) = (0.0, 2.0 * PI);
            while hi - lo > f64::EPSILON * hi {
                let mid = 0.5 * (lo + hi);
                if kepler(mid) < m {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let exact = (0.25 * 0.5 * (lo + hi)).sin().powi(2);
            worst = worst.max((opening_fraction(t) / exact - 1.0).abs());
        }
        assert!(worst < 2e-14, "worst relative error {worst:e}");
    }

    #[test]
    fn flow_force_matches_merritt_coefficient() {
        // 2 Cd Cv cos 69° ≈ 0.4566 with Cd 0.65, Cv 0.98: 10 mm² at 50 bar → 22.8 N.
        let f = flow_force(flow_force_gain(0.65, 0.98, 69f64.to_radians()), 10e-6, 50e5);
        assert!((f - 0.4566 * 10e-6 * 50e5).abs() < 0.01, "{f}");
        assert_eq!(flow_force(flow_force_gain(0.65, 0.98, 1.2), 10e-6, -50e5), 0.0);
    }
}
