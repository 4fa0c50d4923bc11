//! The three-axle truck, from static equilibrium (docs/physics.md §3.8). Coordinates: the body's
//! heave z (m, up), pitch θ (rad, nose up) and roll φ (rad, left side up) at its centre of mass; each
//! axle's bounce z_i (m) and roll φ_i (rad). Corner k is axle i = k/2 on side σ = +1 (left, k even)
//! or −1 (right); axle i is x_i = x_cg − x_axle,i ahead of the centre of mass, its springs and
//! dampers at ±s/2 (`suspension_track`), its tyres at ±t/2 (`tyre_track`):
//!
//! ```text
//! at the damper:  z_b,k = z + x_i θ + σ s/2 φ,   z_a,k = z_i + σ s/2 φ_i,   v_rel,k = ż_b,k − ż_a,k
//! suspension:     F_s,k = k_s,i (z_b,k − z_a,k) + c_s v_rel,k + F_k          (F_k: damper, tension +)
//! tyre:           F_t,k = k_t,i (z_r,k − z_i − σ t/2 φ_i) + c_t (ż_r,k − ż_i − σ t/2 φ̇_i)   (compression +)
//! roll coupling:  T_i = k_roll,i (φ − φ_i)                                     (stabiliser, arms)
//! M z̈   = −Σ F_s,k
//! I_θ θ̈ = −Σ x_i F_s,k
//! I_φ φ̈ = −Σ σ s/2 F_s,k − Σ T_i + M g h φ                                    (h: h_roll)
//! m_i z̈_i = Σ_k∈i (F_s,k + F_t,k),     J_i φ̈_i = Σ_k∈i σ (s/2 F_s,k + t/2 F_t,k) + T_i
//! ```
//! Each damper's force F_k is, by `damper_mode`, its input, the clipped demand of the law at its
//! corner (body and axle velocities at the damper), the passive damper or the tracking damper
//! (the `suspension` crate's, as in `QuarterTruck.fmu`). The road at each tyre is z_road +
//! v_road (t − t_k) over a communication step from t_k. Integration: classical RK4 with equal steps
//! ≤ `h_max`. With the same road under all six tyres at once and every corner alike, the body only
//! heaves and every corner is the quarter truck (a test).

use suspension::integration::rk4_step;
use suspension::laws::{DemandLaw, PassiveDamper};
use suspension::tracking::{DemandHistory, Tracking, COMPRESSION, EXTENSION};

/// Parameters (SI): generated from `modelDescription.xml`, which documents them, one field per
/// parameter (its name in lower case, `.` as `_`); `Default` gives the XML's start values.
pub use crate::model_description::Parameters as Params;

/// Corners (front, first and second drive axle; left before right) and axles.
pub const CORNERS: usize = 6;
pub const AXLES: usize = 3;
/// Degrees of freedom: the body's heave, pitch and roll, then each axle's bounce and roll.
pub const DOF: usize = 9;
/// States: the nine coordinates, their nine rates, then each corner's two tracking-lag states (N,
/// extension then compression; 0 in the other modes).
pub const STATES: usize = 2 * DOF + 2 * CORNERS;
pub type State = [f64; STATES];
const HEAVE: usize = 0;
const PITCH: usize = 1;
const ROLL: usize = 2;

/// The damper modes of `damper_mode`, as in `QuarterTruck.fmu`.
pub const MODE_IDEAL: i32 = 1;
pub const MODE_PASSIVE: i32 = 2;
pub const MODE_TRACKING: i32 = 3;

/// Inputs, held over a communication step: the struct generated from `modelDescription.xml`'s
/// inputs, an array per name over the six corners (road height `z_road` and its rate `v_road`
/// under each tyre, each damper's force `f_damper`, tension positive).
pub use crate::model_description::Inputs;

/// The side of corner `k`: +1 left, −1 right.
pub fn side(k: usize) -> f64 {
    if k.is_multiple_of(2) {
        1.0
    } else {
        -1.0
    }
}

/// One axle's parameters (SI), `x` its distance ahead of the body's centre of mass (m).
#[derive(Clone, Copy, Debug)]
pub struct Axle {
    pub x: f64,
    pub mass: f64,
    pub roll_inertia: f64,
    pub k_susp: f64,
    pub k_tyre: f64,
    pub k_roll: f64,
}

/// The body's and the axle's motion at a corner's damper: displacements (m) and velocities (m/s).
#[derive(Clone, Copy, Debug, Default)]
pub struct AtDamper {
    pub z_body: f64,
    pub v_body: f64,
    pub z_axle: f64,
    pub v_axle: f64,
}

impl AtDamper {
    /// The damper's extension velocity (m/s).
    pub fn v_rel(&self) -> f64 {
        self.v_body - self.v_axle
    }
}

/// The forces at one corner (N).
#[derive(Clone, Copy, Debug, Default)]
pub struct CornerForces {
    /// Damper force on body and axle, tension positive, by `damper_mode`.
    pub suspension: f64,
    /// Dynamic tyre force, compression positive.
    pub tyre: f64,
    /// The clipped demand.
    pub demand: f64,
}

/// Everything evaluated at one state and time.
#[derive(Clone, Copy, Debug)]
pub struct Evaluation {
    pub dydt: State,
    pub corners: [CornerForces; CORNERS],
    pub at_damper: [AtDamper; CORNERS],
}

/// When an evaluation is: `since_step` (s) after the start of the communication step at
/// `step_start` (s), with each corner's demand past.
#[derive(Clone, Copy, Debug)]
pub struct At<'a> {
    pub step_start: f64,
    pub since_step: f64,
    pub past: &'a [DemandHistory; CORNERS],
}

impl Params {
    /// Axle `i` (0 front, 1 and 2 the drive axles).
    pub fn axle(&self, i: usize) -> Axle {
        let (x_axle, mass, roll_inertia, k_susp, k_tyre, k_roll) = match i {
            0 => (0.0, self.front_m_axle, self.front_j_axle, self.front_k_susp, self.front_k_tyre, self.front_k_roll),
            1 => (
                self.drive1_x_axle,
                self.drive1_m_axle,
                self.drive1_j_axle,
                self.drive1_k_susp,
                self.drive1_k_tyre,
                self.drive1_k_roll,
            ),
            _ => (
                self.drive2_x_axle,
                self.drive2_m_axle,
                self.drive2_j_axle,
                self.drive2_k_susp,
                self.drive2_k_tyre,
                self.drive2_k_roll,
            ),
        };
        Axle { x: self.x_cg - x_axle, mass, roll_inertia, k_susp, k_tyre, k_roll }
    }

    /// The demand law of the parameters, every corner's.
    pub fn demand_law(&self) -> DemandLaw {
        DemandLaw { cm: self.cm, alpha: self.alpha, c_ground: self.c_ground, c_min: self.c_min }
    }

    /// The passive damper of `damper_mode` 2, every corner's.
    pub fn passive_damper(&self) -> PassiveDamper {
        PassiveDamper {
            c: self.c_passive,
            compression_ratio: self.passive_compression_ratio,
            v_knee: self.passive_v_knee,
            high_speed_ratio: self.passive_high_speed_ratio,
        }
    }

    /// The tracking damper's delays, lags and floor, every corner's.
    pub fn tracking(&self) -> Tracking {
        Tracking {
            delay: [self.tracking_delay_extension, self.tracking_delay_compression],
            time_constant: [self.tracking_time_constant_extension, self.tracking_time_constant_compression],
            c_min: self.c_min,
        }
    }

    /// The body's and the axle's motion at corner `k`'s damper in state `y`.
    pub fn at_damper(&self, y: &State, k: usize) -> AtDamper {
        let (i, arm) = (k / 2, side(k) * 0.5 * self.suspension_track);
        let x = self.axle(i).x;
        let (q, v) = (&y[..DOF], &y[DOF..2 * DOF]);
        AtDamper {
            z_body: q[HEAVE] + x * q[PITCH] + arm * q[ROLL],
            v_body: v[HEAVE] + x * v[PITCH] + arm * v[ROLL],
            z_axle: q[3 + 2 * i] + arm * q[4 + 2 * i],
            v_axle: v[3 + 2 * i] + arm * v[4 + 2 * i],
        }
    }

    /// The vertical acceleration (m/s²) of the body at `x` (m ahead of its centre of mass) and `y`
    /// (m left of its centre line), from the coordinates' accelerations `a`.
    pub fn body_acceleration(a: &[f64], x: f64, y: f64) -> f64 {
        a[HEAVE] + x * a[PITCH] + y * a[ROLL]
    }

    /// The coordinates' accelerations at state `y` with damper forces `f_damper` (N) and the road
    /// (m, m/s) under each tyre; and the tyre forces (N).
    pub fn accelerations(
        &self,
        y: &State,
        f_damper: &[f64; CORNERS],
        z_road: &[f64; CORNERS],
        v_road: &[f64; CORNERS],
    ) -> ([f64; DOF], [f64; CORNERS]) {
        let (q, v) = (&y[..DOF], &y[DOF..2 * DOF]);
        let mut force = [0.0; DOF]; // generalised forces (N, N·m)
        let mut f_tyre = [0.0; CORNERS];
        for k in 0..CORNERS {
            let (i, sigma) = (k / 2, side(k));
            let axle = self.axle(i);
            let (arm, tyre_arm) = (sigma * 0.5 * self.suspension_track, sigma * 0.5 * self.tyre_track);
            let d = self.at_damper(y, k);
            let f_s = axle.k_susp * (d.z_body - d.z_axle) + self.c_susp * d.v_rel() + f_damper[k];
            let z_hub = q[3 + 2 * i] + tyre_arm * q[4 + 2 * i];
            let v_hub = v[3 + 2 * i] + tyre_arm * v[4 + 2 * i];
            f_tyre[k] = axle.k_tyre * (z_road[k] - z_hub) + self.c_tyre * (v_road[k] - v_hub);
            force[HEAVE] -= f_s;
            force[PITCH] -= axle.x * f_s;
            force[ROLL] -= arm * f_s;
            force[3 + 2 * i] += f_s + f_tyre[k];
            force[4 + 2 * i] += arm * f_s + tyre_arm * f_tyre[k];
        }
        for i in 0..AXLES {
            let t = self.axle(i).k_roll * (q[ROLL] - q[4 + 2 * i]);
            force[ROLL] -= t;
            force[4 + 2 * i] += t;
        }
        force[ROLL] += self.m_body * self.gravity * self.h_roll * q[ROLL];
        let inertia = self.inertia();
        (std::array::from_fn(|j| force[j] / inertia[j]), f_tyre)
    }

    /// The mass or moment of inertia of each coordinate (kg, kg·m²).
    pub fn inertia(&self) -> [f64; DOF] {
        let a = |i| self.axle(i);
        [
            self.m_body,
            self.i_pitch,
            self.i_roll,
            a(0).mass,
            a(0).roll_inertia,
            a(1).mass,
            a(1).roll_inertia,
            a(2).mass,
            a(2).roll_inertia,
        ]
    }

    /// Derivatives and forces at state `y` and time `at`.
    pub fn evaluate(&self, u: &Inputs, y: &State, at: At<'_>) -> Evaluation {
        let at_damper: [AtDamper; CORNERS] = std::array::from_fn(|k| self.at_damper(y, k));
        let law = self.demand_law();
        let tracking = self.tracking();
        let now = at.step_start + at.since_step;
        let mut dydt = [0.0; STATES];
        let corners: [CornerForces; CORNERS] = std::array::from_fn(|k| {
            let d = at_damper[k];
            let demand = law.demand(d.v_rel(), d.v_body, d.v_axle);
            let suspension = match self.damper_mode {
                MODE_IDEAL => demand,
                MODE_PASSIVE => self.passive_damper().force(d.v_rel()),
                MODE_TRACKING => {
                    let lag = [y[2 * DOF + 2 * k], y[2 * DOF + 2 * k + 1]];
                    let delayed = tracking.delayed(&at.past[k], now, demand);
                    let rates = tracking.lag_rates(lag, delayed);
                    dydt[2 * DOF + 2 * k + EXTENSION] = rates[EXTENSION];
                    dydt[2 * DOF + 2 * k + COMPRESSION] = rates[COMPRESSION];
                    tracking.force(tracking.paths(lag, delayed), d.v_rel())
                }
                _ => u.f_damper[k],
            };
            CornerForces { suspension, tyre: 0.0, demand }
        });
        let f_damper = corners.map(|c| c.suspension);
        let z_road: [f64; CORNERS] = std::array::from_fn(|k| u.z_road[k] + u.v_road[k] * at.since_step);
        let (acceleration, f_tyre) = self.accelerations(y, &f_damper, &z_road, &u.v_road);
        dydt[..DOF].copy_from_slice(&y[DOF..2 * DOF]);
        dydt[DOF..2 * DOF].copy_from_slice(&acceleration);
        let corners = std::array::from_fn(|k| CornerForces { tyre: f_tyre[k], ..corners[k] });
        Evaluation { dydt, corners, at_damper }
    }

    /// Each corner's clipped demand (N) at state `y`.
    pub fn demands(&self, y: &State) -> [f64; CORNERS] {
        let law = self.demand_law();
        std::array::from_fn(|k| {
            let d = self.at_damper(y, k);
            law.demand(d.v_rel(), d.v_body, d.v_axle)
        })
    }

    /// Advances `y` over `h` (s) from the start of a communication step at `step_start` (s), in
    /// [`Params::substeps`] equal steps (capped at [`crate::limits::MAX_SUBSTEPS`]). The tracking
    /// damper's demands are kept in `past` at the start of each step.
    pub fn advance(&self, u: &Inputs, y: &mut State, h: f64, step_start: f64, past: &mut [DemandHistory; CORNERS]) {
        let n = self.substeps(h).min(crate::limits::MAX_SUBSTEPS) as usize;
        let dt = h / n as f64;
        for step in 0..n {
            let t = step as f64 * dt;
            if self.damper_mode == MODE_TRACKING {
                for (history, demand) in past.iter_mut().zip(self.demands(y)) {
                    history.push(step_start + t, demand);
                }
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

    /// Runs `p` for `n` communication steps of 1 ms with the road `road(t)` (m) under tyre k;
    /// returns the states at the steps' ends.
    fn run(p: &Params, n: usize, road: impl Fn(usize, f64) -> f64) -> Vec<State> {
        let (mut y, mut past) = (p.start_state(), [DemandHistory::default(); CORNERS]);
        (0..n)
            .map(|step| {
                let t = step as f64 * 1e-3;
                let z_road = std::array::from_fn(|k| road(k, t));
                let v_road = std::array::from_fn(|k| (road(k, t + 1e-3) - road(k, t)) / 1e-3);
                p.advance(&Inputs { z_road, v_road, f_damper: [0.0; CORNERS] }, &mut y, 1e-3, t, &mut past);
                y
            })
            .collect()
    }

    fn wave(t: f64) -> f64 {
        0.01 * (2.0 * std::f64::consts::PI * 1.5 * t).sin()
    }

    #[test]
    fn the_same_road_under_every_tyre_only_heaves_the_body() {
        for damper_mode in [MODE_IDEAL, MODE_PASSIVE] {
            let p = Params { damper_mode, ..Params::default() };
            let states = run(&p, 3000, |_, t| wave(t));
            let heave = states.iter().map(|y| y[0].abs()).fold(0.0, f64::max);
            assert!(heave > 5e-3, "the road moves the body: {heave} m");
            for y in &states {
                // pitch, roll and the axles' roll stay at rounding level; the axles move alike
                assert!(y[1].abs() < 1e-12 && y[2].abs() < 1e-12, "pitch {} roll {}", y[1], y[2]);
                assert!([4, 6, 8].iter().all(|&j| y[j].abs() < 1e-12));
                assert!((y[3] - y[5]).abs() < 1e-12 && (y[3] - y[7]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_road_under_one_side_is_mirrored_by_the_other_side() {
        let p = Params { damper_mode: MODE_IDEAL, ..Params::default() };
        let left = run(&p, 2000, |k, t| if side(k) > 0.0 { wave(t) } else { 0.0 });
        let right = run(&p, 2000, |k, t| if side(k) < 0.0 { wave(t) } else { 0.0 });
        let roll = left.iter().map(|y| y[2].abs()).fold(0.0, f64::max);
        assert!(roll > 1e-3, "one side's road rolls the body: {roll} rad");
        for (l, r) in left.iter().zip(&right) {
            // heave, pitch and axle bounce alike; roll and axle roll opposite
            for j in [0, 1, 3, 5, 7] {
                assert!((l[j] - r[j]).abs() < 1e-12, "coordinate {j}");
            }
            for j in [2, 4, 6, 8] {
                assert!((l[j] + r[j]).abs() < 1e-12, "coordinate {j}");
            }
        }
    }

    #[test]
    fn undamped_energy_is_conserved_by_rk4() {
        let p = Params {
            damper_mode: MODE_PASSIVE,
            c_passive: 0.0,
            pitch_start: 0.01,
            roll_start: 0.02,
            ..Params::default()
        };
        // kinetic, springs, tyres, roll couplings, and gravity's −½ M g h φ²
        let energy = |y: &State| {
            let inertia = p.inertia();
            let mut e: f64 = (0..DOF).map(|j| 0.5 * inertia[j] * y[DOF + j] * y[DOF + j]).sum();
            for k in 0..CORNERS {
                let (i, d) = (k / 2, p.at_damper(y, k));
                let hub = y[3 + 2 * i] + side(k) * 0.5 * p.tyre_track * y[4 + 2 * i];
                e += 0.5 * p.axle(i).k_susp * (d.z_body - d.z_axle).powi(2) + 0.5 * p.axle(i).k_tyre * hub * hub;
            }
            for i in 0..AXLES {
                e += 0.5 * p.axle(i).k_roll * (y[ROLL] - y[4 + 2 * i]).powi(2);
            }
            e - 0.5 * p.m_body * p.gravity * p.h_roll * y[ROLL] * y[ROLL]
        };
        let states = run(&p, 2000, |_, _| 0.0);
        let e0 = energy(&p.start_state());
        for y in &states {
            assert!((energy(y) - e0).abs() < 1e-6 * e0, "energy drift {}", energy(y) / e0 - 1.0);
        }
    }

    #[test]
    fn a_static_road_offset_is_followed() {
        let p = Params { damper_mode: MODE_PASSIVE, ..Params::default() };
        let y = *run(&p, 10_000, |_, _| 0.01).last().unwrap();
        assert!((y[0] - 0.01).abs() < 1e-6 && y[1].abs() < 1e-6 && y[2].abs() < 1e-6, "{y:?}");
        assert!([3, 5, 7].iter().all(|&j| (y[j] - 0.01).abs() < 1e-6));
    }
}
