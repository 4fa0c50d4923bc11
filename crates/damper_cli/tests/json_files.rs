//! The JSON files the command line writes: summary.json of `damper compare` and `damper diagnose`
//! read back into the typed structs unchanged (tests/python/test_summary_schema.py checks them
//! against docs/summary.schema.json), and the truth file of `damper generate`.

use crate::common;

use common::{checked_summary, scratch};
use damper_engine::generate::{Truth, TruthInputs};
use damper_engine::summary::to_json;
use serde_json::Value;
use std::process::Command;

fn damper(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_damper")).args(args).arg("--quiet").output().expect("run damper");
    assert!(out.status.success(), "damper {args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn compare_and_diagnose_summaries_read_back_into_the_typed_structs() {
    let dir = scratch("json_summaries");
    let (csv, truth) = (dir.join("m.csv"), dir.join("m.json"));
    let (csv_s, truth_s) = (csv.to_str().unwrap(), truth.to_str().unwrap());
    damper(&["generate", "--out", csv_s, "--truth", truth_s, "--effect", "seal_friction", "--duration", "5"]);

    let out = dir.join("compare");
    damper(&["compare", csv_s, "--out", out.to_str().unwrap(), "--load-cell-lowpass", "400"]);
    let c = checked_summary(&out);
    assert!(c.verdict.is_none() && c.best_effect.is_none() && c.candidates.is_none() && c.diagnosis.is_none());
    assert_eq!(c.signals.keys().next().map(String::as_str), Some("F_damper"));
    assert!(!c.regimes.is_empty() && !c.worst_windows.is_empty() && c.nrmse_baseline > 0.0);

    let out = dir.join("diagnose");
    damper(&["diagnose", csv_s, "--out", out.to_str().unwrap(), "--load-cell-lowpass", "400"]);
    let d = checked_summary(&out);
    assert_eq!(d.verdict, Some(damper_engine::verdict::Verdict::Effect));
    assert_eq!(d.best_effect.as_deref(), Some("seal_friction"));
    let diagnosis = d.diagnosis.as_ref().expect("diagnose writes the diagnosis");
    assert_eq!(diagnosis.effects, ["seal_friction"]);
    let after = diagnosis.after.as_ref().expect("an effect named: before and after");
    assert!(after.validation_nrmse["F_damper"].after < after.validation_nrmse["F_damper"].before);
    assert_eq!(diagnosis.ladder[0].added, "baseline");
    let tried = damper_engine::candidate::candidates(&Default::default(), false).count();
    assert_eq!(d.candidates.as_ref().map(Vec::len), Some(tried));

    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_truth_file_records_every_seed() {
    let dir = scratch("json_truth");
    let (csv, truth) = (dir.join("t.csv"), dir.join("t.json"));
    let seed = u64::MAX.to_string();
    damper(&[
        "generate",
        "--out",
        csv.to_str().unwrap(),
        "--truth",
        truth.to_str().unwrap(),
        "--seed",
        &seed,
        "--duration",
        "1",
        "--effect",
        "viscous_friction=3000",
    ]);
    let text = std::fs::read_to_string(&truth).unwrap();
    // read as plain JSON (no typed struct in between) and as the typed truth
    let value: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(value["seed"].as_u64(), Some(u64::MAX), "{}", value["seed"]);
    let t: Truth = serde_json::from_str(&text).expect("the truth file reads into Truth");
    assert_eq!(t.seed, u64::MAX);
    assert_eq!(to_json(&t), text);
    assert!(matches!(t.inputs, TruthInputs::Rig { .. }));
    assert_eq!((t.samples, t.duration_s), (1001, 1.0));
    let e = &t.effects[0];
    assert_eq!(
        (e.key.as_str(), e.on, e.value_drawn_at_random, e.random_range),
        ("viscous_friction", true, false, None)
    );
    assert_eq!(e.params.get_index(0).map(|(n, v)| (n.as_str(), *v)), Some(("c_viscous", Some(3000.0))));
    let _ = std::fs::remove_dir_all(&dir);
}
