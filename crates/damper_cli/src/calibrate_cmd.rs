//! `damper calibrate`'s presentation: the terminal table (the identifiability report) and the
//! files written (`parameters.ssv`: the SSP parameter set, or `parameters_<setting>.ssv` for each
//! setting with values of its own; `calibration.json`).

use damper_engine::calibrate::{CalibrateOptions, Calibration, Status};
use damper_engine::calibration_file::{file, note, own_settings, parameter_set};
use damper_engine::ssv;
use damper_engine::summary::to_json;
use std::fmt::Write as _;
use std::path::Path;

/// Writes the parameter set(s) and `calibration.json` to `out`, prints the table unless `quiet`.
pub fn write(c: &Calibration, o: &CalibrateOptions, out: &Path, quiet: bool) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let names: Vec<&str> = c.records.iter().map(|r| r.path.as_str()).collect();
    let note = format!("damper calibrate on {}", names.join(", "));
    let settings = own_settings(c);
    let sets: Vec<(Option<&str>, std::path::PathBuf)> = if settings.is_empty() {
        vec![(None, out.join("parameters.ssv"))]
    } else {
        settings.iter().map(|s| (Some(*s), out.join(format!("parameters_{}.ssv", file_label(s))))).collect()
    };
    for (setting, path) in &sets {
        let name = setting.map_or("calibrated".to_string(), |s| format!("calibrated, setting {s}"));
        std::fs::write(path, ssv::to_string(&name, &note, &parameter_set(c, *setting)))
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let json_path = out.join("calibration.json");
    std::fs::write(&json_path, to_json(&file(c, o.max_relative_uncertainty, o.max_correlation)))
        .map_err(|e| format!("{}: {e}", json_path.display()))?;
    if !quiet {
        print!("{}", terminal_summary(c, o));
        for (setting, path) in &sets {
            println!("parameters{}:  {}", setting.map_or(String::new(), |s| format!(" ({s})")), path.display());
        }
        println!("calibration: {}", json_path.display());
    }
    Ok(())
}

/// A setting's label as part of a file name: letters, digits, '-', '.' kept, the rest '_'.
pub fn file_label(label: &str) -> String {
    label.chars().map(|ch| if ch.is_ascii_alphanumeric() || ch == '-' || ch == '.' { ch } else { '_' }).collect()
}

/// The terminal summary: parameters, records, rounds.
pub fn terminal_summary(c: &Calibration, o: &CalibrateOptions) -> String {
    let mut s = String::new();
    // the name columns as wide as the longest name (a setting's own carries its label)
    let w = c.parameters.iter().map(|p| p.display_name().chars().count() + 2).max().unwrap_or(0).max(14);
    let cw = w + 10;
    let _ = writeln!(
        s,
        "damper calibrate: {} record(s), {} parameters, rtol {:e}; {} model runs in {:.1} s on {} threads",
        c.records.len(),
        c.parameters.len(),
        c.rtol,
        c.model_runs,
        c.seconds,
        c.threads
    );
    let _ = writeln!(
        s,
        "{:<w$}{:<11}{:>12}{:>12}{:>11}{:>9}  {:<cw$}status",
        "parameter", "unit", "start", "calibrated", "std. unc.", "rel.", "strongest correlation"
    );
    for p in &c.parameters {
        let (unc, rel) = match (p.std_error, p.relative()) {
            (Some(u), Some(r)) => (format!("{u:.2e}"), format!("{:.2} %", 100.0 * r)),
            _ => ("–".into(), "–".into()),
        };
        let corr = p.correlation.as_ref().map_or("–".into(), |(n, r)| format!("{n} {r:+.3}"));
        let status = match &p.status {
            Status::Fitted if p.at_bound() => format!("fitted, {}", note(p)),
            Status::Fitted => "fitted".into(),
            Status::Held(why) => format!("NOT IDENTIFIABLE, held at its given value: {why}"),
        };
        let _ = writeln!(
            s,
            "{:<w$}{:<11}{:>12.4e}{:>12.4e}{:>11}{:>9}  {:<cw$}{status}",
            p.display_name(),
            p.unit,
            p.start,
            p.value,
            unc,
            rel,
            corr
        );
    }
    let _ = writeln!(
        s,
        "identified: relative standard uncertainty ≤ {:.0} %, |correlation| ≤ {} with every other fitted parameter, JᵀJ not singular",
        100.0 * o.max_relative_uncertainty,
        o.max_correlation
    );
    let _ = writeln!(s, "{:<40}{:>9}{:>14}{:>10}{:>13}", "record", "samples", "NRMSE before", "after", "noise floor");
    for r in &c.records {
        let _ = writeln!(
            s,
            "{:<40}{:>9}{:>14.4}{:>10.4}{:>13.4}{}",
            r.path,
            r.samples,
            r.nrmse_before,
            r.nrmse_after,
            r.noise_floor,
            if own_settings(c).is_empty() { String::new() } else { format!("  setting {}", r.setting) }
        );
    }
    if let Some(st) = &c.steady {
        let moved: Vec<String> = st.fitted.iter().map(|(n, from, to)| format!("{n} {from:.3e} → {to:.3e}")).collect();
        let _ = writeln!(
            s,
            "steady stage: the force–velocity law on {} quasi-steady samples from {} starts, RMS {:.1} N → {:.1} N; {}",
            st.points,
            st.starts,
            st.rms_before,
            st.rms_after,
            moved.join(", ")
        );
    }
    for (i, r) in c.rounds.iter().enumerate() {
        let _ = writeln!(
            s,
            "fit {}: {} parameters, {} iterations{}, {} model runs, RMS residual {:.1} N{}",
            i + 1,
            r.fitted.len(),
            r.iterations,
            if r.converged { "" } else { " (iteration limit)" },
            r.model_runs,
            r.rms_residual,
            match &r.held {
                Some((n, why)) =>
                    format!("; {n} cannot be pinned ({why}): held at its given value, refitted without it"),
                None => String::new(),
            }
        );
    }
    if !c.given.is_empty() {
        let given: Vec<String> = c.given.iter().map(|(n, v)| format!("{n}={v}")).collect();
        let _ = writeln!(s, "given, not fitted (written to the parameter set too): {}", given.join(" "));
    }
    s
}
