//! The effect catalog: the physical effects a damper model may lack, one file per effect.
//!
//! Each effect has a Boolean switch `effect_<key>` in `modelDescription.xml` and one or more
//! parameters that set its size and shape. An effect tells the tools around the model what it is
//! ([`EffectInfo`]: its parameters, their plausible ranges, the residual signature it leaves when
//! missing), and, if it adds a force or a flow to the circuit, computes it ([`Effect::force`],
//! [`Effect::bypass_flow`], [`Effect::base_flow`]). The plant sums the contributions of the
//! switched-on effects.
//!
//! The structural effects (compressibility, mount compliance, amplifier delay, flow forces,
//! check-valve cracking) change a component's law; their equations live in that component, which
//! their [`EffectInfo::code`] names (`tests/effects.rs` checks that the function is there). Seal
//! friction, piston leakage and viscous friction are written entirely behind the trait. The effect
//! table of docs/effects.md and docs/physics.md §8 is rendered from this catalog (same test).
//!
//! Adding an effect (docs/effects.md walks through `viscous_friction.rs` as the worked example):
//! 1. write `src/effects/<key>.rs` with a unit struct `<Key>` (the key in CamelCase) implementing
//!    [`Effect`]: `build.rs` lists every file of this folder in [`CATALOG`], by key;
//! 2. declare `effect_<key>` (Boolean) and its parameters in `modelDescription.xml` and set the
//!    GUID the build prints: the parameters become fields of `Parameters` (generated from the
//!    XML), the switch is read by [`Effect::is_on`]; `tests/effects.rs` checks that the file and
//!    the XML agree.

use crate::physics::params::Parameters;

/// A parameter of an effect that a diagnosis fits.
#[derive(Clone, Copy, Debug)]
pub struct FittedParameter {
    /// The FMU parameter's name in `modelDescription.xml`.
    pub name: &'static str,
    /// Search range of a fit, in the parameter's SI unit.
    pub search: (f64, f64),
    /// Search (and draw hidden values) on a logarithmic scale.
    pub log: bool,
    /// Physically plausible range; a fitted value outside it is flagged.
    pub plausible: (f64, f64),
    /// Step of a parameter the model quantises (a delay in controller samples): a fit searches
    /// the grid, since a derivative-based fit cannot move on a staircase.
    pub grid: Option<f64>,
    /// Where a fit starts when the effect is switched on.
    pub start: Start,
}

/// Where a fit of a parameter starts when its effect is switched on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// At the model's value (the default, or the calibrated one).
    Model,
    /// At this fraction of the largest |stroke| of the record's fitted part (m): for a position
    /// where something starts to act (an end stop), which a fit can only find from where the
    /// record reaches.
    OfLargestStroke(f64),
    /// At the value of another parameter of the model, named here, in the same unit: where the
    /// physics ties the two (oil saturated with the reservoir's gas at its pre-charge), so that a
    /// damper described with another pre-charge is searched from its own.
    SameAs(&'static str),
}

/// When the diagnosis tries an effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Candidacy {
    /// Switched on where the model lacks it, refitted where it has it.
    Always,
    /// A part of some dampers' build (a passive valve): refitted where the model has it, never
    /// switched on by a diagnosis (a damper does not grow a valve; its signature is a leakage's).
    WhenOn,
    /// Acts through the measured oil temperature: tried only on records with a temperature column.
    WithTemperature,
    /// Acts through the controlled valve (its spool, its amplifier): tried only where the valve is
    /// controlled (`control_mode` 0 or 1), not held.
    Controlled,
}

/// How a data generator hides an effect so that a record shows it.
#[derive(Clone, Copy, Debug)]
pub struct HideWith {
    /// Other parameters set with it: e.g. an end stop placed within the generator's stroke.
    pub set: &'static [(&'static str, f64)],
    /// The oil temperature's rise over the record (K), from `T_ref`: 0 for a constant temperature.
    pub temperature_rise: f64,
}

impl HideWith {
    /// Nothing besides the effect's size.
    pub const NOTHING: HideWith = HideWith { set: &[], temperature_rise: 0.0 };
}

/// A function of this crate: its file, relative to the crate's root, and its name, `Type::method`
/// for a method.
#[derive(Clone, Copy, Debug)]
pub struct CodeRef {
    /// The source file, e.g. `src/physics/valve.rs`.
    pub file: &'static str,
    /// The function's name, e.g. `flow_force` or `DelayLine::push`.
    pub function: &'static str,
}

/// What an effect is, for the tools around the model (diagnosis, data generator, docs).
#[derive(Clone, Copy, Debug)]
pub struct EffectInfo {
    /// The key: the switch is the Boolean parameter `effect_<key>`.
    pub key: &'static str,
    /// One line: what switching it on adds.
    pub meaning: &'static str,
    /// Its equation in plain text, in the parameters' names.
    pub equation: &'static str,
    /// The function that computes the equation.
    pub code: CodeRef,
    /// The parameters a diagnosis fits, one or two; the first is the effect's size.
    pub fitted: &'static [FittedParameter],
    /// Parameters fitted together with `fitted` once the diagnosis keeps the effect (the data pin
    /// them only when the effect is clearly in the record; fitting them for every candidate
    /// would cost more runs and give each candidate more freedom to absorb another's error).
    pub secondary: &'static [FittedParameter],
    /// Its other parameters (held at their values during a fit).
    pub other: &'static [&'static str],
    /// Range a data generator draws the size from when it hides the effect: plausible, and away
    /// from the model's default so that a refitted default-on effect shows.
    pub hidden_range: (f64, f64),
    /// How a generator hides it so that a record shows it.
    pub hide_with: HideWith,
    /// When the diagnosis tries it.
    pub candidacy: Candidacy,
    /// The residual r = F_model − F_measured when the model lacks the effect, in plain words.
    pub signature: &'static str,
}

/// The plant's signals at one instant, as an effect sees them (SI units). The oil's temperature
/// and viscosity come from the measured input `T_oil` and are constant over a step; the solver
/// differentiates an effect's force and flows with respect to the other six.
#[derive(Clone, Copy, Debug)]
pub struct PlantSignals {
    /// Damper extension velocity (m/s).
    pub v_damper: f64,
    /// Damper stroke (m), 0 at mid-stroke.
    pub x_damper: f64,
    /// Extension (annulus) chamber gauge pressure (Pa).
    pub p_ext: f64,
    /// Compression (full-bore) chamber gauge pressure (Pa).
    pub p_comp: f64,
    /// Reservoir gauge pressure (Pa).
    pub p_reservoir: f64,
    /// Spool position (m).
    pub x_spool: f64,
    /// Oil temperature (K): the input `T_oil` (its start value unless a master or a record gives
    /// it).
    pub temperature: f64,
    /// The oil's viscosity over its viscosity at `T_ref` (-): 1 unless `oil_temperature` is on
    /// ([`crate::physics::fluid::viscosity_ratio`]).
    pub viscosity_ratio: f64,
}

/// A physical effect. Implementations are unit structs; everything they need comes from the
/// parameters and the signals, so they stay pure functions that the solver may call at any state.
pub trait Effect: Sync {
    /// What the effect is.
    fn info(&self) -> &'static EffectInfo;
    /// Whether its switch `effect_<key>` is on (an effect without a switch in
    /// `modelDescription.xml` is never on).
    fn is_on(&self, p: &Parameters) -> bool {
        p.switch(self.info().key).unwrap_or(false)
    }
    /// Which of the plant's sums it adds to: none for a structural effect (its law lives in its
    /// component). The plant calls only the effects that add something, so an effect that
    /// writes [`Effect::force`] or [`Effect::bypass_flow`] says so here (`tests/effects.rs`
    /// checks that the others add nothing).
    fn terms(&self) -> Terms {
        Terms::NONE
    }
    /// Force (N) in parallel with the piston, tension (extension) positive; the load cell
    /// measures it and the mount carries it.
    fn force(&self, _p: &Parameters, _s: &PlantSignals) -> f64 {
        0.0
    }
    /// Flow (m³/s) from the extension chamber to the compression chamber past the valve.
    fn bypass_flow(&self, _p: &Parameters, _s: &PlantSignals) -> f64 {
        0.0
    }
    /// Flow (m³/s) from the compression chamber to the reservoir (a base valve).
    fn base_flow(&self, _p: &Parameters, _s: &PlantSignals) -> f64 {
        0.0
    }
    /// The partial derivatives of [`Effect::force`] with respect to each signal (each field of
    /// the result holds ∂force/∂that signal), for the solver's Jacobian. Default: central
    /// differences of `force`, so a new effect needs no derivative to work; the catalog's own
    /// effects write theirs out (`tests/physics.rs` checks them against differences).
    fn force_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        numeric_gradient(s, |s| self.force(p, s))
    }
    /// The partial derivatives of [`Effect::bypass_flow`], as [`Effect::force_gradient`].
    fn bypass_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        numeric_gradient(s, |s| self.bypass_flow(p, s))
    }
    /// The partial derivatives of [`Effect::base_flow`], as [`Effect::force_gradient`].
    fn base_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        numeric_gradient(s, |s| self.base_flow(p, s))
    }
}

impl PlantSignals {
    /// All fields zero (the gradient of a constant).
    pub const ZERO: PlantSignals = PlantSignals {
        v_damper: 0.0,
        x_damper: 0.0,
        p_ext: 0.0,
        p_comp: 0.0,
        p_reservoir: 0.0,
        x_spool: 0.0,
        temperature: 0.0,
        viscosity_ratio: 0.0,
    };

    fn fields_mut(&mut self) -> [&mut f64; 6] {
        [
            &mut self.v_damper,
            &mut self.x_damper,
            &mut self.p_ext,
            &mut self.p_comp,
            &mut self.p_reservoir,
            &mut self.x_spool,
        ]
    }

    fn fields(&self) -> [f64; 6] {
        [self.v_damper, self.x_damper, self.p_ext, self.p_comp, self.p_reservoir, self.x_spool]
    }
}

/// Increment of each signal for central differences: relative, floored at a typical size
/// (velocity, stroke, three pressures, spool position; SI units).
const GRADIENT_SCALE: [f64; 6] = [1e-2, 1e-3, 1e5, 1e5, 1e5, 1e-3];

/// Central-difference gradient of `f` at the signals `s`.
pub fn numeric_gradient(s: &PlantSignals, f: impl Fn(&PlantSignals) -> f64) -> PlantSignals {
    let mut gradient = PlantSignals::ZERO;
    let values = s.fields();
    for (k, slot) in gradient.fields_mut().into_iter().enumerate() {
        let h = 1e-6 * values[k].abs().max(GRADIENT_SCALE[k]);
        let (mut up, mut down) = (*s, *s);
        *up.fields_mut()[k] += h;
        *down.fields_mut()[k] -= h;
        *slot = (f(&up) - f(&down)) / (2.0 * h);
    }
    gradient
}

// The effects' modules and `CATALOG`, from the files of this folder (build.rs).
include!(concat!(env!("OUT_DIR"), "/effect_catalog.rs"));

/// The effect of `key`.
pub fn find(key: &str) -> Option<&'static dyn Effect> {
    CATALOG.into_iter().find(|e| e.info().key == key)
}

/// Which of the plant's sums an effect adds to (see [`Effect::terms`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terms {
    /// A force in parallel with the piston ([`Effect::force`]).
    pub force: bool,
    /// A flow past the valve ([`Effect::bypass_flow`]).
    pub bypass_flow: bool,
    /// A flow from the compression chamber to the reservoir ([`Effect::base_flow`]).
    pub base_flow: bool,
}

impl Terms {
    /// None (a structural effect).
    pub const NONE: Terms = Terms { force: false, bypass_flow: false, base_flow: false };
    /// A force only.
    pub const FORCE: Terms = Terms { force: true, ..Terms::NONE };
    /// A bypass flow only.
    pub const BYPASS_FLOW: Terms = Terms { bypass_flow: true, ..Terms::NONE };
    /// A base flow only.
    pub const BASE_FLOW: Terms = Terms { base_flow: true, ..Terms::NONE };
}

/// The switched-on effects that add a force or a flow, listed once from the parameters, so
/// that an evaluation of the plant calls these alone (with the default parameters, none): asking
/// every effect of the catalog at each evaluation, and differencing the structural effects'
/// zero forces for the Jacobian, had cost a tenth of the model's instructions.
#[derive(Clone, Copy)]
pub struct ActiveEffects {
    force: EffectList,
    bypass_flow: EffectList,
    base_flow: EffectList,
}

/// Up to the whole catalog, in catalog order.
#[derive(Clone, Copy)]
struct EffectList {
    items: [&'static dyn Effect; CATALOG.len()],
    len: usize,
}

impl EffectList {
    fn of(p: &Parameters, adds: impl Fn(Terms) -> bool) -> Self {
        let mut list = EffectList { items: CATALOG, len: 0 };
        for e in CATALOG {
            if e.is_on(p) && adds(e.terms()) {
                list.items[list.len] = e;
                list.len += 1;
            }
        }
        list
    }

    fn iter(&self) -> impl Iterator<Item = &'static dyn Effect> + '_ {
        self.items[..self.len].iter().copied()
    }
}

impl std::fmt::Debug for ActiveEffects {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let keys = |l: &EffectList| l.iter().map(|e| e.info().key).collect::<Vec<_>>();
        f.debug_struct("ActiveEffects")
            .field("force", &keys(&self.force))
            .field("bypass_flow", &keys(&self.bypass_flow))
            .field("base_flow", &keys(&self.base_flow))
            .finish()
    }
}

impl ActiveEffects {
    /// The effects that `p` switches on and that add to a sum.
    pub fn of(p: &Parameters) -> Self {
        ActiveEffects {
            force: EffectList::of(p, |t| t.force),
            bypass_flow: EffectList::of(p, |t| t.bypass_flow),
            base_flow: EffectList::of(p, |t| t.base_flow),
        }
    }

    /// Whether any effect adds a force.
    pub fn adds_force(&self) -> bool {
        self.force.len > 0
    }

    /// Sum of their forces (N).
    #[inline]
    pub fn force(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        self.force.iter().map(|e| e.force(p, s)).sum()
    }

    /// Sum of their bypass flows (m³/s).
    #[inline]
    pub fn bypass_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        self.bypass_flow.iter().map(|e| e.bypass_flow(p, s)).sum()
    }

    /// Sum of their base flows (m³/s).
    #[inline]
    pub fn base_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        self.base_flow.iter().map(|e| e.base_flow(p, s)).sum()
    }

    /// Whether any effect adds a base flow.
    pub fn adds_base_flow(&self) -> bool {
        self.base_flow.len > 0
    }

    /// Gradient of [`ActiveEffects::force`] with respect to the signals.
    #[inline]
    pub fn force_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        self.force.iter().map(|e| e.force_gradient(p, s)).fold(PlantSignals::ZERO, sum)
    }

    /// Gradient of [`ActiveEffects::bypass_flow`] with respect to the signals.
    #[inline]
    pub fn bypass_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        self.bypass_flow.iter().map(|e| e.bypass_flow_gradient(p, s)).fold(PlantSignals::ZERO, sum)
    }

    /// Gradient of [`ActiveEffects::base_flow`] with respect to the signals.
    #[inline]
    pub fn base_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        self.base_flow.iter().map(|e| e.base_flow_gradient(p, s)).fold(PlantSignals::ZERO, sum)
    }
}

#[inline]
fn sum(mut a: PlantSignals, b: PlantSignals) -> PlantSignals {
    for (x, y) in a.fields_mut().into_iter().zip(b.fields()) {
        *x += y;
    }
    a
}
