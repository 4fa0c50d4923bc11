//! Helpers shared by the damper CLI tests.
#![allow(dead_code)]

use damper_engine::comparison::{CompareOptions, Comparison};
use damper_engine::summary::{to_json, Summary};
use serde_json::Value;
use std::path::Path;

const SCHEMA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/summary.schema.json");

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

/// The validator of docs/summary.schema.json.
pub fn validator() -> jsonschema::Validator {
    let schema: Value = serde_json::from_str(&std::fs::read_to_string(SCHEMA).unwrap()).expect("the schema is JSON");
    jsonschema::validator_for(&schema).expect("a valid JSON Schema")
}

/// Where and why `instance` breaks the schema.
pub fn schema_errors(v: &jsonschema::Validator, instance: &Value) -> Vec<String> {
    v.iter_errors(instance).map(|e| format!("{}: {e}", e.instance_path())).collect()
}

/// summary.json in `dir`: valid against the schema, and the typed structs read it and write it
/// back to the same text (same keys, order and numbers).
pub fn checked_summary(v: &jsonschema::Validator, dir: &Path) -> Summary {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let value: Value = serde_json::from_str(&text).expect("summary.json is JSON");
    let errors = schema_errors(v, &value);
    assert!(errors.is_empty(), "{}: {errors:#?}", dir.display());
    let summary: Summary = serde_json::from_str(&text).expect("summary.json reads into Summary");
    assert_eq!(to_json(&summary), text, "{}: written back differently", dir.display());
    summary
}
