//! A passive damper as a user brings one: `damper init` writes the description, `damper describe`
//! shows it and writes it as an SSP parameter set, a record without a demand column runs with the
//! valve held, and the description brings the model to the damper.

use std::path::Path;
use std::process::{Command, Output};

fn damper_in(dir: &Path, args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_damper")).current_dir(dir).args(args).output().expect("run damper");
    assert!(
        o.status.success(),
        "damper {}: {}{}",
        args.join(" "),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("damper_cli_passive_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn summary(dir: &Path, out: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join(out).join("summary.json")).unwrap()).unwrap()
}

#[test]
fn init_then_describe_writes_the_parameter_set() {
    let dir = scratch("init");
    damper_in(&dir, &["init", "--out", "mine.toml"]);
    let again = Command::new(env!("CARGO_BIN_EXE_damper"))
        .current_dir(&dir)
        .args(["init", "--out", "mine.toml"])
        .output()
        .unwrap();
    assert_eq!(again.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&again.stderr).contains("mine.toml: exists"));
    let o = damper_in(&dir, &["describe", "mine.toml", "--ssv", "mine.ssv"]);
    let printed = String::from_utf8_lossy(&o.stdout);
    assert!(printed.contains("D_piston") && printed.contains("[cylinder] piston_diameter"), "{printed}");
    let ssv = std::fs::read_to_string(dir.join("mine.ssv")).unwrap();
    assert!(ssv.contains("name=\"control_mode\"") && ssv.contains("name=\"A_bleed_reb\""), "{ssv}");
}

/// The template's damper generated with the description, compared without a demand column: with
/// the description the model is at the noise floor; the stock (truck) model is far off.
#[test]
fn a_passive_record_is_compared_with_the_valve_held() {
    let dir = scratch("compare");
    damper_in(&dir, &["init", "--out", "mine.toml"]);
    damper_in(
        &dir,
        &[
            "generate",
            "--damper",
            "mine.toml",
            "--out",
            "p.csv",
            "--truth",
            "p.json",
            "--duration",
            "5",
            "--seed",
            "3",
            "--sensor",
            "F_damper=3:0.1",
        ],
    );
    let header = std::fs::read_to_string(dir.join("p.csv")).unwrap();
    let header = header.lines().next().unwrap();
    assert!(!header.contains("F_demand") && !header.contains("x_spool"), "{header}");
    damper_in(&dir, &["compare", "p.csv", "--out", "with", "--damper", "mine.toml", "--load-cell-lowpass", "400"]);
    damper_in(&dir, &["compare", "p.csv", "--out", "stock", "--load-cell-lowpass", "400"]);
    let (with, stock) = (summary(&dir, "with"), summary(&dir, "stock"));
    let ratio =
        |s: &serde_json::Value| s["nrmse_baseline"].as_f64().unwrap() / s["noise_floor_estimate"].as_f64().unwrap();
    assert!(ratio(&with) < 1.3, "with the description: {} × the floor", ratio(&with));
    assert!(ratio(&stock) > 50.0, "the stock model: {} × the floor", ratio(&stock));
    // diagnosed with the stock model: it does not fit, and the reason is the valve's law
    damper_in(&dir, &["diagnose", "p.csv", "--out", "stock_d", "--load-cell-lowpass", "400"]);
    let d = summary(&dir, "stock_d");
    let why = d["explanation"].as_str().unwrap();
    assert_eq!(d["verdict"], "does_not_fit", "{why}");
    assert!(why.contains("The force–velocity laws differ") && why.contains("degressive"), "{why}");
    // a passive description refuses a record with a demand
    let rows: String = (0..400).map(|k| format!("{},0.1,0,{}\n", k as f64 * 1e-3, k % 7)).collect();
    std::fs::write(dir.join("d.csv"), format!("time,v_damper,F_demand,F_damper\n{rows}")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_damper"))
        .current_dir(&dir)
        .args(["compare", "d.csv", "--out", "d", "--damper", "mine.toml"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stderr).contains("a passive damper has no demand"), "{o:?}");
}

/// An end stop the model lacks (its stops off, the catalog's end_stops skipped, as if the catalog
/// had none): one local effect, `unexplained` with the stroke named, not `does_not_fit`; with the
/// catalog's effect, `effect (end_stops)`.
#[test]
fn a_missing_end_stop_is_named_by_the_stroke_it_follows() {
    let dir = scratch("end_stop");
    damper_in(&dir, &["init", "--out", "mine.toml"]);
    let generate = [
        "generate",
        "--damper",
        "mine.toml",
        "--out",
        "e.csv",
        "--truth",
        "e.json",
        "--duration",
        "5",
        "--seed",
        "3",
        "--set",
        "x_end_stop=0.02",
    ];
    damper_in(&dir, &generate);
    let diagnose =
        ["diagnose", "e.csv", "--damper", "mine.toml", "--set", "effect_end_stops=0", "--load-cell-lowpass", "400"];
    damper_in(&dir, &[&diagnose[..], &["--out", "without", "--skip", "end_stops"]].concat());
    let d = summary(&dir, "without");
    let why = d["explanation"].as_str().unwrap();
    assert_eq!(d["verdict"], "unexplained", "{why}");
    assert!(why.contains("follows the stroke alone"), "{why}");
    assert_eq!(d["residual_signature"]["follows"][0]["quantity"], "stroke");
    damper_in(&dir, &[&diagnose[..], &["--out", "with"]].concat());
    let d = summary(&dir, "with");
    assert_eq!(
        (d["verdict"].as_str(), d["effects"][0].as_str()),
        (Some("effect"), Some("end_stops")),
        "{}",
        d["explanation"]
    );
}
