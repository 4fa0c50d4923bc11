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

use crate::solver::cube_root_estimate;
use std::f64::consts::PI;

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
            r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt()
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
    /// φ − sin φ = M = 2A/(n r²) (eccentricity 1), odd about M = π. From the inverse series
    /// φ ≈ s (1 + s²/60 + s⁴/1400 + s⁶/25200), s = (6M)^(1/3), within 1.1 % of the root up to
    /// M = π, two Halley iterations (cubic convergence, error constant ≤ 1/12 there) reach
    /// rounding. They run on ψ = φ/4, whose sine and cosine give sin φ and cos φ by products and
    /// the opening sin²ψ directly: one `sin_cos` per iteration, a fixed cost, about a quarter of
    /// the safeguarded Newton iteration on A(h) it replaced.
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
        let s = cube_root_estimate(6.0 * m_half);
        let s2 = s * s;
        let mut psi = 0.25 * s * (1.0 + s2 * (1.0 / 60.0 + s2 * (1.0 / 1400.0 + s2 / 25_200.0)));
        // Halley on f(ψ) = 4ψ − sin 4ψ − M: f′ = 4 − 4 cos 4ψ = 32 u²c², f″ = 16 sin 4ψ, u = sin ψ, c = cos ψ
        let (mut sin, mut step) = (0.0, 0.0);
        for _ in 0..2 {
            let (u, c) = psi.sin_cos();
            let sin_4psi = 4.0 * u * c * (1.0 - 2.0 * u * u);
            let f = 4.0 * psi - sin_4psi - m_half;
            let slope = 32.0 * u * u * c * c;
            let denominator = 2.0 * slope * slope - 16.0 * f * sin_4psi;
            step = if denominator > 0.0 { 2.0 * f * slope / denominator } else { 0.0 };
            psi -= step;
            // sin(ψ − step), to O(step⁴), from the sine and cosine at hand
            sin = u * (1.0 - 0.5 * step * step) - c * step * (1.0 - step * step / 6.0);
        }
        debug_assert!(step.abs() < 1e-4, "the last correction {step} is too large for the sine's expansion");
        let opening = 2.0 * r * sin * sin;
        self.x_lap + if upper { 2.0 * r - opening } else { opening }
    }
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
    2.0 * cd * cv * theta_jet.cos()
}

#[cfg(test)]
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
    fn flow_force_matches_merritt_coefficient() {
        // 2 Cd Cv cos 69° ≈ 0.4566 with Cd 0.65, Cv 0.98: 10 mm² at 50 bar → 22.8 N.
        let f = flow_force(0.65, 0.98, 69f64.to_radians(), 10e-6, 50e5);
        assert!((f - 0.4566 * 10e-6 * 50e5).abs() < 0.01, "{f}");
        assert_eq!(flow_force(0.65, 0.98, 1.2, 10e-6, -50e5), 0.0);
    }
}
