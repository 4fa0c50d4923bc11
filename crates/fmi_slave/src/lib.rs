//! The FMI Co-Simulation C APIs, FMI 2.0 and FMI 3.0, for any model that implements [`Model`]:
//! plain safe Rust on one side, the C ABI on the other. An FMU crate implements the trait once and
//! calls [`export_fmi2!`] or [`export_fmi3!`] (one per binary: each binary exports exactly its
//! standard's functions); the macros emit the `#[no_mangle] extern "C"` functions, each a thin shim
//! over the generic functions of [`fmi2::api`] or [`fmi3::api`], which check pointers and the
//! state machine, catch panics (a panic becomes a Fatal status, never an unwind into the host) and
//! log through the importer's callback without allocating.
//!
//! Layout: the two standards' modules, [`fmi2`] and [`fmi3`] (each its C types and entry points),
//! over what they share: `instance` (one FMU instance: state machine, experiment times, variable
//! access rules), `state_machine` (the legal-call table of both standards), `logger`, `boundary`
//! (the instance behind a C pointer, the panic guard, the FMU state boxes), `guard` (checked
//! slices), [`snapshot`] (versioned byte format of FMU states) and [`Refusal`] (why a call is
//! refused).
// The C ABI's raw pointers: the crate denies unsafe code (Cargo.toml) except in these modules.
#[allow(unsafe_code)]
mod boundary;
pub mod fmi2;
pub mod fmi3;
#[allow(unsafe_code)]
mod guard;
mod instance;
#[allow(unsafe_code)]
mod logger;
mod refusal;
pub mod snapshot;
mod state_machine;

pub use instance::{Failure, Instance, Standard};
pub use refusal::{check_integer, check_real, Refusal, Unreadable};
pub use state_machine::Phase;

/// Causality of a variable (the subset these FMUs use).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Input,
    Output,
    Parameter,
}

/// What the FMI layer needs to know about a variable.
#[derive(Clone, Copy, Debug)]
pub struct VarInfo {
    pub name: &'static str,
    pub causality: Causality,
}

/// A co-simulation model without FMI types, whichever standard's C API serves it. Value
/// references are checked with the `*_info` functions before the getters and setters are called
/// with them.
pub trait Model: Default {
    /// GUID of the model description (FMI 2.0 `guid`, FMI 3.0 `instantiationToken`).
    const GUID: &'static str;
    /// Everything that defines the model's present condition (the FMU state).
    type State: Clone;
    /// Why a step failed; displayed into a stack buffer (no allocation).
    type StepError: std::fmt::Display;
    /// What a step that succeeded warns about (logged with status Warning; displayed into a stack
    /// buffer too). `std::convert::Infallible` for a model without such warnings.
    type StepWarning: std::fmt::Display;

    fn real_info(vr: u32) -> Option<VarInfo>;
    fn integer_info(vr: u32) -> Option<VarInfo>;
    fn boolean_info(vr: u32) -> Option<VarInfo>;

    fn get_real(&self, vr: u32) -> Result<f64, Refusal>;
    /// The Reals of one get call: `values[i]` of `vrs[i]` for every `i` that `skip` leaves (the FMI
    /// layer's own variables, FMI 3.0's time); the error names the value reference refused. The
    /// default asks [`Model::get_real`] for each; a model whose outputs come from one evaluation
    /// overrides it to evaluate once per call (the trucks: a master reads ten outputs a step).
    fn get_reals(&self, vrs: &[u32], values: &mut [f64], skip: &dyn Fn(usize) -> bool) -> Result<(), (u32, Refusal)> {
        for (i, (&vr, x)) in vrs.iter().zip(values).enumerate() {
            if !skip(i) {
                *x = self.get_real(vr).map_err(|e| (vr, e))?;
            }
        }
        Ok(())
    }
    fn get_integer(&self, vr: u32) -> Result<i32, Refusal>;
    fn get_boolean(&self, vr: u32) -> Result<bool, Refusal>;
    /// What the `set_*` functions below change (the parameters, the inputs and what goes with
    /// them). A batch of values is applied all or nothing: the FMI layer keeps a copy of this
    /// part, not of the whole model, and puts it back when one value is refused. (Copying the
    /// damper's whole model, integrator state and tables, at every set call costs more than its
    /// communication step.)
    type Settable;
    fn settable(&self) -> Self::Settable;
    fn restore_settable(&mut self, settable: Self::Settable);

    /// Sets a value, refusing non-finite or out-of-range values with a message.
    fn set_real(&mut self, vr: u32, value: f64) -> Result<(), Refusal>;
    fn set_integer(&mut self, vr: u32, value: i32) -> Result<(), Refusal>;
    fn set_boolean(&mut self, vr: u32, value: bool) -> Result<(), Refusal>;

    /// `CoSimulation/@canInterpolateInputs` of the FMI 2.0 model description: whether
    /// [`Model::set_real_input_derivative`] takes derivatives (else fmi2SetRealInputDerivatives is
    /// refused before it is called). FMI 3.0 has no input derivatives.
    const CAN_INTERPOLATE_INPUTS: bool = false;
    /// Sets the `order`-th time derivative of the Real input `vr` (causality checked by the
    /// caller), from the start of the next communication step.
    fn set_real_input_derivative(&mut self, vr: u32, order: i32, value: f64) -> Result<(), Refusal> {
        let _ = (vr, order, value);
        Err(Refusal::NoInputDerivatives)
    }
    /// Takes the tolerance a master gives (fmi2SetupExperiment, fmi3EnterInitializationMode):
    /// Ok with what the model made of it, for the log, or Err when the value is refused.
    fn use_tolerance(&mut self, tolerance: f64) -> Result<ToleranceNote, Refusal>;
    /// Checks the parameters and starts at `start_time` (s).
    fn initialize(&mut self, start_time: f64) -> Result<(), Refusal>;
    /// Time of the model's state (s), `None` before initialisation.
    fn time(&self) -> Option<f64>;
    /// Sets the model's clock to the master's communication point (equal to within rounding).
    fn align_time(&mut self, t: f64);
    /// Refuses, before any work, a step of `h` (s) > 0 from the present time that would exceed the
    /// model's documented work limits or that its time arithmetic cannot resolve (docs/robustness.md).
    fn check_step(&self, h: f64) -> Result<(), Self::StepError>;
    /// Advances by `h` (s) > 0 with the present inputs held; on failure (including non-finite
    /// outputs at the new time) the state is unchanged. `Ok(Some(w))`: done, with a warning `w`.
    fn do_step(&mut self, h: f64) -> Result<Option<Self::StepWarning>, Self::StepError>;

    fn state(&self) -> Self::State;
    fn set_state(&mut self, state: &Self::State) -> Result<(), Refusal>;
    /// Whether a state is initialised (then setting it leaves the instance ready to step).
    fn state_time(state: &Self::State) -> Option<f64>;
    fn serialize(state: &Self::State) -> Vec<u8>;
    fn deserialize(bytes: &[u8]) -> Result<Self::State, Refusal>;
}

/// Inside an `impl Model for …` whose Integer and Boolean variables are all parameters: the
/// `*_info` lookups and the Integer and Boolean get and set, through the enums and the `Parameters`
/// accessors that `fmi_codegen` generates (`RealVar`, `IntegerVar`, `BooleanVar` in scope; the
/// parameters in `self.params`). Every FMU of this workspace has the same; Reals differ (inputs,
/// outputs) and stay with each model.
#[macro_export]
macro_rules! parameter_access {
    () => {
        fn real_info(vr: u32) -> Option<$crate::VarInfo> {
            RealVar::from_vr(vr).map(RealVar::info)
        }

        fn integer_info(vr: u32) -> Option<$crate::VarInfo> {
            IntegerVar::from_vr(vr).map(IntegerVar::info)
        }

        fn boolean_info(vr: u32) -> Option<$crate::VarInfo> {
            BooleanVar::from_vr(vr).map(BooleanVar::info)
        }

        fn get_integer(&self, vr: u32) -> Result<i32, $crate::Refusal> {
            IntegerVar::from_vr(vr).and_then(|v| self.params.integer(v)).ok_or($crate::Refusal::UnknownReference(vr))
        }

        fn get_boolean(&self, vr: u32) -> Result<bool, $crate::Refusal> {
            BooleanVar::from_vr(vr).and_then(|v| self.params.boolean(v)).ok_or($crate::Refusal::UnknownReference(vr))
        }

        fn set_integer(&mut self, vr: u32, value: i32) -> Result<(), $crate::Refusal> {
            let v = IntegerVar::from_vr(vr).ok_or($crate::Refusal::UnknownReference(vr))?;
            $crate::check_integer(v.name(), value, v.min(), v.max())?;
            *self.params.integer_mut(v).ok_or($crate::Refusal::NotSettable(v.name()))? = value;
            Ok(())
        }

        fn set_boolean(&mut self, vr: u32, value: bool) -> Result<(), $crate::Refusal> {
            let v = BooleanVar::from_vr(vr).ok_or($crate::Refusal::UnknownReference(vr))?;
            *self.params.boolean_mut(v).ok_or($crate::Refusal::NotSettable(v.name()))? = value;
            Ok(())
        }
    };
}

/// Inside an `impl Model for …` next to [`parameter_access!`]: the Real get and set, which every FMU
/// of this workspace shares. Parameters come from `self.params` (the generated accessors), inputs
/// and outputs from the model, which implements on its type:
///
/// - `fn input(&self, v: RealVar) -> Option<f64>` and `fn input_mut(&mut self, v: RealVar) ->
///   Option<&mut f64>`: an input's value and field (`None` for a variable that is not an input);
/// - `fn output(&self, v: RealVar) -> Result<f64, Refusal>`: an output's value;
/// - `fn real_set(&mut self, v: RealVar)`: what setting `v` means beyond its value (a no-op for
///   most models).
///
/// Values are refused outside the XML's [min, max] or non-finite; an output that is not finite is
/// refused rather than returned.
#[macro_export]
macro_rules! real_access {
    () => {
        fn get_real(&self, vr: u32) -> Result<f64, $crate::Refusal> {
            let v = RealVar::from_vr(vr).ok_or($crate::Refusal::UnknownReference(vr))?;
            if let Some(x) = self.params.real(v).or_else(|| self.input(v)) {
                return Ok(x);
            }
            let x = self.output(v)?;
            if !x.is_finite() {
                return Err($crate::Refusal::OutputNotFinite { name: v.name(), value: x });
            }
            Ok(x)
        }

        fn set_real(&mut self, vr: u32, value: f64) -> Result<(), $crate::Refusal> {
            let v = RealVar::from_vr(vr).ok_or($crate::Refusal::UnknownReference(vr))?;
            $crate::check_real(v.name(), value, v.min(), v.max())?;
            let field = match v.causality() {
                $crate::Causality::Parameter => self.params.real_mut(v),
                $crate::Causality::Input => self.input_mut(v),
                $crate::Causality::Output => None,
            };
            *field.ok_or($crate::Refusal::Output(v.name()))? = value;
            self.real_set(v);
            Ok(())
        }
    };
}

/// What a model made of a master's tolerance, for the log: a note on what it did, or a warning
/// where it used a value other than the one given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ToleranceNote {
    Event(String),
    Warning(String),
}

/// The status codes both standards share: `fmi2Status` and `fmi3Status` number OK, Warning,
/// Discard, Error and Fatal alike, 0 to 4 (FMI 2.0's Pending, 5, is never returned).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

impl Status {
    /// The C enum's value.
    pub const fn code(self) -> std::ffi::c_uint {
        self as std::ffi::c_uint
    }
}
