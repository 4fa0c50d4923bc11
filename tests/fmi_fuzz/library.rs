//! The two FMU binaries, built by this test's profile and opened with dlopen; their C API as a
//! table of function pointers, as an importer sees it.

use super::model_info::ModelInfo;
use fmi2_slave::api::fmi2::*;
use std::ffi::c_void;
use std::path::PathBuf;
use std::sync::OnceLock;

type C = fmi2Component;
type S = fmi2Status;

/// The FMI 2.0 Co-Simulation functions the fuzzer calls.
pub struct Api {
    pub instantiate: unsafe extern "C" fn(
        fmi2String,
        fmi2Type,
        fmi2String,
        fmi2String,
        *const fmi2CallbackFunctions,
        fmi2Boolean,
        fmi2Boolean,
    ) -> C,
    pub free_instance: unsafe extern "C" fn(C),
    pub set_debug_logging: unsafe extern "C" fn(C, fmi2Boolean, usize, *const fmi2String) -> S,
    pub setup_experiment: unsafe extern "C" fn(C, fmi2Boolean, f64, f64, fmi2Boolean, f64) -> S,
    pub enter_initialization_mode: unsafe extern "C" fn(C) -> S,
    pub exit_initialization_mode: unsafe extern "C" fn(C) -> S,
    pub terminate: unsafe extern "C" fn(C) -> S,
    pub reset: unsafe extern "C" fn(C) -> S,
    pub get_real: unsafe extern "C" fn(C, *const u32, usize, *mut f64) -> S,
    pub get_integer: unsafe extern "C" fn(C, *const u32, usize, *mut i32) -> S,
    pub get_boolean: unsafe extern "C" fn(C, *const u32, usize, *mut i32) -> S,
    pub get_string: unsafe extern "C" fn(C, *const u32, usize, *mut fmi2String) -> S,
    pub set_real: unsafe extern "C" fn(C, *const u32, usize, *const f64) -> S,
    pub set_integer: unsafe extern "C" fn(C, *const u32, usize, *const i32) -> S,
    pub set_boolean: unsafe extern "C" fn(C, *const u32, usize, *const i32) -> S,
    pub set_string: unsafe extern "C" fn(C, *const u32, usize, *const fmi2String) -> S,
    pub get_fmu_state: unsafe extern "C" fn(C, *mut fmi2FMUstate) -> S,
    pub set_fmu_state: unsafe extern "C" fn(C, fmi2FMUstate) -> S,
    pub free_fmu_state: unsafe extern "C" fn(C, *mut fmi2FMUstate) -> S,
    pub serialized_size: unsafe extern "C" fn(C, fmi2FMUstate, *mut usize) -> S,
    pub serialize: unsafe extern "C" fn(C, fmi2FMUstate, *mut fmi2Byte, usize) -> S,
    pub deserialize: unsafe extern "C" fn(C, *const fmi2Byte, usize, *mut fmi2FMUstate) -> S,
    pub do_step: unsafe extern "C" fn(C, f64, f64, fmi2Boolean) -> S,
    pub cancel_step: unsafe extern "C" fn(C) -> S,
    pub get_status: unsafe extern "C" fn(C, fmi2StatusKind, *mut S) -> S,
    pub get_real_status: unsafe extern "C" fn(C, fmi2StatusKind, *mut f64) -> S,
    pub get_boolean_status: unsafe extern "C" fn(C, fmi2StatusKind, *mut i32) -> S,
}

/// One FMU: its binary, its C API and its model description.
pub struct Fmu {
    pub name: &'static str,
    pub api: Api,
    pub info: ModelInfo,
    _library: libloading::Library,
}

/// Builds the cdylibs of this test's profile (`cargo test` builds only the rlibs, so the .so
/// files could be stale) and returns the profile's directory.
fn build() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let mut cargo = std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo.args(["build", "--lib", "-p", "semi_active_damper", "-p", "quarter_truck", "-p", "full_truck"]);
    cargo.arg("--manifest-path");
    cargo.arg(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"));
    if profile_dir.ends_with("release") {
        cargo.arg("--release");
    }
    assert!(cargo.status().expect("run cargo").success(), "cargo build --lib failed");
    profile_dir
}

fn open(name: &'static str, library: PathBuf, xml: &str) -> Fmu {
    // SAFETY: the library is this workspace's FMU, whose initialisers are Rust's own.
    let lib = unsafe { libloading::Library::new(&library) }.unwrap_or_else(|e| panic!("{library:?}: {e}"));
    macro_rules! sym {
        ($name:literal) => {
            // SAFETY: the symbol is the FMI 2.0 function of that name, whose C signature the
            // field's type transcribes; the pointer is used only while `lib` lives (in Fmu).
            *unsafe { lib.get(concat!($name, "\0").as_bytes()) }.expect($name)
        };
    }
    let api = Api {
        instantiate: sym!("fmi2Instantiate"),
        free_instance: sym!("fmi2FreeInstance"),
        set_debug_logging: sym!("fmi2SetDebugLogging"),
        setup_experiment: sym!("fmi2SetupExperiment"),
        enter_initialization_mode: sym!("fmi2EnterInitializationMode"),
        exit_initialization_mode: sym!("fmi2ExitInitializationMode"),
        terminate: sym!("fmi2Terminate"),
        reset: sym!("fmi2Reset"),
        get_real: sym!("fmi2GetReal"),
        get_integer: sym!("fmi2GetInteger"),
        get_boolean: sym!("fmi2GetBoolean"),
        get_string: sym!("fmi2GetString"),
        set_real: sym!("fmi2SetReal"),
        set_integer: sym!("fmi2SetInteger"),
        set_boolean: sym!("fmi2SetBoolean"),
        set_string: sym!("fmi2SetString"),
        get_fmu_state: sym!("fmi2GetFMUstate"),
        set_fmu_state: sym!("fmi2SetFMUstate"),
        free_fmu_state: sym!("fmi2FreeFMUstate"),
        serialized_size: sym!("fmi2SerializedFMUstateSize"),
        serialize: sym!("fmi2SerializeFMUstate"),
        deserialize: sym!("fmi2DeSerializeFMUstate"),
        do_step: sym!("fmi2DoStep"),
        cancel_step: sym!("fmi2CancelStep"),
        get_status: sym!("fmi2GetStatus"),
        get_real_status: sym!("fmi2GetRealStatus"),
        get_boolean_status: sym!("fmi2GetBooleanStatus"),
    };
    Fmu { name, api, info: ModelInfo::read(xml), _library: lib }
}

/// How many FMUs the tests load.
pub const FMUS: usize = 3;

/// The damper (index 0), the quarter truck (index 1) and the full truck (index 2), loaded once per
/// test binary.
pub fn fmus() -> &'static [Fmu; FMUS] {
    static FMUS_LOADED: OnceLock<[Fmu; FMUS]> = OnceLock::new();
    FMUS_LOADED.get_or_init(|| {
        // CALL_SEQUENCES_LIBS: a directory with other builds of the binaries (e.g. an older
        // commit's, to see what this test finds there); by default this profile's, rebuilt
        let dir = std::env::var_os("CALL_SEQUENCES_LIBS").map_or_else(build, PathBuf::from);
        let root = env!("CARGO_MANIFEST_DIR");
        [
            open("damper", dir.join("libsemi_active_damper.so"), &format!("{root}/modelDescription.xml")),
            open(
                "truck",
                dir.join("libquarter_truck.so"),
                &format!("{root}/crates/quarter_truck/modelDescription.xml"),
            ),
            open("full_truck", dir.join("libfull_truck.so"), &format!("{root}/crates/full_truck/modelDescription.xml")),
        ]
    })
}

/// The last messages the FMUs logged (a few hundred: the fuzzer's instances log millions).
pub static RECENT: std::sync::Mutex<std::collections::VecDeque<String>> =
    std::sync::Mutex::new(std::collections::VecDeque::new());

/// The importer's logger, declared without the variadic tail (the FMUs pass none).
unsafe extern "C" fn logger(_: *mut c_void, _: fmi2String, _: fmi2Status, _: fmi2String, message: fmi2String) {
    // SAFETY: the FMU passes a NUL-terminated message, valid for the call.
    let text = unsafe { std::ffi::CStr::from_ptr(message) }.to_string_lossy().into_owned();
    if let Ok(mut recent) = RECENT.lock() {
        if recent.len() == 256 {
            recent.pop_front();
        }
        recent.push_back(text);
    }
}

type FixedLogger = unsafe extern "C" fn(*mut c_void, fmi2String, fmi2Status, fmi2String, fmi2String);

/// Callbacks with the logger above.
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
