//! The FMI 2.0 Co-Simulation C API for any model that implements [`Model`]: plain safe Rust on one
//! side, the C ABI on the other. An FMU crate implements the trait and calls
//! [`export_fmi2!`] once; the macro emits the 34 `#[no_mangle] extern "C"` functions, each a thin
//! shim over the generic functions of [`api`], which check pointers and the FMI state machine,
//! catch panics (a panic becomes fmi2Fatal, never an unwind into the host) and log through the
//! importer's callback without allocating.
//!
//! Layout: `fmi2` (the C types), `api` (pointer handling per entry point), `instance` (one FMU instance: state machine,
//! experiment times, variable access rules), `state_machine` (the legal-call table), `logger`,
//! `guard` (panic guard and checked slices), `snapshot` (versioned byte format of FMU states).
// The C ABI's raw pointers: the crate denies unsafe code (Cargo.toml) except in these modules.
#[allow(unsafe_code)]
pub mod api;
pub mod fmi2;
#[allow(unsafe_code)]
mod guard;
mod instance;
#[allow(unsafe_code)]
mod logger;
mod refusal;
pub mod snapshot;
mod state_machine;

pub use instance::{Failure, Instance};
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

/// A co-simulation model without FMI types. Value references are checked with the `*_info`
/// functions before the getters and setters are called with them.
pub trait Model: Default {
    /// GUID of the model description.
    const GUID: &'static str;
    /// Everything that defines the model's present condition (the FMU state).
    type State: Clone;
    /// Why a step failed; displayed into a stack buffer (no allocation).
    type StepError: std::fmt::Display;
    /// What a step that succeeded warns about (logged with status fmi2Warning; displayed into a
    /// stack buffer too). `std::convert::Infallible` for a model without such warnings.
    type StepWarning: std::fmt::Display;

    fn real_info(vr: u32) -> Option<VarInfo>;
    fn integer_info(vr: u32) -> Option<VarInfo>;
    fn boolean_info(vr: u32) -> Option<VarInfo>;

    fn get_real(&self, vr: u32) -> Result<f64, Refusal>;
    fn get_integer(&self, vr: u32) -> Result<i32, Refusal>;
    fn get_boolean(&self, vr: u32) -> Result<bool, Refusal>;
    /// What the `set_*` functions below change (the parameters, the inputs and what goes with
    /// them). A batch of values is applied all or nothing: the FMI layer keeps a copy of this
    /// part, not of the whole model, and puts it back when one value is refused. (Copying the
    /// damper's whole model, integrator state and tables, at every fmi2SetReal costs more than
    /// its communication step.)
    type Settable;
    fn settable(&self) -> Self::Settable;
    fn restore_settable(&mut self, settable: Self::Settable);

    /// Sets a value, refusing non-finite or out-of-range values with a message.
    fn set_real(&mut self, vr: u32, value: f64) -> Result<(), Refusal>;
    fn set_integer(&mut self, vr: u32, value: i32) -> Result<(), Refusal>;
    fn set_boolean(&mut self, vr: u32, value: bool) -> Result<(), Refusal>;

    /// `CoSimulation/@canInterpolateInputs` of the model description: whether
    /// [`Model::set_real_input_derivative`] takes derivatives (else fmi2SetRealInputDerivatives is
    /// refused before it is called).
    const CAN_INTERPOLATE_INPUTS: bool = false;
    /// Sets the `order`-th time derivative of the Real input `vr` (causality checked by the
    /// caller), from the start of the next communication step.
    fn set_real_input_derivative(&mut self, vr: u32, order: i32, value: f64) -> Result<(), Refusal> {
        let _ = (vr, order, value);
        Err(Refusal::NoInputDerivatives)
    }
    /// Takes the tolerance a master gives `fmi2SetupExperiment` (toleranceDefined): Ok with what
    /// the model made of it, for the log, or Err when the value is refused.
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
    /// Whether a state is initialised (then fmi2SetFMUstate leaves the instance in StepComplete).
    fn state_time(state: &Self::State) -> Option<f64>;
    fn serialize(state: &Self::State) -> Vec<u8>;
    fn deserialize(bytes: &[u8]) -> Result<Self::State, Refusal>;
}

/// Inside an `impl Model for …` whose Integer and Boolean variables are all parameters: the
/// `*_info` lookups and the Integer and Boolean get and set, through the enums and the `Parameters`
/// accessors that `fmi2_codegen` generates (`RealVar`, `IntegerVar`, `BooleanVar` in scope; the
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

/// Emits the FMI 2.0 Co-Simulation C API for the [`Model`] type `$model`: call once, at the crate
/// root or in a module of the FMU crate.
// Neither rustc's unsafe_code nor Clippy's undocumented_unsafe_blocks looks at the expansion in
// another crate, so the SAFETY comments below are kept by hand.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        use $crate::api::fmi2 as __fmi2;

        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
            $crate::api::get_types_platform()
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
            $crate::api::get_version()
        }
        /// # Safety
        /// See the FMI 2.0 standard: arrays must hold the given number of valid elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetDebugLogging(
            c: __fmi2::fmi2Component,
            on: __fmi2::fmi2Boolean,
            n: usize,
            categories: *const __fmi2::fmi2String,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_debug_logging::<$model>(c, on, n, categories) }
        }
        /// # Safety
        /// String arguments must be NULL or NUL-terminated; `functions` NULL or valid.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2Instantiate(
            name: __fmi2::fmi2String,
            ty: __fmi2::fmi2Type,
            guid: __fmi2::fmi2String,
            resources: __fmi2::fmi2String,
            functions: *const __fmi2::fmi2CallbackFunctions,
            visible: __fmi2::fmi2Boolean,
            logging_on: __fmi2::fmi2Boolean,
        ) -> __fmi2::fmi2Component {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::instantiate::<$model>(name, ty, guid, resources, functions, visible, logging_on) }
        }
        /// # Safety
        /// `c` must be NULL or an instance of this library, not used afterwards.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2FreeInstance(c: __fmi2::fmi2Component) {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::free_instance::<$model>(c) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2SetupExperiment(
            c: __fmi2::fmi2Component,
            tol_defined: __fmi2::fmi2Boolean,
            tol: f64,
            start: f64,
            stop_defined: __fmi2::fmi2Boolean,
            stop: f64,
        ) -> __fmi2::fmi2Status {
            $crate::api::setup_experiment::<$model>(c, tol_defined, tol, start, stop_defined, stop)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2EnterInitializationMode(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::api::enter_initialization_mode::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2ExitInitializationMode(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::api::exit_initialization_mode::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2Terminate(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::api::terminate::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2Reset(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::api::reset::<$model>(c)
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetReal(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *mut f64,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_real::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetInteger(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *mut i32,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_integer::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetBoolean(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *mut i32,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_boolean::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetString(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            _value: *mut __fmi2::fmi2String,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::no_strings::<$model>(c, "fmi2GetString", vr, nvr) }
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetReal(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *const f64,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_real::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetInteger(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *const i32,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_integer::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetBoolean(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            value: *const i32,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_boolean::<$model>(c, vr, nvr, value) }
        }
        /// # Safety
        /// `vr` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetString(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            _value: *const __fmi2::fmi2String,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::no_strings::<$model>(c, "fmi2SetString", vr, nvr) }
        }
        /// # Safety
        /// `state` must point to writable storage for one pointer.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetFMUstate(
            c: __fmi2::fmi2Component,
            state: *mut __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_fmu_state::<$model>(c, state) }
        }
        /// # Safety
        /// `state` must be a state of this library, not yet freed.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetFMUstate(
            c: __fmi2::fmi2Component,
            state: __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_fmu_state::<$model>(c, state) }
        }
        /// # Safety
        /// `state` must point to NULL or a state of this library.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2FreeFMUstate(
            c: __fmi2::fmi2Component,
            state: *mut __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::free_fmu_state::<$model>(c, state) }
        }
        /// # Safety
        /// `state` must be a state of this library; `size` writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
            c: __fmi2::fmi2Component,
            state: __fmi2::fmi2FMUstate,
            size: *mut usize,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::serialized_fmu_state_size::<$model>(c, state, size) }
        }
        /// # Safety
        /// `state` must be a state of this library; `bytes` must hold `size` bytes.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SerializeFMUstate(
            c: __fmi2::fmi2Component,
            state: __fmi2::fmi2FMUstate,
            bytes: *mut __fmi2::fmi2Byte,
            size: usize,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::serialize_fmu_state::<$model>(c, state, bytes, size) }
        }
        /// # Safety
        /// `bytes` must hold `size` bytes; `state` must point to NULL or a state of this library.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
            c: __fmi2::fmi2Component,
            bytes: *const __fmi2::fmi2Byte,
            size: usize,
            state: *mut __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::deserialize_fmu_state::<$model>(c, bytes, size, state) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetDirectionalDerivative(
            c: __fmi2::fmi2Component,
            _: *const u32,
            _: usize,
            _: *const u32,
            _: usize,
            _: *const f64,
            _: *mut f64,
        ) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(
                c,
                "fmi2GetDirectionalDerivative",
                "providesDirectionalDerivative is false",
            )
        }
        /// # Safety
        /// `vr`, `order` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
            c: __fmi2::fmi2Component,
            vr: *const u32,
            nvr: usize,
            order: *const i32,
            value: *const f64,
        ) -> __fmi2::fmi2Status {
            if !<$model as $crate::Model>::CAN_INTERPOLATE_INPUTS {
                return $crate::api::unsupported::<$model>(
                    c,
                    "fmi2SetRealInputDerivatives",
                    "canInterpolateInputs is false",
                );
            }
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::set_real_input_derivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetRealOutputDerivatives(
            c: __fmi2::fmi2Component,
            _: *const u32,
            _: usize,
            _: *const i32,
            _: *mut f64,
        ) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder is 0")
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2DoStep(
            c: __fmi2::fmi2Component,
            t: f64,
            h: f64,
            _no_set_state_prior: __fmi2::fmi2Boolean,
        ) -> __fmi2::fmi2Status {
            $crate::api::do_step::<$model>(c, t, h)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2CancelStep(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(
                c,
                "fmi2CancelStep",
                "fmi2DoStep is synchronous, no step is ever pending",
            )
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetStatus(
            c: __fmi2::fmi2Component,
            _: __fmi2::fmi2StatusKind,
            _: *mut __fmi2::fmi2Status,
        ) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(
                c,
                "fmi2GetStatus",
                "fmi2DoStep is synchronous, there is no pending status",
            )
        }
        /// # Safety
        /// `value` must be writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetRealStatus(
            c: __fmi2::fmi2Component,
            kind: __fmi2::fmi2StatusKind,
            value: *mut f64,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_real_status::<$model>(c, kind, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetIntegerStatus(
            c: __fmi2::fmi2Component,
            _: __fmi2::fmi2StatusKind,
            _: *mut i32,
        ) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(
                c,
                "fmi2GetIntegerStatus",
                "no Integer status is defined for FMI 2.0 Co-Simulation",
            )
        }
        /// # Safety
        /// `value` must be writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetBooleanStatus(
            c: __fmi2::fmi2Component,
            kind: __fmi2::fmi2StatusKind,
            value: *mut i32,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::api::get_boolean_status::<$model>(c, kind, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetStringStatus(
            c: __fmi2::fmi2Component,
            _: __fmi2::fmi2StatusKind,
            _: *mut __fmi2::fmi2String,
        ) -> __fmi2::fmi2Status {
            $crate::api::unsupported::<$model>(
                c,
                "fmi2GetStringStatus",
                "fmi2DoStep is synchronous, no status message is pending",
            )
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
