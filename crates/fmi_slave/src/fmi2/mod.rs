//! FMI 2.0 Co-Simulation: the C types (module `types`, re-exported here), the entry points generic over
//! the model ([`api`]), and [`export_fmi2!`](crate::export_fmi2), which emits the 34 functions of
//! `fmi2Functions.h` for a model type.

// the C entry points: raw pointers (the crate denies unsafe code elsewhere)
#[allow(unsafe_code)]
pub mod api;
mod types;
pub use types::*;

/// Emits the FMI 2.0 Co-Simulation C API for the [`Model`](crate::Model) type `$model`: call once, at the crate
/// root or in a module of the FMU crate.
// Neither rustc's unsafe_code nor Clippy's undocumented_unsafe_blocks looks at the expansion in
// another crate, so the SAFETY comments below are kept by hand.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        use $crate::fmi2 as __fmi2;

        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetTypesPlatform() -> *const ::std::ffi::c_char {
            $crate::fmi2::api::get_types_platform()
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetVersion() -> *const ::std::ffi::c_char {
            $crate::fmi2::api::get_version()
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
            unsafe { $crate::fmi2::api::set_debug_logging::<$model>(c, "fmi2SetDebugLogging", on != 0, n, categories) }
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
            unsafe {
                $crate::fmi2::api::instantiate::<$model>(name, ty, guid, resources, functions, visible, logging_on)
            }
        }
        /// # Safety
        /// `c` must be NULL or an instance of this library, not used afterwards.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2FreeInstance(c: __fmi2::fmi2Component) {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi2::api::free_instance::<$model>(c) }
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
            $crate::fmi2::api::setup_experiment::<$model>(c, tol_defined, tol, start, stop_defined, stop)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2EnterInitializationMode(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::fmi2::api::enter_initialization_mode::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2ExitInitializationMode(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::fmi2::api::exit_initialization_mode::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2Terminate(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::fmi2::api::terminate::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2Reset(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::fmi2::api::reset::<$model>(c)
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
            unsafe { $crate::fmi2::api::get_real::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::get_integer::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::get_boolean::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::no_strings::<$model>(c, "fmi2GetString", vr, nvr) }
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
            unsafe { $crate::fmi2::api::set_real::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::set_integer::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::set_boolean::<$model>(c, vr, nvr, value) }
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
            unsafe { $crate::fmi2::api::no_strings::<$model>(c, "fmi2SetString", vr, nvr) }
        }
        /// # Safety
        /// `state` must point to writable storage for one pointer.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2GetFMUstate(
            c: __fmi2::fmi2Component,
            state: *mut __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi2::api::get_fmu_state::<$model>(c, "fmi2GetFMUstate", state) }
        }
        /// # Safety
        /// `state` must be a state of this library, not yet freed.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2SetFMUstate(
            c: __fmi2::fmi2Component,
            state: __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi2::api::set_fmu_state::<$model>(c, "fmi2SetFMUstate", state) }
        }
        /// # Safety
        /// `state` must point to NULL or a state of this library.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi2FreeFMUstate(
            c: __fmi2::fmi2Component,
            state: *mut __fmi2::fmi2FMUstate,
        ) -> __fmi2::fmi2Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi2::api::free_fmu_state::<$model>(c, "fmi2FreeFMUstate", state) }
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
            unsafe {
                $crate::fmi2::api::serialized_fmu_state_size::<$model>(c, "fmi2SerializedFMUstateSize", state, size)
            }
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
            unsafe {
                $crate::fmi2::api::serialize_fmu_state::<$model>(
                    c,
                    "fmi2SerializeFMUstate",
                    state,
                    bytes as *mut u8,
                    size,
                )
            }
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
            unsafe {
                $crate::fmi2::api::deserialize_fmu_state::<$model>(
                    c,
                    "fmi2DeSerializeFMUstate",
                    bytes as *const u8,
                    size,
                    state,
                )
            }
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
            $crate::fmi2::api::unsupported::<$model>(
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
                return $crate::fmi2::api::unsupported::<$model>(
                    c,
                    "fmi2SetRealInputDerivatives",
                    "canInterpolateInputs is false",
                );
            }
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi2::api::set_real_input_derivatives::<$model>(c, vr, nvr, order, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetRealOutputDerivatives(
            c: __fmi2::fmi2Component,
            _: *const u32,
            _: usize,
            _: *const i32,
            _: *mut f64,
        ) -> __fmi2::fmi2Status {
            $crate::fmi2::api::unsupported::<$model>(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder is 0")
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2DoStep(
            c: __fmi2::fmi2Component,
            t: f64,
            h: f64,
            _no_set_state_prior: __fmi2::fmi2Boolean,
        ) -> __fmi2::fmi2Status {
            $crate::fmi2::api::do_step::<$model>(c, t, h)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2CancelStep(c: __fmi2::fmi2Component) -> __fmi2::fmi2Status {
            $crate::fmi2::api::unsupported::<$model>(
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
            $crate::fmi2::api::unsupported::<$model>(
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
            unsafe { $crate::fmi2::api::get_real_status::<$model>(c, kind, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetIntegerStatus(
            c: __fmi2::fmi2Component,
            _: __fmi2::fmi2StatusKind,
            _: *mut i32,
        ) -> __fmi2::fmi2Status {
            $crate::fmi2::api::unsupported::<$model>(
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
            unsafe { $crate::fmi2::api::get_boolean_status::<$model>(c, kind, value) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi2GetStringStatus(
            c: __fmi2::fmi2Component,
            _: __fmi2::fmi2StatusKind,
            _: *mut __fmi2::fmi2String,
        ) -> __fmi2::fmi2Status {
            $crate::fmi2::api::unsupported::<$model>(
                c,
                "fmi2GetStringStatus",
                "fmi2DoStep is synchronous, no status message is pending",
            )
        }
    };
}
