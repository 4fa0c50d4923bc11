//! Bad measurement files: every case stops with a message naming the file, the line and the column.

use crate::common;

use damper_engine::comparison::{compare, CompareOptions};
use damper_engine::measurement::{Mapping, Measurement, DEFAULT_MAX_GAP};
use std::path::{Path, PathBuf};

const HEADER: &str = "time,v_damper,F_demand,F_damper";

fn good_rows(n: usize) -> String {
    (0..n).map(|k| format!("{},{},{},{}\n", k as f64 * 1e-3, 0.1, 1000.0, 900.0)).collect()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Reads `text` as `name` and returns the error, which must name the file and contain every part.
fn expect_error(dir: &Path, name: &str, text: &str, maps: &[Mapping], parts: &[&str]) -> String {
    let path = write(dir, name, text);
    let err = Measurement::read(&path, maps, DEFAULT_MAX_GAP).expect_err("a bad file must be refused").to_string();
    assert!(err.contains(name), "error does not name the file: {err}");
    for p in parts {
        assert!(err.contains(p), "error lacks '{p}': {err}");
    }
    eprintln!("{err}");
    err
}

#[test]
fn each_bad_input_is_named_by_file_line_and_column() {
    let dir = common::scratch("csv_errors");
    let rows = good_rows(5);

    // missing and misnamed columns: the header line and the column's name
    expect_error(&dir, "missing.csv", "time,v_damper,F_demand\n0,0,0\n", &[], &["line 1", "missing column 'F_damper'"]);
    expect_error(
        &dir,
        "misnamed.csv",
        &format!("time,v_damper,F_demand,F_Damper\n{rows}"),
        &[],
        &["line 1", "missing column 'F_damper'", "Did you mean 'F_Damper'", "--map"],
    );
    expect_error(
        &dir,
        "no_velocity.csv",
        "time,speed,F_demand,F_damper\n0,0,0,0\n",
        &[],
        &["line 1", "v_damper", "x_damper"],
    );
    // time that does not increase: the line, the time column and both values
    let back = format!("{HEADER}\n0,0,0,0\n0.001,0,0,0\n0.003,0,0,0\n0.002,0,0,0\n0.004,0,0,0\n");
    expect_error(&dir, "backwards.csv", &back, &[], &["line 5", "column 1 ('time')", "0.002", "is before", "line 4"]);
    let dup = format!("{HEADER}\n0,0,0,0\n0.001,0,0,0\n0.001,0,0,0\n");
    expect_error(&dir, "duplicate.csv", &dup, &[], &["line 4", "column 1 ('time')", "repeats"]);

    // bad cells
    let nan = format!("{HEADER}\n0,0,0,0\n0.001,0,NaN,0\n");
    expect_error(&dir, "nan.csv", &nan, &[], &["line 3", "column 3 ('F_demand')", "not a finite number"]);
    let empty = format!("{HEADER}\n0,0,0,0\n0.001,0.1,,0\n");
    expect_error(&dir, "empty.csv", &empty, &[], &["line 3", "column 3 ('F_demand')", "empty cell"]);
    let text = format!("{HEADER}\n0,0,0,0\n0.001,fast,0,0\n");
    expect_error(&dir, "text.csv", &text, &[], &["line 3", "column 2 ('v_damper')", "not a number: 'fast'"]);
    let short = format!("{HEADER}\n0,0,0,0\n0.001,0,0\n");
    expect_error(&dir, "short_row.csv", &short, &[], &["line 3", "column 4", "3 fields", "has 4"]);
    let long = format!("{HEADER}\n0,0,0,0,7\n");
    expect_error(&dir, "long_row.csv", &long, &[], &["line 2", "column 5", "5 fields"]);
    let blank = format!("{HEADER}\n0,0,0,0\n\n0.002,0,0,0\n");
    expect_error(&dir, "blank.csv", &blank, &[], &["line 3", "empty line"]);

    // units: unknown, or of the wrong quantity, in the header
    let unit = format!("time,v_damper,F_demand,F_damper [Nm]\n{rows}");
    expect_error(&dir, "unit.csv", &unit, &[], &["line 1", "column 4 ('F_damper [Nm]')", "unknown unit 'Nm'"]);
    let wrong = format!("time [s],v_damper [mm],F_demand,F_damper\n{rows}");
    expect_error(&dir, "wrong_unit.csv", &wrong, &[], &["line 1", "column 2", "is a length", "v_damper is a velocity"]);

    // mappings that do not fit the file
    let map = [Mapping::parse("vel=v_damper:cm/s").unwrap()];
    expect_error(&dir, "map.csv", &format!("{HEADER}\n{rows}"), &map, &["line 1", "--map names column 'vel'"]);
    let twice = format!("time,v_damper,F_demand,F_damper,load\n{}", "0,0,0,0,0\n");
    let map = [Mapping::parse("load=F_damper:kN").unwrap()];
    expect_error(&dir, "twice.csv", &twice, &map, &["line 1", "column 5 ('load')", "already given by column 4"]);

    // a record too short to split: the last line and the time column
    let few = write(&dir, "few.csv", &format!("{HEADER}\n{}", good_rows(150)));
    let err = compare(&CompareOptions::new(&few)).map(drop).expect_err("too short").to_string();
    eprintln!("{err}");
    for p in ["few.csv", "line 151", "column 1 ('time')", "150 samples", "at least 100"] {
        assert!(err.contains(p), "error lacks '{p}': {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn command_line_mistakes_are_clear() {
    // bad --map: unknown unit, wrong quantity, unknown variable
    assert!(Mapping::parse("vel=v_damper:furlong/s").unwrap_err().to_string().contains("unknown unit 'furlong/s'"));
    assert!(Mapping::parse("vel=v_damper:kN")
        .unwrap_err()
        .to_string()
        .contains("is a force, but v_damper is a velocity"));
    assert!(Mapping::parse("vel=speed:m/s").unwrap_err().to_string().contains("unknown variable 'speed'"));
    // through the binary: non-zero exit, message on stderr
    let dir = common::scratch("cli_errors");
    let bad = write(&dir, "bad.csv", &format!("{HEADER}\n0,0,0,0\n0,0,0,0\n"));
    let exe = env!("CARGO_BIN_EXE_damper");
    let out = std::process::Command::new(exe)
        .args(["compare", bad.to_str().unwrap(), "--out", dir.join("o").to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("bad.csv, line 3, column 1 ('time')"), "{stderr}");
    let out = std::process::Command::new(exe)
        .args(["compare", bad.to_str().unwrap(), "--out", "o", "--with", "friction"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("seal_friction"));
    let out = std::process::Command::new(exe)
        .args(["compare", bad.to_str().unwrap(), "--out", "o", "--set", "air_fracton=0.1"])
        .output()
        .unwrap();
    assert_ne!(out.status.code(), Some(0));
    let _ = std::fs::remove_dir_all(&dir);
}
