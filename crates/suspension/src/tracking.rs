//! The idealised tracking damper (`damper_mode` 3): a damper whose force follows the clipped demand
//! with a pure delay and a first-order lag, set apart for extension and compression, and that stays
//! a semi-active damper (it dissipates, and never gives less than its floor `c_min·v`):
//!
//! ```text
//! F_e(t) = lag_e[F_d(t − d_e)],  F_c(t) = lag_c[F_d(t − d_c)],  lag: τ ḟ = u − f (τ = 0: f = u)
//! F = F_e if v > 0, F_c if v < 0;  then F ← max(F, c_min v) if v > 0, min(F, c_min v) if v < 0, 0 if v = 0
//! ```
//!
//! The two ends are hand results: no delay and no lag give the ideal semi-active damper
//! (`damper_mode` 1) exactly; a lag that never moves gives the passive floor `c_min·v`
//! (`damper_mode` 2 with `c_passive = c_min`). docs/benefit-map.md sweeps between them.

use crate::error::SuspensionError;

/// Samples of the demand the history keeps: 127 ms at the default 0.25 ms internal step.
pub const HISTORY: usize = 512;

/// The demand's past (N) at the starts of the internal steps, for the pure delay. A ring of fixed
/// size: no allocation while stepping, and `Copy` like the rest of the FMU state.
#[derive(Clone, Copy, Debug)]
pub struct DemandHistory {
    /// Times (s) and demands (N), oldest overwritten first.
    pub time: [f64; HISTORY],
    pub demand: [f64; HISTORY],
    /// Index of the newest sample, and how many are held (public for the FMU state's bytes;
    /// [`DemandHistory::check`] tells a restored one apart from a corrupt one).
    pub newest: usize,
    pub len: usize,
}

impl Default for DemandHistory {
    fn default() -> Self {
        Self { time: [0.0; HISTORY], demand: [0.0; HISTORY], newest: 0, len: 0 }
    }
}

impl DemandHistory {
    /// Appends the demand `f` (N) at time `t` (s), not earlier than the newest sample.
    pub fn push(&mut self, t: f64, f: f64) {
        self.newest = if self.len == 0 { 0 } else { (self.newest + 1) % HISTORY };
        self.len = (self.len + 1).min(HISTORY);
        self.time[self.newest] = t;
        self.demand[self.newest] = f;
    }

    /// Whether a restored history is one [`DemandHistory::push`] could have made: finite numbers,
    /// indices inside the ring.
    pub fn check(&self) -> Result<(), SuspensionError> {
        if !self.time.iter().chain(&self.demand).all(|x| x.is_finite()) {
            return Err(SuspensionError::PastNotFinite);
        }
        if self.len > HISTORY || self.newest >= HISTORY {
            return Err(SuspensionError::PastIndex);
        }
        Ok(())
    }

    /// The span of time (s) the history covers once full, at internal steps of `dt` (s).
    pub fn span(dt: f64) -> f64 {
        (HISTORY - 2) as f64 * dt
    }

    /// The `i`-th sample back from the newest (0: the newest), as (time, demand).
    fn back(&self, i: usize) -> (f64, f64) {
        let k = (self.newest + HISTORY - i) % HISTORY;
        (self.time[k], self.demand[k])
    }

    /// The demand (N) at time `at` (s), with `present` the demand at `now` (s) ≥ every sample:
    /// linear between the samples around `at` (or between the newest and the present), the oldest
    /// sample before it (the demand before the start is the start's), `present` when there is no
    /// past.
    pub fn at(&self, at: f64, now: f64, present: f64) -> f64 {
        if at >= now || self.len == 0 {
            return present;
        }
        let mut later = (now, present);
        for i in 0..self.len {
            let (t, f) = self.back(i);
            if t <= at {
                let w = if later.0 > t { (at - t) / (later.0 - t) } else { 1.0 };
                return f + w * (later.1 - f);
            }
            later = (t, f);
        }
        later.1
    }
}

/// The delays (s) and lag time constants (s) of the two directions, and the floor (N·s/m).
#[derive(Clone, Copy, Debug)]
pub struct Tracking {
    pub delay: [f64; 2],
    pub time_constant: [f64; 2],
    pub c_min: f64,
}

/// Index of the extension and the compression path in [`Tracking`]'s arrays.
pub const EXTENSION: usize = 0;
pub const COMPRESSION: usize = 1;

/// `force` (N, tension positive) kept to what a semi-active damper moving at `v` (m/s, extension
/// positive) can give: dissipative and at least its floor `c_min·v`.
pub fn dissipative(force: f64, v: f64, c_min: f64) -> f64 {
    if v > 0.0 {
        force.max(c_min * v)
    } else if v < 0.0 {
        force.min(c_min * v)
    } else {
        0.0
    }
}

impl Tracking {
    /// The delayed demand (N) of each path at `now` (s), `present` the demand at `now`.
    pub fn delayed(&self, past: &DemandHistory, now: f64, present: f64) -> [f64; 2] {
        std::array::from_fn(|i| if self.delay[i] > 0.0 { past.at(now - self.delay[i], now, present) } else { present })
    }

    /// The force of each path (N): its lag state `lag`, or the delayed demand where it has no lag.
    pub fn paths(&self, lag: [f64; 2], delayed: [f64; 2]) -> [f64; 2] {
        std::array::from_fn(|i| if self.time_constant[i] > 0.0 { lag[i] } else { delayed[i] })
    }

    /// The rates of the lag states (N/s); 0 for a path without a lag.
    pub fn lag_rates(&self, lag: [f64; 2], delayed: [f64; 2]) -> [f64; 2] {
        std::array::from_fn(|i| {
            let tau = self.time_constant[i];
            if tau > 0.0 {
                (delayed[i] - lag[i]) / tau
            } else {
                0.0
            }
        })
    }

    /// The damper force (N) at velocity `v` (m/s) from the paths' forces.
    pub fn force(&self, paths: [f64; 2], v: f64) -> f64 {
        let path = if v > 0.0 { paths[EXTENSION] } else { paths[COMPRESSION] };
        dissipative(path, v, self.c_min)
    }

    /// The longest delay (s).
    pub fn longest_delay(&self) -> f64 {
        self.delay[EXTENSION].max(self.delay[COMPRESSION])
    }

    /// The fastest lag rate (1/s): 0 without a lag.
    pub fn fastest_rate(&self) -> f64 {
        self.time_constant.iter().filter(|t| **t > 0.0).map(|t| 1.0 / t).fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_history_interpolates_and_holds_its_start() {
        let mut h = DemandHistory::default();
        assert_eq!(h.at(0.5, 1.0, 7.0), 7.0, "no past: the present");
        for k in 0..4 {
            h.push(k as f64, 10.0 * k as f64);
        }
        assert_eq!(h.at(1.25, 4.0, 40.0), 12.5);
        assert_eq!(h.at(3.5, 4.0, 100.0), 65.0, "between the newest and the present");
        assert_eq!(h.at(-2.0, 4.0, 40.0), 0.0, "before the start: the start's");
        assert_eq!(h.at(4.0, 4.0, 40.0), 40.0);
    }

    #[test]
    fn the_ring_keeps_the_newest_samples() {
        let mut h = DemandHistory::default();
        for k in 0..(HISTORY + 10) {
            h.push(k as f64, k as f64);
        }
        assert_eq!(h.len, HISTORY);
        let now = (HISTORY + 10) as f64;
        assert_eq!(h.at(now - 100.5, now, now), now - 100.5);
        assert_eq!(h.at(0.0, now, now), 10.0, "older than the ring: its oldest");
    }

    #[test]
    fn the_force_dissipates_above_its_floor() {
        let t = Tracking { delay: [0.0; 2], time_constant: [0.0; 2], c_min: 1000.0 };
        assert_eq!(t.force([5000.0, -3000.0], 0.5), 5000.0);
        assert_eq!(t.force([-200.0, -3000.0], 0.5), 500.0, "a pushing force is the floor");
        assert_eq!(t.force([5000.0, -3000.0], -0.5), -3000.0);
        assert_eq!(t.force([5000.0, -100.0], -0.5), -500.0);
        assert_eq!(t.force([5000.0, -3000.0], 0.0), 0.0);
    }
}
