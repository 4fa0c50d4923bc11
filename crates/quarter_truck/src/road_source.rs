//! Where the quarter truck's road comes from (`road_source`): the inputs z_road and v_road, fed by
//! a master at each communication point, or an ISO 8608 random road the FMU makes from its
//! `road_*` parameters at initialisation ([`suspension::road`]) and feeds itself, so that a master
//! without Python (ecos, libcosim, OMSimulator) can run the HiL scenarios' roads at the FMUs' speed.
//!
//! The self-made road feeds what a master would: at the start of the step from t_k by h, z_road =
//! z(t_k) and v_road = (z(t_k + h) − z(t_k))/h ([`suspension::road::Road::segment`]), from which
//! the truck extrapolates as it does with a master's inputs. So a run with `road_source = 1` and
//! one with the same road fed from `damper_tools.roads.road_case` differ only by the profile's
//! rounding (about 1e-15 of its RMS, the inverse FFT's).

use crate::slave::Slave;
use crate::truck::Params;
use fmi_slave::Refusal;
use std::sync::Arc;
use suspension::error::RoadError;
use suspension::road::{Road, RoadParameters, RoadSegment};

/// `road_source` 0: the road is the inputs z_road and v_road.
pub const SOURCE_INPUTS: i32 = 0;
/// `road_source` 1: the FMU makes an ISO 8608 road from the `road_*` parameters.
pub const SOURCE_ISO8608: i32 = 1;

/// The road the FMU made, with the parameters it was made from (a restored state or a reset
/// with the same parameters keeps it rather than making it again).
///
/// Shared (`Arc`), because an FMU state is a copy of the slave: a master that saves a state at
/// every step (fmpy's `fmi2GetFMUstate` loop, an optimiser's line search) copies a pointer, not a
/// profile of 15 000 samples (120 kB for the default 300 m).
#[derive(Clone, Debug, Default)]
pub struct RoadSource {
    made: Option<(RoadParameters, Arc<Road>)>,
}

impl RoadSource {
    /// Makes the road of `wanted` (none for the inputs), unless it has it already.
    fn make(&mut self, wanted: Option<RoadParameters>) -> Result<(), Refusal> {
        self.made = match (wanted, self.made.take()) {
            (None, _) => None,
            (Some(p), Some((q, road))) if p == q => Some((q, road)),
            (Some(p), _) => Some((p, Arc::new(Road::new(&p).map_err(Refusal::model)?))),
        };
        Ok(())
    }

    /// Whether the road lasts from `t` to `t + h` (s) (the distance grows with t: the ends decide);
    /// the inputs' road always does.
    fn covers(&self, t: f64, h: f64) -> bool {
        self.made.as_ref().is_none_or(|(_, road)| road.covers(t) && road.covers(t + h))
    }

    /// The road over the step from `t` by `h` (s); `None` for the inputs' road.
    fn segment(&self, t: f64, h: f64) -> Option<Result<RoadSegment, RoadError>> {
        self.made.as_ref().map(|(_, road)| road.segment(t, h))
    }

    /// The road height (m) under the wheel at `t` (s); `None` for the inputs' road.
    fn z_at(&self, t: f64) -> Option<Result<f64, RoadError>> {
        self.made.as_ref().map(|(_, road)| road.z_at(t))
    }
}

impl Params {
    /// The road parameters, when `road_source` asks the FMU to make its road.
    fn road(&self) -> Option<RoadParameters> {
        (self.road_source == SOURCE_ISO8608).then(|| RoadParameters {
            gd0: self.road_gd0,
            seed: u64::try_from(self.road_seed).unwrap_or_default(), // the XML's min is 0
            speed: self.road_speed,
            length: self.road_length,
            dx: self.road_dx,
            waviness: self.road_waviness,
            n_min: self.road_n_min,
            n_max: self.road_n_max,
            n0: self.road_n0,
            fade_in: self.road_fade_in,
            fade_start: self.road_fade_start,
            offset: self.road_offset,
        })
    }
}

impl Slave {
    /// Makes the road the parameters ask for (truck_slave's hook). At initialisation (`fresh`) the
    /// inputs take the road under the wheel at the start time, at rest, for the outputs before the
    /// first step; a restored state keeps its own inputs.
    pub(crate) fn start_road(&mut self, fresh: bool) -> Result<(), Refusal> {
        self.road.make(self.params.road())?;
        if fresh {
            if let Some(z) = self.road.z_at(self.time) {
                (self.inputs.z_road, self.inputs.v_road) = (z.map_err(Refusal::model)?, 0.0);
            }
        }
        Ok(())
    }

    /// Whether the road lasts over the step from the present time by `h` (s).
    pub(crate) fn road_covers(&self, h: f64) -> bool {
        self.road.covers(self.time, h)
    }

    /// Feeds the made road to the inputs at the start of the step by `h` (s); the inputs' road
    /// stays as the master set it. [`Slave::road_covers`] has checked the step.
    pub(crate) fn feed_road(&mut self, h: f64) {
        if let Some(Ok(RoadSegment { z_road, v_road })) = self.road.segment(self.time, h) {
            (self.inputs.z_road, self.inputs.v_road) = (z_road, v_road);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model_description::IntegerVar;
    use fmi_slave::Model;

    const STEP: f64 = 1e-3;

    fn own_road(seconds: f64) -> (Slave, Road) {
        let p = RoadParameters::road_case(128e-6, 14.0, seconds, 7, STEP, 0.2).unwrap();
        let mut s = Slave::default();
        s.params.road_source = SOURCE_ISO8608;
        s.params.road_seed = 7;
        (s.params.road_length, s.params.road_fade_in, s.params.road_fade_start) = (p.length, 0.2, STEP);
        s.initialize(0.0).unwrap();
        (s, Road::new(&p).unwrap())
    }

    #[test]
    fn the_made_road_feeds_what_a_master_would() {
        let (mut s, road) = own_road(0.5);
        for k in 0..500 {
            s.check_step(STEP).unwrap();
            s.do_step(STEP).unwrap();
            let fed = road.at_step(k, STEP).unwrap();
            // the slave's clock is k·STEP to rounding (it adds the steps up)
            assert!((s.inputs.v_road - fed.v_road).abs() <= 1e-9, "step {k}");
            assert!((s.inputs.z_road - (fed.z_road + fed.v_road * STEP)).abs() <= 1e-12, "step {k}");
        }
        assert!(s.inputs.z_road.abs() > 1e-4, "the road has risen from level");
    }

    #[test]
    fn a_step_beyond_the_road_is_refused() {
        let (mut s, _) = own_road(0.01);
        for _ in 0..10 {
            s.do_step(STEP).unwrap();
        }
        // the profile covers 0.14 m + 1 m: 1.14 m / 14 m/s ≈ 81 ms of road, 71 ms left
        assert!(s.check_step(0.07).is_ok());
        assert!(s.check_step(0.075).is_err());
    }

    #[test]
    fn a_restored_state_makes_its_road_again_and_goes_on_alike() {
        let (mut s, _) = own_road(0.2);
        for _ in 0..50 {
            s.do_step(STEP).unwrap();
        }
        let restored = Slave::deserialize(&Slave::serialize(&s)).unwrap();
        assert!(restored.road.made.is_none(), "the bytes hold no road");
        let mut t = Slave::default();
        t.set_state(&restored).unwrap();
        for _ in 0..100 {
            s.do_step(STEP).unwrap();
            t.do_step(STEP).unwrap();
        }
        assert_eq!((s.y, s.inputs.z_road.to_bits()), (t.y, t.inputs.z_road.to_bits()));
        // a state taken in memory shares the profile rather than copying it
        let copy = s.state();
        assert!(Arc::ptr_eq(&copy.road.made.unwrap().1, &s.road.made.unwrap().1));
    }

    #[test]
    fn the_inputs_road_is_left_to_the_master() {
        let mut s = Slave::default();
        assert_eq!(s.params.integer(IntegerVar::RoadSource), Some(SOURCE_INPUTS));
        s.initialize(0.0).unwrap();
        (s.inputs.z_road, s.inputs.v_road) = (0.01, 0.5);
        s.do_step(STEP).unwrap();
        assert_eq!((s.inputs.z_road, s.inputs.v_road), (0.01 + 0.5 * STEP, 0.5));
        assert!(s.road.made.is_none());
    }
}
