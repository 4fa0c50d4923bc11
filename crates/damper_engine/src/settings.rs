//! Several settings of one adjustable damper in one calibration: records grouped by the setting
//! they were taken at (a label such as "rebound 6 clicks"), the parameters an adjuster moves
//! fitted once per setting, every other parameter once for all records.
//!
//! ```text
//! θ = (θ_shared, θ_adjuster[setting 1], …, θ_adjuster[setting S])
//! record r at setting s(r) runs with θ_shared and θ_adjuster[s(r)]
//! ```
//! A dyno campaign sweeps an adjuster over its clicks with the rest of the damper unchanged: the
//! shared parameters (gas, blow-offs, seals, air, mount) see every record, which pins them better
//! than any one setting, and the adjuster's value per setting is its click map.

use crate::error::Error;
use crate::parameters::set_real;
use semi_active_damper::physics::params::Parameters;
use std::path::{Path, PathBuf};

/// One value of a fit vector: a parameter shared by every record, or one setting's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    pub name: &'static str,
    /// The setting (index into [`Settings::labels`]) it belongs to; None: shared.
    pub setting: Option<usize>,
}

impl Entry {
    /// Whether a record at `setting` runs with this value.
    pub fn applies_to(&self, setting: usize) -> bool {
        self.setting.is_none_or(|s| s == setting)
    }
}

/// The settings of a calibration's records.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Settings {
    /// One label per setting, in the order of the records.
    pub labels: Vec<String>,
    /// The setting of each record (index into `labels`).
    pub of_record: Vec<usize>,
}

impl Settings {
    /// Groups `records` by `given` (label, records at that setting); a record named in none is a
    /// setting of its own, labelled by its file stem. Errors name the record that is not among
    /// the calibration's records or is given two settings.
    pub fn group(records: &[PathBuf], given: &[(String, Vec<PathBuf>)]) -> Result<Settings, Error> {
        let mut label_of: Vec<Option<&str>> = vec![None; records.len()];
        for (label, paths) in given {
            for path in paths {
                let i = records
                    .iter()
                    .position(|r| same_file(r, path))
                    .ok_or_else(|| Error::SettingStranger { label: label.clone(), path: path.clone() })?;
                if let Some(other) = label_of[i] {
                    return Err(Error::SettingTwice {
                        path: path.clone(),
                        first: other.to_string(),
                        second: label.clone(),
                    });
                }
                label_of[i] = Some(label);
            }
        }
        let mut labels: Vec<String> = Vec::new();
        let mut of_record = Vec::with_capacity(records.len());
        for (path, label) in records.iter().zip(label_of) {
            let label = label.map_or_else(|| stem(path), str::to_string);
            let i = labels.iter().position(|l| *l == label).unwrap_or_else(|| {
                labels.push(label);
                labels.len() - 1
            });
            of_record.push(i);
        }
        Ok(Settings { labels, of_record })
    }

    /// The fit's entries: `shared` once, then each of `per_setting` once per setting.
    pub fn entries(&self, shared: &[&'static str], per_setting: &[&'static str]) -> Vec<Entry> {
        let mut out: Vec<Entry> = shared.iter().map(|&name| Entry { name, setting: None }).collect();
        for s in 0..self.labels.len() {
            out.extend(per_setting.iter().map(|&name| Entry { name, setting: Some(s) }));
        }
        out
    }

    /// How an entry is named in reports: `A_bleed_reb[rebound 6 clicks]` for a setting's own.
    pub fn display(&self, e: &Entry) -> String {
        match e.setting {
            Some(s) => format!("{}[{}]", e.name, self.labels[s]),
            None => e.name.to_string(),
        }
    }
}

/// Sets on `p` the values `x` of the entries that apply to `setting`.
pub fn apply(p: &mut Parameters, entries: &[Entry], x: &[f64], setting: usize) -> Result<(), Error> {
    for (e, &v) in entries.iter().zip(x) {
        if e.applies_to(setting) {
            set_real(p, e.name, v)?;
        }
    }
    Ok(())
}

/// The file stem of a record, its setting's label when none is given.
fn stem(path: &Path) -> String {
    path.file_stem().map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned())
}

/// The same record, named the same way or resolving to the same file.
fn same_file(a: &Path, b: &Path) -> bool {
    a == b || matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(names: &[&str]) -> Vec<PathBuf> {
        names.iter().map(PathBuf::from).collect()
    }

    #[test]
    fn records_group_by_their_given_setting_and_the_rest_stand_alone() {
        let records = paths(&["a/gas.csv", "a/click0.csv", "a/click6.csv", "a/sweep6.csv"]);
        let given = vec![("6 clicks".to_string(), paths(&["a/click6.csv", "a/sweep6.csv"]))];
        let s = Settings::group(&records, &given).unwrap();
        assert_eq!(s.labels, ["gas", "click0", "6 clicks"]);
        assert_eq!(s.of_record, [0, 1, 2, 2]);
        let e = s.entries(&["p_reservoir0"], &["A_bleed_reb"]);
        assert_eq!(e.len(), 4);
        assert!(e[0].applies_to(2) && e[3].applies_to(2) && !e[3].applies_to(1));
        assert_eq!(s.display(&e[3]), "A_bleed_reb[6 clicks]");
    }

    #[test]
    fn a_setting_naming_a_stranger_or_a_record_twice_is_refused() {
        let records = paths(&["a.csv", "b.csv"]);
        let err = Settings::group(&records, &[("x".into(), paths(&["c.csv"]))]).unwrap_err().to_string();
        assert!(err.contains("c.csv is not one of the records"), "{err}");
        let twice = vec![("x".into(), paths(&["a.csv"])), ("y".into(), paths(&["a.csv"]))];
        let err = Settings::group(&records, &twice).unwrap_err().to_string();
        assert!(err.contains("two settings, x and y"), "{err}");
    }

    #[test]
    fn a_setting_s_own_value_reaches_only_its_records() {
        let records = paths(&["a.csv", "b.csv"]);
        let s = Settings::group(&records, &[]).unwrap();
        let e = s.entries(&["F_coulomb"], &["A_bleed_reb"]);
        let x = [40.0, 1e-6, 2e-6];
        let mut p = Parameters::default();
        apply(&mut p, &e, &x, 1).unwrap();
        assert_eq!((p.f_coulomb, p.a_bleed_reb), (40.0, 2e-6));
        apply(&mut p, &e, &x, 0).unwrap();
        assert_eq!(p.a_bleed_reb, 1e-6);
    }
}
