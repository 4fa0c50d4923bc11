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

use crate::solver::{cube_root_estimate, cube_root_halley_step};
use std::f64::consts::{FRAC_PI_2, PI};

/// The coefficients, lowest first, of P in the starter φ ≈ s (1 + P(s²)) for Kepler's equation
/// φ − sin φ = s³/6 with 0 ≤ s ≤ (6π)^(1/3) ([`ValvePorts::position_for_area`]): a least-squares
/// fit of degree 7 to the root at 400 Chebyshev points of s² (numpy's `Polynomial.fit`), within
/// 4e-7 of the root relative (the test `the_kepler_starter_is_within_its_bound` holds it). Its
/// first terms are near the inverse series' 1/60 and 1/1400.
const KEPLER_STARTER: [f64; 8] = [
    -2.992838293209165e-07,
    0.0166718334940775,
    0.0006998116530200269,
    5.488546648055911e-05,
    -5.159680623863694e-06,
    2.1761353005714727e-06,
    -2.5755765376692247e-07,
    1.619156874337786e-08,
];

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
            r * r * acos_one_minus(h / r) - (r - h) * (2.0 * r * h - h * h).sqrt()
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
    /// φ − sin φ = M = 2A/(n r²) (eccentricity 1), odd about M = π. The starter is
    /// φ ≈ s (1 + P(s²)), s = (6M)^(1/3), with P of degree 7 fitted to the root over
    /// 0 ≤ M ≤ π (`KEPLER_STARTER`): within 4e-7 of it. One Halley iteration (cubic convergence,
    /// error constant ≤ 1/12 there) then reaches rounding. It runs on ψ = φ/4, whose sine and
    /// cosine give sin φ and cos φ by products and the opening sin²ψ directly: one `sin_cos`, a
    /// fixed cost. (The inverse series' first terms, 1 + s²/60 + s⁴/1400 + s⁶/25200, are within
    /// 1.1 % and took two iterations, two `sin_cos`.)
    pub fn position_for_area(&self, area: f64) -> f64 {
        let r = self.r_port;
        let scale = self.n_ports * r * r;
        let m = (2.0 * area / scale).clamp(0.0, 2.0 * PI);
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
        // the estimate's 1e-4 would be the starter's error: one more Halley step takes it to 1e-12
        let s = cube_root_halley_step(cube_root_estimate(6.0 * m_half), 6.0 * m_half);
        let s2 = s * s;
        let p = KEPLER_STARTER.iter().rev().fold(0.0, |acc, &c| acc * s2 + c);
        let psi = 0.25 * s * (1.0 + p);
        // Halley on f(ψ) = 4ψ − sin 4ψ − M: f′ = 4 − 4 cos 4ψ = 32 u²c², f″ = 16 sin 4ψ, u = sin ψ, c = cos ψ
        let (u, c) = libm::sincos(psi);
        let sin_4psi = 4.0 * u * c * (1.0 - 2.0 * u * u);
        let f = 4.0 * psi - sin_4psi - m_half;
        let slope = 32.0 * u * u * c * c;
        let denominator = 2.0 * slope * slope - 16.0 * f * sin_4psi;
        let step = if denominator > 0.0 { 2.0 * f * slope / denominator } else { 0.0 };
        debug_assert!(step.abs() <= 1e-5 * psi, "the correction {step} is larger than the starter's error");
        // sin(ψ − step), to O(step⁴), from the sine and cosine at hand
        let sin = u * (1.0 - 0.5 * step * step) - c * step * (1.0 - step * step / 6.0);
        let opening = 2.0 * r * sin * sin;
        self.x_lap + if upper { 2.0 * r - opening } else { opening }
    }
}

/// acos(1 − u) (rad) for 0 ≤ u ≤ 2, the half angle of a port's uncovered segment at the opening
/// u = h/r, within a few ulps: an arcsine on |z| ≤ 1/2 only, through the half-angle identities
/// acos(1 − u) = 2 asin(√(u/2)) and π − 2 asin(√(1 − u/2)) at the ends. Every evaluation of the
/// plant takes the port area, and glibc's `acos` (with its argument reduction for the whole
/// range) was 4 % of the damper's instructions.
fn acos_one_minus(u: f64) -> f64 {
    if u <= 0.5 {
        2.0 * asin_within_half((0.5 * u).sqrt())
    } else if u < 1.5 {
        FRAC_PI_2 - asin_within_half(1.0 - u)
    } else {
        PI - 2.0 * asin_within_half((1.0 - 0.5 * u).sqrt())
    }
}

/// asin z for |z| ≤ 1/2, within an ulp: z + z·t·P(t)/Q(t), t = z², with fdlibm's coefficients
/// (e_asin.c, the rational approximation it uses on the same range).
fn asin_within_half(z: f64) -> f64 {
    const P: [f64; 6] = [
        0.16666666666666666,
        -0.3255658186224009,
        0.20121253213486293,
        -0.04005553450067941,
        0.0007915349942898145,
        3.479331075960212e-05,
    ];
    const Q: [f64; 4] = [-2.403394911734414, 2.0209457602335057, -0.6882839716054533, 0.07703815055590194];
    let t = z * z;
    let p = t * (P[0] + t * (P[1] + t * (P[2] + t * (P[3] + t * (P[4] + t * P[5])))));
    let q = 1.0 + t * (Q[0] + t * (Q[1] + t * (Q[2] + t * Q[3])));
    z + z * (p / q)
}

/// Force (N) of the proportional solenoid with force constant `k_sol` (N/A) at current `i` (A),
/// spool position `x_spool` (m); `kappa` is the relative force slope over the stroke `x_max` (m).
pub fn solenoid_force(k_sol: f64, kappa: f64, x_max: f64, i: f64, x_spool: f64) -> f64 {
    k_sol * i * (1.0 + kappa * (x_spool / x_max - 0.5))
}

/// Steady flow force (N) on the spool, acting to close the valve: jet momentum through the open
/// area `area` (m²) under the pressure drop `dp` (Pa) (only positive drops drive the jet).
pub fn flow_force(cd: f64, cv: f64, theta_jet: f64, area: f64, dp: f64) -> f64 {
    flow_force_gain(cd, cv, theta_jet) * area * dp.max(0.0)
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

    #[test]
    fn acos_one_minus_is_the_library_acos() {
        // at arguments x whose 1 − x is exact, so that both see the same angle
        let check = |x: f64| {
            let u = 1.0 - x;
            assert_eq!(1.0 - u, x);
            let (fast, library) = (acos_one_minus(u), x.acos());
            assert!((fast - library).abs() <= 4.0 * f64::EPSILON * library, "u {u:e}: {fast} vs {library}");
        };
        for k in 0..=20_000 {
            check(1.0 - 2.0 * k as f64 / 20_000.0);
        }
        // small openings, where the segment's area is a small difference of its two terms
        for k in 0..=300 {
            check(1.0 - 10f64.powf(-15.0 + 14.0 * k as f64 / 300.0));
        }
        assert_eq!(acos_one_minus(0.0), 0.0);
        assert_eq!(acos_one_minus(2.0), PI);
    }

    #[test]
    fn the_kepler_starter_is_within_its_bound() {
        let s_max = (6.0 * PI).cbrt();
        for k in 1..=4000 {
            let s = s_max * k as f64 / 4000.0;
            let m = s * s * s / 6.0;
            // the root by bisection on φ − sin φ (monotone), in the form that keeps small φ exact
            let (mut lo, mut hi) = (0.0, 2.0 * PI);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                let g = if mid < 0.1 {
                    mid.powi(3) / 6.0 * (1.0 - mid * mid / 20.0 + mid.powi(4) / 840.0)
                } else {
                    mid - mid.sin()
                };
                if g < m {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            let root = 0.5 * (lo + hi);
            let starter = s * (1.0 + KEPLER_STARTER.iter().rev().fold(0.0, |acc, &c| acc * s * s + c));
            assert!((starter / root - 1.0).abs() < 4e-7, "s {s}: starter {starter}, root {root}");
        }
    }

    #[test]
    fn flow_force_matches_merritt_coefficient() {
        // 2 Cd Cv cos 69° ≈ 0.4566 with Cd 0.65, Cv 0.98: 10 mm² at 50 bar → 22.8 N.
        let f = flow_force(0.65, 0.98, 69f64.to_radians(), 10e-6, 50e5);
        assert!((f - 0.4566 * 10e-6 * 50e5).abs() < 0.01, "{f}");
        assert_eq!(flow_force(0.65, 0.98, 1.2, 10e-6, -50e5), 0.0);
    }
}
