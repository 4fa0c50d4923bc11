//! generate → compare round trips: nothing hidden (the residual is the sensor noise), and a hidden
//! effect (the error grows and shows its signature). Each case runs 5 s of data at 1 kHz.

use crate::common;

use common::{compare, generate, regime, scratch};
use damper_engine::generate::InputStyle;

/// The whiteness statistic may exceed its 95 % quantile by chance; a model error puts it far
/// above (thousands here). This factor keeps the test from failing on the 5 % chance alone.
const LJUNG_BOX_MARGIN: f64 = 1.5;

fn assert_at_floor(c: &damper_engine::comparison::Comparison, expected: f64, what: &str) {
    let f = c.analysis.force();
    let w = &c.analysis.whiteness;
    eprintln!(
        "{what}: validation NRMSE {:.5}, expected floor {expected:.5} (ratio {:.3}), lag {} samples ({:+.3} ms), \
         Ljung-Box Q({}) {:.1} (95 % {:.1}), {:.1} % of lags outside the band",
        f.validation.nrmse,
        f.validation.nrmse / expected,
        f.lag.samples,
        f.lag.refined_seconds * 1e3,
        w.ljung_box_lags,
        w.ljung_box_q,
        w.chi2_95,
        100.0 * w.fraction_outside
    );
    let ratio = f.validation.nrmse / expected;
    assert!((0.9..1.1).contains(&ratio), "{what}: NRMSE {} is not at the noise floor {expected}", f.validation.nrmse);
    assert!(w.ljung_box_q < LJUNG_BOX_MARGIN * w.chi2_95, "{what}: residual not white, Q = {}", w.ljung_box_q);
    assert!(w.fraction_outside <= 0.1, "{what}: {} of the lags outside ±1.96/√N", w.fraction_outside);
    assert_eq!(f.lag.samples, 0, "{what}: lag");
    let said = damper_engine::analysis::observations(&c.analysis);
    assert!(said[0].contains("at the noise floor"), "{what}: {said:?}");
    assert!(f.lag.refined_seconds.abs() < 0.25e-3, "{what}: refined lag {}", f.lag.refined_seconds);
    for x in &c.analysis.input_correlations {
        assert!(x.max_abs < 2.0 * x.band, "{what}: residual correlates with {}: {}", x.input, x.max_abs);
    }
}

#[test]
fn nothing_hidden_rig_force_control_is_at_the_noise_floor() {
    let dir = scratch("floor_rig");
    let (csv, g) = generate(&dir, "rig", |_| {});
    let c = compare(&dir, &csv, "out", |_| {});
    assert_at_floor(&c, g.expected_floor, "rig, force control");
    // the other measured signals fit too
    for s in &c.analysis.fits {
        assert!(s.validation.nrmse < 0.05, "{}: NRMSE {}", s.column, s.validation.nrmse);
    }
    assert!(dir.join("out/report.html").exists() && dir.join("out/summary.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn nothing_hidden_hil_and_spool_control_are_at_the_noise_floor() {
    let dir = scratch("floor_other");
    let (csv, g) = generate(&dir, "hil", |o| o.input = InputStyle::Hil);
    let c = compare(&dir, &csv, "out_hil", |o| o.tare_load_cell = true);
    assert_at_floor(&c, g.expected_floor, "HiL (tared)");
    // without the tare the model is off by the gas force, and says so
    let raw = compare(&dir, &csv, "out_hil_raw", |_| {});
    assert!(raw.analysis.force().validation.nrmse > 10.0 * g.expected_floor);
    assert!(raw.warnings.iter().any(|w| w.contains("--tare-load-cell")), "{:?}", raw.warnings);

    let (csv, g) = generate(&dir, "spool", |o| o.spool_control = true);
    let c = compare(&dir, &csv, "out_spool", |_| {});
    assert_eq!(c.setup.model.params.control_mode, 1);
    assert_at_floor(&c, g.expected_floor, "rig, spool-position control");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_missing_load_cell_filter_shows_as_a_sub_sample_lag() {
    let dir = scratch("lowpass");
    let (csv, g) = generate(&dir, "rig", |_| {});
    let c = compare(&dir, &csv, "out", |o| o.load_cell_lowpass_hz = None);
    let f = c.analysis.force();
    eprintln!(
        "no load-cell filter in the model: NRMSE {:.4}, lag {:+.3} ms",
        f.validation.nrmse,
        f.lag.refined_seconds * 1e3
    );
    assert!(f.validation.nrmse > 3.0 * g.expected_floor);
    // a first-order 400 Hz low-pass delays by 1/(2π·400 Hz) = 0.40 ms
    assert!((f.lag.refined_seconds - 0.398e-3).abs() < 0.1e-3, "lag {}", f.lag.refined_seconds);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hidden_seal_friction_jumps_at_velocity_reversals() {
    let dir = scratch("friction");
    // spool-position control: no force loop hides the friction, as in the paper's valve tests
    let (csv, g) = generate(&dir, "friction", |o| {
        o.spool_control = true;
        o.effects = vec!["seal_friction=300".into()];
    });
    let c = compare(&dir, &csv, "out", |_| {});
    let f = c.analysis.force();
    let ext = regime(&c, "direction", "extension");
    let comp = regime(&c, "direction", "compression");
    let jump = c.analysis.reversal_jump.expect("reversals");
    eprintln!(
        "seal friction 300 N: NRMSE {:.4} (floor {:.4}), mean residual extension {:+.0} N, compression {:+.0} N, \
         jump at reversals {jump:+.0} N, lag {:+.2} ms",
        f.validation.nrmse,
        g.expected_floor,
        ext.mean,
        comp.mean,
        f.lag.refined_seconds * 1e3
    );
    assert!(f.validation.nrmse > 5.0 * g.expected_floor);
    assert!(!c.analysis.whiteness.white);
    // model − measured = −F_c·sign(v): the same offset in every velocity band, whatever the valve does
    assert!((ext.mean + 300.0).abs() < 30.0 && (comp.mean - 300.0).abs() < 30.0);
    for band in ["0.05 ≤ |v|", "0.1 ≤ |v|"] {
        let r = regime(&c, "velocity", band);
        assert!((r.rms - 300.0).abs() < 40.0, "{band}: RMS {}", r.rms);
    }
    let said = damper_engine::analysis::observations(&c.analysis);
    assert!(said.iter().any(|o| o.contains("friction-like")), "{said:?}");
    // the residual steps by −2·F_c at a reversal (a little less: tanh(v/v_friction) is smooth)
    assert!((-650.0..-450.0).contains(&jump), "jump {jump}");
    // and the same data without the hidden effect have none of this
    let with = compare(&dir, &csv, "out_with", |o| o.with = vec!["seal_friction=300".into()]);
    assert!(with.analysis.force().validation.nrmse < 1.1 * g.expected_floor);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn hidden_amplifier_delay_shows_as_a_lag() {
    let dir = scratch("delay");
    // Spool-position control: the truth's amplifier delays 6 ms, the model's 3 ms. The spool loop
    // is closed, so no signal is a pure shift, but the spool position's steps come Δτ = 3 ms late.
    let (csv, g) = generate(&dir, "delay_spool", |o| {
        o.spool_control = true;
        o.effects = vec!["amplifier_delay=0.006".into()];
    });
    let c = compare(&dir, &csv, "out_spool", |_| {});
    let f = c.analysis.force();
    let spool = c.analysis.fits.iter().find(|s| s.column.name() == "x_spool").expect("x_spool measured");
    let steps = regime(&c, "events", "after a demand step");
    eprintln!(
        "spool control, amplifier delay 6 ms vs 3 ms: NRMSE {:.4} (floor {:.4}), force lag {:+.2} ms, on the changes \
         {:+.2} ms, x_spool lag {:+.2} ms, on the changes {:+.2} ms; after demand steps {:.0} % of the error in {:.0} % of the time",
        f.validation.nrmse,
        g.expected_floor,
        f.lag.refined_seconds * 1e3,
        f.lag.changes_seconds * 1e3,
        spool.lag.refined_seconds * 1e3,
        spool.lag.changes_seconds * 1e3,
        100.0 * steps.error_share,
        100.0 * steps.time_share
    );
    // the force in spool control is mostly the velocity's: the delay shows after the spool steps only
    assert!(f.validation.nrmse > 1.3 * g.expected_floor && !c.analysis.whiteness.white);
    assert!((spool.lag.changes_seconds - 3e-3).abs() < 0.5e-3, "spool lag {}", spool.lag.changes_seconds);
    assert!((1e-3..3.5e-3).contains(&f.lag.changes_seconds), "force lag {}", f.lag.changes_seconds);
    assert!(steps.concentration > 2.0, "demand steps: concentration {}", steps.concentration);

    // Force control, 5 ms against 3 ms: the force loop takes up part of the delay.
    let (csv, g) = generate(&dir, "delay_force", |o| o.effects = vec!["amplifier_delay=0.005".into()]);
    let c = compare(&dir, &csv, "out_force", |_| {});
    let f = c.analysis.force();
    let spool = c.analysis.fits.iter().find(|s| s.column.name() == "x_spool").expect("x_spool measured");
    let rate = |name: &str| regime(&c, "force rate", name).rms;
    eprintln!(
        "force control, amplifier delay 5 ms vs 3 ms: NRMSE {:.4} (floor {:.4}), force lag on the changes {:+.2} ms, \
         x_spool lag {:+.2} ms, RMS residual by force rate {:.0} / {:.0} N (slowest / fastest band)",
        f.validation.nrmse,
        g.expected_floor,
        f.lag.changes_seconds * 1e3,
        spool.lag.refined_seconds * 1e3,
        rate("0 ≤"),
        rate("|dF/dt| ≥")
    );
    assert!(f.validation.nrmse > 10.0 * g.expected_floor);
    assert!((0.5e-3..2.5e-3).contains(&f.lag.changes_seconds), "force lag {}", f.lag.changes_seconds);
    assert!((1e-3..3e-3).contains(&spool.lag.refined_seconds), "spool lag {}", spool.lag.refined_seconds);
    // a delay's error grows with the rate of change of the force
    assert!(rate("|dF/dt| ≥") > 3.0 * rate("0 ≤"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_command_line_runs_end_to_end() {
    let dir = scratch("cli");
    let exe = env!("CARGO_BIN_EXE_damper");
    let csv = dir.join("m.csv");
    let truth = dir.join("truth/m.json");
    let out = std::process::Command::new(exe)
        .args(["generate", "--out", csv.to_str().unwrap(), "--truth", truth.to_str().unwrap()])
        .args(["--effect", "seal_friction", "--seed", "5", "--duration", "3", "--quiet"])
        .output()
        .expect("run damper");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let truth: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&truth).unwrap()).unwrap();
    assert_eq!(truth["effects"][0]["key"], "seal_friction", "{}", truth["effects"]);
    assert_eq!(truth["effects"][0]["value_drawn_at_random"], true);
    let report = dir.join("report");
    let out = std::process::Command::new(exe)
        .args(["compare", csv.to_str().unwrap(), "--out", report.to_str().unwrap(), "--load-cell-lowpass", "400"])
        .output()
        .expect("run damper");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("F_damper") && stdout.contains("validation NRMSE"), "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("summary.json")).unwrap()).unwrap();
    assert!(summary["nrmse_baseline"].as_f64().is_some_and(|x| x > 0.0), "{}", summary["nrmse_baseline"]);
    for key in ["regimes", "worst_windows"] {
        assert!(summary[key].as_array().is_some_and(|a| !a.is_empty()), "summary.json: {key} {}", summary[key]);
    }
    assert!(summary["lag"]["seconds"].is_number() && summary["whiteness"]["white"].is_boolean());
    assert!(summary["verdict"].is_null() && summary.as_object().unwrap().contains_key("verdict"));
    let html = std::fs::read_to_string(report.join("report.html")).unwrap();
    assert!(html.contains("<svg"));
    for outside in ["<script", "<link", "src=\"http", "href=\"http", "url(http"] {
        assert!(!html.contains(outside), "the report must open offline: it has {outside}");
    }
    // a usage error exits with 2, a data error with 1
    let bad = std::process::Command::new(exe).args(["compare", "--out", "x"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let missing = std::process::Command::new(exe)
        .args(["compare", dir.join("nope.csv").to_str().unwrap(), "--out", report.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(missing.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("nope.csv"));
    let _ = std::fs::remove_dir_all(&dir);
}
