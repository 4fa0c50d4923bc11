//! Reading a measurement CSV: columns named like the FMU's variables (or mapped with `--map`),
//! units converted to SI, every problem reported with file, line and column. Nothing is dropped:
//! a bad cell, a short row or a time that does not increase stops the run.
//!
//! Format: optional comment lines starting with `#`, one header line, then one sample per line.
//! The delimiter is the header's most frequent of `,` `;` tab. A header cell may carry its unit,
//! `F_damper [kN]` or `F_damper (kN)`; `--map SOURCE=NAME[:UNIT]` renames a column and sets its
//! unit. Columns the tool does not use are listed, not read.

use crate::units::{unit, unit_list, Column};
use std::collections::BTreeMap;
use std::path::Path;

/// `--map SOURCE=NAME[:UNIT]`: the CSV column `source` is the variable `target`, in `unit`.
#[derive(Clone, Debug, PartialEq)]
pub struct Mapping {
    pub source: String,
    pub target: Column,
    pub unit: Option<String>,
}

impl Mapping {
    /// Parses `SOURCE=NAME[:UNIT]`, e.g. `vel=v_damper:cm/s` or `Force=F_damper:kN`.
    pub fn parse(text: &str) -> Result<Mapping, String> {
        let usage = "expected --map SOURCE=NAME[:UNIT], e.g. --map vel=v_damper:cm/s";
        let (source, rest) = text.split_once('=').ok_or_else(|| format!("--map {text}: {usage}"))?;
        let (name, unit_text) = match rest.split_once(':') {
            Some((n, u)) => (n.trim(), Some(u.trim().to_string())),
            None => (rest.trim(), None),
        };
        let target = Column::from_name(name).ok_or_else(|| {
            let names: Vec<_> = Column::ALL.iter().map(|c| c.name()).collect();
            format!("--map {text}: unknown variable '{name}'; the variables are {}", names.join(", "))
        })?;
        if let Some(u) = &unit_text {
            check_unit(u, target).map_err(|e| format!("--map {text}: {e}"))?;
        }
        if source.trim().is_empty() {
            return Err(format!("--map {text}: {usage}"));
        }
        Ok(Mapping { source: source.trim().to_string(), target, unit: unit_text })
    }
}

/// SI factor of `u` for `column`, or why it does not fit.
fn check_unit(u: &str, column: Column) -> Result<f64, String> {
    match unit(u) {
        None => Err(format!("unknown unit '{u}' (known: {})", unit_list())),
        Some((q, _)) if q != column.quantity() => {
            Err(format!("unit '{u}' is {q}, but {} is {}", column.name(), column.quantity()))
        }
        Some((_, f)) => Ok(f),
    }
}

/// Where a variable came from in the file.
#[derive(Clone, Debug)]
pub struct ColumnSource {
    pub column: Column,
    /// Header cell as written.
    pub header: String,
    /// 1-based column number.
    pub index: usize,
    pub unit: String,
    /// Factor to SI.
    pub factor: f64,
}

/// A measurement in SI units.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The file as named on the command line.
    pub path: String,
    pub time: Vec<f64>,
    /// Every variable read (not `time`), in SI; `v_damper` also when derived from `x_damper`.
    pub columns: BTreeMap<Column, Vec<f64>>,
    /// File line (1-based) of each sample.
    pub lines: Vec<usize>,
    pub sources: Vec<ColumnSource>,
    /// Header cells not used, as written.
    pub ignored: Vec<String>,
    /// True when `v_damper` was derived from `x_damper`.
    pub velocity_from_displacement: bool,
    /// Things the reader decided that the user should know.
    pub notes: Vec<String>,
}

impl Measurement {
    pub fn len(&self) -> usize {
        self.time.len()
    }

    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    pub fn get(&self, c: Column) -> Option<&[f64]> {
        if c == Column::Time {
            return Some(&self.time);
        }
        self.columns.get(&c).map(|v| v.as_slice())
    }

    pub fn has(&self, c: Column) -> bool {
        self.columns.contains_key(&c)
    }

    /// The CSV column a variable came from, for messages: `column 3 ('Force [kN]')`.
    pub fn describe_column(&self, c: Column) -> String {
        match self.sources.iter().find(|s| s.column == c) {
            Some(s) => format!("column {} ('{}')", s.index, s.header),
            None => format!("'{}'", c.name()),
        }
    }

    /// Median sample interval [s].
    pub fn median_interval(&self) -> f64 {
        let mut dt: Vec<f64> = self.time.windows(2).map(|w| w[1] - w[0]).collect();
        dt.sort_by(|a, b| a.total_cmp(b));
        dt.get(dt.len() / 2).copied().unwrap_or(f64::NAN)
    }

    /// Reads and checks a measurement CSV.
    pub fn read(path: &Path, maps: &[Mapping]) -> Result<Measurement, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        Measurement::parse(&path.display().to_string(), &text, maps)
    }

    /// Parses CSV text; `name` is used in messages.
    pub fn parse(name: &str, text: &str, maps: &[Mapping]) -> Result<Measurement, String> {
        let lines: Vec<&str> = text.lines().map(|l| l.strip_suffix('\r').unwrap_or(l)).collect();
        let header_at = lines
            .iter()
            .position(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
            .ok_or_else(|| format!("{name}, line 1: no header line (the file is empty or all comments)"))?;
        let header_line = header_at + 1;
        let delim = detect_delimiter(lines[header_at]);
        let cells: Vec<String> = split(lines[header_at], delim).into_iter().map(unquote).collect();

        // Resolve every header cell to a variable, a unit and a factor.
        let mut chosen: BTreeMap<Column, ColumnSource> = BTreeMap::new();
        let mut ignored = Vec::new();
        let mut notes = Vec::new();
        for m in maps {
            if !cells.iter().any(|c| c == &m.source || strip_unit(c).0 == m.source) {
                return Err(format!(
                    "{name}, line {header_line}: --map names column '{}', which the header does not have (columns: {})",
                    m.source,
                    cells.join(", ")
                ));
            }
        }
        for (i, cell) in cells.iter().enumerate() {
            let (bare, header_unit) = strip_unit(cell);
            let map = maps.iter().find(|m| &m.source == cell || m.source == bare);
            let column = match map {
                Some(m) => Some(m.target),
                None => Column::from_name(&bare),
            };
            let Some(column) = column else {
                ignored.push(cell.clone());
                continue;
            };
            let where_ = format!("{name}, line {header_line}, column {} ('{cell}')", i + 1);
            let unit_text = match (map.and_then(|m| m.unit.clone()), header_unit) {
                (Some(u), Some(h)) if !u.eq_ignore_ascii_case(&h) => {
                    notes.push(format!("column '{cell}': --map unit {u} used instead of the header's {h}"));
                    u
                }
                (Some(u), _) => u,
                (None, Some(h)) => h,
                (None, None) => column.si_unit().to_string(),
            };
            let factor = check_unit(&unit_text, column).map_err(|e| format!("{where_}: {e}"))?;
            if let Some(prev) = chosen.get(&column) {
                return Err(format!(
                    "{where_}: is {} again, already given by column {} ('{}'); drop one or --map it to another name",
                    column.name(),
                    prev.index,
                    prev.header
                ));
            }
            chosen.insert(column, ColumnSource { column, header: cell.clone(), index: i + 1, unit: unit_text, factor });
        }

        let missing = |c: Column, also: &str| -> String {
            let mut msg = format!(
                "{name}, line {header_line}: missing column '{}' ({}, {}){also}; the header has: {}",
                c.name(),
                c.meaning(),
                c.si_unit(),
                cells.join(", ")
            );
            if let Some(close) = cells.iter().find(|h| {
                let b = strip_unit(h).0;
                b.eq_ignore_ascii_case(c.name()) || b.replace([' ', '-'], "_").eq_ignore_ascii_case(c.name())
            }) {
                msg += &format!(". Did you mean '{close}'? Use --map '{}={}:UNIT'", strip_unit(close).0, c.name());
            } else {
                msg += &format!(". If it is named differently, use --map SOURCE={}:UNIT", c.name());
            }
            msg
        };
        if !chosen.contains_key(&Column::Time) {
            return Err(missing(Column::Time, ""));
        }
        if !chosen.contains_key(&Column::VDamper) && !chosen.contains_key(&Column::XDamper) {
            return Err(missing(Column::VDamper, " (or x_damper, the displacement)"));
        }
        if !chosen.contains_key(&Column::FDamper) {
            return Err(missing(Column::FDamper, ""));
        }
        if !chosen.contains_key(&Column::FDemand) && !chosen.contains_key(&Column::XSpoolDemand) {
            return Err(missing(Column::FDemand, " (or x_spool_demand for spool-position control)"));
        }
        if chosen.contains_key(&Column::VDamper) {
            if let Some(x) = chosen.remove(&Column::XDamper) {
                notes.push(format!("x_damper (column {}) not used: v_damper is given", x.index));
                ignored.push(x.header);
            }
        }

        // Data rows.
        let n_fields = cells.len();
        let used: Vec<&ColumnSource> = chosen.values().collect();
        let mut data: BTreeMap<Column, Vec<f64>> = used.iter().map(|s| (s.column, Vec::new())).collect();
        let mut sample_lines = Vec::new();
        let last_content = lines.iter().rposition(|l| !l.trim().is_empty()).unwrap_or(header_at);
        for (k, raw) in lines.iter().enumerate().skip(header_at + 1) {
            let line_no = k + 1;
            if k > last_content {
                break; // trailing blank lines
            }
            let trimmed = raw.trim();
            if trimmed.starts_with('#') {
                continue;
            }
            if trimmed.is_empty() {
                return Err(format!("{name}, line {line_no}: empty line inside the data"));
            }
            let fields = split(raw, delim);
            if fields.len() != n_fields {
                let col = fields.len().min(n_fields) + 1;
                return Err(format!(
                    "{name}, line {line_no}, column {col}: {} fields, but the header (line {header_line}) has {n_fields}",
                    fields.len()
                ));
            }
            for s in &used {
                let cell = unquote(fields[s.index - 1].clone());
                let where_ = || format!("{name}, line {line_no}, column {} ('{}')", s.index, s.header);
                if cell.is_empty() {
                    return Err(format!("{}: empty cell", where_()));
                }
                let value: f64 = cell.parse().map_err(|_| format!("{}: not a number: '{cell}'", where_()))?;
                if !value.is_finite() {
                    return Err(format!("{}: {cell} is not a finite number", where_()));
                }
                data.get_mut(&s.column).expect("column").push(value * s.factor);
            }
            sample_lines.push(line_no);
        }

        let time = data.remove(&Column::Time).expect("time");
        let ts = &chosen[&Column::Time];
        if time.len() < 3 {
            return Err(format!(
                "{name}, line {}, column {} ('{}'): only {} samples; a measurement needs many more",
                sample_lines.last().copied().unwrap_or(header_line),
                ts.index,
                ts.header,
                time.len()
            ));
        }
        for k in 1..time.len() {
            if time[k] <= time[k - 1] {
                let what = if time[k] == time[k - 1] { "repeats" } else { "is before" };
                return Err(format!(
                    "{name}, line {}, column {} ('{}'): time {} {what} the previous sample's {} (line {}); time must increase",
                    sample_lines[k],
                    ts.index,
                    ts.header,
                    time[k] / ts.factor,
                    time[k - 1] / ts.factor,
                    sample_lines[k - 1]
                ));
            }
        }

        let mut velocity_from_displacement = false;
        if !data.contains_key(&Column::VDamper) {
            let x = data.remove(&Column::XDamper).expect("x_damper");
            data.insert(Column::VDamper, differentiate(&time, &x));
            velocity_from_displacement = true;
            notes.push(
                "v_damper derived from x_damper by central differences (second order, one-sided at the ends); \
                 displacement noise is amplified by about 1/(sqrt(2)·dt)"
                    .to_string(),
            );
        }
        if data.contains_key(&Column::FDemand) && data.contains_key(&Column::XSpoolDemand) {
            notes.push(
                "F_demand and x_spool_demand both given: force control; x_spool_demand is compared with the \
                 model's spool demand (x_spool_ref)"
                    .to_string(),
            );
        }
        let mut sources: Vec<ColumnSource> = chosen.into_values().collect();
        sources.sort_by_key(|s| s.index);
        let m = Measurement {
            path: name.to_string(),
            time,
            columns: data,
            lines: sample_lines,
            sources,
            ignored,
            velocity_from_displacement,
            notes,
        };
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for w in m.time.windows(2) {
            lo = lo.min(w[1] - w[0]);
            hi = hi.max(w[1] - w[0]);
        }
        if hi > 1.01 * lo {
            let mut m = m;
            m.notes.push(format!(
                "sampling is not uniform (interval {:.4} to {:.4} ms); the model steps over each interval, \
                 spectra and correlations assume the median interval",
                lo * 1e3,
                hi * 1e3
            ));
            return Ok(m);
        }
        Ok(m)
    }
}

/// Velocity from displacement: three-point central difference on a possibly non-uniform grid,
/// second-order one-sided differences at the ends.
pub fn differentiate(t: &[f64], x: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut v = vec![0.0; n];
    for i in 1..n - 1 {
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        v[i] =
            (-h1 / (h0 * (h0 + h1))) * x[i - 1] + ((h1 - h0) / (h0 * h1)) * x[i] + (h0 / (h1 * (h0 + h1))) * x[i + 1];
    }
    let (h0, h1) = (t[1] - t[0], t[2] - t[1]);
    let s = h0 + h1;
    v[0] = -(2.0 * h0 + h1) / (h0 * s) * x[0] + s / (h0 * h1) * x[1] - h0 / (h1 * s) * x[2];
    // mirror for the last point: differentiate in reversed time
    let (h0, h1) = (t[n - 1] - t[n - 2], t[n - 2] - t[n - 3]);
    let s = h0 + h1;
    v[n - 1] = (2.0 * h0 + h1) / (h0 * s) * x[n - 1] - s / (h0 * h1) * x[n - 2] + h0 / (h1 * s) * x[n - 3];
    v
}

fn detect_delimiter(header: &str) -> char {
    let counts = [',', ';', '\t'].map(|d| (header.matches(d).count(), d));
    counts.iter().max_by_key(|(c, _)| *c).map(|&(c, d)| if c == 0 { ',' } else { d }).unwrap_or(',')
}

fn split(line: &str, delim: char) -> Vec<String> {
    line.split(delim).map(|s| s.trim().to_string()).collect()
}

fn unquote(s: String) -> String {
    let t = s.trim();
    if t.len() >= 2 && ((t.starts_with('"') && t.ends_with('"')) || (t.starts_with('\'') && t.ends_with('\''))) {
        t[1..t.len() - 1].trim().to_string()
    } else {
        t.to_string()
    }
}

/// `"F_damper [kN]"` → (`F_damper`, Some(`kN`)); also `(kN)`.
fn strip_unit(cell: &str) -> (String, Option<String>) {
    let c = cell.trim();
    for (open, close) in [('[', ']'), ('(', ')')] {
        if c.ends_with(close) {
            if let Some(i) = c.rfind(open) {
                let name = c[..i].trim();
                if !name.is_empty() {
                    return (name.to_string(), Some(c[i + 1..c.len() - 1].trim().to_string()));
                }
            }
        }
    }
    (c.to_string(), None)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivative_is_exact_for_quadratics() {
        let t: Vec<f64> = (0..10).map(|k| (k as f64) * 0.1 + 0.01 * (k * k) as f64).collect();
        let x: Vec<f64> = t.iter().map(|t| 3.0 * t * t - t + 2.0).collect();
        let v = differentiate(&t, &x);
        for (ti, vi) in t.iter().zip(&v) {
            assert!((vi - (6.0 * ti - 1.0)).abs() < 1e-9, "{ti} {vi}");
        }
    }

    #[test]
    fn header_units_and_maps() {
        let csv = "# comment\ntime [ms],vel,F_demand [kN],F_damper,extra\n0,0,0,0,x\n1,10,1,5,y\n2,20,2,6,z\n";
        let maps = [Mapping::parse("vel=v_damper:cm/s").unwrap()];
        let m = Measurement::parse("a.csv", csv, &maps).unwrap();
        assert_eq!(m.time, vec![0.0, 1e-3, 2e-3]);
        assert_eq!(m.get(Column::VDamper).unwrap(), &[0.0, 0.1, 0.2]);
        assert_eq!(m.get(Column::FDemand).unwrap(), &[0.0, 1e3, 2e3]);
        assert_eq!(m.ignored, vec!["extra".to_string()]);
        assert_eq!(m.lines, vec![3, 4, 5]);
    }
}
