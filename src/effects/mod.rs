//! The effect catalog: the physical effects a damper model may lack, one file per effect.
//!
//! Each effect has a Boolean switch `effect_<key>` in `modelDescription.xml` and one or more
//! parameters that set its size and shape. An effect tells the tools around the model what it is
//! ([`EffectInfo`]: its parameters, their plausible ranges, the residual signature it leaves when
//! missing), and, if it adds a force or a flow to the circuit, computes it ([`Effect::force`],
//! [`Effect::bypass_flow`]). The plant sums the contributions of the switched-on effects.
//!
//! The structural effects (compressibility, mount compliance, amplifier delay, flow forces,
//! check-valve cracking) change a component's law; their equations live in that component, which
//! their [`EffectInfo::code`] names (`tests/effects.rs` checks that the function is there). Seal
//! friction, piston leakage and viscous friction are written entirely behind the trait. The effect
//! table of docs/effects.md and docs/physics.md §8 is rendered from this catalog (same test).
//!
//! Adding an effect (docs/effects.md walks through `viscous_friction.rs` as the worked example):
//! 1. write `src/effects/<key>.rs` with a unit struct implementing [`Effect`];
//! 2. list it in [`CATALOG`] below;
//! 3. declare `effect_<key>` (Boolean) and its parameters in `modelDescription.xml`, add the
//!    fields to `Parameters`, and follow the compile errors (`variables.rs`, `snapshot.rs`) and
//!    the build's GUID message; `tests/effects.rs` checks that the file and the XML agree.

mod amplifier_delay;
mod check_valve_cracking;
mod compressibility;
mod flow_forces;
mod mount_compliance;
mod piston_leakage;
mod seal_friction;
mod viscous_friction;

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
    /// the grid, since a simplex cannot move on a staircase.
    pub grid: Option<f64>,
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
    /// The residual r = F_model − F_measured when the model lacks the effect, in plain words.
    pub signature: &'static str,
}

/// The plant's signals at one instant, as an effect sees them (SI units).
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
}

/// A physical effect. Implementations are unit structs; everything they need comes from the
/// parameters and the signals, so they stay pure functions that the solver may call at any state.
pub trait Effect: Sync {
    /// What the effect is.
    fn info(&self) -> &'static EffectInfo;
    /// Whether its switch `effect_<key>` is on.
    fn is_on(&self, p: &Parameters) -> bool;
    /// Force (N) in parallel with the piston, tension (extension) positive; the load cell
    /// measures it and the mount carries it.
    fn force(&self, _p: &Parameters, _s: &PlantSignals) -> f64 {
        0.0
    }
    /// Flow (m³/s) from the extension chamber to the compression chamber past the valve.
    fn bypass_flow(&self, _p: &Parameters, _s: &PlantSignals) -> f64 {
        0.0
    }
}

/// Every effect, in the order of docs/effects.md.
pub const CATALOG: [&dyn Effect; 8] = [
    &compressibility::Compressibility,
    &mount_compliance::MountCompliance,
    &amplifier_delay::AmplifierDelay,
    &flow_forces::FlowForces,
    &seal_friction::SealFriction,
    &piston_leakage::PistonLeakage,
    &check_valve_cracking::CheckValveCracking,
    &viscous_friction::ViscousFriction,
];

/// The effect of `key`.
pub fn find(key: &str) -> Option<&'static dyn Effect> {
    CATALOG.into_iter().find(|e| e.info().key == key)
}

// Two sums, not one loop returning both: over the constant CATALOG the compiler resolves each
// iterator chain statically, and a single loop calling both hooks ran the model 30 % slower
// (`cargo bench --bench realtime`: 153x against 214x real time).

/// Sum of the switched-on effects' forces (N).
pub fn total_force(p: &Parameters, s: &PlantSignals) -> f64 {
    CATALOG.iter().filter(|e| e.is_on(p)).map(|e| e.force(p, s)).sum()
}

/// Sum of the switched-on effects' bypass flows (m³/s).
pub fn total_bypass_flow(p: &Parameters, s: &PlantSignals) -> f64 {
    CATALOG.iter().filter(|e| e.is_on(p)).map(|e| e.bypass_flow(p, s)).sum()
}
