//! Quarter truck with a suspension damper, from static equilibrium (docs/physics.md §3.7, §4.5):
//!
//! ```text
//! M_s z̈_s = −F_s,          F_s = k_s (z_s − z_u) + c_s (ż_s − ż_u) + F      (F: damper, tension +)
//! M_u z̈_u = F_s + F_t,     F_t = k_t (z_r − z_u) + c_t (ż_r − ż_u)          (tyre, compression +)
//! clipped MSD (paper eqs. 1–2): F_d = C_m [α V_rel + (1 − α) V_body] − C_g ż_u where it resists
//!                               V_rel at least as much as c_min V_rel, else c_min V_rel (the paper:
//!                               C_g = 0, c_min = 0), V_rel = ż_s − ż_u (extension +),  V_body = ż_s
//! ```
//! The road is z_r(t) = z_road + v_road (t − t_k) over a communication step from t_k; the damper
//! force input is held. The tracking damper (`damper_mode` 3, [`crate::tracking`]) adds two lag
//! states and the demand's past. Integration: classical RK4 with equal steps ≤ `h_max`.

use suspension::integration::rk4_step;
pub use suspension::laws::{DemandLaw, PassiveDamper};
use suspension::tracking::{DemandHistory, Tracking, COMPRESSION, EXTENSION};

/// Parameters (SI): generated from `modelDescription.xml`, which documents them, one field per
/// parameter (its name in lower case); `Default` gives the XML's start values.
pub use crate::model_description::Parameters as Params;

/// Inputs, held over a communication step: the struct generated from `modelDescription.xml`'s
/// inputs (road height `z_road`, its rate `v_road`, the damper force `f_damper`).
pub use crate::model_description::Inputs;

/// States [z_body, v_body, z_axle, v_axle, f_extension, f_compression] (m, m/s, m, m/s, N, N): the
/// last two are the tracking damper's lag states (0 in the other modes).
pub type State = [f64; 6];

/// The damper modes of `damper_mode`.
pub const MODE_IDEAL: i32 = 1;
pub const MODE_PASSIVE: i32 = 2;
pub const MODE_TRACKING: i32 = 3;

/// Everything evaluated at one state and time.
#[derive(Clone, Copy, Debug, Default)]
pub struct Evaluation {
    pub dydt: State,
    /// Damper force on the masses (N), by `damper_mode`.
    pub f_suspension: f64,
    /// Dynamic tyre force, compression positive (N).
    pub f_tyre: f64,
    /// Clipped MSD demand (N).
    pub f_demand: f64,
}

/// When an evaluation is: `since_step` (s) after the start of the communication step (the road's
/// extrapolation), at the absolute time `step_start + since_step`, with the demand's past before it.
#[derive(Clone, Copy, Debug)]
pub struct At<'a> {
    pub step_start: f64,
    pub since_step: f64,
    pub past: &'a DemandHistory,
}

impl Params {
    /// The tracking damper's delays, lags and floor.
    pub fn tracking(&self) -> Tracking {
        Tracking {
            delay: [self.tracking_delay_extension, self.tracking_delay_compression],
            time_constant: [self.tracking_time_constant_extension, self.tracking_time_constant_compression],
            c_min: self.c_min,
        }
    }

    /// The passive damper (`damper_mode` 2): slope `c_passive` in extension and
    /// `passive_compression_ratio` times it in compression, each changing by
    /// `passive_high_speed_ratio` beyond ±`passive_v_knee`.
    pub fn passive_damper(&self) -> PassiveDamper {
        PassiveDamper {
            c: self.c_passive,
            compression_ratio: self.passive_compression_ratio,
            v_knee: self.passive_v_knee,
            high_speed_ratio: self.passive_high_speed_ratio,
        }
    }

    /// The demand law of the parameters.
    pub fn demand_law(&self) -> DemandLaw {
        DemandLaw { cm: self.cm, alpha: self.alpha, c_ground: self.c_ground, c_min: self.c_min }
    }

    /// The clipped demand (N) at state `y`.
    pub fn demand(&self, y: &State) -> f64 {
        self.demand_law().demand(y[1] - y[3], y[1], y[3])
    }

    /// Derivatives and forces at state `y` and time `at`.
    pub fn evaluate(&self, u: &Inputs, y: &State, at: At<'_>) -> Evaluation {
        let [z_s, v_s, z_u, v_u, lag_e, lag_c] = *y;
        let v_rel = v_s - v_u;
        let f_demand = self.demand(y);
        let mut lag_rates = [0.0; 2];
        let f_suspension = match self.damper_mode {
            MODE_IDEAL => f_demand,
            MODE_PASSIVE => self.passive_damper().force(v_rel),
            MODE_TRACKING => {
                let tracking = self.tracking();
                let delayed = tracking.delayed(at.past, at.step_start + at.since_step, f_demand);
                lag_rates = tracking.lag_rates([lag_e, lag_c], delayed);
                tracking.force(tracking.paths([lag_e, lag_c], delayed), v_rel)
            }
            _ => u.f_damper,
        };
        let f_s = self.k_susp * (z_s - z_u) + self.c_susp * v_rel + f_suspension;
        let z_r = u.z_road + u.v_road * at.since_step;
        let f_tyre = self.k_tyre * (z_r - z_u) + self.c_tyre * (u.v_road - v_u);
        Evaluation {
            dydt: [
                v_s,
                -f_s / self.m_body,
                v_u,
                (f_s + f_tyre) / self.m_axle,
                lag_rates[EXTENSION],
                lag_rates[COMPRESSION],
            ],
            f_suspension,
            f_tyre,
            f_demand,
        }
    }

    /// Advances `y` over `h` (s) from the start of a communication step at `step_start` (s), in
    /// [`Params::substeps`] equal steps (the slave refuses a step of more than
    /// [`crate::limits::MAX_SUBSTEPS`]; this caps them there too). The tracking damper's demand is
    /// kept in `past` at the start of each step.
    pub fn advance(&self, u: &Inputs, y: &mut State, h: f64, step_start: f64, past: &mut DemandHistory) {
        let n = self.substeps(h).min(crate::limits::MAX_SUBSTEPS) as usize;
        let dt = h / n as f64;
        for step in 0..n {
            let t = step as f64 * dt;
            if self.damper_mode == MODE_TRACKING {
                past.push(step_start + t, self.demand(y));
            }
            let past = &*past;
            *y = rk4_step(y, dt, |y, s| self.evaluate(u, y, At { step_start, since_step: t + s, past }).dydt);
        }
    }
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;
    use suspension::tracking::dissipative;

    fn table1() -> Params {
        Params {
            m_body: 4450.0,
            m_axle: 420.0,
            k_susp: 0.5e6,
            k_tyre: 1.95e6,
            cm: 24e3,
            alpha: 0.8,
            h_max: 2.5e-4,
            damper_mode: 2,
            ..Params::default()
        }
    }

    /// Runs `p` for `n` communication steps of 1 ms over a 1.5 Hz road of 1 cm; per step the force
    /// on the masses, the demand and the damper velocity at its end.
    fn run(p: &Params, n: usize) -> Vec<(f64, f64, f64)> {
        let (mut y, mut past) = (p.start_state(), DemandHistory::default());
        let road = |t: f64| 0.01 * (2.0 * std::f64::consts::PI * 1.5 * t).sin();
        (0..n)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let u = Inputs { z_road: road(t), v_road: (road(t + 1e-3) - road(t)) / 1e-3, f_damper: 0.0 };
                p.advance(&u, &mut y, 1e-3, t, &mut past);
                let at = At { step_start: t + 1e-3, since_step: 0.0, past: &past };
                let e = p.evaluate(&u, &y, at);
                (e.f_suspension, e.f_demand, y[1] - y[3])
            })
            .collect()
    }

    #[test]
    fn no_delay_and_no_lag_is_the_ideal_damper() {
        let ideal = run(&Params { damper_mode: MODE_IDEAL, ..table1() }, 3000);
        let tracking = run(&Params { damper_mode: MODE_TRACKING, ..table1() }, 3000);
        assert!(ideal.iter().any(|r| r.0.abs() > 1e3), "the road works the damper");
        assert!(ideal.iter().zip(&tracking).all(|(a, b)| a.0.to_bits() == b.0.to_bits()));
    }

    #[test]
    fn a_lag_that_never_moves_is_the_passive_floor() {
        let c_min = 3000.0;
        let passive = run(&Params { damper_mode: MODE_PASSIVE, c_passive: c_min, ..table1() }, 3000);
        let slow = Params {
            damper_mode: MODE_TRACKING,
            c_min,
            tracking_time_constant_extension: 1e9,
            tracking_time_constant_compression: 1e9,
            ..table1()
        };
        let tracking = run(&slow, 3000);
        let scale = passive.iter().map(|r| r.0.abs()).fold(0.0, f64::max);
        assert!(scale > 50.0, "the floor works: {scale} N");
        for (a, b) in passive.iter().zip(&tracking) {
            assert!((a.0 - b.0).abs() < 1e-6 * scale, "{} against {}", b.0, a.0);
        }
    }

    #[test]
    fn the_force_is_the_demand_of_a_delay_before() {
        // 5 ms in extension, 12 ms in compression: whole internal steps, where the past is exact
        let p = Params {
            damper_mode: MODE_TRACKING,
            tracking_delay_extension: 5e-3,
            tracking_delay_compression: 12e-3,
            ..table1()
        };
        let r = run(&p, 3000);
        let (mut extension, mut compression) = (0, 0);
        for k in 20..r.len() {
            let (force, _, v) = r[k];
            let back = if v > 0.0 { 5 } else { 12 };
            let expected = dissipative(r[k - back].1, v, 0.0);
            assert!((force - expected).abs() < 1e-9 * (1.0 + expected.abs()), "step {k}: {force} against {expected}");
            extension += (v > 0.0 && force > 0.0) as usize;
            compression += (v < 0.0 && force < 0.0) as usize;
        }
        assert!(extension > 100 && compression > 100, "{extension} {compression}");
    }

    #[test]
    fn undamped_energy_is_conserved_by_rk4() {
        let p = Params { c_passive: 0.0, ..table1() };
        let energy = |y: &State| {
            0.5 * p.m_body * y[1] * y[1]
                + 0.5 * p.m_axle * y[3] * y[3]
                + 0.5 * p.k_susp * (y[0] - y[2]).powi(2)
                + 0.5 * p.k_tyre * y[2] * y[2]
        };
        let mut y = [0.01, 0.0, 0.0, 0.0, 0.0, 0.0];
        let mut past = DemandHistory::default();
        let e0 = energy(&y);
        for _ in 0..2000 {
            p.advance(&Inputs::default(), &mut y, 1e-3, 0.0, &mut past);
        }
        assert!((energy(&y) - e0).abs() < 1e-6 * e0, "energy drift {}", energy(&y) / e0 - 1.0);
    }

    #[test]
    fn static_road_offset_is_followed() {
        // a constant road height of 1 cm: with passive damping both masses settle 1 cm up
        let p = Params { c_passive: 20e3, ..table1() };
        let (mut y, mut past) = ([0.0; 6], DemandHistory::default());
        for _ in 0..10_000 {
            p.advance(&Inputs { z_road: 0.01, ..Default::default() }, &mut y, 1e-3, 0.0, &mut past);
        }
        assert!((y[0] - 0.01).abs() < 1e-6 && (y[2] - 0.01).abs() < 1e-6, "{y:?}");
    }
}
