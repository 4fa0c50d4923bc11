//! The FMU binaries of both standards, built by this test's profile and opened with dlopen; each
//! binary's C API as a table of function pointers, as an importer sees it, behind one set of
//! methods that speak both standards, so that the fuzzer's sequences are written once.

use super::model_info::ModelInfo;
use fmi_slave::fmi2::*;
use fmi_slave::fmi3::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3String};
use std::ffi::{c_char, c_void};
use std::path::{Path, PathBuf};
use std::ptr::null;
use std::sync::OnceLock;

/// An instance or state handle (`void*` in both standards).
pub type H = *mut c_void;
/// A status (both standards number OK … Fatal 0 … 4).
pub type S = u32;

/// The standard a binary implements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    Fmi2,
    Fmi3,
}

/// The functions both standards have with the same C signature.
pub struct Common {
    pub free_instance: unsafe extern "C" fn(H),
    pub enter_initialization_mode2: Option<unsafe extern "C" fn(H) -> S>,
    pub exit_initialization_mode: unsafe extern "C" fn(H) -> S,
    pub terminate: unsafe extern "C" fn(H) -> S,
    pub reset: unsafe extern "C" fn(H) -> S,
    pub get_fmu_state: unsafe extern "C" fn(H, *mut H) -> S,
    pub set_fmu_state: unsafe extern "C" fn(H, H) -> S,
    pub free_fmu_state: unsafe extern "C" fn(H, *mut H) -> S,
    pub serialized_size: unsafe extern "C" fn(H, H, *mut usize) -> S,
    pub serialize: unsafe extern "C" fn(H, H, *mut u8, usize) -> S,
    pub deserialize: unsafe extern "C" fn(H, *const u8, usize, *mut H) -> S,
}

/// The FMI 2.0 functions of their own signature.
pub struct Fmi2 {
    pub instantiate:
        unsafe extern "C" fn(fmi2String, fmi2Type, fmi2String, fmi2String, *const fmi2CallbackFunctions, i32, i32) -> H,
    pub set_debug_logging: unsafe extern "C" fn(H, i32, usize, *const fmi2String) -> S,
    pub setup_experiment: unsafe extern "C" fn(H, i32, f64, f64, i32, f64) -> S,
    pub get_real: unsafe extern "C" fn(H, *const u32, usize, *mut f64) -> S,
    pub get_integer: unsafe extern "C" fn(H, *const u32, usize, *mut i32) -> S,
    pub get_boolean: unsafe extern "C" fn(H, *const u32, usize, *mut i32) -> S,
    pub get_string: unsafe extern "C" fn(H, *const u32, usize, *mut fmi2String) -> S,
    pub set_real: unsafe extern "C" fn(H, *const u32, usize, *const f64) -> S,
    pub set_integer: unsafe extern "C" fn(H, *const u32, usize, *const i32) -> S,
    pub set_boolean: unsafe extern "C" fn(H, *const u32, usize, *const i32) -> S,
    pub set_string: unsafe extern "C" fn(H, *const u32, usize, *const fmi2String) -> S,
    pub do_step: unsafe extern "C" fn(H, f64, f64, i32) -> S,
    pub cancel_step: unsafe extern "C" fn(H) -> S,
    pub get_status: unsafe extern "C" fn(H, fmi2StatusKind, *mut S) -> S,
    pub get_real_status: unsafe extern "C" fn(H, fmi2StatusKind, *mut f64) -> S,
    pub get_boolean_status: unsafe extern "C" fn(H, fmi2StatusKind, *mut i32) -> S,
}

type Instantiate3 = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    bool,
    bool,
    bool,
    bool,
    *const u32,
    usize,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
    *const c_void,
) -> H;

/// The FMI 3.0 functions of their own signature. Booleans are passed as bytes (`u8`, the C `bool`'s
/// ABI), so that the fuzzer can hand the FMU bytes other than 0 and 1.
pub struct Fmi3 {
    pub instantiate: Instantiate3,
    pub instantiate_model_exchange: unsafe extern "C" fn(
        fmi3String,
        fmi3String,
        fmi3String,
        bool,
        bool,
        fmi3InstanceEnvironment,
        fmi3LogMessageCallback,
    ) -> H,
    pub set_debug_logging: unsafe extern "C" fn(H, bool, usize, *const fmi3String) -> S,
    pub enter_initialization_mode: unsafe extern "C" fn(H, bool, f64, f64, bool, f64) -> S,
    pub get_float64: unsafe extern "C" fn(H, *const u32, usize, *mut f64, usize) -> S,
    pub get_int32: unsafe extern "C" fn(H, *const u32, usize, *mut i32, usize) -> S,
    pub get_boolean: unsafe extern "C" fn(H, *const u32, usize, *mut u8, usize) -> S,
    pub set_float64: unsafe extern "C" fn(H, *const u32, usize, *const f64, usize) -> S,
    pub set_int32: unsafe extern "C" fn(H, *const u32, usize, *const i32, usize) -> S,
    pub set_boolean: unsafe extern "C" fn(H, *const u32, usize, *const u8, usize) -> S,
    /// Getters and setters of types these FMUs have no variables of (their values never read):
    /// (name, function) with the common shape (instance, vr, nvr, values, nValues).
    pub no_variables: Vec<(&'static str, unsafe extern "C" fn(H, *const u32, usize, *mut c_void, usize) -> S)>,
    /// Functions these FMUs refuse whatever the state, called with the instance alone.
    pub refused: Vec<(&'static str, unsafe extern "C" fn(H) -> S)>,
    pub do_step: unsafe extern "C" fn(H, f64, f64, bool, *mut bool, *mut bool, *mut bool, *mut f64) -> S,
}

/// One standard's table.
pub enum Api {
    Fmi2(Fmi2),
    Fmi3(Fmi3),
}

/// One FMU: its binary, its C API and its model description.
pub struct Fmu {
    pub name: &'static str,
    pub standard: Standard,
    pub common: Common,
    pub api: Api,
    pub info: ModelInfo,
    _library: libloading::Library,
}

/// The FMU crates and their model descriptions (relative to the workspace root).
const CRATES: [(&str, &str, &str); 3] = [
    ("damper", "semi_active_damper", "modelDescription.xml"),
    ("truck", "quarter_truck", "crates/quarter_truck/modelDescription.xml"),
    ("full_truck", "full_truck", "crates/full_truck/modelDescription.xml"),
];

/// `cargo SUBCOMMAND` on this workspace.
fn cargo(subcommand: &str) -> std::process::Command {
    let mut cargo = std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo.arg(subcommand).arg("--manifest-path").arg(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"));
    cargo
}

/// The directory of the cdylibs of this test's profile for `standard`. The FMI 2.0 ones are those
/// `cargo test` compiled into deps/ with the rlibs, where all three are there
/// ([`fresh_cdylib`](crate::common::cdylib::fresh_cdylib)); else they are built, as the FMI 3.0 ones
/// always are: the crates' feature `fmi3`, built into the target directory's fmi3/ (as
/// scripts/package_fmu.py builds them), so that they do not replace the FMI 2.0 ones.
fn build(standard: Standard) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let fresh = |(_, krate, _): &(&str, &str, &str)| crate::common::cdylib::fresh_cdylib(&profile_dir, krate).is_some();
    if standard == Standard::Fmi2 && CRATES.iter().all(fresh) {
        return profile_dir.join("deps");
    }
    let release = profile_dir.ends_with("release");
    let mut cargo = cargo("build");
    cargo.arg("--lib");
    for (_, krate, _) in CRATES {
        cargo.args(["-p", krate]);
    }
    if release {
        cargo.arg("--release");
    }
    let dir = match standard {
        Standard::Fmi2 => profile_dir,
        Standard::Fmi3 => {
            let target = profile_dir.parent().unwrap().join("fmi3");
            let features: Vec<String> = CRATES.iter().map(|(_, krate, _)| format!("{krate}/fmi3")).collect();
            cargo.arg("--features").arg(features.join(",")).arg("--target-dir").arg(&target);
            target.join(if release { "release" } else { "debug" })
        }
    };
    assert!(cargo.status().expect("run cargo").success(), "cargo build --lib failed");
    dir
}

/// The FMI 3.0 model description generated from an FMI 2.0 one (`fmi3-model-description`).
fn fmi3_description(xml: &Path) -> String {
    let out = cargo("run")
        .args(["--quiet", "--release", "-p", "fmi_codegen", "--bin", "fmi3-model-description", "--"])
        .arg(xml)
        .output()
        .expect("run cargo");
    assert!(out.status.success(), "fmi3-model-description failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8")
}

/// # Safety
/// `lib` must be this workspace's FMU binary of the standard whose symbol names the caller asks for.
unsafe fn symbol<T: Copy>(lib: &libloading::Library, name: &str) -> T {
    let name = format!("{name}\0");
    // SAFETY: the symbol is the FMI function of that name, whose C signature T transcribes; the
    // pointer is used only while `lib` lives (in Fmu).
    *unsafe { lib.get::<T>(name.as_bytes()) }.unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn open(name: &'static str, standard: Standard, library: PathBuf, xml: &Path) -> Fmu {
    // SAFETY: the library is this workspace's FMU, whose initialisers are Rust's own.
    let lib = unsafe { libloading::Library::new(&library) }.unwrap_or_else(|e| panic!("{library:?}: {e}"));
    let p = match standard {
        Standard::Fmi2 => "fmi2",
        Standard::Fmi3 => "fmi3",
    };
    macro_rules! sym {
        ($name:expr) => {
            // SAFETY: the name is the standard's, in its own binary, and the field's type its signature.
            unsafe { symbol(&lib, &format!("{p}{}", $name)) }
        };
    }
    let common = Common {
        free_instance: sym!("FreeInstance"),
        enter_initialization_mode2: (standard == Standard::Fmi2).then(|| sym!("EnterInitializationMode")),
        exit_initialization_mode: sym!("ExitInitializationMode"),
        terminate: sym!("Terminate"),
        reset: sym!("Reset"),
        get_fmu_state: sym!(if standard == Standard::Fmi2 { "GetFMUstate" } else { "GetFMUState" }),
        set_fmu_state: sym!(if standard == Standard::Fmi2 { "SetFMUstate" } else { "SetFMUState" }),
        free_fmu_state: sym!(if standard == Standard::Fmi2 { "FreeFMUstate" } else { "FreeFMUState" }),
        serialized_size: sym!(if standard == Standard::Fmi2 {
            "SerializedFMUstateSize"
        } else {
            "SerializedFMUStateSize"
        }),
        serialize: sym!(if standard == Standard::Fmi2 { "SerializeFMUstate" } else { "SerializeFMUState" }),
        deserialize: sym!(if standard == Standard::Fmi2 { "DeSerializeFMUstate" } else { "DeserializeFMUState" }),
    };
    let (api, info) = match standard {
        Standard::Fmi2 => {
            let api = Fmi2 {
                instantiate: sym!("Instantiate"),
                set_debug_logging: sym!("SetDebugLogging"),
                setup_experiment: sym!("SetupExperiment"),
                get_real: sym!("GetReal"),
                get_integer: sym!("GetInteger"),
                get_boolean: sym!("GetBoolean"),
                get_string: sym!("GetString"),
                set_real: sym!("SetReal"),
                set_integer: sym!("SetInteger"),
                set_boolean: sym!("SetBoolean"),
                set_string: sym!("SetString"),
                do_step: sym!("DoStep"),
                cancel_step: sym!("CancelStep"),
                get_status: sym!("GetStatus"),
                get_real_status: sym!("GetRealStatus"),
                get_boolean_status: sym!("GetBooleanStatus"),
            };
            (Api::Fmi2(api), ModelInfo::read(&std::fs::read_to_string(xml).unwrap()))
        }
        Standard::Fmi3 => {
            let no_variables = ["GetFloat32", "SetFloat32", "GetInt64", "SetUInt16", "GetString", "SetString"];
            let refused = [
                "EnterEventMode",
                "EnterStepMode",
                "EnterConfigurationMode",
                "EnterContinuousTimeMode",
                "EvaluateDiscreteStates",
            ];
            let api = Fmi3 {
                instantiate: sym!("InstantiateCoSimulation"),
                instantiate_model_exchange: sym!("InstantiateModelExchange"),
                set_debug_logging: sym!("SetDebugLogging"),
                enter_initialization_mode: sym!("EnterInitializationMode"),
                get_float64: sym!("GetFloat64"),
                get_int32: sym!("GetInt32"),
                get_boolean: sym!("GetBoolean"),
                set_float64: sym!("SetFloat64"),
                set_int32: sym!("SetInt32"),
                set_boolean: sym!("SetBoolean"),
                no_variables: no_variables.iter().map(|n| (*n, sym!(n))).collect(),
                refused: refused.iter().map(|n| (*n, sym!(n))).collect(),
                do_step: sym!("DoStep"),
            };
            (Api::Fmi3(api), ModelInfo::read(&fmi3_description(xml)))
        }
    };
    Fmu { name, standard, common, api, info, _library: lib }
}

/// How many FMUs the tests load, of each standard.
pub const FMUS: usize = 3;

/// The damper (index 0), the quarter truck (index 1) and the full truck (index 2) of `standard`,
/// loaded once per test binary.
pub fn fmus(standard: Standard) -> &'static [Fmu; FMUS] {
    static FMI2: OnceLock<[Fmu; FMUS]> = OnceLock::new();
    static FMI3: OnceLock<[Fmu; FMUS]> = OnceLock::new();
    let cell = if standard == Standard::Fmi2 { &FMI2 } else { &FMI3 };
    cell.get_or_init(|| {
        // CALL_SEQUENCES_LIBS: a directory with other builds of the FMI 2.0 binaries (e.g. an older
        // commit's, to see what this test finds there); by default this profile's, rebuilt
        let given = std::env::var_os("CALL_SEQUENCES_LIBS").filter(|_| standard == Standard::Fmi2);
        let dir = given.map_or_else(|| build(standard), PathBuf::from);
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        CRATES.map(|(name, krate, xml)| open(name, standard, dir.join(format!("lib{krate}.so")), &root.join(xml)))
    })
}

/// The last messages the FMUs logged (a few hundred: the fuzzer's instances log millions).
pub static RECENT: std::sync::Mutex<std::collections::VecDeque<String>> =
    std::sync::Mutex::new(std::collections::VecDeque::new());

fn remember(message: *const c_char) {
    // SAFETY: the FMU passes a NUL-terminated message, valid for the call.
    let text = unsafe { std::ffi::CStr::from_ptr(message) }.to_string_lossy().into_owned();
    if let Ok(mut recent) = RECENT.lock() {
        if recent.len() == 256 {
            recent.pop_front();
        }
        recent.push_back(text);
    }
}

/// The FMI 2.0 importer's logger, declared without the variadic tail (the FMUs pass none).
unsafe extern "C" fn logger(_: *mut c_void, _: fmi2String, _: fmi2Status, _: fmi2String, message: fmi2String) {
    remember(message);
}

/// The FMI 3.0 importer's logger.
unsafe extern "C" fn log_message(_: *mut c_void, _: u32, _: fmi3String, message: fmi3String) {
    remember(message);
}

type FixedLogger = unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String);

/// FMI 2.0 callbacks with the logger above.
pub fn callbacks() -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        // SAFETY: the FMUs call the logger with exactly the fixed arguments (no '%' directive),
        // which the x86-64 C ABI passes alike for a variadic declaration.
        logger: unsafe { std::mem::transmute::<FixedLogger, fmi2CallbackLogger>(logger) },
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    }
}

/// How an instance is asked for: valid, or one of the ways an importer gets it wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instantiation {
    Valid,
    NullName,
    EmptyName,
    OtherGuid,
    NullGuid,
    /// FMI 2.0 fmuType ModelExchange, FMI 3.0 fmi3InstantiateModelExchange.
    ModelExchange,
    /// FMI 3.0 only: eventModeUsed, or required intermediate variables, which these FMUs lack.
    EventMode,
    IntermediateVariables,
}

impl Fmu {
    /// An instance of this FMU, asked for as `how` says (`other_guid`: another FMU's).
    ///
    /// # Safety
    /// The pointers it passes are its own; the instance must be freed by the caller.
    pub unsafe fn instantiate(&self, how: Instantiation, logging: bool, other_guid: &str) -> H {
        let guid =
            std::ffi::CString::new(if how == Instantiation::OtherGuid { other_guid } else { &self.info.guid }).unwrap();
        let name = match how {
            Instantiation::NullName => null(),
            Instantiation::EmptyName => c"".as_ptr(),
            _ => c"fuzz".as_ptr(),
        };
        let g = if how == Instantiation::NullGuid { null() } else { guid.as_ptr() };
        match &self.api {
            Api::Fmi2(f) => {
                let ty = if how == Instantiation::ModelExchange {
                    fmi2Type_fmi2ModelExchange
                } else {
                    fmi2Type_fmi2CoSimulation
                };
                let cb = callbacks();
                // SAFETY: NULL or NUL-terminated strings and a callback struct alive for the call.
                unsafe { (f.instantiate)(name, ty, g, null(), &cb, 0, logging as i32) }
            }
            Api::Fmi3(f) => {
                let required = [1u32];
                let n_required = usize::from(how == Instantiation::IntermediateVariables);
                let event_mode = how == Instantiation::EventMode;
                let log: fmi3LogMessageCallback = Some(log_message);
                if how == Instantiation::ModelExchange {
                    // SAFETY: as above.
                    return unsafe {
                        (f.instantiate_model_exchange)(name, g, null(), false, logging, std::ptr::null_mut(), log)
                    };
                }
                // SAFETY: as above; `required` holds n_required value references.
                unsafe {
                    (f.instantiate)(
                        name,
                        g,
                        null(),
                        false,
                        logging,
                        event_mode,
                        false,
                        required.as_ptr(),
                        n_required,
                        std::ptr::null_mut(),
                        log,
                        null(),
                    )
                }
            }
        }
    }
}

/// The calls whose C signatures differ between the standards, spoken alike: FMI 2.0 ignores
/// `n_values` (it has none) and the experiment's arguments of fmi2EnterInitializationMode (its
/// fmi2SetupExperiment takes them); FMI 3.0's Booleans are bytes.
///
/// Every method's safety: `c` must be a live instance of this FMU; pointers must hold the counts given (NULL only for 0).
impl Fmu {
    /// The standard's name of a function: `fmi2…` or `fmi3…`, from the two spellings.
    pub fn name(&self, fmi2: &'static str, fmi3: &'static str) -> &'static str {
        if self.standard == Standard::Fmi2 {
            fmi2
        } else {
            fmi3
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn set_debug_logging(&self, c: H, on: bool, n: usize, categories: *const *const c_char) -> S {
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(f) => unsafe { (f.set_debug_logging)(c, on as i32, n, categories) },
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe { (f.set_debug_logging)(c, on, n, categories) },
        }
    }

    /// fmi2SetupExperiment; `None` for FMI 3.0, which has no such call.
    ///
    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn setup_experiment(&self, c: H, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Option<S> {
        let (tol_defined, tol) = (tolerance.is_some() as i32, tolerance.unwrap_or(0.0));
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(f) => Some(unsafe {
                (f.setup_experiment)(c, tol_defined, tol, start, stop.is_some() as i32, stop.unwrap_or(f64::NAN))
            }),
            Api::Fmi3(_) => None,
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn enter_initialization_mode(&self, c: H, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> S {
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(_) => unsafe { (self.common.enter_initialization_mode2.expect("FMI 2.0"))(c) },
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe {
                let tol = tolerance.unwrap_or(0.0);
                (f.enter_initialization_mode)(
                    c,
                    tolerance.is_some(),
                    tol,
                    start,
                    stop.is_some(),
                    stop.unwrap_or(f64::NAN),
                )
            },
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn get_real(&self, c: H, vr: *const u32, n: usize, values: *mut f64, n_values: usize) -> S {
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(f) => unsafe { (f.get_real)(c, vr, n, values) },
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe { (f.get_float64)(c, vr, n, values, n_values) },
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn set_real(&self, c: H, vr: *const u32, n: usize, values: *const f64, n_values: usize) -> S {
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(f) => unsafe { (f.set_real)(c, vr, n, values) },
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe { (f.set_float64)(c, vr, n, values, n_values) },
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn get_integer(&self, c: H, vrs: &[u32], n_values: usize) -> S {
        let mut out = vec![0i32; vrs.len()];
        match &self.api {
            // SAFETY: see the impl's safety section; out holds vrs.len() elements.
            Api::Fmi2(f) => unsafe { (f.get_integer)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) },
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe { (f.get_int32)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n_values) },
        }
    }

    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn get_boolean(&self, c: H, vrs: &[u32], n_values: usize) -> S {
        match &self.api {
            Api::Fmi2(f) => {
                let mut out = vec![7i32; vrs.len()];
                // SAFETY: see the impl's safety section; out holds vrs.len() elements.
                unsafe { (f.get_boolean)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) }
            }
            Api::Fmi3(f) => {
                let mut out = vec![7u8; vrs.len()];
                // SAFETY: as above.
                let s = unsafe { (f.get_boolean)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n_values) };
                assert!(s != 0 || out.iter().all(|b| *b <= 1), "fmi3GetBoolean wrote a byte other than 0 or 1");
                s
            }
        }
    }

    /// Sets Integers or Booleans from `values` (FMI 3.0 Booleans: their low byte, so 2 or 255 too).
    ///
    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn set_integer_or_boolean(
        &self,
        c: H,
        boolean: bool,
        vrs: &[u32],
        values: &[i32],
        n_values: usize,
    ) -> S {
        let (vp, n) = (vrs.as_ptr(), vrs.len());
        match &self.api {
            // SAFETY: see the impl's safety section; values holds n elements.
            Api::Fmi2(f) if boolean => unsafe { (f.set_boolean)(c, vp, n, values.as_ptr()) },
            // SAFETY: as above.
            Api::Fmi2(f) => unsafe { (f.set_integer)(c, vp, n, values.as_ptr()) },
            Api::Fmi3(f) if boolean => {
                let bytes: Vec<u8> = values.iter().map(|x| *x as u8).collect();
                // SAFETY: as above.
                unsafe { (f.set_boolean)(c, vp, n, bytes.as_ptr(), n_values) }
            }
            // SAFETY: as above.
            Api::Fmi3(f) => unsafe { (f.set_int32)(c, vp, n, values.as_ptr(), n_values) },
        }
    }

    /// A step: the status, and FMI 3.0's lastSuccessfulTime and whether any other out-argument
    /// said yes (events, termination, early return: these FMUs never do).
    ///
    /// # Safety
    /// As the `impl` block says.
    pub unsafe fn do_step(&self, c: H, t: f64, h: f64) -> (S, Option<(f64, bool)>) {
        match &self.api {
            // SAFETY: see the impl's safety section.
            Api::Fmi2(f) => (unsafe { (f.do_step)(c, t, h, 0) }, None),
            Api::Fmi3(f) => {
                let (mut event, mut terminate, mut early, mut last) = (true, true, true, f64::NAN);
                // SAFETY: as above; the out-arguments are valid locals.
                let s = unsafe { (f.do_step)(c, t, h, false, &mut event, &mut terminate, &mut early, &mut last) };
                (s, Some((last, event || terminate || early)))
            }
        }
    }
}
