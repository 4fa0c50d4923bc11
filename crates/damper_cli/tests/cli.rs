//! The `damper` command line as a user meets it: per-command help, usage errors with exit status
//! 2, the global options, and results that do not depend on `--threads`.

use std::path::Path;
use std::process::{Command, Output};

fn damper<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_damper")).args(args).output().expect("run damper")
}

/// `damper` run in `dir`, with file names relative to it.
fn damper_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_damper")).current_dir(dir).args(args).output().expect("run damper")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn compare_help_shows_compare_s_options_only() {
    let o = damper(["compare", "--help"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let help = stdout(&o);
    assert!(help.contains("--load-cell-lowpass"), "{help}");
    assert!(!help.contains("--truth"), "generate's option in compare's help:\n{help}");
    assert!(help.contains("Examples:"), "{help}");
}

#[test]
fn help_command_prints_that_command_s_help_only() {
    let o = damper(["help", "compare"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let help = stdout(&o);
    assert!(help.contains("--load-cell-lowpass"), "{help}");
    assert!(!help.contains("--errors-in-variables"), "generate's option in compare's help:\n{help}");
}

#[test]
fn short_help_flag_is_help_not_a_file_name() {
    let o = damper(["compare", "-h"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("Usage: damper compare"), "{}", stdout(&o));
    let o = damper(["diagnose", "-h"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("--skip"), "{}", stdout(&o));
}

#[test]
fn an_unknown_command_is_a_usage_error_that_names_the_commands() {
    for typo in ["diagnos", "frobnicate"] {
        let o = damper([typo]);
        assert_eq!(o.status.code(), Some(2), "{typo}");
        let err = stderr(&o);
        for command in ["diagnose", "compare", "generate", "effects"] {
            assert!(err.contains(command), "{typo}: {command} not named in:\n{err}");
        }
    }
}

#[test]
fn version_is_the_package_version() {
    let o = damper(["--version"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert_eq!(stdout(&o).trim(), format!("damper {}", env!("CARGO_PKG_VERSION")));
}

#[test]
fn threads_must_be_a_positive_whole_number() {
    for bad in ["0", "x", "-2", "1.5"] {
        let o = damper(["--threads", bad, "effects"]);
        assert_eq!(o.status.code(), Some(2), "--threads {bad}");
        let err = stderr(&o);
        assert!(err.contains(&format!("invalid value '{bad}' for '--threads <N>'")), "{err}");
        assert!(err.contains("at least 1"), "{err}");
    }
}

#[test]
fn bad_values_name_the_option_and_what_it_takes() {
    let cases: [(&[&str], &str); 6] = [
        (&["--input", "lab"], "[possible values: rig, hil]"),
        (&["--control", "current"], "[possible values: force, spool]"),
        (&["--noise", "-1"], "'-1' for '--noise <K>': must be ≥ 0"),
        (&["--lowpass", "fast"], "'fast' for '--lowpass <HZ|off>': a frequency in Hz, or off"),
        (&["--effect", "seal"], "seal_friction"),
        (&["--sensor", "F_damper=loud"], "expected NAME=NOISE[:QUANTUM]"),
    ];
    for (args, expected) in cases {
        let o = damper(["generate", "--out", "never.csv", "--truth", "never.json"].iter().chain(args));
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = stderr(&o);
        assert!(err.contains("invalid value") && err.contains(expected), "{args:?}: {err}");
    }
    assert!(!Path::new("never.csv").exists());
}

/// summary.json without its one timing field, the model's wall time.
fn summary_without_timing(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    assert!(text.contains("\"verdict\""), "{text}");
    text.lines().filter(|l| !l.trim_start().starts_with("\"model_run_s\"")).collect::<Vec<_>>().join("\n")
}

#[test]
fn diagnose_gives_the_same_numbers_on_one_and_on_two_threads() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let run = |args: &[&str]| damper_in(d, args);
    let o =
        run(&["generate", "--out", "a.csv", "--truth", "t.json", "--seed", "3", "--duration", "2", "--minimal", "-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(o.stdout.is_empty() && o.stderr.is_empty(), "-q printed something");

    // five candidates of the catalog: the record's verdict is `unexplained`, so the ladder fits their
    // pairs too (every pair of the whole catalog took 23 s a run, these 3 s), in parallel on two threads
    let skip = ["end_stops", "gas_release", "gas_charge", "piston_leakage", "flow_forces", "amplifier_delay"]
        .into_iter()
        .flat_map(|e| ["--skip", e]);
    let args = |out: &'static str, threads: &'static str, verbosity: &'static str| {
        let mut a = vec!["diagnose", "a.csv", "--out", out, "--threads", threads, verbosity];
        a.extend(skip.clone());
        a
    };
    let one = run(&args("one", "1", "-v"));
    assert_eq!(one.status.code(), Some(0), "{}", stderr(&one));
    // -v: what the reader decided, every candidate fit, the timing
    let err = stderr(&one);
    assert!(err.contains("← column 4 ('F_damper')"), "{err}");
    assert!(err.contains("fitted seal_friction") && err.contains("on 1 threads") && err.contains("time:"), "{err}");
    assert!(stdout(&one).contains("verdict: unexplained"), "{}", stdout(&one));

    let two = run(&args("two", "2", "-q"));
    assert_eq!(two.status.code(), Some(0), "{}", stderr(&two));
    assert!(two.stdout.is_empty() && two.stderr.is_empty(), "-q printed something");

    assert_eq!(summary_without_timing(&d.join("one")), summary_without_timing(&d.join("two")));
}

#[test]
fn max_gap_decides_which_dropped_samples_are_bridged() {
    let dir = tempfile::tempdir().expect("temp dir");
    let d = dir.path();
    let run = |args: &[&str]| damper_in(d, args);
    let o =
        run(&["generate", "--out", "a.csv", "--truth", "t.json", "--seed", "5", "--duration", "1", "--minimal", "-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // drop 8 samples (t = 0.500 … 0.507 s) from the middle of the record
    let text = std::fs::read_to_string(d.join("a.csv")).expect("a.csv");
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| {
            let t: f64 = l.split(',').next().and_then(|t| t.parse().ok()).unwrap_or(-1.0);
            !(0.4995..0.5075).contains(&t)
        })
        .collect();
    assert_eq!(kept.len() + 8, text.lines().count());
    std::fs::write(d.join("gap.csv"), kept.join("\n") + "\n").expect("write gap.csv");

    let refused = run(&["compare", "gap.csv", "--out", "refused", "-q"]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(stderr(&refused).contains("--max-gap"), "{}", stderr(&refused));

    let bridged = run(&["compare", "gap.csv", "--out", "bridged", "--max-gap", "8", "-q"]);
    assert_eq!(bridged.status.code(), Some(0), "{}", stderr(&bridged));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("bridged/summary.json")).expect("summary")).expect("json");
    let warnings = summary["warnings"].as_array().expect("warnings");
    assert!(warnings.iter().any(|w| w.as_str().is_some_and(|w| w.contains("8 missing"))), "{warnings:?}");
}
