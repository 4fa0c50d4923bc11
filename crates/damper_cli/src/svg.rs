//! Inline SVG line and scatter plots for the report: linear or logarithmic axes with "nice" ticks,
//! legends, shaded spans and bands. Long time series are reduced per pixel column to their first,
//! smallest, largest and last value, so peaks survive and the file stays small.

use std::fmt::Write;
use std::sync::atomic::{AtomicUsize, Ordering};

pub const MEASURED: &str = "#222222";
pub const MODEL: &str = "#1f77b4";
pub const RESIDUAL: &str = "#9467bd";
pub const ACCENT: &str = "#d62728";
pub const GREEN: &str = "#2ca02c";
pub const ORANGE: &str = "#ff7f0e";
pub const BAND: &str = "#888888";

static NEXT_ID: AtomicUsize = AtomicUsize::new(0);

#[derive(Clone, Debug, Default)]
pub struct Axis {
    pub label: String,
    pub log: bool,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

impl Axis {
    pub fn new(label: &str) -> Axis {
        Axis { label: label.to_string(), ..Axis::default() }
    }
    pub fn log(mut self) -> Axis {
        self.log = true;
        self
    }
    pub fn range(mut self, min: f64, max: f64) -> Axis {
        self.min = Some(min);
        self.max = Some(max);
        self
    }
}

#[derive(Clone, Debug)]
pub enum Kind {
    Line {
        width: f64,
        dash: bool,
    },
    Points {
        radius: f64,
    },
    /// Vertical bars from 0 (correlations).
    Stems,
}

#[derive(Clone, Debug)]
pub struct Series {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub color: String,
    pub label: String,
    pub kind: Kind,
    pub opacity: f64,
}

impl Series {
    pub fn line(x: Vec<f64>, y: Vec<f64>, color: &str, label: &str) -> Series {
        Series {
            x,
            y,
            color: color.into(),
            label: label.into(),
            kind: Kind::Line { width: 1.2, dash: false },
            opacity: 1.0,
        }
    }
    pub fn dashed(mut self) -> Series {
        if let Kind::Line { dash, .. } = &mut self.kind {
            *dash = true;
        }
        self
    }
    pub fn width(mut self, w: f64) -> Series {
        if let Kind::Line { width, .. } = &mut self.kind {
            *width = w;
        }
        self
    }
    pub fn points(x: Vec<f64>, y: Vec<f64>, color: &str, label: &str) -> Series {
        Series { x, y, color: color.into(), label: label.into(), kind: Kind::Points { radius: 1.3 }, opacity: 0.35 }
    }
    pub fn stems(x: Vec<f64>, y: Vec<f64>, color: &str, label: &str) -> Series {
        Series { x, y, color: color.into(), label: label.into(), kind: Kind::Stems, opacity: 1.0 }
    }
    pub fn opacity(mut self, o: f64) -> Series {
        self.opacity = o;
        self
    }
}

#[derive(Clone, Debug)]
pub struct Plot {
    pub title: String,
    pub width: f64,
    pub height: f64,
    pub x: Axis,
    pub y: Axis,
    pub series: Vec<Series>,
    /// Horizontal bands (lo, hi, label): e.g. the ±1.96/√N whiteness band.
    pub hbands: Vec<(f64, f64, String)>,
    /// Shaded x spans (lo, hi, color, label).
    pub vspans: Vec<(f64, f64, String, String)>,
    /// Vertical lines (x, color, label).
    pub vlines: Vec<(f64, String, String)>,
    pub zero_line: bool,
}

impl Plot {
    pub fn new(title: &str, x: Axis, y: Axis) -> Plot {
        Plot {
            title: title.to_string(),
            width: 900.0,
            height: 300.0,
            x,
            y,
            series: Vec::new(),
            hbands: Vec::new(),
            vspans: Vec::new(),
            vlines: Vec::new(),
            zero_line: false,
        }
    }
    pub fn size(mut self, w: f64, h: f64) -> Plot {
        self.width = w;
        self.height = h;
        self
    }
    pub fn with(mut self, s: Series) -> Plot {
        self.series.push(s);
        self
    }

    fn data_range(&self, axis_x: bool) -> (f64, f64) {
        let axis = if axis_x { &self.x } else { &self.y };
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for s in &self.series {
            let vals = if axis_x { &s.x } else { &s.y };
            for &v in vals {
                if v.is_finite() && (!axis.log || v > 0.0) {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
            if !axis_x && matches!(s.kind, Kind::Stems) {
                lo = lo.min(0.0);
                hi = hi.max(0.0);
            }
        }
        if !axis_x {
            for (a, b, _) in &self.hbands {
                lo = lo.min(*a);
                hi = hi.max(*b);
            }
        }
        let lo = axis.min.unwrap_or(lo);
        let hi = axis.max.unwrap_or(hi);
        if !lo.is_finite() || !hi.is_finite() {
            return if axis.log { (1.0, 10.0) } else { (0.0, 1.0) };
        }
        if axis.log {
            let (l, h) = (libm::log10(lo), libm::log10(hi));
            if h - l < 1e-9 {
                return (libm::pow(10.0, l - 0.5), libm::pow(10.0, h + 0.5));
            }
            (lo, hi)
        } else if degenerate(lo, hi) {
            let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
            (lo - d, hi + d)
        } else if axis.min.is_none() && axis.max.is_none() && !axis_x {
            let pad = 0.04 * (hi - lo);
            (lo - pad, hi + pad)
        } else {
            (lo, hi)
        }
    }

    /// The SVG element.
    pub fn svg(&self) -> String {
        let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
        let f = self.frame();
        let mut s = String::new();
        self.write_frame(&mut s, &f, id);
        self.write_grid(&mut s, &f);
        self.write_axis_labels(&mut s, &f);
        let _ = write!(s, r#"<g clip-path="url(#c{id})">"#);
        self.write_spans_and_bands(&mut s, &f);
        for series in &self.series {
            self.write_series(&mut s, &f, series);
        }
        self.write_vlines(&mut s, &f);
        s.push_str("</g>");
        self.write_legend(&mut s, &f);
        s.push_str("</svg>");
        s
    }

    /// The plot's size, margins and data ranges.
    fn frame(&self) -> Frame {
        let (w, h) = (self.width, self.height);
        let (ml, mr, mt, mb) = (MARGIN_LEFT, MARGIN_RIGHT, MARGIN_TOP, MARGIN_BOTTOM);
        let (x0, x1) = self.data_range(true);
        let (y0, y1) = self.data_range(false);
        Frame { w, h, ml, mt, pw: w - ml - mr, ph: h - mt - mb, x0, x1, y0, y1, x_log: self.x.log, y_log: self.y.log }
    }

    /// The `<svg>` element's opening, the plotting area's clip path and box, and the title.
    fn write_frame(&self, s: &mut String, f: &Frame, id: usize) {
        let Frame { w, h, ml, mt, pw, ph, .. } = *f;
        let _ = write!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w} {h}" width="{w}" height="{h}" font-family="Helvetica,Arial,sans-serif" font-size="11">"#
        );
        let _ = write!(
            s,
            r#"<defs><clipPath id="c{id}"><rect x="{ml}" y="{mt}" width="{pw}" height="{ph}"/></clipPath></defs>"#
        );
        let _ = write!(s, r##"<rect x="{ml}" y="{mt}" width="{pw}" height="{ph}" fill="#fff" stroke="#999"/>"##);
        let _ = write!(s, r#"<text x="{}" y="16" font-size="13" font-weight="bold">{}</text>"#, ml, esc(&self.title));
    }

    /// The grid lines and the tick labels of both axes.
    fn write_grid(&self, s: &mut String, f: &Frame) {
        let Frame { ml, mt, pw, ph, x0, x1, y0, y1, .. } = *f;
        for v in ticks(x0, x1, self.x.log) {
            let px = f.tx(v);
            let _ = write!(s, r##"<line x1="{px:.1}" y1="{mt}" x2="{px:.1}" y2="{}" stroke="#e5e5e5"/>"##, mt + ph);
            let _ = write!(
                s,
                r#"<text x="{px:.1}" y="{}" text-anchor="middle">{}</text>"#,
                mt + ph + 14.0,
                fmt_tick(v, x0, x1, self.x.log)
            );
        }
        for v in ticks(y0, y1, self.y.log) {
            let py = f.ty(v);
            let _ = write!(s, r##"<line x1="{ml}" y1="{py:.1}" x2="{}" y2="{py:.1}" stroke="#e5e5e5"/>"##, ml + pw);
            let _ = write!(
                s,
                r#"<text x="{}" y="{:.1}" text-anchor="end">{}</text>"#,
                ml - 4.0,
                py + 4.0,
                fmt_tick(v, y0, y1, self.y.log)
            );
        }
    }

    /// The axes' labels: below the plot, and turned along the left edge.
    fn write_axis_labels(&self, s: &mut String, f: &Frame) {
        let Frame { h, ml, mt, pw, ph, .. } = *f;
        let _ = write!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            ml + pw / 2.0,
            h - 6.0,
            esc(&self.x.label)
        );
        let _ = write!(
            s,
            r#"<text x="14" y="{}" text-anchor="middle" transform="rotate(-90 14 {})">{}</text>"#,
            mt + ph / 2.0,
            mt + ph / 2.0,
            esc(&self.y.label)
        );
    }

    /// The shaded x spans, the horizontal bands and the zero line, under the series.
    fn write_spans_and_bands(&self, s: &mut String, f: &Frame) {
        let Frame { ml, mt, pw, ph, y0, y1, .. } = *f;
        for (a, b, color, _) in &self.vspans {
            let (pa, pb) = (f.tx(*a), f.tx(*b));
            let _ = write!(
                s,
                r#"<rect x="{:.1}" y="{mt}" width="{:.1}" height="{ph}" fill="{color}" opacity="0.15"/>"#,
                pa.min(pb),
                (pb - pa).abs().max(MIN_SPAN_PX)
            );
        }
        for (a, b, _) in &self.hbands {
            let (pa, pb) = (f.ty(*a), f.ty(*b));
            let _ = write!(
                s,
                r##"<rect x="{ml}" y="{:.1}" width="{pw}" height="{:.1}" fill="#888" opacity="0.18"/>"##,
                pa.min(pb),
                (pb - pa).abs()
            );
        }
        if self.zero_line && !self.y.log && y0 < 0.0 && y1 > 0.0 {
            let p = f.ty(0.0);
            let _ = write!(
                s,
                r##"<line x1="{ml}" y1="{p:.1}" x2="{}" y2="{p:.1}" stroke="#666" stroke-width="0.8"/>"##,
                ml + pw
            );
        }
    }

    /// One series, reduced to the plot's pixel columns: a path, dots or stems.
    fn write_series(&self, s: &mut String, f: &Frame, series: &Series) {
        let pts: Vec<(f64, f64)> = reduce(&series.x, &series.y, f.pw as usize, self.x.log, self.y.log)
            .into_iter()
            .map(|(x, y)| (f.tx(x), f.ty(y)))
            .collect();
        match series.kind {
            Kind::Line { width, dash } => {
                let mut d = String::new();
                // a point off the plot (NaN) lifts the pen: a gap, not a line across it
                let mut pen = false;
                for (px, py) in &pts {
                    if px.is_finite() && py.is_finite() {
                        let _ = write!(d, "{}{:.1},{:.1}", if pen { "L" } else { "M" }, px, py);
                        pen = true;
                    } else {
                        pen = false;
                    }
                }
                let _ = write!(
                    s,
                    r#"<path d="{d}" fill="none" stroke="{}" stroke-width="{width}" stroke-opacity="{}"{} stroke-linejoin="round"/>"#,
                    series.color,
                    series.opacity,
                    if dash { r#" stroke-dasharray="5,3""# } else { "" }
                );
            }
            Kind::Points { radius } => {
                let _ = write!(s, r#"<g fill="{}" fill-opacity="{}">"#, series.color, series.opacity);
                for (px, py) in &pts {
                    if px.is_finite() && py.is_finite() {
                        let _ = write!(s, r#"<circle cx="{px:.1}" cy="{py:.1}" r="{radius}"/>"#);
                    }
                }
                s.push_str("</g>");
            }
            Kind::Stems => {
                let base = f.ty(if self.y.log { f.y0 } else { 0.0f64.clamp(f.y0, f.y1) });
                let mut d = String::new();
                for (px, py) in &pts {
                    if px.is_finite() && py.is_finite() {
                        let _ = write!(d, "M{px:.1},{base:.1}L{px:.1},{py:.1}");
                    }
                }
                let _ = write!(s, r#"<path d="{d}" stroke="{}" stroke-width="1.5" fill="none"/>"#, series.color);
            }
        }
    }

    /// The vertical lines, over the series.
    fn write_vlines(&self, s: &mut String, f: &Frame) {
        let Frame { mt, ph, .. } = *f;
        for (x, color, _) in &self.vlines {
            let p = f.tx(*x);
            let _ = write!(
                s,
                r#"<line x1="{p:.1}" y1="{mt}" x2="{p:.1}" y2="{}" stroke="{color}" stroke-width="1.2" stroke-dasharray="4,3"/>"#,
                mt + ph
            );
        }
    }

    /// The legend's entries (label, color, drawn as a line rather than a patch): the labelled
    /// series, bands, spans and lines, a label given twice listed once.
    fn legend_entries(&self) -> Vec<(String, String, bool)> {
        let mut entries: Vec<(String, String, bool)> = Vec::new();
        for series in &self.series {
            if !series.label.is_empty() {
                entries.push((series.label.clone(), series.color.clone(), true));
            }
        }
        for (_, _, label) in &self.hbands {
            if !label.is_empty() {
                entries.push((label.clone(), BAND.to_string(), false));
            }
        }
        for (_, _, color, label) in &self.vspans {
            if !label.is_empty() && !entries.iter().any(|e| &e.0 == label) {
                entries.push((label.clone(), color.clone(), false));
            }
        }
        for (_, color, label) in &self.vlines {
            if !label.is_empty() && !entries.iter().any(|e| &e.0 == label) {
                entries.push((label.clone(), color.clone(), true));
            }
        }
        entries
    }

    /// The legend, right-aligned along the top of the plotting area, the last entry rightmost.
    fn write_legend(&self, s: &mut String, f: &Frame) {
        let Frame { ml, mt, pw, .. } = *f;
        let mut lx = ml + pw - 8.0;
        for (label, color, line) in self.legend_entries().iter().rev() {
            let tw = LEGEND_CHAR_PX * label.chars().count() as f64;
            lx -= tw + 26.0;
            let ly = mt + 12.0;
            let _ = write!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="16" fill="#fff" fill-opacity="0.85"/>"##,
                lx - 2.0,
                ly - 11.0,
                tw + 24.0
            );
            if *line {
                let _ = write!(
                    s,
                    r#"<line x1="{lx:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{color}" stroke-width="2.5"/>"#,
                    ly - 3.5,
                    lx + 16.0,
                    ly - 3.5
                );
            } else {
                let _ = write!(
                    s,
                    r#"<rect x="{lx:.1}" y="{:.1}" width="16" height="9" fill="{color}" opacity="0.35"/>"#,
                    ly - 8.0
                );
            }
            let _ = write!(s, r#"<text x="{:.1}" y="{ly:.1}">{}</text>"#, lx + 20.0, esc(label));
        }
    }
}

/// Left margin (px): the y axis's tick labels and its turned label.
const MARGIN_LEFT: f64 = 64.0;
/// Right margin (px).
const MARGIN_RIGHT: f64 = 16.0;
/// Top margin (px): the title.
const MARGIN_TOP: f64 = 26.0;
/// Bottom margin (px): the x axis's tick labels and its label.
const MARGIN_BOTTOM: f64 = 40.0;
/// Narrowest shaded span drawn (px): a span shorter than a pixel would vanish.
const MIN_SPAN_PX: f64 = 1.0;
/// Width of a legend character (px) at the plots' font size (11 px, Helvetica), for the room
/// each entry takes.
const LEGEND_CHAR_PX: f64 = 6.5;

/// Where a plot draws: its size and margins (px) and the data ranges its axes span.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// Width and height of the whole plot (px).
    w: f64,
    h: f64,
    /// Left and top margins (px).
    ml: f64,
    mt: f64,
    /// Width and height of the plotting area (px).
    pw: f64,
    ph: f64,
    /// The x axis's range, in data units.
    x0: f64,
    x1: f64,
    /// The y axis's range, in data units.
    y0: f64,
    y1: f64,
    x_log: bool,
    y_log: bool,
}

impl Frame {
    /// The pixel column of data value `v` on the x axis.
    fn tx(&self, v: f64) -> f64 {
        let (x0, x1) = (self.x0, self.x1);
        let f = if self.x_log {
            (libm::log10(v) - libm::log10(x0)) / (libm::log10(x1) - libm::log10(x0))
        } else {
            (v - x0) / (x1 - x0)
        };
        self.ml + f * self.pw
    }

    /// The pixel row of data value `v` on the y axis (down the screen).
    fn ty(&self, v: f64) -> f64 {
        let (y0, y1) = (self.y0, self.y1);
        let f = if self.y_log {
            (libm::log10(v) - libm::log10(y0)) / (libm::log10(y1) - libm::log10(y0))
        } else {
            (v - y0) / (y1 - y0)
        };
        self.mt + (1.0 - f) * self.ph
    }
}

/// Reduces a series for drawing: monotonic x → per-pixel-column first/min/max/last; otherwise a
/// stride down to at most 8000 points. Points off a log axis are dropped.
fn reduce(x: &[f64], y: &[f64], columns: usize, xlog: bool, ylog: bool) -> Vec<(f64, f64)> {
    let ok = |a: f64, b: f64| a.is_finite() && (!xlog || a > 0.0) && (!ylog || b > 0.0);
    let n = x.len().min(y.len());
    let monotonic = x.windows(2).all(|w| w[1] >= w[0]);
    if n <= 4 * columns.max(1) || !monotonic {
        let stride = if monotonic { 1 } else { n.div_ceil(8000).max(1) };
        return (0..n)
            .step_by(stride)
            .map(|i| if ok(x[i], y[i]) { (x[i], y[i]) } else { (f64::NAN, f64::NAN) })
            .collect();
    }
    let (xa, xb) = (x[0], x[n - 1]);
    let mut out = Vec::with_capacity(4 * columns);
    let mut i = 0;
    for c in 0..columns {
        let edge = xa + (xb - xa) * (c + 1) as f64 / columns as f64;
        let start = i;
        while i < n && (x[i] <= edge || c + 1 == columns) {
            i += 1;
        }
        if i == start {
            continue;
        }
        let seg = start..i;
        let (mut imin, mut imax) = (start, start);
        for k in seg.clone() {
            if y[k] < y[imin] {
                imin = k;
            }
            if y[k] > y[imax] {
                imax = k;
            }
        }
        let mut idx = vec![start, imin, imax, i - 1];
        idx.sort_unstable();
        idx.dedup();
        for k in idx {
            out.push(if ok(x[k], y[k]) { (x[k], y[k]) } else { (f64::NAN, f64::NAN) });
        }
    }
    out
}

/// A linear range too narrow for its values to resolve: a constant channel, or one constant but
/// for rounding in its last digits (1e6 Pa and 1e6 Pa + 3e-10). No tick step moves a value there.
fn degenerate(lo: f64, hi: f64) -> bool {
    hi - lo <= 1e-9 * lo.abs().max(hi.abs())
}

/// Nice tick values in [lo, hi]; none for a range that is not finite (or not positive on a log
/// axis), one at `lo` for a degenerate range.
fn ticks(lo: f64, hi: f64, log: bool) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite() && lo <= hi) || (log && lo <= 0.0) {
        return Vec::new();
    }
    if log {
        let (a, b) = (libm::log10(lo).floor() as i32, libm::log10(hi).ceil() as i32);
        let decades = b - a;
        let mults: &[f64] = if decades <= 2 { &[1.0, 2.0, 5.0] } else { &[1.0] };
        let step = ((decades as f64) / 8.0).ceil().max(1.0) as i32;
        let mut t = Vec::new();
        let mut e = a;
        while e <= b {
            for m in mults {
                let v = m * libm::pow(10.0, f64::from(e));
                if v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9) {
                    t.push(v);
                }
            }
            e += step;
        }
        return t;
    }
    if degenerate(lo, hi) {
        return vec![lo];
    }
    let span = hi - lo;
    let raw = span / 6.0;
    let mag = libm::pow(10.0, libm::log10(raw).floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * mag).find(|s| span / s <= 7.0).unwrap_or(10.0 * mag);
    // counted, not stepped until past `hi`: the count is at most 7 whatever the rounding of v + step
    let first = (lo / step).ceil();
    let count = ((hi + 1e-9 * step) / step).floor() - first;
    (0..=count as usize)
        .map(|k| {
            let v = (first + k as f64) * step;
            if v.abs() < 1e-12 * step {
                0.0
            } else {
                v
            }
        })
        .collect()
}

fn fmt_tick(v: f64, lo: f64, hi: f64, log: bool) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if log || !(1e-3..1e5).contains(&a) {
        if log && (1e-3..1e5).contains(&a) {
            return trim(format!("{v:.3}"));
        }
        let e = libm::log10(a).floor() as i32;
        let m = v / libm::pow(10.0, f64::from(e));
        return if (m - m.round()).abs() < 1e-9 && m.round() == 1.0 {
            format!("1e{e}")
        } else {
            format!("{}e{e}", trim(format!("{m:.2}")))
        };
    }
    let span = (hi - lo).abs().max(1e-300);
    let decimals = (-libm::log10(span / 6.0).floor() as i32 + 1).clamp(0, 6) as usize;
    trim(format!("{v:.decimals$}"))
}

fn trim(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Escapes text for SVG/HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_nice() {
        assert_eq!(ticks(0.0, 10.0, false), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(1.0, 1000.0, true), vec![1.0, 10.0, 100.0, 1000.0]);
        assert_eq!(fmt_tick(0.5, 0.0, 1.0, false), "0.5");
        assert_eq!(fmt_tick(1e-6, 1e-7, 1e-3, true), "1e-6");
    }

    #[test]
    fn degenerate_and_non_finite_ranges_have_few_ticks() {
        // a constant 1e6 Pa channel with rounding in its last digits: the step (5e-11) is below the
        // values' resolution (1.2e-10), so stepping from lo never passed hi
        assert_eq!(ticks(1e6, 1e6 + 3e-10, false), vec![1e6]);
        assert_eq!(ticks(1e6, 1e6, false), vec![1e6]);
        assert_eq!(ticks(0.0, 0.0, false), vec![0.0]);
        assert_eq!(ticks(-2.5, -2.5, false), vec![-2.5]);
        for (lo, hi) in [(f64::NAN, 1.0), (0.0, f64::NAN), (0.0, f64::INFINITY), (f64::NEG_INFINITY, 0.0), (1.0, 0.0)] {
            assert!(ticks(lo, hi, false).is_empty(), "{lo}..{hi}");
            assert!(ticks(lo, hi, true).is_empty(), "{lo}..{hi} (log)");
        }
        assert!(ticks(0.0, 10.0, true).is_empty(), "a log axis from 0");
        // the plot pads a degenerate range around the value: ticks across it, the value in view
        let plot = Plot::new("p_ext", Axis::new("t"), Axis::new("p")).with(Series::line(
            vec![0.0, 1.0, 2.0],
            vec![1e6, 1e6 + 3e-10, 1e6],
            MEASURED,
            "",
        ));
        let (y0, y1) = plot.data_range(false);
        assert!(y0 < 1e6 - 1e4 && y1 > 1e6 + 1e4, "{y0}..{y1}");
        let t = ticks(y0, y1, false);
        assert!((3..=8).contains(&t.len()) && t.iter().all(|v| (y0..=y1).contains(v)), "{t:?}");
        assert!(plot.svg().ends_with("</svg>"));
    }

    #[test]
    fn long_series_are_reduced() {
        let x: Vec<f64> = (0..100_000).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| (v * 0.01).sin()).collect();
        let r = reduce(&x, &y, 800, false, false);
        assert!(r.len() <= 3200);
        let svg = Plot::new("t", Axis::new("x"), Axis::new("y")).with(Series::line(x, y, MODEL, "s")).svg();
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>"));
    }
}
