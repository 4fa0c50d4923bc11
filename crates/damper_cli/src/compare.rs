//! `damper compare`: the model driven by the measured inputs, overlaid on the measurement, and
//! where it fails. Writes `DIR/report.html` and `DIR/summary.json` and prints a summary.

use crate::describe::describe_model;
use crate::{json_summary, report};
use damper_engine::analysis::{lag_ms, observations};
use damper_engine::comparison::{compare, CompareOptions, Comparison};
use damper_engine::summary::to_json;
use std::path::Path;

/// `damper compare`: compare, write the report and the summary to `out`, print the summary unless
/// `quiet`.
pub fn run(opts: &CompareOptions, out: &Path, quiet: bool) -> Result<Comparison, String> {
    let c = compare(opts).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let json_path = out.join("summary.json");
    std::fs::write(&json_path, to_json(&json_summary::compared(&c)))
        .map_err(|e| format!("{}: {e}", json_path.display()))?;
    let html_path = out.join("report.html");
    std::fs::write(&html_path, report::html(&c)).map_err(|e| format!("{}: {e}", html_path.display()))?;
    if !quiet {
        print!("{}", terminal_summary(&c));
        println!("report:  {}", html_path.display());
        println!("summary: {}", json_path.display());
    }
    Ok(c)
}

/// The terminal summary.
pub fn terminal_summary(c: &Comparison) -> String {
    use std::fmt::Write;
    let a = &c.analysis;
    let m = &c.measurement;
    let mut s = String::new();
    let dur = m.time[m.len() - 1] - m.time[0];
    let _ = writeln!(
        s,
        "damper compare: {} — {} samples, {:.0} Hz, {:.2} s, {}",
        m.path,
        m.len(),
        1.0 / a.dt,
        dur,
        c.drive.control_words()
    );
    let _ = writeln!(s, "model: {}", describe_model(&c.setup));
    let _ = writeln!(s, "model run: {:.2} s ({:.0}× real time)", c.run_seconds, dur / c.run_seconds.max(1e-9));
    let _ = writeln!(
        s,
        "{:<16}{:>10}{:>10}{:>12}{:>10}{:>12}",
        "signal", "train fit", "NRMSE", "valid. fit", "NRMSE", "lag [ms]"
    );
    for f in &a.fits {
        let _ = writeln!(
            s,
            "{:<16}{:>9.1}%{:>10.4}{:>11.1}%{:>10.4}{:>12}",
            f.column.name(),
            f.train.fit_percent,
            f.train.nrmse,
            f.validation.fit_percent,
            f.validation.nrmse,
            lag_ms(f.lag.refined_seconds, 2)
        );
    }
    let f = a.force();
    let _ = writeln!(
        s,
        "F_damper validation NRMSE {:.4} (white-noise floor estimate {:.4}); lag {} ({} ms refined, {} ms on the \
         changes; + = measurement later)",
        f.validation.nrmse,
        a.noise_floor_estimate,
        if f.lag.found { format!("{} samples", f.lag.samples) } else { "not found".into() },
        lag_ms(f.lag.refined_seconds, 2),
        lag_ms(f.lag.changes_seconds, 2)
    );
    if let Some(j) = a.reversal_jump {
        let _ = writeln!(
            s,
            "residual jump across velocity reversals: {j:+.0} N over {} reversals (a missing friction F·sign(v) gives −2F)",
            a.reversals.len()
        );
    }
    let w = &a.whiteness;
    let _ = writeln!(
        s,
        "residual whiteness (validation): {:.1} % of lags 1..{} outside ±1.96/√N, Ljung–Box Q({}) = {:.1} vs {:.1}: {}",
        100.0 * w.fraction_outside,
        w.max_lag,
        w.ljung_box_lags,
        w.ljung_box_q,
        w.chi2_95,
        if w.white { "white" } else { "not white" }
    );
    let _ = writeln!(s, "observations:");
    for o in observations(a) {
        let _ = writeln!(s, "  - {o}");
    }
    let mut hot: Vec<_> = a.regimes.iter().filter(|r| r.samples > 0 && r.time_share >= 0.01).collect();
    hot.sort_by(|x, y| y.concentration.total_cmp(&x.concentration));
    let _ = writeln!(s, "where it fails (share of squared error / share of time):");
    for r in hot.iter().take(4) {
        let _ = writeln!(
            s,
            "  {:<11} {:<36} {:>5.1} % / {:>5.1} %  (×{:.2}), RMS {:.0} N, mean {:+.0} N",
            r.group,
            r.name,
            100.0 * r.error_share,
            100.0 * r.time_share,
            r.concentration,
            r.rms,
            r.mean
        );
    }
    if let Some(wst) = a.worst.first() {
        let _ = writeln!(
            s,
            "worst window: {:.3}–{:.3} s, RMS {:.0} N ({})",
            wst.t_start,
            wst.t_end,
            wst.rms,
            wst.tags.join(", ")
        );
    }
    for w in &c.warnings {
        let _ = writeln!(s, "note: {w}");
    }
    s
}
