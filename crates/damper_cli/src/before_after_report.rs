//! Step 4's evidence in the report and on the terminal: the model before and after adding the
//! effects the diagnosis names, on the same record: the fit of every signal, the error in every
//! regime, the residual's whiteness, and the residual over time, against velocity and in
//! frequency, each before and after in one view.

use crate::report::scaled;
use crate::svg::{esc, Axis, Plot, Series, ACCENT, GREEN, MEASURED, RESIDUAL};
use damper_engine::analysis::{lag_ms, Analysis};
use damper_engine::before_after::{regime_rows, After};
use damper_engine::comparison::Comparison;
use damper_engine::units::Column;
use std::fmt::Write;

fn change(before: f64, after: f64) -> String {
    if before.is_finite() && after.is_finite() && before > 0.0 {
        format!("{:+.0} %", 100.0 * (after / before - 1.0))
    } else {
        "—".into()
    }
}

/// The report section.
pub fn html(c: &Comparison, after: &After) -> String {
    let (b, a) = (&c.analysis, &after.analysis);
    let t = &c.measurement.time;
    let v = c.measurement.get(Column::VDamper).expect("v_damper");
    let added = after.effects.join(" + ");
    let mut h = format!(
        "<h2>Before and after adding {}</h2><p class=\"small\">The baseline model against the model with {} at the fitted values, \
         on the same record. Validation part for the fits; the whole record for the regimes.</p>",
        esc(&added),
        esc(&added)
    );
    h.push_str("<table><tr><th class=\"l\">signal</th><th>NRMSE before</th><th>NRMSE after</th><th>change</th><th>lag before [ms]</th><th>lag after [ms]</th></tr>");
    for (fb, fa) in b.fits.iter().zip(&a.fits) {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td>{:.4}</td><td>{:.4}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            fb.column.name(),
            fb.validation.nrmse,
            fa.validation.nrmse,
            change(fb.validation.nrmse, fa.validation.nrmse),
            lag_ms(fb.lag.refined_seconds, 2),
            lag_ms(fa.lag.refined_seconds, 2)
        );
    }
    let _ = write!(
        h,
        "</table><p>Noise floor (white noise in the residual): {:.4}. Residual whiteness (Ljung–Box Q over {} lags): before {:.0} ({}), after {:.0} ({}). \
         Residual jump across velocity reversals: before {}, after {}.</p>",
        a.noise_floor_estimate,
        b.whiteness.ljung_box_lags,
        b.whiteness.ljung_box_q,
        if b.whiteness.white { "white" } else { "not white" },
        a.whiteness.ljung_box_q,
        if a.whiteness.white { "white" } else { "not white" },
        b.reversal_jump.map_or("—".into(), |j| format!("{j:+.0} N")),
        a.reversal_jump.map_or("—".into(), |j| format!("{j:+.0} N")),
    );
    h.push_str("<h3>Error by regime, before and after</h3><table><tr><th class=\"l\">group</th><th class=\"l\">regime</th><th>time</th><th>RMS before [N]</th><th>RMS after [N]</th><th>change</th></tr>");
    for (group, name, share, rb, ra) in regime_rows(b, a) {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{group}</td><td class=\"l\">{}</td><td>{:.1} %</td><td>{rb:.0}</td><td>{ra:.0}</td><td>{}</td></tr>",
            esc(name),
            100.0 * share,
            change(rb, ra)
        );
    }
    h.push_str("</table>");
    let mut res = Plot::new("F_damper residual, before and after", Axis::new("time [s]"), Axis::new("residual [kN]"))
        .with(Series::line(t.clone(), scaled(&b.residual, 1e-3), RESIDUAL, "before").width(0.9))
        .with(Series::line(t.clone(), scaled(&a.residual, 1e-3), GREEN, &format!("after (+ {added})")).width(0.9));
    res.zero_line = true;
    h += &res.svg();
    let bins = |an: &Analysis| -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let x = an.velocity_bins.iter().map(|b| b.v).collect();
        let r = an.velocity_bins.iter().map(|b| b.rising.map_or(f64::NAN, |x| x * 1e-3)).collect();
        let f = an.velocity_bins.iter().map(|b| b.falling.map_or(f64::NAN, |x| x * 1e-3)).collect();
        (x, r, f)
    };
    let ((xb, rb, fb), (xa, ra, fa)) = (bins(b), bins(a));
    let mut hyst = Plot::new(
        "Mean residual against velocity, before and after",
        Axis::new("v_damper [m/s]"),
        Axis::new("residual [kN]"),
    )
    .size(900.0, 320.0)
    .with(Series::points(v.to_vec(), scaled(&a.residual, 1e-3), GREEN, "after, samples"))
    .with(Series::line(xb.clone(), rb, RESIDUAL, "before, velocity rising").width(2.0))
    .with(Series::line(xb, fb, ACCENT, "before, velocity falling").width(2.0))
    .with(Series::line(xa.clone(), ra, MEASURED, "after, velocity rising").width(2.0))
    .with(Series::line(xa, fa, MEASURED, "after, velocity falling").width(2.0).dashed());
    hyst.zero_line = true;
    h += &hyst.svg();
    let idx: Vec<usize> = (1..b.psd_freq.len()).collect();
    let fx: Vec<f64> = idx.iter().map(|&i| b.psd_freq[i]).collect();
    h += &Plot::new(
        "Residual spectrum, before and after",
        Axis::new("frequency [Hz]").log(),
        Axis::new("PSD [N²/Hz]").log(),
    )
    .with(Series::line(fx.clone(), idx.iter().map(|&i| b.psd_residual[i]).collect(), RESIDUAL, "before"))
    .with(Series::line(fx, idx.iter().map(|&i| a.psd_residual[i]).collect(), GREEN, "after"))
    .svg();
    h
}

/// The terminal lines: the regimes where the error was largest, before → after.
pub fn terminal(c: &Comparison, after: &After) -> String {
    let mut rows = regime_rows(&c.analysis, &after.analysis);
    rows.sort_by(|x, y| y.3.total_cmp(&x.3));
    let mut t =
        format!("before → after adding {} (RMS force error by regime, the worst five):\n", after.effects.join(" + "));
    for (g, n, _, rb, ra) in rows.into_iter().take(5) {
        let _ = writeln!(t, "  {g:<11} {n:<36} {rb:>6.0} N → {ra:>5.0} N  ({})", change(rb, ra));
    }
    t
}
