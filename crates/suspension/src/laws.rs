//! The demand law and the passive damper, per damper (forces tension positive, velocities
//! extension positive, SI).

use crate::tracking::dissipative;

/// The demand law: the paper's Modified Skyhook (eqs. 1–2), with an optional groundhook term and a
/// floor.
#[derive(Clone, Copy, Debug)]
pub struct DemandLaw {
    /// Skyhook coefficient C_m (N·s/m).
    pub cm: f64,
    /// Blend α (1): 1 = relative velocity, 0 = pure skyhook.
    pub alpha: f64,
    /// Groundhook coefficient (N·s/m) on the axle velocity.
    pub c_ground: f64,
    /// Floor of the clip (N·s/m).
    pub c_min: f64,
}

impl DemandLaw {
    /// The clipped demand (N, tension positive) at relative velocity `v_rel`, body velocity
    /// `v_body` and axle velocity `v_axle` (m/s) at the damper: C_m [α v_rel + (1 − α) v_body] −
    /// C_g v_axle, kept dissipative and at least `c_min·v_rel`.
    pub fn demand(&self, v_rel: f64, v_body: f64, v_axle: f64) -> f64 {
        let f = self.cm * (self.alpha * v_rel + (1.0 - self.alpha) * v_body) - self.c_ground * v_axle;
        dissipative(f, v_rel, self.c_min)
    }

    /// The largest damping coefficient (N·s/m) the law can put between body and axle (for the
    /// stability bound of explicit integration).
    pub fn largest_coefficient(&self) -> f64 {
        (self.cm + self.c_ground).max(self.c_min)
    }
}

/// A passive damper: slope `c` in extension and `compression_ratio·c` in compression, each
/// changing by `high_speed_ratio` beyond ±`v_knee` (a blow-off valve opening).
#[derive(Clone, Copy, Debug)]
pub struct PassiveDamper {
    /// Low-speed extension coefficient (N·s/m).
    pub c: f64,
    /// Compression coefficient over extension one (1).
    pub compression_ratio: f64,
    /// Damper speed of the knee (m/s).
    pub v_knee: f64,
    /// Slope beyond the knee over the one below (1).
    pub high_speed_ratio: f64,
}

impl PassiveDamper {
    /// A linear symmetric damper of coefficient `c` (N·s/m).
    pub fn linear(c: f64) -> Self {
        Self { c, compression_ratio: 1.0, v_knee: f64::INFINITY, high_speed_ratio: 1.0 }
    }

    /// The force (N, tension positive) at damper speed `v` (m/s, extension positive).
    pub fn force(&self, v: f64) -> f64 {
        let low = v.max(-self.v_knee).min(self.v_knee);
        let shaped = low + self.high_speed_ratio * (v - low);
        let c = if v < 0.0 { self.c * self.compression_ratio } else { self.c };
        c * shaped
    }

    /// The largest slope (N·s/m) of the force–velocity law.
    pub fn largest_coefficient(&self) -> f64 {
        self.c * self.compression_ratio.max(1.0) * self.high_speed_ratio.max(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_passive_damper_is_linear_by_default_and_shaped_on_request() {
        let linear = PassiveDamper::linear(20e3);
        for v in [-0.7, -0.05, 0.0, 0.05, 0.7] {
            assert_eq!(linear.force(v), 20e3 * v);
        }
        let shaped = PassiveDamper { c: 20e3, compression_ratio: 0.4, v_knee: 0.1, high_speed_ratio: 0.25 };
        // extension: 20 kNs/m to 0.1 m/s (2 kN), then 5 kNs/m
        assert!((shaped.force(0.3) - (2000.0 + 5000.0 * 0.2)).abs() < 1e-9);
        assert!((shaped.force(0.05) - 1000.0).abs() < 1e-9);
        // compression: 8 kNs/m to -0.1 m/s (-0.8 kN), then 2 kNs/m
        assert!((shaped.force(-0.3) - (-800.0 - 2000.0 * 0.2)).abs() < 1e-9);
    }

    #[test]
    fn msd_is_clipped_to_dissipation() {
        let msd = |c_min, v_rel, v_body| {
            DemandLaw { cm: 24e3, alpha: 0.8, c_ground: 0.0, c_min }.demand(v_rel, v_body, v_body - v_rel)
        };
        assert!((msd(0.0, 0.1, 0.0) - 1920.0).abs() < 1e-9);
        // body moving up fast while the damper compresses slowly: demand would push, so 0
        assert_eq!(msd(0.0, -0.01, 0.5), 0.0);
        assert_eq!(msd(0.0, 0.0, 0.3), 0.0);
        // with a floor: the floor where the law asks for less or pushes
        assert_eq!(msd(5e3, -0.01, 0.5), -50.0);
        assert!((msd(5e3, 0.1, -0.3) - 500.0).abs() < 1e-9);
        // groundhook: the axle moving down while the damper extends asks for C_g |v_axle|
        let ground = DemandLaw { cm: 0.0, alpha: 0.8, c_ground: 10e3, c_min: 0.0 };
        assert!((ground.demand(0.1, 0.0, -0.1) - 1000.0).abs() < 1e-9);
        assert_eq!(ground.demand(0.1, 0.2, 0.1), 0.0, "the axle moving up: it would push");
    }
}
