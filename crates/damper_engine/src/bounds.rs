//! The box a fitted parameter is searched in by Levenberg–Marquardt (`crate::lm`), for the
//! diagnosis's candidates and for calibration: bounds, and a logarithmic scale for parameters
//! spanning decades (leakage, stiffness).

/// How a parameter is searched: its box, and whether on a logarithmic scale (needs lo > 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bound {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
}

impl Bound {
    /// The searched coordinate of `x`: ln x on a logarithmic scale, x otherwise.
    pub fn to_internal(self, x: f64) -> f64 {
        if self.log {
            libm::log(x)
        } else {
            x
        }
    }

    /// The parameter at the searched coordinate `u`.
    pub fn to_physical(self, u: f64) -> f64 {
        if self.log {
            libm::exp(u)
        } else {
            u
        }
    }

    /// The box in the searched coordinate.
    pub fn internal_box(self) -> (f64, f64) {
        (self.to_internal(self.lo), self.to_internal(self.hi))
    }

    /// dθ/du at `x`.
    pub fn slope(self, x: f64) -> f64 {
        if self.log {
            x
        } else {
            1.0
        }
    }

    /// `x` moved into the box.
    pub fn clamp(self, x: f64) -> f64 {
        x.max(self.lo).min(self.hi)
    }

    /// True when `x` lies within `fraction` of the (searched) range of a bound.
    pub fn near_bound(self, x: f64, fraction: f64) -> bool {
        let (lo, hi) = self.internal_box();
        let u = self.to_internal(x);
        (u - lo) < fraction * (hi - lo) || (hi - u) < fraction * (hi - lo)
    }
}
