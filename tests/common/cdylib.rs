//! The FMU crates' cdylibs of a test program's profile, for the tests that load them or pack them
//! into an .fmu (this crate's tests/import_fmu.rs and fmi_fuzz, and damper_cli's
//! tests/fmu_backend.rs, which includes this file).

use std::path::{Path, PathBuf};

/// `krate`'s cdylib in `profile_dir` (target/<profile>) as `cargo test` compiled it into deps/, in
/// the same rustc run as the rlib the test program links (cargo does not copy it up to the profile
/// folder: cargo#8311); none when it is not there or older than the rlib (a build of the rlib
/// alone). A `cargo build -p` of the crates instead resolves their features without the
/// workspace's and recompiles shared dependencies inside the test, and again in the next
/// `--workspace` build (about a minute of CI each time).
pub fn fresh_cdylib(profile_dir: &Path, krate: &str) -> Option<PathBuf> {
    let deps = profile_dir.join("deps");
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    let so = deps.join(format!("lib{krate}.so"));
    let (written, rlib) = (modified(&so)?, modified(&deps.join(format!("lib{krate}.rlib")))?);
    // written together with the rlib: at most a few seconds apart, in either order
    let apart = written.duration_since(rlib).or_else(|_| rlib.duration_since(written)).ok()?;
    (apart.as_secs() < 5).then_some(so)
}

/// The damper's cdylib of `profile_dir` ([`fresh_cdylib`]), else a `cargo build --lib -p
/// semi_active_damper` of that profile in the workspace of `root` (its directory).
pub fn damper_library(profile_dir: &Path, root: &str) -> PathBuf {
    if let Some(so) = fresh_cdylib(profile_dir, "semi_active_damper") {
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
