//! `damper diagnose`: compare (steps 1–2), then name the missing effect (step 3) and show the error
//! fall as the candidates are added in turn (step 4, the ladder). Writes `report.html` (the
//! compare report with a diagnosis section) and `summary.json` (with `verdict`, `best_effect`,
//! `effects`, `nrmse_baseline`, `candidates`, `ladder`), and prints a terminal summary.

use crate::before_after::{self, After};
use crate::compare::{self, CompareOptions, Comparison};
use crate::diagnose::{diagnose, Candidate, Diagnosis, FitSetup, Progress};
use crate::ladder::Rung;
use crate::summary::{self, Summary};
use crate::svg::esc;
use crate::units::Column;

/// A finished diagnosis with its comparison.
pub struct Diagnosed {
    pub comparison: Comparison,
    pub diagnosis: Diagnosis,
    /// The model with the named effects, when the verdict is `effect`.
    pub after: Option<After>,
}

/// Reads, compares and diagnoses (no files written, nothing printed) on `threads` threads;
/// `progress` is told of each candidate fitted.
pub fn diagnose_measurement(
    opts: &CompareOptions,
    threads: usize,
    progress: &Progress<'_>,
) -> Result<Diagnosed, String> {
    let c = compare::compare(opts)?;
    let split = compare::split_index(&c.measurement, opts.split)?;
    let measured = c.measurement.get(Column::FDamper).ok_or("the measurement has no F_damper column")?.to_vec();
    let simulate = c.setup.backend.force_simulator(&c.drive, opts.load_cell_lowpass_hz);
    let baseline = c.setup.model.params;
    let skipped =
        opts.skip.iter().map(|k| crate::parameters::effect(k).map(|e| e.key)).collect::<Result<Vec<_>, _>>()?;
    let candidates: Vec<_> = crate::diagnose::catalog().filter(|e| !skipped.contains(&e.key)).collect();
    if candidates.is_empty() {
        return Err("--skip leaves no candidate effect".into());
    }
    let pool = crate::model::thread_pool(threads)?;
    let fit = FitSetup { simulate: &simulate, measured: &measured, split, pool: &pool, progress };
    let d = diagnose(&fit, &candidates, &baseline, &c.prediction.f_damper)?;
    drop(simulate);
    let after = match d.effects.as_slice() {
        [] => None,
        effects => Some(before_after::after(&c, effects, d.ladder.params)?),
    };
    Ok(Diagnosed { comparison: c, diagnosis: d, after })
}

fn candidate(c: &Candidate) -> summary::Candidate {
    summary::Candidate {
        effect: c.effect.into(),
        action: c.action.into(),
        nrmse_train: c.nrmse_train,
        nrmse_validation: c.nrmse_validation,
        reduction: c.reduction,
        explained: c.explained,
        params: summary::fitted(&c.params),
        plausible: c.plausible,
        flags: c.flags.clone(),
        signature: c.signature.into(),
        model_runs: c.evaluations,
    }
}

/// The summary of compare with the diagnosis filled in.
pub fn summary(r: &Diagnosed) -> Summary {
    let d = &r.diagnosis;
    Summary {
        nrmse_baseline: d.nrmse_baseline,
        verdict: Some(d.verdict.into()),
        best_effect: d.best_effect.map(String::from),
        candidates: Some(d.candidates.iter().map(candidate).collect()),
        diagnosis: Some(summary::Diagnosis {
            effects: d.effects.iter().map(|e| e.to_string()).collect(),
            nrmse_after_ladder: d.ladder.nrmse_validation,
            after: r.after.as_ref().map(|a| before_after::summary(&r.comparison, a)),
            nrmse_noise_floor: d.nrmse_noise_floor,
            explanation: d.explanation.clone(),
            ladder: d
                .ladder
                .rungs
                .iter()
                .map(|l| summary::Rung {
                    added: l.added.into(),
                    refit: l.refit,
                    params: summary::fitted(&l.params),
                    nrmse_validation: l.nrmse_validation,
                    explained: l.explained,
                    kept: l.kept,
                })
                .collect(),
        }),
        ..compare::summary(&r.comparison)
    }
}

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

/// The diagnosis section of the report.
pub fn html_section(r: &Diagnosed) -> String {
    let d = &r.diagnosis;
    let mut h = format!(
        "<h2>Which effect is missing</h2><p><b>Verdict: {}</b>{}. {}</p>\
         <p class=\"small\">Every effect of the catalog (docs/effects.md) is switched on, or refitted where the baseline has \
         it, its parameters are fitted on the train part (Nelder–Mead on bounded scales; delays on the controller's sample grid), \
         and the candidate is scored by the validation NRMSE. Named only when it explains at least {:.0} % of the validation error above the noise floor \
         (b² − c²)/(b² − f²), with plausible parameters, clearly more than the best plausible runner-up or alone down to the noise floor; or when the ladder's effects together reach the floor. Noise floor: white sensor noise estimated from the second \
         differences of the residual. Parameter errors: Gauss–Newton from the curvature of the sum of squares (optimistic for \
         coloured residuals).</p>",
        d.verdict,
        if d.effects.is_empty() { String::new() } else { format!(": {}", d.effects.join(" + ")) },
        esc(&d.explanation),
        100.0 * crate::diagnose::MIN_EXPLAINED
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
    t.push_str(&format!(" (noise floor {:.4})\n", d.nrmse_noise_floor));
    t
}

/// The end of `damper diagnose`: writes the report and the summary of `r` to `opts.out`, prints
/// the summary unless `opts.quiet`.
pub fn write(opts: &CompareOptions, r: &Diagnosed) -> Result<(), String> {
    std::fs::create_dir_all(&opts.out).map_err(|e| format!("{}: cannot create: {e}", opts.out.display()))?;
    let json_path = opts.out.join("summary.json");
    std::fs::write(&json_path, summary::to_json(&summary(r))).map_err(|e| format!("{}: {e}", json_path.display()))?;
    let mut html = crate::report::html(&r.comparison);
    let cut = html.find("<h2>Which effect is missing</h2>").or_else(|| html.rfind("</body>")).unwrap_or(html.len());
    html.truncate(cut);
    html.push_str(&html_section(r));
    if let Some(a) = &r.after {
        html.push_str(&before_after::html(&r.comparison, a));
    }
    html.push_str("</body></html>");
    let html_path = opts.out.join("report.html");
    std::fs::write(&html_path, html).map_err(|e| format!("{}: {e}", html_path.display()))?;
    if !opts.quiet {
        print!("{}", compare::terminal_summary(&r.comparison));
        print!("{}", terminal_summary(r));
        if let Some(a) = &r.after {
            print!("{}", before_after::terminal(&r.comparison, a));
        }
        println!("report:  {}", html_path.display());
        println!("summary: {}", json_path.display());
    }
    Ok(())
}
