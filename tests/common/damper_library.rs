//! The damper's cdylib of a test program's profile, for the tests that pack it into an .fmu (this
//! crate's tests/import_fmu.rs and damper_cli's tests/fmu_backend.rs, which includes this file).

use std::path::{Path, PathBuf};

/// The damper's cdylib in `profile_dir` (target/<profile>): the one `cargo test` compiled into deps/
/// in the same rustc run as the rlib the test program links (cargo does not copy it up to the
/// profile folder: cargo#8311), else a `cargo build --lib -p semi_active_damper` of that profile in
/// the workspace of `root` (its directory). That build resolves the damper's features without the
/// workspace's and recompiled shared dependencies inside the test (about a minute of CI).
pub fn damper_library(profile_dir: &Path, root: &str) -> PathBuf {
    let deps = profile_dir.join("deps");
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let so = deps.join("libsemi_active_damper.so");
    // written together with the rlib: at most a few seconds apart, in either order
    let with_rlib = match (modified(&so), modified(&deps.join("libsemi_active_damper.rlib"))) {
        (Some(so), Some(rlib)) => {
            so.duration_since(rlib).or_else(|_| rlib.duration_since(so)).is_ok_and(|d| d.as_secs() < 5)
        }
        _ => false,
    };
    if with_rlib {
        return so;
    }
    let mut cargo = std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cargo.args(["build", "--lib", "-p", "semi_active_damper", "--manifest-path", &format!("{root}/Cargo.toml")]);
    if profile_dir.ends_with("release") {
        cargo.arg("--release");
    }
    assert!(cargo.status().expect("run cargo").success(), "cargo build --lib failed");
    profile_dir.join("libsemi_active_damper.so")
}
