//! Quarter truck with a suspension damper, from static equilibrium (docs/physics.md §3.7, §4.5):
//!
//! ```text
//! M_s z̈_s = −F_s,          F_s = k_s (z_s − z_u) + c_s (ż_s − ż_u) + F      (F: damper, tension +)
//! M_u z̈_u = F_s + F_t,     F_t = k_t (z_r − z_u) + c_t (ż_r − ż_u)          (tyre, compression +)
//! clipped MSD (paper eqs. 1–2): F_d = C_m [α V_rel + (1 − α) V_body] if F_d·V_rel > 0, else 0,
//!                               V_rel = ż_s − ż_u (extension +),  V_body = ż_s
//! ```
//! The road is z_r(t) = z_road + v_road (t − t_k) over a communication step from t_k; the damper
//! force input is held. Integration: classical RK4 with equal steps ≤ `h_max`.

/// Parameters (SI): generated from `modelDescription.xml`, which documents them, one field per
/// parameter (its name in lower case); `Default` gives the XML's start values.
pub use crate::model_description::Parameters as Params;

/// Inputs, held over a communication step.
#[derive(Clone, Copy, Debug, Default)]
pub struct Inputs {
    /// Road height (m).
    pub z_road: f64,
    /// Road height rate (m/s).
    pub v_road: f64,
    /// Damper force, tension positive (N).
    pub f_damper: f64,
}

/// States [z_body, v_body, z_axle, v_axle] (m, m/s, m, m/s).
pub type State = [f64; 4];

/// Clipped Modified Skyhook demand (N) for relative velocity `v_rel` and body velocity `v_body`.
pub fn msd_demand(cm: f64, alpha: f64, v_rel: f64, v_body: f64) -> f64 {
    let f = cm * (alpha * v_rel + (1.0 - alpha) * v_body);
    if f * v_rel > 0.0 {
        f
    } else {
        0.0
    }
}

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

impl Params {
    /// Derivatives and forces at state `y`, `t` (s) after the start of the communication step.
    pub fn evaluate(&self, u: &Inputs, y: &State, t: f64) -> Evaluation {
        let [z_s, v_s, z_u, v_u] = *y;
        let v_rel = v_s - v_u;
        let f_demand = msd_demand(self.cm, self.alpha, v_rel, v_s);
        let f_suspension = match self.damper_mode {
            1 => f_demand,
            2 => self.c_passive * v_rel,
            _ => u.f_damper,
        };
        let f_s = self.k_susp * (z_s - z_u) + self.c_susp * v_rel + f_suspension;
        let z_r = u.z_road + u.v_road * t;
        let f_tyre = self.k_tyre * (z_r - z_u) + self.c_tyre * (u.v_road - v_u);
        Evaluation {
            dydt: [v_s, -f_s / self.m_body, v_u, (f_s + f_tyre) / self.m_axle],
            f_suspension,
            f_tyre,
            f_demand,
        }
    }

    /// Advances `y` over `h` (s) from the start of a communication step, in
    /// [`Params::substeps`] equal steps (the slave refuses a step of more than
    /// [`crate::limits::MAX_SUBSTEPS`]; this caps them there too).
    pub fn advance(&self, u: &Inputs, y: &mut State, h: f64) {
        let n = self.substeps(h).min(crate::limits::MAX_SUBSTEPS) as usize;
        let dt = h / n as f64;
        let add = |y: &State, k: &State, s: f64| -> State { std::array::from_fn(|i| y[i] + s * k[i]) };
        for step in 0..n {
            let t = step as f64 * dt;
            let k1 = self.evaluate(u, y, t).dydt;
            let k2 = self.evaluate(u, &add(y, &k1, 0.5 * dt), t + 0.5 * dt).dydt;
            let k3 = self.evaluate(u, &add(y, &k2, 0.5 * dt), t + 0.5 * dt).dydt;
            let k4 = self.evaluate(u, &add(y, &k3, dt), t + dt).dydt;
            *y = std::array::from_fn(|i| y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
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

    #[test]
    fn msd_is_clipped_to_dissipation() {
        assert!((msd_demand(24e3, 0.8, 0.1, 0.0) - 1920.0).abs() < 1e-9);
        // body moving up fast while the damper compresses slowly: demand would push, so 0
        assert_eq!(msd_demand(24e3, 0.8, -0.01, 0.5), 0.0);
        assert_eq!(msd_demand(24e3, 0.8, 0.0, 0.3), 0.0);
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
        let mut y = [0.01, 0.0, 0.0, 0.0];
        let e0 = energy(&y);
        for _ in 0..2000 {
            p.advance(&Inputs::default(), &mut y, 1e-3);
        }
        assert!((energy(&y) - e0).abs() < 1e-6 * e0, "energy drift {}", energy(&y) / e0 - 1.0);
    }

    #[test]
    fn static_road_offset_is_followed() {
        // a constant road height of 1 cm: with passive damping both masses settle 1 cm up
        let p = Params { c_passive: 20e3, ..table1() };
        let mut y = [0.0; 4];
        for _ in 0..10_000 {
            p.advance(&Inputs { z_road: 0.01, ..Default::default() }, &mut y, 1e-3);
        }
        assert!((y[0] - 0.01).abs() < 1e-6 && (y[2] - 0.01).abs() < 1e-6, "{y:?}");
    }
}
