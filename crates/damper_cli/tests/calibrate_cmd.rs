//! `damper calibrate` as a user runs it: a record of a damper with two parameters moved, the
//! table, parameters.ssv and calibration.json, `--params` taken by compare, exit statuses.

use std::path::Path;
use std::process::{Command, Output};

fn damper_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_damper")).current_dir(dir).args(args).output().expect("run damper")
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn calibrate_writes_the_parameter_set_that_compare_takes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = damper_in(
        d,
        &["generate", "--out", "r.csv", "--truth", "t.json", "--duration", "4", "--seed", "3"]
            .iter()
            .copied()
            .chain(["--set", "air_fraction=0.03", "--set", "p_reservoir0=6e5", "--set", "rtol=1e-6"])
            .collect::<Vec<_>>(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let args = ["calibrate", "r.csv", "--out", "cal", "--fit", "air_fraction", "--fit", "p_reservoir0"];
    let o = damper_in(d, &[&args[..], &["--load-cell-lowpass", "400", "--threads", "2"]].concat());
    let out = text(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(out.contains("air_fraction") && out.contains("fitted") && out.contains("NRMSE before"), "{out}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("cal/calibration.json")).unwrap()).unwrap();
    let p = &json["parameters"][0];
    assert_eq!(p["name"], "air_fraction");
    let (value, unc) = (p["value"].as_f64().unwrap(), p["std_uncertainty"].as_f64().unwrap());
    assert!((value - 0.03).abs() < 3.0 * unc + 1e-4, "{p}");
    let ssv = std::fs::read_to_string(d.join("cal/parameters.ssv")).unwrap();
    assert!(ssv.contains("http://ssp-standard.org/SSP1/SystemStructureParameterValues"), "{ssv}");

    // compare with the calibrated set: at the noise floor
    let o = damper_in(
        d,
        &["compare", "r.csv", "--out", "c", "--params", "cal/parameters.ssv", "--load-cell-lowpass", "400"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    // a bad parameter file: exit status 1, the file, line and parameter named
    std::fs::write(d.join("bad.ssv"), ssv.replacen("name=\"air_fraction\"", "name=\"air_fractio\"", 1)).unwrap();
    let o = damper_in(d, &["compare", "r.csv", "--out", "c", "--params", "bad.ssv"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("bad.ssv, line 4, parameter air_fractio: unknown parameter"), "{}", text(&o));
    // a parameter that cannot be fitted: a usage error
    let o = damper_in(d, &["calibrate", "r.csv", "--out", "x", "--fit", "n_ports"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("only Real parameters"), "{}", text(&o));
}

#[test]
fn calibrate_help_has_examples_and_the_default_list() {
    let o = damper_in(Path::new("."), &["calibrate", "--help"]);
    assert_eq!(o.status.code(), Some(0));
    let help = text(&o);
    assert!(help.contains("Examples:") && help.contains("--fit-controller") && help.contains("p_reservoir0"), "{help}");
}
