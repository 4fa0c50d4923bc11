//! `damper diagnose`'s presentation: the diagnosis section of `report.html`, the terminal summary,
//! and the files written (`report.html`: the compare report with a diagnosis section;
//! `summary.json`: with `verdict`, `best_effect`, `effects`, `nrmse_baseline`, `candidates`,
//! `ladder`).

use crate::svg::esc;
use crate::{before_after_report, compare, json_summary, report};
use damper_engine::criteria::{DOES_NOT_FIT_NRMSE, EXPLAINED_FACTOR, MIN_EXPLAINED, MOVED_SIGMAS};
use damper_engine::diagnose_measurement::Diagnosed;
use damper_engine::dsp::NoiseEstimate;
use damper_engine::floor::Floor;
use damper_engine::ladder::Rung;
use damper_engine::missing_effect::Diagnosis;
use damper_engine::record_parts::FAR_FACTOR;
use damper_engine::summary::to_json;
use std::fmt::Write as _;
use std::path::Path;

/// A rung as the report and the terminal name it: `+ effect` or `effect refitted`, and a note
/// when it was not kept.
fn rung_label(l: &Rung) -> (String, &'static str) {
    let what = match (l.added, l.refit) {
        ("baseline", _) => "baseline".to_string(),
        (e, true) => format!("{e} refitted"),
        (e, false) => format!("+ {e}"),
    };
    let note = match (l.kept, l.refit) {
        (true, _) => "",
        (false, true) => " (unchanged)",
        (false, false) => " (not kept)",
    };
    (what, note)
}

/// The floor's parts, one line, and the samples left out.
fn floor_line(f: &Floor) -> String {
    format!(
        "floor {:.4} = sensor noise {:.4} (σ {:.1} N; cross-checks {:.1} N windowed, {:.1} N median-absolute, {:.1} N over all samples) ⊕ the model's numerical error {:.4} (rtol {:.0e} against {:.0e}) ⊕ the velocity's noise carried through the model where the noise estimate cannot see it {:.4} (all of it {:.4}); {} validation samples left out, where a velocity noise of {:.2} mm/s moves the force by more than {:.0} N",
        f.nrmse,
        f.nrmse_noise,
        f.noise.sigma,
        f.noise.sigma_window,
        f.noise.sigma_mad,
        f.noise.sigma_all,
        f.nrmse_numerics,
        f.rtol,
        f.rtol_check,
        f.nrmse_inputs_unseen,
        f.nrmse_inputs,
        f.left_out_validation,
        1e3 * f.delta_v,
        f.sensitive_threshold,
    )
}

fn floor_html(f: &Floor) -> String {
    format!("<p class=\"small\">The {}. Noise: {}.</p>", esc(&floor_line(f)), esc(NoiseEstimate::METHOD))
}

/// The diagnosis section of the report.
pub fn html_section(r: &Diagnosed) -> String {
    let d = &r.diagnosis;
    let mut h = format!(
        "<h2>Which effect is missing</h2><p><b>Verdict: {}</b>{}. {}</p>\
         <p class=\"small\">Every effect of the catalog (docs/effects.md) is switched on, or refitted where the baseline has \
         it, its parameters are fitted on the train part (Levenberg–Marquardt on bounded scales; delays on the controller's sample grid), \
         and the candidate is scored by the validation NRMSE. Verdicts: <i>effect</i> when the named effects leave at most {EXPLAINED_FACTOR}× the floor and \
         the first explains at least {:.0} % of the validation error above the floor (b² − c²)/(b² − f²) with plausible parameters, clearly more than the best \
         plausible runner-up (or the ladder's effects reach the floor together); <i>partial</i> when they explain a clear share but leave more; \
         <i>does_not_fit</i> when even the best leaves an NRMSE of {DOES_NOT_FIT_NRMSE} or more (calibrate first); <i>none</i> at the floor; else <i>unexplained</i>. \
         A refit within {MOVED_SIGMAS} standard uncertainties of the model's value is not an effect. Parameter errors: the sandwich of the curvature of the sum of squares around the residuals' long-run \
         covariance, plus the spread the measured velocity's noise carries into the parameters.</p>{}",
        d.verdict,
        if d.effects.is_empty() { String::new() } else { format!(": {}", d.effects.join(" + ")) },
        esc(&d.explanation),
        100.0 * MIN_EXPLAINED,
        floor_html(&d.floor)
    );
    h.push_str(
        "<table><tr><th>rank</th><th>effect</th><th>action</th><th>validation NRMSE</th><th>change</th><th>fitted parameters \
         (± 1 σ)</th><th>plausible</th><th>signature</th></tr>",
    );
    for (i, c) in d.candidates.iter().enumerate() {
        let params: Vec<String> = c
            .params
            .iter()
            .map(|(n, v, e)| match e {
                Some(e) => format!("{n} = {v:.4e} ± {e:.1e}"),
                None => format!("{n} = {v:.4e} (not determined)"),
            })
            .collect();
        h.push_str(&format!(
            "<tr><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{:.4}</td><td>{:+.0} %</td><td class=\"l\">{}</td>\
             <td class=\"l\">{}</td><td class=\"l\">{}</td></tr>",
            i + 1,
            c.effect,
            c.action,
            c.nrmse_validation,
            -100.0 * c.reduction,
            esc(&params.join("; ")),
            if c.plausible { "yes".to_string() } else { esc(&c.flags.join("; ")) },
            esc(c.signature)
        ));
    }
    h.push_str("</table><h3>Ladder: the validation NRMSE as effects are added one at a time, each fitted on top of those kept</h3><table>");
    h.push_str(&format!(
        "<tr><th class=\"l\">model</th><th>validation NRMSE</th><th>share of the error left above the floor it explains</th>\
         <th class=\"l\">its parameters on this rung</th></tr><tr><td class=\"l\">noise floor</td><td>{:.4}</td><td></td><td></td></tr>",
        d.nrmse_noise_floor
    ));
    for l in &d.ladder.rungs {
        let (what, note) = rung_label(l);
        let params: Vec<String> = l.params.iter().map(|(n, v, _)| format!("{n} = {v:.4e}")).collect();
        let share = if l.added == "baseline" { String::new() } else { format!("{:.0} %", 100.0 * l.explained) };
        h.push_str(&format!(
            "<tr><td class=\"l\">{what}{note}</td><td>{:.4}</td><td>{share}</td><td class=\"l\">{}</td></tr>",
            l.nrmse_validation,
            esc(&params.join("; "))
        ));
    }
    h.push_str("</table>");
    h += &parts_html(d);
    h
}

/// The baseline's error in each part of the record against that part's floor.
fn parts_html(d: &Diagnosis) -> String {
    let mut h = format!(
        "<h3>The baseline over the whole record</h3><p class=\"small\">The RMS residual of each part against the part's floor          (its white noise and the model's numerical error). A part more than {FAR_FACTOR}× its floor rules out the verdict <i>none</i>.</p>         <table><tr><th class=\"l\">part</th><th>from [s]</th><th>to [s]</th><th>RMS residual [N]</th><th>floor [N]</th><th>ratio</th></tr>"
    );
    for p in &d.parts {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td><td>{}{:.2}{}</td></tr>",
            p.name,
            p.t_start,
            p.t_end,
            p.rms_residual,
            p.rms_floor,
            if p.ratio() > FAR_FACTOR { "<b>" } else { "" },
            p.ratio(),
            if p.ratio() > FAR_FACTOR { "</b>" } else { "" }
        );
    }
    h.push_str("</table>");
    h
}

/// The diagnosis for the terminal.
pub fn terminal_summary(r: &Diagnosed) -> String {
    let d = &r.diagnosis;
    let mut t = format!(
        "\nverdict: {}{}\n  {}\n",
        d.verdict,
        if d.effects.is_empty() { String::new() } else { format!(" ({})", d.effects.join(" + ")) },
        d.explanation
    );
    t.push_str("  rank effect                 validation NRMSE   change  parameters\n");
    for (i, c) in d.candidates.iter().enumerate() {
        let params: Vec<String> = c.params.iter().map(|(n, v, _)| format!("{n}={v:.4e}")).collect();
        t.push_str(&format!(
            "  {:>4} {:<22} {:>16.4} {:>+5.0} %  {}{}\n",
            i + 1,
            c.effect,
            c.nrmse_validation,
            -100.0 * c.reduction,
            params.join(" "),
            if c.plausible { "" } else { "  (implausible)" }
        ));
    }
    t.push_str("  ladder:");
    for l in &d.ladder.rungs {
        let (what, note) = rung_label(l);
        t.push_str(&format!(" {what} {:.4}{note} →", l.nrmse_validation));
    }
    t.truncate(t.len() - " →".len());
    t.push_str(&format!(" (floor {:.4})\n  {}\n", d.nrmse_noise_floor, floor_line(&d.floor)));
    t
}

/// The end of `damper diagnose`: writes the report and the summary of `r` to `out`, prints the
/// summary unless `quiet`.
pub fn write(r: &Diagnosed, out: &Path, quiet: bool) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: cannot create: {e}", out.display()))?;
    let json_path = out.join("summary.json");
    std::fs::write(&json_path, to_json(&json_summary::diagnosed(r)))
        .map_err(|e| format!("{}: {e}", json_path.display()))?;
    let mut html = report::html(&r.comparison);
    let cut = html.find("<h2>Which effect is missing</h2>").or_else(|| html.rfind("</body>")).unwrap_or(html.len());
    html.truncate(cut);
    html.push_str(&html_section(r));
    if let Some(a) = &r.after {
        html.push_str(&before_after_report::html(&r.comparison, a));
    }
    html.push_str("</body></html>");
    let html_path = out.join("report.html");
    std::fs::write(&html_path, html).map_err(|e| format!("{}: {e}", html_path.display()))?;
    if !quiet {
        print!("{}", compare::terminal_summary(&r.comparison));
        print!("{}", terminal_summary(r));
        if let Some(a) = &r.after {
            print!("{}", before_after_report::terminal(&r.comparison, a));
        }
        println!("report:  {}", html_path.display());
        println!("summary: {}", json_path.display());
    }
    Ok(())
}
