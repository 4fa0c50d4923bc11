//! Checks `modelDescription.xml` and generates the variable enums, the `Parameters` struct and the
//! GUID from it (see `crates/fmi_codegen`), and the effect catalog from the files of
//! `src/effects/`: an effect is one new file there (and its parameters in the XML), nothing else.
use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    fmi_codegen::generate();
    effect_catalog();
}

/// Writes `$OUT_DIR/effect_catalog.rs`: a module for every `src/effects/<key>.rs` but `mod.rs`, and
/// `CATALOG`, each file's unit struct `<Key>` (the key in CamelCase), in the order of the keys.
fn effect_catalog() {
    println!("cargo:rerun-if-changed=src/effects");
    let dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it")).join("src/effects");
    let mut keys: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("a readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "rs") && p.file_stem().is_some_and(|s| s != "mod"))
        .map(|p| p.file_stem().expect("a file name").to_string_lossy().into_owned())
        .collect();
    keys.sort();
    let mut out = String::new();
    for key in &keys {
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_') {
            panic!("src/effects/{key}.rs: an effect's file is named by its key, in lower_snake_case");
        }
        let path = dir.join(format!("{key}.rs"));
        let _ = writeln!(out, "#[path = {:?}]\nmod {key};", path.display().to_string());
    }
    let _ = writeln!(out, "/// Every effect, one file each in `src/effects/`, in the order of their keys.");
    let _ = write!(out, "pub const CATALOG: [&dyn Effect; {}] = [", keys.len());
    for key in &keys {
        let _ = write!(out, "&{key}::{}, ", camel(key));
    }
    let _ = writeln!(out, "];");
    let target = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it")).join("effect_catalog.rs");
    std::fs::write(target, out).expect("OUT_DIR is writable");
}

fn camel(key: &str) -> String {
    key.split('_').filter(|part| !part.is_empty()).map(|part| part[..1].to_ascii_uppercase() + &part[1..]).collect()
}
