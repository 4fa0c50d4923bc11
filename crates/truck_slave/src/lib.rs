//! The co-simulation slave that `QuarterTruck.fmu` and `FullTruck.fmu` share: [`truck_slave!`]
//! defines, inside a truck crate's `slave` module, the `Slave` struct (the FMU state: parameters,
//! inputs, states, the demand's past, time) and its `fmi_slave::Model` implementation: variable
//! access through the generated enums with the XML's ranges, initialisation with the RK4 stability
//! check, RK4 steps that put everything back when a step fails, and the FMU state's checks.
//!
//! A macro, not a generic type, because the slave works on each crate's own generated variable
//! enums and parameter struct (from its `modelDescription.xml`), which share no trait, and because
//! the crate's `Visit` impl of the state (its field order, `fmu_state.rs`) must be on a local type.
//!
//! The invoking module has in scope: the generated `RealVar`, `IntegerVar`, `BooleanVar`,
//! `Causality`, `GUID`, `CAN_INTERPOLATE_INPUTS`; the truck's `Params`, `Inputs`, `State`,
//! `Evaluation`, `At`, `MODE_TRACKING`; `MAX_SUBSTEPS`, `MAGIC`, `DemandHistory` (`Inputs` is the
//! generated struct of the crate's inputs); and
//! from `fmi_slave`: `Model`, `Refusal`, `ToleranceNote`, `check_real`, `check_integer`,
//! `snapshot`. It implements on `Slave` what differs between the trucks:
//!
//! - `fn output_at(&self, y: &State, e: &Evaluation, v: RealVar) -> Option<f64>`: an output's value;
//! - `fn outputs_finite(&self) -> bool`: whether every output is a finite number;
//! - `fn pasts(&self) -> &[DemandHistory]`: the demands' pasts, for the restored state's check;
//! - `fn hold_road_end(&mut self, h: f64)` and `fn road_finite(&self) -> bool`: the road inputs
//!   extrapolated over a step of `h` (s), held at their end values for the outputs;
//! - `fn start_road(&mut self, fresh: bool) -> Result<(), Refusal>`, `fn road_covers(&self, h: f64)
//!   -> bool` and `fn feed_road(&mut self, h: f64)`: a road the FMU makes itself (the `road` field,
//!   of type `$road`), made at initialisation (`fresh`: the inputs take it at the start time) and
//!   for a restored state (a deserialized one lacks it), checked to cover a step before it starts,
//!   and fed to the road inputs at the step's start.

/// Defines `Slave` with the demand's past of type `$past` and the FMU's own road of type `$road`
/// ([crate docs](crate)).
#[macro_export]
macro_rules! truck_slave {
    ($past:ty, $road:ty) => {
        /// The FMU state: parameters, inputs, and once initialised the states and time.
        #[derive(Clone, Debug, Default)]
        pub struct Slave {
            pub(crate) params: Params,
            pub(crate) inputs: Inputs,
            pub(crate) y: State,
            /// The clipped demand's past, for the tracking damper's delay.
            pub(crate) past: $past,
            pub(crate) time: f64,
            pub(crate) initialized: bool,
            /// A road the FMU makes from its parameters (not in the serialized state: the
            /// parameters make it again).
            pub(crate) road: $road,
        }

        impl Slave {
            /// State and evaluation for the outputs: the present state, or the start state before
            /// initialisation. The road is taken at the end of the last step (the held inputs).
            fn evaluation(&self) -> (State, Evaluation) {
                let y = if self.initialized { self.y } else { self.params.start_state() };
                let at = At { step_start: self.time, since_step: 0.0, past: &self.past };
                (y, self.params.evaluate(&self.inputs, &y, at))
            }

            /// An output's value, at the present state (the start state before initialisation).
            fn output(&self, v: RealVar) -> Result<f64, Refusal> {
                let (y, e) = self.evaluation();
                self.output_at(&y, &e, v).ok_or(Refusal::UnknownReference(v.vr()))
            }

            fn input(&self, v: RealVar) -> Option<f64> {
                self.inputs.real(v)
            }

            fn input_mut(&mut self, v: RealVar) -> Option<&mut f64> {
                self.inputs.real_mut(v)
            }

            /// Setting a Real means nothing beyond its value.
            fn real_set(&mut self, _: RealVar) {}

            /// Checks that a restored state is one this FMU could have made: every parameter in
            /// its XML range (and, once initialised, stable), every number finite.
            fn check_restored(&self) -> Result<(), Refusal> {
                for v in RealVar::ALL {
                    if let Some(x) = self.params.real(v) {
                        check_real(v.name(), x, v.min(), v.max())?;
                    }
                    if let Some(x) = self.inputs.real(v) {
                        check_real(v.name(), x, None, None)?;
                    }
                }
                for v in IntegerVar::ALL {
                    if let Some(x) = self.params.integer(v) {
                        check_integer(v.name(), x, v.min(), v.max())?;
                    }
                }
                if !self.y.iter().chain([&self.time]).all(|x| x.is_finite()) {
                    return Err(Refusal::StateNotFinite("a state or the time"));
                }
                for past in self.pasts() {
                    past.check().map_err(Refusal::model)?;
                }
                if self.initialized {
                    self.params.validate().map_err(Refusal::model)?;
                }
                Ok(())
            }
        }

        /// The FMU state's layout of one demand history (both trucks': [`fmu_state`](crate::fmu_state)).
        pub(crate) fn visit_history<V: snapshot::Visitor>(history: &mut DemandHistory, v: &mut V) {
            let DemandHistory { time, demand, newest, len } = history;
            for x in time.iter_mut().chain(demand.iter_mut()) {
                v.real(x);
            }
            snapshot::uint(v, newest);
            snapshot::uint(v, len);
        }

        impl Model for Slave {
            const GUID: &'static str = GUID;
            const CAN_INTERPOLATE_INPUTS: bool = CAN_INTERPOLATE_INPUTS;
            type State = Slave;
            type StepError = &'static str;
            type StepWarning = std::convert::Infallible;

            fmi_slave::parameter_access!();

            fmi_slave::real_access!();

            /// One evaluation of the equations for every output of the call.
            fn get_reals(
                &self,
                vrs: &[u32],
                values: &mut [f64],
                skip: &dyn Fn(usize) -> bool,
            ) -> Result<(), (u32, Refusal)> {
                let mut evaluated: Option<(State, Evaluation)> = None;
                for (i, (&vr, x)) in vrs.iter().zip(values).enumerate() {
                    if skip(i) {
                        continue;
                    }
                    let v = RealVar::from_vr(vr).ok_or_else(|| (vr, Refusal::UnknownReference(vr)))?;
                    if let Some(known) = self.params.real(v).or_else(|| self.input(v)) {
                        *x = known;
                        continue;
                    }
                    let (y, e) = evaluated.get_or_insert_with(|| self.evaluation());
                    let value = self.output_at(y, e, v).ok_or_else(|| (vr, Refusal::UnknownReference(vr)))?;
                    if !value.is_finite() {
                        return Err((vr, Refusal::OutputNotFinite { name: v.name(), value }));
                    }
                    *x = value;
                }
                Ok(())
            }

            type Settable = (Params, Inputs);

            fn settable(&self) -> Self::Settable {
                (self.params, self.inputs)
            }

            fn restore_settable(&mut self, (params, inputs): Self::Settable) {
                (self.params, self.inputs) = (params, inputs);
            }

            /// The truck integrates with fixed RK4 steps: a tolerance has nothing to control.
            fn use_tolerance(&mut self, tolerance: f64) -> Result<ToleranceNote, Refusal> {
                Ok(ToleranceNote::Event(format!(
                    "tolerance {tolerance} not used: fixed RK4 steps no longer than the parameter h_max"
                )))
            }

            fn initialize(&mut self, start_time: f64) -> Result<(), Refusal> {
                self.params.validate().map_err(Refusal::model)?;
                self.time = start_time;
                self.start_road(true)?;
                self.y = self.params.start_state();
                self.past = Default::default();
                self.initialized = true;
                Ok(())
            }

            fn time(&self) -> Option<f64> {
                self.initialized.then_some(self.time)
            }

            fn align_time(&mut self, t: f64) {
                self.time = t;
            }

            fn check_step(&self, h: f64) -> Result<(), &'static str> {
                if self.params.substeps(h) > MAX_SUBSTEPS {
                    return Err("more than 1e7 integration steps (h/h_max) in one step");
                }
                let dt = h / self.params.substeps(h);
                if self.params.damper_mode == MODE_TRACKING
                    && self.params.tracking().longest_delay() > DemandHistory::span(dt)
                {
                    return Err("a tracking delay longer than the demand's past holds (510 internal steps of the \
                                step divided by h_max): raise h_max or shorten tracking_delay_*");
                }
                if !self.road_covers(h) {
                    return Err("the step would take the wheel beyond the end of the road the FMU made \
                                (road_source = 1): raise road_length");
                }
                Ok(())
            }

            fn do_step(&mut self, h: f64) -> Result<Option<Self::StepWarning>, &'static str> {
                // what a refused step puts back; the demand's past (4 kB a side and corner) only
                // where it moves
                let (y0, inputs0, time0) = (self.y, self.inputs, self.time);
                let past0 = (self.params.damper_mode == MODE_TRACKING).then_some(self.past);
                self.feed_road(h);
                let mut y = self.y;
                self.params.advance(&self.inputs, &mut y, h, self.time, &mut self.past);
                let restore = |s: &mut Self| {
                    (s.y, s.inputs, s.time) = (y0, inputs0, time0);
                    if let Some(past) = past0 {
                        s.past = past;
                    }
                };
                if !y.iter().all(|x| x.is_finite()) {
                    restore(self);
                    return Err("non-finite state");
                }
                self.y = y;
                self.hold_road_end(h);
                self.time += h;
                if !self.outputs_finite() || !self.road_finite() {
                    restore(self);
                    return Err("an output is not finite at the end of the step");
                }
                Ok(None)
            }

            fn state(&self) -> Slave {
                self.clone()
            }

            /// A restored state (a deserialized one has no road of its own) gets its road again.
            fn set_state(&mut self, s: &Slave) -> Result<(), Refusal> {
                let mut restored = s.clone();
                if restored.initialized {
                    restored.start_road(false)?;
                }
                *self = restored;
                Ok(())
            }

            fn state_time(s: &Slave) -> Option<f64> {
                s.time()
            }

            fn serialize(s: &Slave) -> Vec<u8> {
                snapshot::to_bytes(MAGIC, GUID, s)
            }

            fn deserialize(bytes: &[u8]) -> Result<Slave, Refusal> {
                let mut s = Slave::default();
                snapshot::from_bytes(MAGIC, GUID, bytes, &mut s)?;
                s.check_restored().map_err(Refusal::restored)?;
                Ok(s)
            }
        }
    };
}
