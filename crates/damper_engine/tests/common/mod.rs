//! Helpers shared by the engine's tests.

use damper_engine::generate::{self, GenerateOptions, Generated};
use std::path::{Path, PathBuf};

/// A fresh, empty scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("damper_engine_test_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Generates `name.csv` (+ `name_truth.json`) in `dir` with `configure` applied to the defaults
/// (rig inputs, 5 s at 1 kHz, seed 1).
pub fn generate(dir: &Path, name: &str, configure: impl FnOnce(&mut GenerateOptions)) -> (PathBuf, Generated) {
    let csv = dir.join(format!("{name}.csv"));
    let mut o = GenerateOptions::new(&csv, dir.join(format!("{name}_truth.json")));
    o.duration = 5.0;
    configure(&mut o);
    let g = generate::write(&o).expect("generate");
    (csv, g)
}
