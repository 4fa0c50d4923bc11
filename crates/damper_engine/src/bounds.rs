//! The box a fitted parameter is searched in, shared by the diagnosis's Nelder–Mead
//! (`crate::fit`) and calibration's Levenberg–Marquardt (`crate::lm`): bounds, and a logarithmic
//! scale for parameters spanning decades (leakage, stiffness).

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
            x.ln()
        } else {
            x
        }
    }

    /// The parameter at the searched coordinate `u`.
    pub fn to_physical(self, u: f64) -> f64 {
        if self.log {
            u.exp()
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

    /// The unbounded coordinate u of `x` under θ = lo + (hi − lo)·(1 + sin u)/2 (on the searched
    /// scale), where any u maps into the box.
    pub fn unbounded_at(self, x: f64) -> f64 {
        let (lo, hi) = self.internal_box();
        (2.0 * (self.to_internal(x) - lo) / (hi - lo) - 1.0).clamp(-1.0, 1.0).asin()
    }

    /// The parameter at the unbounded coordinate `u` ([`Bound::unbounded_at`]).
    pub fn value_at_unbounded(self, u: f64) -> f64 {
        let (lo, hi) = self.internal_box();
        self.to_physical(lo + (hi - lo) * ((1.0 + u.sin()) / 2.0))
    }

    /// True when `x` lies within `fraction` of the (searched) range of a bound.
    pub fn near_bound(self, x: f64, fraction: f64) -> bool {
        let (lo, hi) = self.internal_box();
        let u = self.to_internal(x);
        (u - lo) < fraction * (hi - lo) || (hi - u) < fraction * (hi - lo)
    }
}
