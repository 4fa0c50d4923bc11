//! Reading a measurement CSV: columns named like the FMU's variables (or mapped with `--map`),
//! units converted to SI, every problem reported with file, line and column. Nothing is dropped:
//! a bad cell, a short row or a time that does not increase stops the run.
//!
//! Format: RFC 4180 (the `csv` crate: quoted cells may hold the delimiter, `""` is a quote), UTF-8
//! with or without a byte-order mark; optional comment lines starting with `#`, one header line,
//! then one sample per line. The delimiter is the header's most frequent of `,` `;` tab outside
//! quotes. A header cell may carry its unit, `F_damper [kN]` or `F_damper (kN)`;
//! `--map SOURCE=NAME[:UNIT]` renames a column and sets its unit. Columns the tool does not use are
//! listed, not read.
//!
//! Decimal comma: with `;` or tab as delimiter, numbers with a comma and none with a point are read
//! with a decimal comma. In a `,` file a comma can only be inside a quoted cell; it is read as a
//! decimal comma when no number has a point and at least one cannot be a thousands separator
//! (`"1,5"`, unlike `"1,500"`); otherwise the file is refused. Either way a note says so.
//!
//! Time: a number in s, ms or µs, or ISO 8601 timestamps (`2026-03-04T10:15:30.123`, a space for
//! the `T`, optional `Z` or offset), taken as seconds from the first sample.
//!
//! Sampling: the model and the analysis want a uniform grid. An interval more than
//! [`GAP_FACTOR`] times the median is a gap: gaps of up to `max_gap` missing samples are bridged,
//! a longer one is an error. When there is a gap, or an interval deviates from the median by more
//! than [`JITTER_TOLERANCE`] of it, every channel is resampled onto a uniform grid at the median
//! interval by linear interpolation; the notes list each gap and the resampling.

use crate::dsp::differentiate;
use crate::error::{Error, Place};
use crate::units::{unit, unit_list, Column};
use crate::velocity_noise::VelocityNoise;
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
    pub fn parse(text: &str) -> Result<Mapping, Error> {
        let usage = "expected --map SOURCE=NAME[:UNIT], e.g. --map vel=v_damper:cm/s";
        let bad = |problem: String| Error::BadOption { option: format!("--map {text}"), problem };
        let (source, rest) = text.split_once('=').ok_or_else(|| bad(usage.to_string()))?;
        let (name, unit_text) = match rest.split_once(':') {
            Some((n, u)) => (n.trim(), Some(u.trim().to_string())),
            None => (rest.trim(), None),
        };
        let target = Column::from_name(name).ok_or_else(|| {
            let names: Vec<_> = Column::ALL.iter().map(|c| c.name()).collect();
            bad(format!("unknown variable '{name}'; the variables are {}", names.join(", ")))
        })?;
        if let Some(u) = &unit_text {
            check_unit(u, target).map_err(|e| e.context(format!("--map {text}")))?;
        }
        if source.trim().is_empty() {
            return Err(bad(usage.to_string()));
        }
        Ok(Mapping { source: source.trim().to_string(), target, unit: unit_text })
    }
}

/// SI factor of `u` for `column`, or why it does not fit.
fn check_unit(u: &str, column: Column) -> Result<f64, Error> {
    match unit(u) {
        None => Err(Error::UnknownUnitOf { symbol: u.to_string(), known: unit_list() }),
        Some((q, _)) if q != column.quantity() => Err(Error::UnitOfOtherQuantity {
            unit: u.to_string(),
            quantity: q.to_string(),
            column: column.name(),
            column_quantity: column.quantity().to_string(),
        }),
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
    /// Offset to SI after the factor (temperatures: °C to K): SI = value·factor + offset.
    pub offset: f64,
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
    /// The `#` comment lines: (line, text after the `#`), for what a logger states (a sample rate).
    pub comments: Vec<(usize, String)>,
    /// Samples left out of every score and fit (a force channel flat at its rail), with why.
    pub excluded: Vec<bool>,
    /// The stroke at the first sample (m) where the record measures the displacement: its first
    /// sample, or where the velocity fused with it starts ([`crate::stroke`]).
    pub x_start: Option<f64>,
    /// The velocity's noise when it is made from the displacement (a logger's derivative, or this
    /// reader's), or when a transducer's was smoothed: coloured, and what the sensitivity test, the
    /// floor and the parameters' uncertainties perturb the model with.
    pub velocity_noise: Option<VelocityNoise>,
    /// Where the logger's velocity made from the displacement was kept, the motion made again from
    /// the displacement ([`crate::motion::motion`]; [`Measurement::with_velocity_made_again`]).
    pub made_again: Option<Box<crate::motion::Motion>>,
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

    /// The record driven by the velocity made again from its displacement, where the logger's was
    /// kept: the diagnosis's choice, whose floor then carries the velocity's whole error.
    pub fn with_velocity_made_again(mut self) -> Measurement {
        if let Some(again) = self.made_again.take() {
            if let Some(v) = again.v {
                self.columns.insert(Column::VDamper, v);
                self.x_start = again.x_start;
                self.velocity_noise = again.velocity_noise;
                self.notes.push(
                    "the diagnosis drives the model with v_damper made again from x_damper: its error, corners \
                     rounded off and noise alike, is carried into the floor"
                        .into(),
                );
                self.notes.extend(again.notes);
            }
        }
        self
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

    /// Median sample interval (s).
    pub fn median_interval(&self) -> f64 {
        median_interval(&self.time)
    }

    /// Reads and checks a measurement CSV; gaps of up to `max_gap` missing samples are bridged.
    pub fn read(path: &Path, maps: &[Mapping], max_gap: usize) -> Result<Measurement, Error> {
        Measurement::read_flipped(path, maps, max_gap, &[])
    }

    /// [`Measurement::read`] with the columns `flips` negated (`--flip`: a logger's other sign
    /// convention; the velocity and the displacement together, as they describe one motion).
    pub fn read_flipped(path: &Path, maps: &[Mapping], max_gap: usize, flips: &[Column]) -> Result<Measurement, Error> {
        let bytes = std::fs::read(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
        Measurement::parse_flipped(&path.display().to_string(), &bytes, maps, max_gap, flips)
    }

    /// Parses CSV bytes; `name` is used in messages.
    pub fn parse(name: &str, bytes: &[u8], maps: &[Mapping], max_gap: usize) -> Result<Measurement, Error> {
        Measurement::parse_flipped(name, bytes, maps, max_gap, &[])
    }

    /// [`Measurement::parse`] with the columns `flips` negated (see [`Measurement::read_flipped`]).
    pub fn parse_flipped(
        name: &str,
        bytes: &[u8],
        maps: &[Mapping],
        max_gap: usize,
        flips: &[Column],
    ) -> Result<Measurement, Error> {
        let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        let comments = comment_lines(bytes);
        let table = Table::read(name, bytes)?;
        let mut notes = Vec::new();
        let (chosen, ignored) = resolve_columns(name, &table, maps, &mut notes)?;
        check_required_columns(name, &table, &chosen, &mut notes)?;

        // Data rows: the cells of the columns used, as written.
        let lines: Vec<usize> = table.rows.iter().map(|r| r.line).collect();
        let cells = Cells::read(name, &table, &chosen, &lines)?;
        let (time, mut data) = cells.samples(&table, &chosen[&Column::Time], &mut notes)?;
        flip_columns(name, &mut data, flips, &mut notes)?;
        let velocity_from_displacement = derive_missing_velocity(&time, &mut data, &mut notes);
        if data.contains_key(&Column::FDemand) && data.contains_key(&Column::XSpoolDemand) {
            notes.push(
                "F_demand and x_spool_demand both given: force control; x_spool_demand is compared with the \
                 model's spool demand (x_spool_ref)"
                    .to_string(),
            );
        }
        let gaps = gaps(&time, max_gap, |k| cells.previous_sample(k))?;
        let (time, lines) = on_uniform_grid(time, lines, &gaps, max_gap, &mut data, &mut notes);
        let m = model_motion(name, &time, &mut data, &chosen, velocity_from_displacement)?;
        notes.extend(m.notes);
        let (x_start, velocity_noise, made_again) = (m.x_start, m.velocity_noise, m.made_again);
        let mut sources: Vec<ColumnSource> = chosen.into_values().collect();
        sources.sort_by_key(|s| s.index);
        let excluded = vec![false; time.len()];
        Ok(Measurement {
            path: name.to_string(),
            time,
            columns: data,
            lines,
            sources,
            ignored,
            velocity_from_displacement,
            notes,
            comments,
            excluded,
            x_start,
            velocity_noise,
            made_again,
        })
    }
}

/// Every variable's values but the time's, in SI, by variable.
type Channels = BTreeMap<Column, Vec<f64>>;

/// Fewest samples of a measurement: the median interval and the central differences need three.
const MIN_SAMPLES: usize = 3;
/// Seconds per nanosecond: timestamps are differenced in integer nanoseconds.
const SECONDS_PER_NANOSECOND: f64 = 1e-9;

/// The `#` comment lines: (line, text after the `#`, trimmed).
fn comment_lines(bytes: &[u8]) -> Vec<(usize, String)> {
    bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .filter_map(|(i, l)| {
            l.trim_ascii().strip_prefix(b"#").map(|c| (i + 1, String::from_utf8_lossy(c).trim().to_string()))
        })
        .collect()
}

/// The header's cells quoted and listed, for messages.
fn listed(header: &[String]) -> String {
    header.iter().map(|c| format!("'{c}'")).collect::<Vec<_>>().join(", ")
}

/// Resolves every header cell to a variable, a unit and a factor: the columns read (by variable)
/// and the cells not read. `notes` gets each `--map` unit used instead of the header's.
fn resolve_columns(
    name: &str,
    table: &Table,
    maps: &[Mapping],
    notes: &mut Vec<String>,
) -> Result<(BTreeMap<Column, ColumnSource>, Vec<String>), Error> {
    let header_line = table.header_line;
    let cells = &table.header;
    for m in maps {
        if !cells.iter().any(|c| c == &m.source || strip_unit(c).0 == m.source) {
            return Err(in_file(
                Place::line(name, header_line),
                format!(
                    "--map names column '{}', which the header does not have (columns: {})",
                    m.source,
                    listed(cells)
                ),
            ));
        }
    }
    let mut chosen: BTreeMap<Column, ColumnSource> = BTreeMap::new();
    let mut ignored = Vec::new();
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
        let where_ = Place::field(name, header_line, format!("column {} ('{cell}')", i + 1));
        let unit_text = column_unit(cell, column, map, header_unit, notes);
        let factor = check_unit(&unit_text, column).map_err(|e| e.at(where_.clone()))?;
        if let Some(prev) = chosen.get(&column) {
            return Err(in_file(
                where_,
                format!(
                    "is {} again, already given by column {} ('{}'); drop one or --map it to another name",
                    column.name(),
                    prev.index,
                    prev.header
                ),
            ));
        }
        let offset = crate::units::unit_offset(&unit_text);
        chosen.insert(
            column,
            ColumnSource { column, header: cell.clone(), index: i + 1, unit: unit_text, factor, offset },
        );
    }
    Ok((chosen, ignored))
}

/// The unit of header cell `cell` read as `column`: the `--map`'s (noted where it overrides the
/// header's), the header's, or the variable's SI unit.
fn column_unit(
    cell: &str,
    column: Column,
    map: Option<&Mapping>,
    header_unit: Option<String>,
    notes: &mut Vec<String>,
) -> String {
    match (map.and_then(|m| m.unit.clone()), header_unit) {
        (Some(u), Some(h)) if !u.eq_ignore_ascii_case(&h) => {
            notes.push(format!("column '{cell}': --map unit {u} used instead of the header's {h}"));
            u
        }
        (Some(u), _) => u,
        (None, Some(h)) => h,
        (None, None) => column.si_unit().to_string(),
    }
}

/// The message for a missing column `c` (`also`: what may replace it), naming a header cell
/// that looks like it.
fn missing_column(name: &str, table: &Table, c: Column, also: &str) -> Error {
    let cells = &table.header;
    let mut msg = format!(
        "missing column '{}' ({}, {}){also}; the header has: {}",
        c.name(),
        c.meaning(),
        c.si_unit(),
        listed(cells),
    );
    if let Some(close) = cells.iter().find(|h| {
        let b = strip_unit(h).0;
        b.eq_ignore_ascii_case(c.name()) || b.replace([' ', '-'], "_").eq_ignore_ascii_case(c.name())
    }) {
        msg += &format!(". Did you mean '{close}'? Use --map '{}={}:UNIT'", strip_unit(close).0, c.name());
    } else {
        msg += &format!(". If it is named differently, use --map SOURCE={}:UNIT", c.name());
    }
    in_file(Place::line(name, table.header_line), msg)
}

/// `at: problem`.
fn in_file(at: Place, problem: impl Into<String>) -> Error {
    Error::InFile { at, problem: problem.into() }
}

/// Time, a motion and the force must be there; notes a passive record (no demand) and a record
/// with both velocity and displacement.
fn check_required_columns(
    name: &str,
    table: &Table,
    chosen: &BTreeMap<Column, ColumnSource>,
    notes: &mut Vec<String>,
) -> Result<(), Error> {
    if !chosen.contains_key(&Column::Time) {
        return Err(missing_column(name, table, Column::Time, ""));
    }
    if !chosen.contains_key(&Column::VDamper) && !chosen.contains_key(&Column::XDamper) {
        return Err(missing_column(name, table, Column::VDamper, " (or x_damper, the displacement)"));
    }
    if !chosen.contains_key(&Column::FDamper) {
        return Err(missing_column(name, table, Column::FDamper, ""));
    }
    if !chosen.contains_key(&Column::FDemand) && !chosen.contains_key(&Column::XSpoolDemand) {
        notes.push(
            "no F_demand or x_spool_demand column: a passive record, the model's valve held at x_spool_start \
             without a controller (control_mode 2)"
                .to_string(),
        );
    }
    if let (Some(v), Some(x)) = (chosen.get(&Column::VDamper), chosen.get(&Column::XDamper)) {
        notes.push(format!(
            "v_damper (column {}) and x_damper (column {}) both given: the notes below say how they make the \
             model's motion and its starting stroke",
            v.index, x.index
        ));
    }
    Ok(())
}

/// Each data row's cells of the columns `used`, as written; a row with another number of fields
/// than the header is an error.
fn used_cells<'a>(name: &str, table: &'a Table, used: &[&ColumnSource]) -> Result<Vec<Vec<&'a str>>, Error> {
    let n_fields = table.header.len();
    let header_line = table.header_line;
    let mut raw: Vec<Vec<&str>> = Vec::with_capacity(table.rows.len());
    for row in &table.rows {
        if row.cells.len() != n_fields {
            let col = row.cells.len().min(n_fields) + 1;
            let hint = if row.cells.len() > n_fields && table.delimiter == b',' {
                "; a decimal comma splits a number in a comma-separated file: quote such numbers, or export \
                 with ';' as the delimiter"
            } else {
                ""
            };
            return Err(in_file(
                Place::field(name, row.line, format!("column {col}")),
                format!("{} fields, but the header (line {header_line}) has {n_fields}{hint}", row.cells.len()),
            ));
        }
        raw.push(used.iter().map(|s| row.cells[s.index - 1].as_str()).collect());
    }
    Ok(raw)
}

/// The cells of the columns used, as written (`raw[k][j]`: row `k`, used column `j`), with the
/// file line of each row, for the values and the messages.
struct Cells<'a> {
    name: &'a str,
    used: Vec<&'a ColumnSource>,
    lines: &'a [usize],
    raw: Vec<Vec<&'a str>>,
    /// The time column's index in `used`.
    time_j: usize,
}

impl<'a> Cells<'a> {
    /// The cells of the columns `chosen` in `table`'s rows (`lines`: each row's file line).
    fn read(
        name: &'a str,
        table: &'a Table,
        chosen: &'a BTreeMap<Column, ColumnSource>,
        lines: &'a [usize],
    ) -> Result<Cells<'a>, Error> {
        let used: Vec<&ColumnSource> = chosen.values().collect();
        let raw = used_cells(name, table, &used)?;
        let time_j = used.iter().position(|s| s.column == Column::Time).expect("time");
        Ok(Cells { name, used, lines, raw, time_j })
    }

    /// The samples' times (s, increasing) and every other variable's values in SI: numbers (with
    /// a decimal comma where the file writes one, noted) or timestamps (noted; `ts` is the time
    /// column's source).
    fn samples(
        &self,
        table: &Table,
        ts: &ColumnSource,
        notes: &mut Vec<String>,
    ) -> Result<(Vec<f64>, Channels), Error> {
        let time_j = self.time_j;
        let first_stamp = self.raw.first().and_then(|r| parse_timestamp(r[time_j]));
        let timestamps = first_stamp.is_some();
        let numeric = |j: usize| !(timestamps && j == time_j);
        let decimal_comma = decimal_comma(&self.raw, &numeric, &|k, j| self.at(k, j), table.delimiter)?;
        if let Some(note) = &decimal_comma {
            notes.push(note.clone());
        }
        let mut data = self.values(&numeric, decimal_comma.is_some(), first_stamp)?;
        if timestamps {
            notes.push(format!(
                "time column {} ('{}') holds timestamps: converted to seconds from the first sample ({})",
                ts.index, ts.header, self.raw[0][time_j]
            ));
        }
        if self.raw.len() < MIN_SAMPLES {
            return Err(in_file(
                Place::field(
                    self.name,
                    self.lines.last().copied().unwrap_or(table.header_line),
                    format!("column {} ('{}')", ts.index, ts.header),
                ),
                format!("only {} samples; a measurement needs many more", self.raw.len()),
            ));
        }
        let time = data.remove(&Column::Time).expect("time");
        self.check_time_increases(&time)?;
        Ok((time, data))
    }

    /// Where cell (`k`, `j`) is, for messages: file, line, column.
    fn at(&self, k: usize, j: usize) -> Place {
        Place::field(self.name, self.lines[k], format!("column {} ('{}')", self.used[j].index, self.used[j].header))
    }

    /// Where sample `k`'s time is, with the previous sample's, for a gap.
    fn previous_sample(&self, k: usize) -> Place {
        let time_j = self.time_j;
        let at = self.at(k, time_j);
        let field = format!(
            "{} (previous sample {} at line {})",
            at.field.as_deref().unwrap_or_default(),
            self.raw[k - 1][time_j],
            self.lines[k - 1]
        );
        Place { field: Some(field), ..at }
    }

    /// Every cell's value in SI, by variable: numbers (`numeric(j)`, with a decimal comma when
    /// `decimal_comma`) or timestamps in seconds from `first_stamp`.
    fn values(
        &self,
        numeric: &dyn Fn(usize) -> bool,
        decimal_comma: bool,
        first_stamp: Option<(i64, bool)>,
    ) -> Result<Channels, Error> {
        let mut data: Channels = self.used.iter().map(|s| (s.column, Vec::with_capacity(self.raw.len()))).collect();
        for (k, row) in self.raw.iter().enumerate() {
            for (j, (s, cell)) in self.used.iter().zip(row).enumerate() {
                if cell.is_empty() {
                    return Err(in_file(self.at(k, j), "empty cell"));
                }
                let value = if numeric(j) {
                    self.number(k, j, cell, s, decimal_comma)?
                } else {
                    self.seconds_from_first(k, j, cell, first_stamp)?
                };
                data.get_mut(&s.column).expect("column").push(value);
            }
        }
        Ok(data)
    }

    /// Cell (`k`, `j`), `cell`, as a finite number in SI through its column's unit `s`.
    fn number(&self, k: usize, j: usize, cell: &str, s: &ColumnSource, decimal_comma: bool) -> Result<f64, Error> {
        let text = if decimal_comma { cell.replace(',', ".") } else { cell.to_string() };
        let value: f64 = text.parse().map_err(|_| in_file(self.at(k, j), format!("not a number: '{cell}'")))?;
        if !value.is_finite() {
            return Err(in_file(self.at(k, j), format!("{cell} is not a finite number")));
        }
        Ok(value * s.factor + s.offset)
    }

    /// Cell (`k`, `j`), `cell`, a timestamp, in seconds from the first sample's, `first_stamp`
    /// (nanoseconds, and whether it has a time zone).
    fn seconds_from_first(
        &self,
        k: usize,
        j: usize,
        cell: &str,
        first_stamp: Option<(i64, bool)>,
    ) -> Result<f64, Error> {
        let (ns, zoned) = parse_timestamp(cell).ok_or_else(|| {
            in_file(
                self.at(k, j),
                format!("'{cell}' is not an ISO 8601 timestamp like the first sample's '{}'", self.raw[0][j]),
            )
        })?;
        let (ns0, zoned0) = first_stamp.expect("the time column holds timestamps");
        if zoned != zoned0 {
            return Err(in_file(
                self.at(k, j),
                format!(
                    "'{cell}' {}, the first sample's '{}' {}; the timestamps must agree",
                    if zoned { "has a time zone" } else { "has no time zone" },
                    self.raw[0][j],
                    if zoned0 { "has one" } else { "has none" }
                ),
            ));
        }
        // nanoseconds as integers: no rounding in the difference of two long timestamps
        Ok((ns - ns0) as f64 * SECONDS_PER_NANOSECOND)
    }

    /// An error at the first sample whose `time` does not increase.
    fn check_time_increases(&self, time: &[f64]) -> Result<(), Error> {
        let time_j = self.time_j;
        for k in 1..time.len() {
            if time[k] <= time[k - 1] {
                let what = if time[k] == time[k - 1] { "repeats" } else { "is before" };
                return Err(in_file(
                    self.at(k, time_j),
                    format!(
                        "time {} {what} the previous sample's {} (line {}); time must increase",
                        self.raw[k][time_j],
                        self.raw[k - 1][time_j],
                        self.lines[k - 1]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Negates the columns `flips` (the velocity and the displacement together: one motion), each
/// noted; a flip of a column the file lacks is an error.
fn flip_columns(name: &str, data: &mut Channels, flips: &[Column], notes: &mut Vec<String>) -> Result<(), Error> {
    for &c in flips {
        let motion = [Column::VDamper, Column::XDamper];
        let negated: Vec<Column> = if motion.contains(&c) { motion.to_vec() } else { vec![c] };
        let mut done = Vec::new();
        for column in negated {
            if let Some(x) = data.get_mut(&column) {
                x.iter_mut().for_each(|v| *v = -*v);
                done.push(column.name());
            }
        }
        if done.is_empty() {
            return Err(in_file(Place::file(name), format!("--flip {}: the file has no such column", c.name())));
        }
        notes.push(format!(
            "{} negated (--flip {}): the file's sign convention is the other one",
            done.join(" and "),
            c.name()
        ));
    }
    Ok(())
}

/// Derives `v_damper` from `x_damper` where the file has no velocity (noted); whether it did.
fn derive_missing_velocity(time: &[f64], data: &mut Channels, notes: &mut Vec<String>) -> bool {
    if data.contains_key(&Column::VDamper) {
        return false;
    }
    let v = differentiate(time, &data[&Column::XDamper]);
    data.insert(Column::VDamper, v);
    notes.push(
        "v_damper derived from x_damper by central differences (second order, one-sided at the ends); \
         displacement noise is amplified by about 1/(sqrt(2)·dt)"
            .to_string(),
    );
    true
}

/// The samples' times and file lines, every channel of `data` resampled onto the uniform grid
/// where the sampling has gaps or jitter ([`uniform_grid`]), else as they are.
fn on_uniform_grid(
    time: Vec<f64>,
    lines: Vec<usize>,
    gaps: &[Gap],
    max_gap: usize,
    data: &mut Channels,
    notes: &mut Vec<String>,
) -> (Vec<f64>, Vec<usize>) {
    match uniform_grid(&time, &lines, gaps, max_gap, notes) {
        Some((grid, grid_lines)) => {
            for x in data.values_mut() {
                *x = interpolate(&time, x, &grid);
            }
            (grid, grid_lines)
        }
        None => (time, lines),
    }
}

/// The model's motion: a noisy velocity smoothed, then made to follow a measured displacement
/// ([`crate::motion::motion`]); its velocity replaces `data`'s.
fn model_motion(
    name: &str,
    time: &[f64],
    data: &mut Channels,
    chosen: &BTreeMap<Column, ColumnSource>,
    velocity_from_displacement: bool,
) -> Result<crate::motion::Motion, Error> {
    let mut m = crate::motion::motion(
        time,
        data.remove(&Column::VDamper),
        data.get(&Column::XDamper).map(Vec::as_slice),
        velocity_from_displacement,
    )
    .map_err(|e| {
        let v_column = chosen.get(&Column::VDamper).map_or("derived".to_string(), |c| format!("column {}", c.index));
        let x_column = chosen.get(&Column::XDamper).map_or(0, |c| c.index);
        e.context(format!("v_damper ({v_column}) and x_damper (column {x_column})")).at(Place::file(name))
    })?;
    if let Some(v) = m.v.take() {
        data.insert(Column::VDamper, v);
    }
    Ok(m)
}

/// An interval longer than this many median intervals is a gap (dropped samples).
pub const GAP_FACTOR: f64 = 1.5;
/// Intervals within this share of the median are uniform sampling.
pub const JITTER_TOLERANCE: f64 = 0.01;
/// Default of `max_gap`: the most missing samples in one gap that are interpolated.
pub const DEFAULT_MAX_GAP: usize = 5;

/// Median sample interval (the upper median for an even count).
fn median_interval(time: &[f64]) -> f64 {
    let mut dt: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    dt.sort_by(|a, b| a.total_cmp(b));
    dt.get(dt.len() / 2).copied().unwrap_or(f64::NAN)
}

/// A gap before sample `at`: about `missing` samples were dropped.
struct Gap {
    at: usize,
    missing: usize,
}

/// Every interval longer than [`GAP_FACTOR`] median intervals; one that lost more than `max_gap`
/// samples is an error (`where_(k)` names sample `k`).
fn gaps(time: &[f64], max_gap: usize, where_: impl Fn(usize) -> Place) -> Result<Vec<Gap>, Error> {
    let median = median_interval(time);
    let mut gaps = Vec::new();
    for k in 1..time.len() {
        let dt = time[k] - time[k - 1];
        if dt > GAP_FACTOR * median {
            let missing = ((dt / median).round() as usize).saturating_sub(1).max(1);
            if missing > max_gap {
                return Err(in_file(
                    where_(k),
                    format!(
                        "a gap of {:.6} s, about {missing} samples missing at the median interval {:.6} s; \
                         gaps of up to --max-gap {max_gap} samples are interpolated: cut the record at this line \
                         or raise --max-gap",
                        dt, median
                    ),
                ));
            }
            gaps.push(Gap { at: k, missing });
        }
    }
    Ok(gaps)
}

/// The uniform grid at the median interval, and the file line of the sample at or before each grid
/// time, when the sampling has gaps or jitter beyond [`JITTER_TOLERANCE`]; `None` when it is
/// uniform. Notes what it found and did.
fn uniform_grid(
    time: &[f64],
    lines: &[usize],
    gaps: &[Gap],
    max_gap: usize,
    notes: &mut Vec<String>,
) -> Option<(Vec<f64>, Vec<usize>)> {
    let median = median_interval(time);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for k in 1..time.len() {
        if gaps.iter().all(|g| g.at != k) {
            lo = lo.min(time[k] - time[k - 1]);
            hi = hi.max(time[k] - time[k - 1]);
        }
    }
    let jitter = (hi - median).max(median - lo) / median;
    if gaps.is_empty() && jitter <= JITTER_TOLERANCE {
        return None;
    }
    if jitter > JITTER_TOLERANCE {
        notes.push(format!(
            "sampling is not uniform: intervals {:.4} to {:.4} ms, {:.1} % from the median {:.4} ms (tolerance {} %)",
            lo * 1e3,
            hi * 1e3,
            100.0 * jitter,
            median * 1e3,
            100.0 * JITTER_TOLERANCE
        ));
    }
    if !gaps.is_empty() {
        let list: Vec<String> = gaps
            .iter()
            .map(|g| {
                format!(
                    "t = {:.4} to {:.4} s between lines {} and {} ({} missing)",
                    time[g.at - 1],
                    time[g.at],
                    lines[g.at - 1],
                    lines[g.at],
                    g.missing
                )
            })
            .collect();
        notes.push(format!(
            "{} gap(s) in the sampling, each of at most --max-gap {max_gap} samples, bridged by linear interpolation: {}",
            gaps.len(),
            list.join("; ")
        ));
    }
    let t0 = time[0];
    // the small allowance keeps the last sample when the span is a whole number of intervals
    let n = ((time[time.len() - 1] - t0) / median + 1e-6).floor() as usize + 1;
    let grid: Vec<f64> = (0..n).map(|i| t0 + i as f64 * median).collect();
    let mut grid_lines = Vec::with_capacity(n);
    let mut k = 0;
    for &t in &grid {
        while k + 1 < time.len() && time[k + 1] <= t {
            k += 1;
        }
        grid_lines.push(lines[k]);
    }
    notes.push(format!(
        "all channels resampled by linear interpolation onto a uniform grid of {:.4} ms ({:.1} Hz): {n} samples \
         from {} measured; a sample's line is that of the measured sample at or before it",
        median * 1e3,
        1.0 / median,
        time.len()
    ));
    Some((grid, grid_lines))
}

/// `x(t)` linearly interpolated at each of `grid` (within `t[0] ..= t[last]`).
fn interpolate(t: &[f64], x: &[f64], grid: &[f64]) -> Vec<f64> {
    let mut k = 0;
    grid.iter()
        .map(|&g| {
            while k + 2 < t.len() && t[k + 1] <= g {
                k += 1;
            }
            let w = ((g - t[k]) / (t[k + 1] - t[k])).clamp(0.0, 1.0);
            x[k] + w * (x[k + 1] - x[k])
        })
        .collect()
}

/// Nanoseconds since 1970 of an ISO 8601 timestamp, and whether it carried a zone (`Z` or an
/// offset); a decimal comma before the fraction (allowed by ISO 8601) is read too.
fn parse_timestamp(cell: &str) -> Option<(i64, bool)> {
    use chrono::{DateTime, NaiveDateTime};
    let text = cell.replace(',', ".");
    for format in ["%Y-%m-%dT%H:%M:%S%.f", "%Y-%m-%d %H:%M:%S%.f"] {
        if let Ok(t) = NaiveDateTime::parse_from_str(&text, format) {
            return t.and_utc().timestamp_nanos_opt().map(|ns| (ns, false));
        }
        if let Ok(t) = DateTime::parse_from_str(&text, &format!("{format}%#z")) {
            return t.timestamp_nanos_opt().map(|ns| (ns, true));
        }
    }
    None
}

/// Whether the numbers are written with a decimal comma, from the cells of the columns used
/// (`numeric(j)`: column `j` holds numbers); then the note to record. An error when it is ambiguous.
fn decimal_comma(
    raw: &[Vec<&str>],
    numeric: &dyn Fn(usize) -> bool,
    where_: &dyn Fn(usize, usize) -> Place,
    delimiter: u8,
) -> Result<Option<String>, Error> {
    let cells = || {
        raw.iter().enumerate().flat_map(move |(k, row)| {
            row.iter().enumerate().filter(move |(j, _)| numeric(*j)).map(move |(j, c)| (k, j, *c))
        })
    };
    let Some((kc, jc, with_comma)) = cells().find(|(_, _, c)| c.contains(',')) else {
        return Ok(None);
    };
    if let Some((kp, jp, with_point)) = cells().find(|(_, _, c)| c.contains('.')) {
        return Err(in_file(
            where_(kc, jc),
            format!(
                "'{with_comma}' has a comma, but {} has '{with_point}' with a point: the numbers must use one \
                 decimal separator, and no thousands separators",
                where_(kp, jp)
            ),
        ));
    }
    if delimiter == b',' {
        // "1,500" may be 1.5 or 1500; only a comma that cannot separate thousands ("1,5") decides.
        let thousands = |c: &str| {
            let mut groups = c.trim_start_matches(['+', '-']).split(',');
            let first = groups.next().unwrap_or("");
            (1..=3).contains(&first.len())
                && first.bytes().all(|b| b.is_ascii_digit())
                && groups.all(|g| g.len() == 3 && g.bytes().all(|b| b.is_ascii_digit()))
        };
        if cells().filter(|(_, _, c)| c.contains(',')).all(|(_, _, c)| thousands(c)) {
            return Err(in_file(
                where_(kc, jc),
                format!(
                    "'{with_comma}' in a comma-separated file may be a decimal comma or a thousands separator; \
                     export the numbers without thousands separators, or with ';' as the delimiter"
                ),
            ));
        }
    }
    Ok(Some(format!(
        "numbers are written with a decimal comma (first: '{with_comma}', {}); read as decimal points",
        where_(kc, jc)
    )))
}

/// One data line's cells, trimmed and unquoted.
struct Row {
    line: usize,
    cells: Vec<String>,
}

/// The header and the data rows of a CSV file, with their line numbers.
struct Table {
    delimiter: u8,
    header_line: usize,
    header: Vec<String>,
    rows: Vec<Row>,
}

impl Table {
    /// Reads `bytes` (no byte-order mark): `#` lines skipped, empty lines allowed before the header
    /// and at the end, every cell checked to be UTF-8.
    fn read(name: &str, bytes: &[u8]) -> Result<Table, Error> {
        let header_text = bytes
            .split(|&b| b == b'\n')
            .map(|l| l.trim_ascii())
            .find(|l| !l.is_empty() && !l.starts_with(b"#"))
            .ok_or_else(|| in_file(Place::line(name, 1), "no header line (the file is empty or all comments)"))?;
        let delimiter = detect_delimiter(header_text);
        let newlines: Vec<usize> = bytes.iter().enumerate().filter(|(_, &b)| b == b'\n').map(|(i, _)| i).collect();
        let line_of = |byte: usize| 1 + newlines.partition_point(|&n| n < byte);
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .delimiter(delimiter)
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_reader(bytes);
        let mut header: Option<(usize, Vec<String>)> = None;
        let mut rows = Vec::new();
        // a blank line seen after the header: an error if data follows it
        let mut blank: Option<usize> = None;
        let mut record = csv::ByteRecord::new();
        while reader.read_byte_record(&mut record).map_err(|source| Error::Csv { file: name.to_string(), source })? {
            let (start, empty) = skip_to_record(bytes, record.position().map_or(0, |p| p.byte() as usize));
            let line = line_of(start);
            let mut cells = Vec::with_capacity(record.len());
            for (j, field) in record.iter().enumerate() {
                let text = std::str::from_utf8(field).map_err(|e| {
                    let column = match &header {
                        Some((_, h)) if j < h.len() => format!("column {} ('{}')", j + 1, h[j]),
                        _ => format!("column {}", j + 1),
                    };
                    in_file(
                        Place::field(name, line, column),
                        format!(
                            "not UTF-8: byte 0x{:02X} in '{}'. The file is probably in a Windows code page \
                             (cp1252, latin-1); convert it to UTF-8, e.g. iconv -f cp1252 -t utf-8 {name} > \
                             converted.csv",
                            field[e.valid_up_to()],
                            String::from_utf8_lossy(field)
                        ),
                    )
                })?;
                cells.push(text.to_string());
            }
            let is_blank = cells.iter().all(|c| c.is_empty()) && cells.len() == 1;
            if cells.first().is_some_and(|c| c.starts_with('#')) {
                continue; // an indented comment
            }
            if header.is_none() {
                if !is_blank {
                    header = Some((line, cells));
                }
                continue;
            }
            if let Some(empty) = empty {
                blank.get_or_insert(line_of(empty));
            }
            if is_blank {
                blank.get_or_insert(line);
                continue;
            }
            if let Some(b) = blank {
                return Err(in_file(Place::line(name, b), "empty line inside the data"));
            }
            rows.push(Row { line, cells });
        }
        let (header_line, header) = header.expect("the header line was found above");
        Ok(Table { delimiter, header_line, header, rows })
    }
}

/// csv reports a record's position where it began looking: before the empty and `#` lines it
/// skipped, and at the `\n` of the previous line's `\r\n`. Returns the record's first byte and the
/// first empty line skipped.
fn skip_to_record(bytes: &[u8], mut p: usize) -> (usize, Option<usize>) {
    if p > 0 && bytes.get(p) == Some(&b'\n') && bytes[p - 1] == b'\r' {
        p += 1;
    }
    let mut empty = None;
    while p < bytes.len() {
        let end = bytes[p..].iter().position(|&b| b == b'\n').map_or(bytes.len(), |i| p + i);
        let line = &bytes[p..end];
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        if line.is_empty() {
            empty.get_or_insert(p);
        } else if !line.starts_with(b"#") {
            break;
        }
        p = end + 1;
    }
    (p, empty)
}

/// The header's most frequent of `,` `;` tab outside quotes (the later on a tie); `,` when it has none.
fn detect_delimiter(header: &[u8]) -> u8 {
    let mut counts = [(0usize, b','), (0, b';'), (0, b'\t')];
    let mut quoted = false;
    for &b in header {
        if b == b'"' {
            quoted = !quoted;
        } else if !quoted {
            if let Some(c) = counts.iter_mut().find(|(_, d)| *d == b) {
                c.0 += 1;
            }
        }
    }
    counts.iter().max_by_key(|(c, _)| *c).map(|&(c, d)| if c == 0 { b',' } else { d }).unwrap_or(b',')
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
        let m = Measurement::parse("a.csv", csv.as_bytes(), &maps, DEFAULT_MAX_GAP).unwrap();
        assert_eq!(m.time, vec![0.0, 1e-3, 2e-3]);
        assert_eq!(m.get(Column::VDamper).unwrap(), &[0.0, 0.1, 0.2]);
        assert_eq!(m.get(Column::FDemand).unwrap(), &[0.0, 1e3, 2e3]);
        assert_eq!(m.ignored, vec!["extra".to_string()]);
        assert_eq!(m.lines, vec![3, 4, 5]);
    }
}
