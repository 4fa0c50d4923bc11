//! The self-contained HTML report of `damper compare`: inline CSS and SVG, no scripts, no links
//! to anything outside the file.

use crate::describe::describe_model;
use crate::svg::{esc, Axis, Plot, Series, ACCENT, GREEN, MEASURED, MODEL, ORANGE, RESIDUAL};
use damper_engine::analysis::{lag_ms, observations, Analysis, Regime, Window, V_REVERSAL};
use damper_engine::comparison::Comparison;
use damper_engine::model::Demand;
use damper_engine::residual_signature;
use damper_engine::units::Column;
use std::fmt::Write;

const CSS: &str = r#"
body { font-family: Helvetica, Arial, sans-serif; margin: 24px auto; max-width: 960px; color: #222; line-height: 1.4; }
h1 { font-size: 22px; margin-bottom: 4px; } h2 { font-size: 18px; margin-top: 32px; border-bottom: 1px solid #ccc; }
h3 { font-size: 15px; margin-bottom: 4px; }
table { border-collapse: collapse; margin: 8px 0; font-size: 13px; }
th, td { padding: 3px 8px; border-bottom: 1px solid #e3e3e3; text-align: right; }
th { background: #f4f4f4; } td.l, th.l { text-align: left; }
.note { background: #fff8e1; border-left: 4px solid #f0c000; padding: 6px 10px; margin: 8px 0; font-size: 13px; }
.defs { background: #f6f8fa; padding: 8px 12px; font-size: 13px; }
.hot { background: #fde0dc; } .bar { display: inline-block; height: 10px; background: #d62728; opacity: 0.6; }
.small { font-size: 12px; color: #555; } svg { display: block; margin: 6px 0 14px 0; }
code { background: #f2f2f2; padding: 0 3px; }
"#;

fn pct(x: f64) -> String {
    if x.is_finite() {
        format!("{:.1} %", 100.0 * x)
    } else {
        "—".into()
    }
}

fn num(x: f64, decimals: usize) -> String {
    if x.is_finite() {
        format!("{x:.decimals$}")
    } else {
        "—".into()
    }
}

/// A value in engineering style for tables.
fn eng(x: f64) -> String {
    if !x.is_finite() {
        return "—".into();
    }
    let a = x.abs();
    if a != 0.0 && !(1e-2..1e5).contains(&a) {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}

/// `x` times `f` (a unit change for a plot).
pub fn scaled(x: &[f64], f: f64) -> Vec<f64> {
    x.iter().map(|v| v * f).collect()
}

/// Newtons to kilonewtons: the forces' plot unit.
const KN_PER_N: f64 = 1e-3;
/// Metres to millimetres: the spool demand's plot unit.
const MM_PER_M: f64 = 1e3;
/// Seconds to milliseconds: the lags' unit.
const MS_PER_S: f64 = 1e3;
/// The worst windows drawn zoomed in (the table lists them all).
const ZOOMED_WINDOWS: usize = 2;
/// Context shown either side of a zoomed worst window, as a share of the record's duration (-)…
const ZOOM_PAD_SHARE: f64 = 0.15;
/// … and at most this (s): enough to see the motion around the window without shrinking it.
const ZOOM_PAD_MAX: f64 = 0.2;
/// A regime whose error concentration exceeds this (-) is shaded: it holds half again its share
/// of time in squared error…
const HOT_CONCENTRATION: f64 = 1.5;
/// … provided it covers at least this share of the record's time (-): a handful of samples
/// concentrates error by chance.
const HOT_MIN_TIME_SHARE: f64 = 0.01;
/// Concentration at which a regime's bar stops growing (-).
const BAR_MAX_CONCENTRATION: f64 = 5.0;
/// Bar length per unit of concentration (px).
const BAR_PX_PER_CONCENTRATION: f64 = 24.0;
/// How far below its peak the lag plot reaches, in heights of the peak above the curve's minimum
/// (-); never below that minimum.
const LAG_PLOT_DROP: f64 = 2.0;
/// Smallest height (-) of the peak above the minimum that the lag plot's range is drawn with: a
/// flat correlation curve still gets a range.
const LAG_PLOT_MIN_SPAN: f64 = 1e-6;
/// Smallest model run time (s) the real-time factor divides by: a run faster than the clock.
const MIN_RUN_SECONDS: f64 = 1e-9;

/// The report.
pub fn html(c: &Comparison) -> String {
    let mut h = String::new();
    head(&mut h, c);
    summary_section(&mut h, c);
    definitions(&mut h, c);
    fit_table(&mut h, &c.analysis);
    overlay_section(&mut h, c);
    residual_section(&mut h, &c.analysis, &c.measurement.time);
    regime_table(&mut h, c);
    worst_window_table(&mut h, &c.analysis);
    hysteresis_section(&mut h, c);
    h += &signature_section(c);
    spectrum_section(&mut h, &c.analysis);
    whiteness_section(&mut h, &c.analysis);
    lag_section(&mut h, &c.analysis);
    inputs_section(&mut h, c);
    h.push_str(
        "<h2>Which effect is missing</h2><p class=\"small\">Run <code>damper diagnose</code> with the same options: each catalog \
         effect switched on (or refitted), its parameters fitted on the train part and scored on the validation part, ranked, with a \
         verdict and the ladder of the error as the effects are added.</p></body></html>",
    );
    h
}

/// The record's duration (s), first sample to last.
fn duration(t: &[f64]) -> f64 {
    t[t.len() - 1] - t[0]
}

/// The document's head (title, style) and the page's title.
fn head(h: &mut String, c: &Comparison) {
    let m = &c.measurement;
    let _ = write!(
        h,
        "<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>damper compare — {}</title><style>{CSS}</style></head><body>",
        esc(&m.path)
    );
    let _ = write!(
        h,
        "<h1>Model versus measurement</h1><p class=\"small\">damper compare {} · {}</p>",
        env!("CARGO_PKG_VERSION"),
        esc(&m.path)
    );
}

/// The summary box: the record, the model, the force's score, the observations and warnings.
fn summary_section(h: &mut String, c: &Comparison) {
    let (a, m) = (&c.analysis, &c.measurement);
    let f = a.force();
    let dur = duration(&m.time);
    let _ = write!(
        h,
        "<p><b>{}</b> samples at {:.0} Hz ({:.2} s), {}; velocity {}. Model: {}. Model run {:.2} s ({:.0}× real time).</p>",
        m.len(),
        1.0 / a.dt,
        dur,
        c.drive.control_words(),
        if m.velocity_from_displacement { "derived from x_damper" } else { "measured" },
        esc(&describe_model(&c.setup)),
        c.run_seconds,
        dur / c.run_seconds.max(MIN_RUN_SECONDS)
    );
    let _ = write!(
        h,
        "<p>F_damper, validation part: <b>NRMSE {:.4}</b> (fit {:.1} %); white-noise floor estimated from the residual {:.4}; \
         lag {} ({} ms refined); residual {}.</p>",
        f.validation.nrmse,
        f.validation.fit_percent,
        a.noise_floor_estimate,
        if f.lag.found { format!("{} samples", f.lag.samples) } else { "not found".into() },
        lag_ms(f.lag.refined_seconds, 2),
        if a.whiteness.white { "white (Ljung–Box)" } else { "<b>not white</b> (Ljung–Box)" }
    );
    h.push_str(
        "<p><b>Observations</b> (what the residual shows; naming the missing effect is diagnose's job):</p><ul>",
    );
    for o in observations(a) {
        let _ = write!(h, "<li>{}</li>", esc(&o));
    }
    h.push_str("</ul>");
    for w in &c.warnings {
        let _ = write!(h, "<div class=\"note\">{}</div>", esc(w));
    }
}

/// The definitions of the residual, the scores, the parts and the lag.
fn definitions(h: &mut String, c: &Comparison) {
    let a = &c.analysis;
    let _ = write!(
        h,
        "<div class=\"defs\"><b>Definitions.</b> Residual r = ŷ − y (model minus measured, as in docs/effects.md; positive where the model is above the measurement). \
         fit % = 100·(1 − ‖y − ŷ‖/‖y − ȳ‖); NRMSE = RMSE/std(y), so fit % = 100·(1 − NRMSE); ȳ, std(y) over the part scored. \
         Train part: the first {:.0} % of the samples (t &lt; {:.3} s); validation: the rest. \
         The model is driven by the measured inputs at the measurement's sample times (inputs held over each interval), starting at rest at the first sample. \
         Regimes, spectra, worst windows and the lag use the whole record; whiteness and the residual–input cross-correlations use the validation part. \
         Lag: the k maximising Σ y(t+k)·ŷ(t) within ±{:.0} ms (positive: the measured force comes later), refined by a parabola through the peak. \
         White-noise floor estimate: σ from the residual's second differences (var = 6σ² for white noise, a smooth model error barely contributes), divided by std(y).</div>",
        100.0 * a.split_fraction,
        c.measurement.time[a.split],
        a.force().lag.max_seconds * MS_PER_S
    );
}

/// Section 1: each compared signal's scores on both parts and its lags.
fn fit_table(h: &mut String, a: &Analysis) {
    let _ = write!(
        h,
        "<h2>1. Fit per signal</h2><table><tr><th class=\"l\">signal</th><th>unit</th><th>train fit</th><th>train NRMSE</th>\
         <th>validation fit</th><th>validation NRMSE</th><th>validation RMSE</th><th>validation bias</th><th>lag [ms]</th><th>lag of changes [ms]</th></tr>"
    );
    for s in &a.fits {
        let label = if s.column == Column::XSpoolDemand {
            "x_spool_demand (vs model x_spool_ref)".to_string()
        } else {
            s.column.name().to_string()
        };
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td><td>{:.1} %</td><td>{:.4}</td><td>{:.1} %</td><td><b>{:.4}</b></td><td>{}</td><td>{}</td><td>{:+.2}</td><td>{:+.2}</td></tr>",
            label,
            s.column.si_unit(),
            s.train.fit_percent,
            s.train.nrmse,
            s.validation.fit_percent,
            s.validation.nrmse,
            eng(s.validation.rmse),
            eng(s.validation.bias),
            lag_ms(s.lag.refined_seconds, 2),
            lag_ms(s.lag.changes_seconds, 2)
        );
    }
    h.push_str("</table>");
}

/// Section 2: the measured and modelled force over the record, the worst windows zoomed in, and
/// every other compared signal.
fn overlay_section(h: &mut String, c: &Comparison) {
    let (a, t) = (&c.analysis, &c.measurement.time);
    h.push_str("<h2>2. Overlay</h2>");
    *h += &force_overlay(c).svg();
    for (k, w) in a.worst.iter().take(ZOOMED_WINDOWS).enumerate() {
        *h += &worst_window_plot(c, k, w).svg();
    }
    for s in a.fits.iter().skip(1) {
        let (unit, factor) = s.column.display_unit();
        let ym = c.measurement.get(s.column).expect("measured");
        let model_signal = c.prediction.get(s.column).expect("model");
        let mut pl = Plot::new(
            &format!(
                "{}: measured and model{}",
                s.column.name(),
                if s.column == Column::XSpoolDemand { " (x_spool_ref)" } else { "" }
            ),
            Axis::new("time [s]"),
            Axis::new(&format!("{} [{unit}]", s.column.name())),
        )
        .size(900.0, 220.0)
        .with(Series::line(t.clone(), scaled(ym, factor), MEASURED, "measured").width(0.9))
        .with(Series::line(t.clone(), scaled(model_signal, factor), MODEL, "model").width(0.9));
        pl.vlines.push((t[a.split], ORANGE.into(), String::new()));
        *h += &pl.svg();
    }
}

/// The measured and modelled force (and the force demand) over the whole record, the split and
/// the worst windows marked.
fn force_overlay(c: &Comparison) -> Plot {
    let (a, t) = (&c.analysis, &c.measurement.time);
    let y = c.measurement.get(Column::FDamper).expect("F_damper");
    let mut overlay = Plot::new("F_damper: measured and model", Axis::new("time [s]"), Axis::new("force [kN]"))
        .with(Series::line(t.clone(), scaled(y, KN_PER_N), MEASURED, "measured").width(1.0))
        .with(Series::line(t.clone(), scaled(&c.prediction.f_damper, KN_PER_N), MODEL, "model").width(1.0));
    if let Demand::Force(fd) = &c.drive.demand {
        overlay = overlay.with(Series::line(t.clone(), scaled(fd, KN_PER_N), GREEN, "F_demand").dashed().width(0.8));
    }
    overlay.vlines.push((t[a.split], ORANGE.into(), "train | validation".into()));
    for w in &a.worst {
        overlay.vspans.push((w.t_start, w.t_end, ACCENT.into(), "worst windows".into()));
    }
    overlay
}

/// The `k`-th worst window `w` zoomed in: forces and residual, with some context either side.
fn worst_window_plot(c: &Comparison, k: usize, w: &Window) -> Plot {
    let (a, t) = (&c.analysis, &c.measurement.time);
    let y = c.measurement.get(Column::FDamper).expect("F_damper");
    let pad = (ZOOM_PAD_SHARE * duration(t)).min(ZOOM_PAD_MAX);
    let (i0, i1) = (index_at(t, w.t_start - pad), index_at(t, w.t_end + pad) + 1);
    let mut z = Plot::new(
        &format!("Worst window {}: {:.3}–{:.3} s ({})", k + 1, w.t_start, w.t_end, w.tags.join(", ")),
        Axis::new("time [s]"),
        Axis::new("force [kN]"),
    )
    .size(900.0, 260.0)
    .with(Series::line(t[i0..i1].to_vec(), scaled(&y[i0..i1], KN_PER_N), MEASURED, "measured"))
    .with(Series::line(t[i0..i1].to_vec(), scaled(&c.prediction.f_damper[i0..i1], KN_PER_N), MODEL, "model"))
    .with(Series::line(t[i0..i1].to_vec(), scaled(&a.residual[i0..i1], KN_PER_N), RESIDUAL, "residual"));
    if let Demand::Force(fd) = &c.drive.demand {
        z = z.with(Series::line(t[i0..i1].to_vec(), scaled(&fd[i0..i1], KN_PER_N), GREEN, "F_demand").dashed());
    }
    z.vspans.push((w.t_start, w.t_end, ACCENT.into(), String::new()));
    z.zero_line = true;
    z
}

/// Section 3: the force residual over the record.
fn residual_section(h: &mut String, a: &Analysis, t: &[f64]) {
    h.push_str("<h2>3. Residual over time</h2>");
    let mut res = Plot::new("F_damper residual (model − measured)", Axis::new("time [s]"), Axis::new("residual [kN]"))
        .with(Series::line(t.to_vec(), scaled(&a.residual, KN_PER_N), RESIDUAL, "residual").width(0.9));
    res.vlines.push((t[a.split], ORANGE.into(), "train | validation".into()));
    for w in &a.worst {
        res.vspans.push((w.t_start, w.t_end, ACCENT.into(), "worst windows".into()));
    }
    res.zero_line = true;
    *h += &res.svg();
}

/// Section 4 (start): the regimes' share of the error against their share of time, and the
/// events (reversals, demand steps, the residual's jump at a reversal).
fn regime_table(h: &mut String, c: &Comparison) {
    let a = &c.analysis;
    h.push_str("<h2>4. Where it fails</h2><p class=\"small\">Each regime: its share of the record's squared force error against its share of time. \
        A concentration above 1 (shaded) means the error gathers there. Mean residual: model − measured.</p>");
    h.push_str("<table><tr><th class=\"l\">group</th><th class=\"l\">regime</th><th>samples</th><th>time</th><th>error share</th><th>concentration</th><th class=\"l\"></th><th>RMS [N]</th><th>mean [N]</th></tr>");
    for r in &a.regimes {
        regime_row(h, r);
    }
    h.push_str("</table>");
    let _ = write!(
        h,
        "<p class=\"small\">{} velocity reversals (crossing ±{} m/s), {} demand steps (jumps ≥ {}). Residual jump across a velocity reversal \
         (mean over 5–25 ms after minus 25–5 ms before, + for compression → extension; a friction-like force F·sign(v) missing from the model gives −2F): <b>{}</b>.</p>",
        a.reversals.len(),
        V_REVERSAL,
        a.demand_steps.len(),
        if c.drive.control_mode() == 0 { "1 kN" } else { "0.1 mm" },
        a.reversal_jump.map_or("—".to_string(), |j| format!("{j:+.0} N"))
    );
}

/// One regime's row, shaded where the error gathers, with a bar of its concentration.
fn regime_row(h: &mut String, r: &Regime) {
    let hot = r.samples > 0 && r.concentration > HOT_CONCENTRATION && r.time_share >= HOT_MIN_TIME_SHARE;
    let bar = if r.concentration.is_finite() {
        (r.concentration.min(BAR_MAX_CONCENTRATION) * BAR_PX_PER_CONCENTRATION) as usize
    } else {
        0
    };
    let _ = write!(
        h,
        "<tr{}><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"l\"><span class=\"bar\" style=\"width:{bar}px\"></span></td><td>{}</td><td>{}</td></tr>",
        if hot { " class=\"hot\"" } else { "" },
        r.group,
        esc(&r.name),
        r.samples,
        pct(r.time_share),
        pct(r.error_share),
        num(r.concentration, 2),
        num(r.rms, 0),
        if r.mean.is_finite() { format!("{:+.0}", r.mean) } else { "—".into() }
    );
}

/// The worst time windows' table.
fn worst_window_table(h: &mut String, a: &Analysis) {
    h.push_str("<h3>Worst time windows</h3><table><tr><th>#</th><th>from [s]</th><th>to [s]</th><th>RMS [N]</th><th>mean [N]</th><th>mean |v| [m/s]</th><th class=\"l\">what happens</th></tr>");
    for (k, w) in a.worst.iter().enumerate() {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{:.0}</td><td>{:+.0}</td><td>{:.3}</td><td class=\"l\">{}</td></tr>",
            k + 1,
            w.t_start,
            w.t_end,
            w.rms,
            w.mean,
            w.mean_abs_velocity,
            esc(&w.tags.join(", "))
        );
    }
    h.push_str("</table>");
}

/// The residual against the damper velocity, with its bin means on rising and falling velocity
/// (a hysteresis loop, or a jump at v = 0).
fn hysteresis_section(h: &mut String, c: &Comparison) {
    let a = &c.analysis;
    let v = c.measurement.get(Column::VDamper).expect("v_damper");
    h.push_str("<h3>Residual against velocity</h3><p class=\"small\">Dots: every sample (thinned to 8000). Lines: the mean residual in 40 velocity bins, \
        separately while the velocity rises and falls; two branches that differ are a hysteresis loop (delay, compliance), a jump at v = 0 the same on both branches points to friction-like force.</p>");
    let mut hyst = Plot::new("Residual vs damper velocity", Axis::new("v_damper [m/s]"), Axis::new("residual [kN]"))
        .size(900.0, 340.0)
        .with(Series::points(v.to_vec(), scaled(&a.residual, KN_PER_N), RESIDUAL, "samples"));
    let bins_x: Vec<f64> = a.velocity_bins.iter().map(|b| b.v).collect();
    let rise: Vec<f64> = a.velocity_bins.iter().map(|b| b.rising.map_or(f64::NAN, |x| x * KN_PER_N)).collect();
    let fall: Vec<f64> = a.velocity_bins.iter().map(|b| b.falling.map_or(f64::NAN, |x| x * KN_PER_N)).collect();
    hyst = hyst
        .with(Series::line(bins_x.clone(), rise, ACCENT, "mean, velocity rising").width(2.2))
        .with(Series::line(bins_x, fall, MODEL, "mean, velocity falling").width(2.2));
    hyst.zero_line = true;
    *h += &hyst.svg();
}

/// Section 5: the residual's and the measured force's spectra, and the residual per band.
fn spectrum_section(h: &mut String, a: &Analysis) {
    h.push_str("<h2>5. Residual spectrum</h2>");
    // from the first bin above 0 Hz: the axis is logarithmic
    let fpos: Vec<usize> = (1..a.psd_freq.len()).collect();
    let fx: Vec<f64> = fpos.iter().map(|&i| a.psd_freq[i]).collect();
    let mut spec = Plot::new(
        "Power spectral density (Welch, Hann, 50 % overlap)",
        Axis::new("frequency [Hz]").log(),
        Axis::new("PSD [N²/Hz]").log(),
    )
    .with(Series::line(fx.clone(), fpos.iter().map(|&i| a.psd_measured[i]).collect(), MEASURED, "measured force"))
    .with(Series::line(fx, fpos.iter().map(|&i| a.psd_residual[i]).collect(), RESIDUAL, "residual"));
    for b in a.bands.iter().skip(1) {
        spec.vlines.push((b.lo, "#bbbbbb".into(), String::new()));
    }
    *h += &spec.svg();
    h.push_str("<table><tr><th>band [Hz]</th><th>share of residual variance</th><th>RMS residual [N]</th><th>band NRMSE (residual/measured)</th></tr>");
    for b in &a.bands {
        let _ = write!(
            h,
            "<tr><td>{:.0}–{:.0}</td><td>{}</td><td>{:.1}</td><td>{}</td></tr>",
            b.lo,
            b.hi,
            pct(b.residual_share),
            b.residual_rms,
            num(b.band_nrmse, 3)
        );
    }
    h.push_str("</table>");
}

/// The lags (ms) of a correlation of `len` values centred on lag 0, at sample interval `dt` (s).
fn centred_lags_ms(len: usize, dt: f64) -> Vec<f64> {
    let l = (len / 2) as f64;
    (0..len).map(|i| (i as f64 - l) * dt * MS_PER_S).collect()
}

/// Section 6: the residual's whiteness (autocorrelation, Ljung–Box) and its cross-correlation
/// with each input.
fn whiteness_section(h: &mut String, a: &Analysis) {
    let w = &a.whiteness;
    let _ = write!(
        h,
        "<h2>6. Whiteness and correlation with the inputs</h2><p>Validation part, N = {}. {:.1} % of the lags 1..{} lie outside ±1.96/√N = ±{:.4} (about 5 % for white noise). \
         Ljung–Box Q({}) = {:.1} against the 95 % quantile {:.1}: <b>{}</b>.</p>",
        w.samples,
        100.0 * w.fraction_outside,
        w.max_lag,
        w.band,
        w.ljung_box_lags,
        w.ljung_box_q,
        w.chi2_95,
        if w.white { "white" } else { "not white" }
    );
    let lags_ac: Vec<f64> = (0..a.autocorrelation.len()).map(|k| k as f64 * a.dt * MS_PER_S).collect();
    let mut ac = Plot::new("Residual autocorrelation", Axis::new("lag [ms]"), Axis::new("autocorrelation"))
        .size(900.0, 240.0)
        .with(Series::stems(lags_ac, a.autocorrelation.clone(), RESIDUAL, "r(k)"));
    ac.hbands.push((-w.band, w.band, "±1.96/√N".into()));
    *h += &ac.svg();
    for x in &a.input_correlations {
        let lx = centred_lags_ms(x.values.len(), a.dt);
        let mut pl = Plot::new(
            &format!(
                "Cross-correlation of the residual with {} (max |c| {:.3} at {:+.1} ms)",
                x.input.name(),
                x.max_abs,
                x.at_lag_seconds * MS_PER_S
            ),
            Axis::new("lag [ms] (positive: residual after the input)"),
            Axis::new("correlation"),
        )
        .size(900.0, 220.0)
        .with(Series::stems(lx, x.values.clone(), MODEL, ""));
        pl.hbands.push((-x.band, x.band, "±1.96/√N".into()));
        *h += &pl.svg();
    }
}

/// Section 7: the lag between measured and modelled force, and the correlation curve it peaks on.
fn lag_section(h: &mut String, a: &Analysis) {
    let f = a.force();
    let lx = centred_lags_ms(a.lag_curve.len(), a.dt);
    let _ = write!(
        h,
        "<h2>7. Lag between measured and modelled force</h2><p>Peak of the cross-correlation at <b>{} samples ({} ms)</b>, refined {} ms, correlation {:.4}. \
         Positive: the measured force comes later than the model's. The same estimate on the sample-to-sample changes of both forces, \
         which weights steps and fast transients (a delay in the valve path shows there even when the velocity-driven force dominates): <b>{} ms</b>. \
         A peak at the edge of the ±{:.0} ms searched is the search's limit, not a delay: \"not found\".</p>",
        f.lag.samples,
        lag_ms(f.lag.seconds, 2),
        lag_ms(f.lag.refined_seconds, 3),
        f.lag.peak,
        lag_ms(f.lag.changes_seconds, 2),
        f.lag.max_seconds * MS_PER_S
    );
    let lo = a.lag_curve.iter().cloned().fold(f64::INFINITY, f64::min);
    let mut lag =
        Plot::new("Cross-correlation, measured against model force", Axis::new("lag [ms]"), Axis::new("correlation"))
            .size(900.0, 220.0)
            .with(Series::line(lx, a.lag_curve.clone(), MODEL, ""));
    lag.y.min = Some(lo.max(f.lag.peak - LAG_PLOT_DROP * (f.lag.peak - lo).max(LAG_PLOT_MIN_SPAN)));
    lag.vlines.push((f.lag.refined_seconds * MS_PER_S, ACCENT.into(), "estimate".into()));
    *h += &lag.svg();
}

/// Section 8: the measured inputs, and the CSV columns they were read from.
fn inputs_section(h: &mut String, c: &Comparison) {
    let (m, t) = (&c.measurement, &c.measurement.time);
    let v = m.get(Column::VDamper).expect("v_damper");
    h.push_str("<h2>8. Measured inputs</h2>");
    let mut inp = Plot::new("v_damper", Axis::new("time [s]"), Axis::new("v_damper [m/s]"))
        .size(900.0, 200.0)
        .with(Series::line(t.clone(), v.to_vec(), MEASURED, "").width(0.8));
    inp.zero_line = true;
    *h += &inp.svg();
    if let Demand::SpoolPosition(xs) = &c.drive.demand {
        *h += &Plot::new("x_spool_demand", Axis::new("time [s]"), Axis::new("x_spool_demand [mm]"))
            .size(900.0, 200.0)
            .with(Series::line(t.clone(), scaled(xs, MM_PER_M), MEASURED, "").width(0.8))
            .svg();
    }
    h.push_str("<h3>Columns read</h3><table><tr><th class=\"l\">variable</th><th class=\"l\">CSV column</th><th>#</th><th>unit</th></tr>");
    for s in &m.sources {
        let _ = write!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td></tr>",
            s.column.name(),
            esc(&s.header),
            s.index,
            esc(&s.unit)
        );
    }
    h.push_str("</table>");
}

/// What the residual follows (ranked), and the residual against the stroke: a force that hangs on
/// the position (an end stop, a bump rubber) shows there and nowhere else.
fn signature_section(c: &Comparison) -> String {
    let a = &c.analysis;
    let mut h = String::from("<h3>What the residual follows</h3><p class=\"small\">Share of the residual's variance above the white noise that a function of each quantity explains (the bin means of the residual over 20 equal-width bins, less chance). The first is where to look for a missing effect.</p><table><tr><th class=\"l\">quantity</th><th>share</th></tr>");
    for f in &a.signature {
        let _ = write!(h, "<tr><td class=\"l\">{}</td><td>{}</td></tr>", f.quantity.name(), pct(f.share));
    }
    h.push_str("</table>");
    let _ = write!(h, "<p>{}.</p>", esc(&residual_signature::sentence(&a.signature, a.dominant_band)));
    let x = &c.prediction.x_damper;
    let keep: Vec<bool> = c.measurement.excluded.iter().map(|e| !e).collect();
    let (centres, means, _) = residual_signature::binned(x, &a.residual, &keep);
    let mut plot = Plot::new("Residual vs stroke", Axis::new("x_damper [mm]"), Axis::new("residual [kN]"))
        .size(900.0, 340.0)
        .with(Series::points(scaled(x, MM_PER_M), scaled(&a.residual, KN_PER_N), RESIDUAL, "samples"))
        .with(
            Series::line(scaled(&centres, MM_PER_M), scaled(&means, KN_PER_N), ACCENT, "mean in 20 stroke bins")
                .width(2.2),
        );
    plot.zero_line = true;
    h += &plot.svg();
    h
}

fn index_at(t: &[f64], x: f64) -> usize {
    t.partition_point(|&v| v < x).min(t.len() - 1)
}
