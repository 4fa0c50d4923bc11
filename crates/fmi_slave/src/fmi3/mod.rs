//! FMI 3.0 Co-Simulation: the C types (module `types`, re-exported here), the entry points generic over
//! the model ([`api`]), and [`export_fmi3!`](crate::export_fmi3), which emits the 75 functions of
//! `fmi3Functions.h` for a model type. What these FMUs do not provide (Model Exchange, Scheduled
//! Execution, Event Mode and clocks, configuration mode, directional and adjoint derivatives,
//! output derivatives, per-element dependencies, variable types other than Float64, Int32 and
//! Boolean) is refused with a logged error that says why, as the capability flags of the model
//! description declare.

// the C entry points: raw pointers (the crate denies unsafe code elsewhere)
#[allow(unsafe_code)]
pub mod api;
mod types;
pub use types::*;

/// A function the FMU does not provide: refused with a logged error naming why. Its arguments
/// after the instance are never read.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_refused {
    ($model:ty, $name:ident, $why:literal $(, $arg:ty)*) => {
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(c: $crate::fmi3::fmi3Instance $(, _: $arg)*) -> $crate::fmi3::fmi3Status {
            $crate::fmi3::api::unsupported::<$model>(c, stringify!($name), $why)
        }
    };
}

/// A getter or setter of a variable type these FMUs have none of: with `nValueReferences` 0 a
/// legal no-op (subject to the state table), else refused.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_no_variables {
    ($model:ty, $name:ident, $ty:literal, $values:ty $(, $arg:ty)*) => {
        /// # Safety
        /// `vr` must hold `nvr` elements (or be NULL when `nvr` is 0).
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: $crate::fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize
            $(, _: $arg)*,
            _: $values,
            _: usize,
        ) -> $crate::fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::no_variables::<$model>(c, stringify!($name), $ty, vr, nvr) }
        }
    };
}

/// A clock, interval or shift function: these FMUs have no clocks.
#[doc(hidden)]
#[macro_export]
macro_rules! __fmi3_no_clocks {
    ($model:ty, $name:ident $(, $arg:ty)*) => {
        $crate::__fmi3_refused!($model, $name, "this FMU has no clocks", *const u32, usize $(, $arg)*);
    };
}

/// Emits the FMI 3.0 Co-Simulation C API for the [`Model`](crate::Model) type `$model`, whose
/// independent variable `time` has the value reference `$time_vr` in the FMI 3.0 model
/// description: call once, at the crate root or in a module of the FMU crate, in a binary that
/// does not also export FMI 2.0.
// Neither rustc's unsafe_code nor Clippy's undocumented_unsafe_blocks looks at the expansion in
// another crate, so the SAFETY comments below are kept by hand.
#[macro_export]
macro_rules! export_fmi3 {
    ($model:ty, time_vr = $time_vr:expr) => {
        use $crate::fmi3 as __fmi3;

        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3GetVersion() -> *const ::std::ffi::c_char {
            $crate::fmi3::api::get_version()
        }
        /// # Safety
        /// See the FMI 3.0 standard: arrays must hold the given number of valid elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SetDebugLogging(
            c: __fmi3::fmi3Instance,
            on: __fmi3::fmi3Boolean,
            n: usize,
            categories: *const __fmi3::fmi3String,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::set_debug_logging::<$model>(c, "fmi3SetDebugLogging", on, n, categories) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3InstantiateModelExchange(
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3Boolean,
            _: __fmi3::fmi3Boolean,
            environment: __fmi3::fmi3InstanceEnvironment,
            log_message: __fmi3::fmi3LogMessageCallback,
        ) -> __fmi3::fmi3Instance {
            $crate::fmi3::api::refuse_instantiation("fmi3InstantiateModelExchange", environment, log_message)
        }
        /// # Safety
        /// String arguments must be NULL or NUL-terminated; `log_message`, if set, must stay
        /// callable while the instance lives.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
            name: __fmi3::fmi3String,
            token: __fmi3::fmi3String,
            _resource_path: __fmi3::fmi3String,
            _visible: __fmi3::fmi3Boolean,
            logging_on: __fmi3::fmi3Boolean,
            event_mode_used: __fmi3::fmi3Boolean,
            early_return_allowed: __fmi3::fmi3Boolean,
            _required: *const u32,
            n_required: usize,
            environment: __fmi3::fmi3InstanceEnvironment,
            log_message: __fmi3::fmi3LogMessageCallback,
            _intermediate_update: __fmi3::fmi3IntermediateUpdateCallback,
        ) -> __fmi3::fmi3Instance {
            let options = $crate::fmi3::api::CoSimulationOptions {
                logging_on,
                event_mode_used,
                early_return_allowed,
                n_required_intermediate_variables: n_required,
            };
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe {
                $crate::fmi3::api::instantiate_co_simulation::<$model>(
                    name,
                    token,
                    $time_vr,
                    options,
                    environment,
                    log_message,
                )
            }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3InstantiateScheduledExecution(
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3String,
            _: __fmi3::fmi3Boolean,
            _: __fmi3::fmi3Boolean,
            environment: __fmi3::fmi3InstanceEnvironment,
            log_message: __fmi3::fmi3LogMessageCallback,
            _: __fmi3::fmi3ClockUpdateCallback,
            _: __fmi3::fmi3LockPreemptionCallback,
            _: __fmi3::fmi3UnlockPreemptionCallback,
        ) -> __fmi3::fmi3Instance {
            $crate::fmi3::api::refuse_instantiation("fmi3InstantiateScheduledExecution", environment, log_message)
        }
        /// # Safety
        /// `c` must be NULL or an instance of this library, not used afterwards.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3FreeInstance(c: __fmi3::fmi3Instance) {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::free_instance::<$model>(c) }
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3EnterInitializationMode(
            c: __fmi3::fmi3Instance,
            tol_defined: __fmi3::fmi3Boolean,
            tol: f64,
            start: f64,
            stop_defined: __fmi3::fmi3Boolean,
            stop: f64,
        ) -> __fmi3::fmi3Status {
            $crate::fmi3::api::enter_initialization_mode::<$model>(
                c,
                tol_defined.then_some(tol),
                start,
                stop_defined.then_some(stop),
            )
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3ExitInitializationMode(c: __fmi3::fmi3Instance) -> __fmi3::fmi3Status {
            $crate::fmi3::api::exit_initialization_mode::<$model>(c)
        }
        $crate::__fmi3_refused!($model, fmi3EnterEventMode, "hasEventMode is false");
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3Terminate(c: __fmi3::fmi3Instance) -> __fmi3::fmi3Status {
            $crate::fmi3::api::terminate::<$model>(c)
        }
        #[unsafe(no_mangle)]
        pub extern "C" fn fmi3Reset(c: __fmi3::fmi3Instance) -> __fmi3::fmi3Status {
            $crate::fmi3::api::reset::<$model>(c)
        }

        $crate::__fmi3_no_variables!($model, fmi3GetFloat32, "Float32", *mut f32);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3GetFloat64(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *mut f64,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::get_float64::<$model>(c, vr, nvr, value, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3GetInt8, "Int8", *mut i8);
        $crate::__fmi3_no_variables!($model, fmi3GetUInt8, "UInt8", *mut u8);
        $crate::__fmi3_no_variables!($model, fmi3GetInt16, "Int16", *mut i16);
        $crate::__fmi3_no_variables!($model, fmi3GetUInt16, "UInt16", *mut u16);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3GetInt32(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *mut i32,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::get_int32::<$model>(c, vr, nvr, value, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3GetUInt32, "UInt32", *mut u32);
        $crate::__fmi3_no_variables!($model, fmi3GetInt64, "Int64", *mut i64);
        $crate::__fmi3_no_variables!($model, fmi3GetUInt64, "UInt64", *mut u64);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3GetBoolean(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *mut __fmi3::fmi3Boolean,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's;
            // a C bool is one byte, written 0 or 1.
            unsafe { $crate::fmi3::api::get_boolean::<$model>(c, vr, nvr, value as *mut u8, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3GetString, "String", *mut __fmi3::fmi3String);
        $crate::__fmi3_no_variables!($model, fmi3GetBinary, "Binary", *mut __fmi3::fmi3Binary, *mut usize);
        $crate::__fmi3_no_clocks!($model, fmi3GetClock, *mut __fmi3::fmi3Clock);

        $crate::__fmi3_no_variables!($model, fmi3SetFloat32, "Float32", *const f32);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SetFloat64(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *const f64,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::set_float64::<$model>(c, vr, nvr, value, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3SetInt8, "Int8", *const i8);
        $crate::__fmi3_no_variables!($model, fmi3SetUInt8, "UInt8", *const u8);
        $crate::__fmi3_no_variables!($model, fmi3SetInt16, "Int16", *const i16);
        $crate::__fmi3_no_variables!($model, fmi3SetUInt16, "UInt16", *const u16);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SetInt32(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *const i32,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::set_int32::<$model>(c, vr, nvr, value, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3SetUInt32, "UInt32", *const u32);
        $crate::__fmi3_no_variables!($model, fmi3SetInt64, "Int64", *const i64);
        $crate::__fmi3_no_variables!($model, fmi3SetUInt64, "UInt64", *const u64);
        /// # Safety
        /// `vr` and `value` must hold `nvr` elements.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SetBoolean(
            c: __fmi3::fmi3Instance,
            vr: *const u32,
            nvr: usize,
            value: *const __fmi3::fmi3Boolean,
            n_values: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's;
            // the C bools are read as bytes.
            unsafe { $crate::fmi3::api::set_boolean::<$model>(c, vr, nvr, value as *const u8, n_values) }
        }
        $crate::__fmi3_no_variables!($model, fmi3SetString, "String", *const __fmi3::fmi3String);
        $crate::__fmi3_no_variables!($model, fmi3SetBinary, "Binary", *const __fmi3::fmi3Binary, *const usize);
        $crate::__fmi3_no_clocks!($model, fmi3SetClock, *const __fmi3::fmi3Clock);

        $crate::__fmi3_refused!(
            $model,
            fmi3GetNumberOfVariableDependencies,
            "providesPerElementDependencies is false: the model description's dependencies are complete",
            u32,
            *mut usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetVariableDependencies,
            "providesPerElementDependencies is false: the model description's dependencies are complete",
            u32,
            *mut usize,
            *mut u32,
            *mut usize,
            *mut __fmi3::fmi3DependencyKind,
            usize
        );

        /// # Safety
        /// `state` must point to writable storage for one pointer.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3GetFMUState(
            c: __fmi3::fmi3Instance,
            state: *mut __fmi3::fmi3FMUState,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::get_fmu_state::<$model>(c, "fmi3GetFMUState", state) }
        }
        /// # Safety
        /// `state` must be a state of this library, not yet freed.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SetFMUState(
            c: __fmi3::fmi3Instance,
            state: __fmi3::fmi3FMUState,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::set_fmu_state::<$model>(c, "fmi3SetFMUState", state) }
        }
        /// # Safety
        /// `state` must point to NULL or a state of this library.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3FreeFMUState(
            c: __fmi3::fmi3Instance,
            state: *mut __fmi3::fmi3FMUState,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::free_fmu_state::<$model>(c, "fmi3FreeFMUState", state) }
        }
        /// # Safety
        /// `state` must be a state of this library; `size` writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
            c: __fmi3::fmi3Instance,
            state: __fmi3::fmi3FMUState,
            size: *mut usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe {
                $crate::fmi3::api::serialized_fmu_state_size::<$model>(c, "fmi3SerializedFMUStateSize", state, size)
            }
        }
        /// # Safety
        /// `state` must be a state of this library; `bytes` must hold `size` bytes.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3SerializeFMUState(
            c: __fmi3::fmi3Instance,
            state: __fmi3::fmi3FMUState,
            bytes: *mut __fmi3::fmi3Byte,
            size: usize,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::serialize_fmu_state::<$model>(c, "fmi3SerializeFMUState", state, bytes, size) }
        }
        /// # Safety
        /// `bytes` must hold `size` bytes; `state` must point to NULL or a state of this library.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3DeserializeFMUState(
            c: __fmi3::fmi3Instance,
            bytes: *const __fmi3::fmi3Byte,
            size: usize,
            state: *mut __fmi3::fmi3FMUState,
        ) -> __fmi3::fmi3Status {
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe {
                $crate::fmi3::api::deserialize_fmu_state::<$model>(c, "fmi3DeserializeFMUState", bytes, size, state)
            }
        }

        $crate::__fmi3_refused!(
            $model,
            fmi3GetDirectionalDerivative,
            "providesDirectionalDerivatives is false",
            *const u32,
            usize,
            *const u32,
            usize,
            *const f64,
            usize,
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetAdjointDerivative,
            "providesAdjointDerivatives is false",
            *const u32,
            usize,
            *const u32,
            usize,
            *const f64,
            usize,
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!($model, fmi3EnterConfigurationMode, "this FMU has no structural parameters");
        $crate::__fmi3_refused!($model, fmi3ExitConfigurationMode, "this FMU has no structural parameters");
        $crate::__fmi3_no_clocks!($model, fmi3GetIntervalDecimal, *mut f64, *mut __fmi3::fmi3IntervalQualifier);
        $crate::__fmi3_no_clocks!(
            $model,
            fmi3GetIntervalFraction,
            *mut u64,
            *mut u64,
            *mut __fmi3::fmi3IntervalQualifier
        );
        $crate::__fmi3_no_clocks!($model, fmi3GetShiftDecimal, *mut f64);
        $crate::__fmi3_no_clocks!($model, fmi3GetShiftFraction, *mut u64, *mut u64);
        $crate::__fmi3_no_clocks!($model, fmi3SetIntervalDecimal, *const f64);
        $crate::__fmi3_no_clocks!($model, fmi3SetIntervalFraction, *const u64, *const u64);
        $crate::__fmi3_no_clocks!($model, fmi3SetShiftDecimal, *const f64);
        $crate::__fmi3_no_clocks!($model, fmi3SetShiftFraction, *const u64, *const u64);
        $crate::__fmi3_refused!($model, fmi3EvaluateDiscreteStates, "hasEventMode is false");
        $crate::__fmi3_refused!(
            $model,
            fmi3UpdateDiscreteStates,
            "hasEventMode is false",
            *mut __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean,
            *mut f64
        );

        $crate::__fmi3_refused!($model, fmi3EnterContinuousTimeMode, "Model Exchange: this FMU is Co-Simulation only");
        $crate::__fmi3_refused!(
            $model,
            fmi3CompletedIntegratorStep,
            "Model Exchange: this FMU is Co-Simulation only",
            __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean,
            *mut __fmi3::fmi3Boolean
        );
        $crate::__fmi3_refused!($model, fmi3SetTime, "Model Exchange: this FMU is Co-Simulation only", f64);
        $crate::__fmi3_refused!(
            $model,
            fmi3SetContinuousStates,
            "Model Exchange: this FMU is Co-Simulation only",
            *const f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetContinuousStateDerivatives,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetEventIndicators,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetContinuousStates,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetNominalsOfContinuousStates,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut f64,
            usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetNumberOfEventIndicators,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut usize
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetNumberOfContinuousStates,
            "Model Exchange: this FMU is Co-Simulation only",
            *mut usize
        );

        $crate::__fmi3_refused!(
            $model,
            fmi3EnterStepMode,
            "hasEventMode is false: the FMU is in Step Mode from fmi3ExitInitializationMode on"
        );
        $crate::__fmi3_refused!(
            $model,
            fmi3GetOutputDerivatives,
            "maxOutputDerivativeOrder is 0",
            *const u32,
            usize,
            *const i32,
            *mut f64,
            usize
        );
        /// # Safety
        /// The four out-arguments must be writable.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn fmi3DoStep(
            c: __fmi3::fmi3Instance,
            t: f64,
            h: f64,
            _no_set_state_prior: __fmi3::fmi3Boolean,
            event_handling_needed: *mut __fmi3::fmi3Boolean,
            terminate_simulation: *mut __fmi3::fmi3Boolean,
            early_return: *mut __fmi3::fmi3Boolean,
            last_successful_time: *mut f64,
        ) -> __fmi3::fmi3Status {
            let out = $crate::fmi3::api::StepOut {
                event_handling_needed,
                terminate_simulation,
                early_return,
                last_successful_time,
            };
            // SAFETY: the caller upholds this function's safety section, which is the api function's.
            unsafe { $crate::fmi3::api::do_step::<$model>(c, t, h, out) }
        }
        $crate::__fmi3_refused!(
            $model,
            fmi3ActivateModelPartition,
            "Scheduled Execution: this FMU is Co-Simulation only",
            u32,
            f64
        );
    };
}
