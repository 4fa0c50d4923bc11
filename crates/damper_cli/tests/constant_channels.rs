//! A measurement whose channels are constant but for rounding in their last digits (a logger
//! writing 1e6 Pa as `1000000` and `1000000.0000000003`): the report's plots must still finish.
//! The axis ticks of such a range once stepped by less than the values' resolution, forever.

use crate::common;

use common::{checked_summary, generate, scratch};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The compare run takes about a second; a hang is anything far beyond.
const DEADLINE: Duration = Duration::from_secs(60);

/// Replaces the cells of `column` by `values`, taken in turn.
fn set_column(csv: &str, column: &str, values: &[&str]) -> String {
    let mut lines = csv.lines();
    let header = lines.next().expect("header");
    let j = header.split(',').position(|c| c == column).unwrap_or_else(|| panic!("no column {column}"));
    let mut out = format!("{header}\n");
    for (k, line) in lines.enumerate() {
        let mut cells: Vec<&str> = line.split(',').collect();
        cells[j] = values[k % values.len()];
        out += &cells.join(",");
        out.push('\n');
    }
    out
}

#[test]
fn constant_channels_with_rounding_noise_give_a_report() {
    let dir = scratch("constant_channels");
    // spool-position control: the report plots the spool demand alone, so its range is the
    // channel's own; the spool held at 2.5 mm, the valve a fixed orifice while the rod moves
    let (csv, _) = generate(&dir, "rig", |o| {
        o.spool_control = true;
        o.duration = 2.0;
    });
    let text = std::fs::read_to_string(&csv).unwrap();
    let text = set_column(&text, "x_spool_demand", &["0.0025", "0.0025000000000000005"]);
    let text = set_column(&text, "p_ext", &["1000000", "1000000.0000000003"]);
    let constant = dir.join("constant.csv");
    std::fs::write(&constant, text).unwrap();

    let out = dir.join("out");
    // stderr to a file: a pipe nobody reads while waiting could fill and stall the child
    let stderr_path = dir.join("stderr.txt");
    let mut child = Command::new(env!("CARGO_BIN_EXE_damper"))
        .args(["compare", constant.to_str().unwrap(), "--out", out.to_str().unwrap(), "--quiet"])
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&stderr_path).unwrap())
        .spawn()
        .expect("run damper");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for damper") {
            break status;
        }
        if start.elapsed() > DEADLINE {
            child.kill().expect("kill damper");
            child.wait().expect("reap damper");
            panic!("damper compare still running after {DEADLINE:?}: the report hangs");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert!(status.success(), "{}", std::fs::read_to_string(&stderr_path).unwrap());
    let html = std::fs::read_to_string(out.join("report.html")).expect("report.html");
    assert!(html.contains("x_spool_demand [mm]") && html.trim_end().ends_with("</html>"));
    // regimes without samples have no RMS: written as null, read back as NaN
    let summary = checked_summary(&out);
    assert!(summary.signals.contains_key("p_ext"));
    assert!(summary.regimes.iter().any(|r| r.samples == 0 && r.rms_residual.is_nan()));
    let _ = std::fs::remove_dir_all(&dir);
}
