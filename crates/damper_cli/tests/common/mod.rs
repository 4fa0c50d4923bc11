//! Helpers shared by the damper CLI tests.
#![allow(dead_code)]

use damper_engine::comparison::{CompareOptions, Comparison};
use damper_engine::summary::{to_json, Summary};
use std::path::Path;

// The engine's test helpers, shared rather than copied.
#[path = "../../../damper_engine/tests/common/mod.rs"]
mod engine_common;
#[allow(unused_imports)] // each test binary uses its own subset
pub use engine_common::{generate, scratch};

/// Compares `csv` with the default model plus `configure`, load-cell filter 400 Hz (the
/// generator's default), and writes the report into `dir/out_name`.
pub fn compare(
    dir: &std::path::Path,
    csv: &std::path::Path,
    out: &str,
    configure: impl FnOnce(&mut CompareOptions),
) -> Comparison {
    let mut o = CompareOptions::new(csv);
    o.load_cell_lowpass_hz = Some(400.0);
    configure(&mut o);
    damper_cli::compare::run(&o, &dir.join(out), true).expect("compare")
}

pub fn regime<'a>(c: &'a Comparison, group: &str, name_starts: &str) -> &'a damper_engine::analysis::Regime {
    c.analysis
        .regimes
        .iter()
        .find(|r| r.group == group && r.name.starts_with(name_starts))
        .unwrap_or_else(|| panic!("no regime {group}/{name_starts}"))
}

/// summary.json in `dir`, read into the typed structs and written back to the same text (same
/// keys, order and numbers). Its validity against docs/summary.schema.json is
/// tests/python/test_summary_schema.py's.
pub fn checked_summary(dir: &Path) -> Summary {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let summary: Summary = serde_json::from_str(&text).expect("summary.json reads into Summary");
    assert_eq!(to_json(&summary), text, "{}: written back differently", dir.display());
    summary
}
