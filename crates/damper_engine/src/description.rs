//! A damper described from its datasheet: a TOML file (`damper init` writes the documented
//! template, [`TEMPLATE`]) whose keys name what a datasheet gives (bore, rod, stroke, gas
//! pre-charge and volume, the valves' data) in any unit, mapped onto the model's parameters.
//! Every problem names the file, the line and the key.

use crate::error::{Error, Place};
use crate::parameters::{lookup, set_parameter, Param};
use crate::quantity::{parse_quantity, parse_unit, Dimension};
use semi_active_damper::physics::params::Parameters;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

/// The documented template `damper init` writes.
pub const TEMPLATE: &str = include_str!("damper_template.toml");

/// What a damper is, for the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// No proportional valve: the valve held shut (`control_mode` 2), the passive valves of the
    /// description its valves.
    Passive,
    /// The paper's semi-active damper with its controller: the model's defaults.
    SemiActive,
}

/// How a key's value becomes its parameter's.
#[derive(Clone, Copy, Debug)]
enum Convert {
    /// The same quantity.
    Same,
    /// Half of it (a full stroke to the half stroke).
    Half,
    /// A diameter to a circle's area.
    CircleArea,
}

/// A key of the description: its section, name, parameter and conversion, and the switch it
/// turns on when given (the part exists).
struct Key {
    section: &'static str,
    key: &'static str,
    parameter: &'static str,
    convert: Convert,
    switch: Option<&'static str>,
}

const fn key(section: &'static str, key: &'static str, parameter: &'static str) -> Key {
    Key { section, key, parameter, convert: Convert::Same, switch: None }
}

const fn part(section: &'static str, name: &'static str, parameter: &'static str, switch: &'static str) -> Key {
    Key { section, key: name, parameter, convert: Convert::Same, switch: Some(switch) }
}

/// Every key the description may hold (the template lists them, with their meaning).
const KEYS: [Key; 38] = [
    key("cylinder", "piston_diameter", "D_piston"),
    key("cylinder", "rod_diameter", "D_rod"),
    Key { convert: Convert::Half, ..key("cylinder", "stroke", "L_half_stroke") },
    key("cylinder", "dead_length", "L_dead"),
    key("cylinder", "extra_volume", "V_hose"),
    key("gas", "precharge", "p_reservoir0"),
    key("gas", "volume", "V_gas0"),
    key("gas", "polytropic_index", "n_polytropic"),
    key("oil", "density", "rho"),
    key("oil", "bulk_modulus", "beta_oil"),
    key("oil", "air_fraction", "air_fraction"),
    key("oil", "viscosity_temperature_coefficient", "visc_temp_coeff"),
    key("oil", "reference_temperature", "T_ref"),
    part("oil", "gas_solubility", "gas_solubility", "effect_gas_release"),
    part("oil", "saturation_pressure", "p_saturation", "effect_gas_release"),
    part("rebound_valve", "laminar_bleed", "G_bleed_reb", "effect_rebound_valve"),
    part("rebound_valve", "bleed_area", "A_bleed_reb", "effect_rebound_valve"),
    Key {
        convert: Convert::CircleArea,
        ..part("rebound_valve", "bleed_diameter", "A_bleed_reb", "effect_rebound_valve")
    },
    part("rebound_valve", "blow_off_pressure", "p_open_reb", "effect_rebound_valve"),
    part("rebound_valve", "blow_off_area_per_pressure", "k_open_reb", "effect_rebound_valve"),
    part("rebound_valve", "blow_off_area", "A_open_reb", "effect_rebound_valve"),
    part("rebound_valve", "discharge_coefficient", "Cd_passive", "effect_rebound_valve"),
    part("compression_valve", "laminar_bleed", "G_bleed_comp", "effect_compression_valve"),
    part("compression_valve", "bleed_area", "A_bleed_comp", "effect_compression_valve"),
    Key {
        convert: Convert::CircleArea,
        ..part("compression_valve", "bleed_diameter", "A_bleed_comp", "effect_compression_valve")
    },
    part("compression_valve", "blow_off_pressure", "p_open_comp", "effect_compression_valve"),
    part("compression_valve", "blow_off_area_per_pressure", "k_open_comp", "effect_compression_valve"),
    part("compression_valve", "blow_off_area", "A_open_comp", "effect_compression_valve"),
    key("check_valves", "area", "A_cv_max"),
    key("check_valves", "cracking_pressure", "p_cv_crack"),
    key("check_valves", "full_open_pressure", "p_cv_full"),
    key("mount", "stiffness", "k1_mount"),
    key("mount", "cubic_stiffness", "k3_mount"),
    part("seals", "friction", "F_coulomb", "effect_seal_friction"),
    key("seals", "friction_velocity", "v_friction"),
    part("seals", "viscous_friction", "c_viscous", "effect_viscous_friction"),
    part("end_stops", "free_stroke", "x_end_stop", "effect_end_stops"),
    part("end_stops", "stiffness", "k_end_stop", "effect_end_stops"),
];

/// The sections of [`KEYS`] and `[parameters]`.
fn sections() -> Vec<&'static str> {
    let mut out: Vec<&'static str> = KEYS.iter().map(|k| k.section).collect();
    out.dedup();
    out.push("parameters");
    out
}

/// One setting the description makes, and where it comes from.
#[derive(Clone, Debug)]
pub struct Setting {
    /// The FMU parameter.
    pub parameter: String,
    /// Its value, as `set_parameter` reads it (SI).
    pub value: String,
    /// `FILE, line N, [section] key`.
    pub source: String,
}

/// A damper description, read and checked.
#[derive(Clone, Debug)]
pub struct Description {
    pub path: String,
    pub name: String,
    pub kind: Kind,
    /// In file order: what the kind sets first, then each key's parameter and the switches of
    /// the parts given.
    pub settings: Vec<Setting>,
}

/// The line (1-based) of each `[section] key` and of each `[section]` header (key "").
fn lines(text: &str) -> BTreeMap<(String, String), usize> {
    let mut out = BTreeMap::new();
    let mut section = String::new();
    for (i, line) in text.lines().enumerate() {
        let l = line.trim();
        if let Some(name) = l.strip_prefix('[').and_then(|r| r.split(']').next()) {
            section = name.trim().to_string();
            out.insert((section.clone(), String::new()), i + 1);
        } else if let Some((k, _)) = l.split_once('=').filter(|_| !l.starts_with('#')) {
            out.entry((section.clone(), k.trim().trim_matches('"').to_string())).or_insert(i + 1);
        }
    }
    out
}

/// The closest of `names` to `name`, for "did you mean".
fn closest<'a>(name: &str, names: impl Iterator<Item = &'a str>) -> String {
    let distance = |a: &str, b: &str| crate::parameters::distance(a, b);
    names
        .map(|n| (distance(n, name), n))
        .filter(|(d, _)| *d <= 4)
        .min()
        .map_or(String::new(), |(_, n)| format!("; did you mean {n}?"))
}

impl Description {
    /// Reads and checks a description file.
    pub fn read(path: &Path) -> Result<Description, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
        Description::parse(&path.display().to_string(), &text)
    }

    /// Parses description text; `name` is used in messages.
    pub fn parse(name: &str, text: &str) -> Result<Description, Error> {
        let table: toml::Table = text.parse().map_err(|source: toml::de::Error| {
            let line = source.span().map_or(0, |s| text[..s.start.min(text.len())].lines().count().max(1));
            Error::Toml { file: name.to_string(), line, source: Box::new(source) }
        })?;
        let at = lines(text);
        let line = |section: &str, key: &str| at.get(&(section.to_string(), key.to_string())).copied().unwrap_or(0);
        let mut d =
            Description { path: name.into(), name: String::new(), kind: Kind::SemiActive, settings: Vec::new() };
        let known = sections();
        for (section, value) in &table {
            match (section.as_str(), value) {
                ("kind", toml::Value::String(k)) => {
                    d.kind = match k.as_str() {
                        "passive" => Kind::Passive,
                        "semi_active" => Kind::SemiActive,
                        other => {
                            return Err(Error::InFile {
                                at: Place::field(name, line("", "kind"), "kind"),
                                problem: format!("'{other}' is not a kind (passive or semi_active)"),
                            })
                        }
                    }
                }
                ("name", toml::Value::String(n)) => d.name = n.clone(),
                (s, toml::Value::Table(_)) if known.contains(&s) => {}
                (s, toml::Value::Table(_)) => {
                    return Err(Error::InFile {
                        at: Place::line(name, line(s, "")),
                        problem: format!(
                            "unknown section [{s}]{} (sections: {})",
                            closest(s, known.iter().copied()),
                            known.join(", ")
                        ),
                    })
                }
                (k, _) => {
                    return Err(Error::InFile {
                        at: Place::line(name, line("", k)),
                        problem: format!("unknown top-level key '{k}' (kind, name, or a section)"),
                    })
                }
            }
        }
        d.settings.extend(kind_settings(d.kind, name));
        for (section, value) in &table {
            let toml::Value::Table(entries) = value else { continue };
            for (k, v) in entries {
                let place = Place::field(name, line(section, k), format!("[{section}] {k}"));
                d.settings.extend(setting(section, k, v, &place)?);
            }
        }
        Ok(d)
    }

    /// Applies the settings to `p`, in order.
    pub fn apply(&self, p: &mut Parameters) -> Result<(), Error> {
        for s in &self.settings {
            set_parameter(p, &s.parameter, &s.value).map_err(|e| e.context(&s.source))?;
        }
        p.validate().map_err(|source| Error::InvalidDamper { path: self.path.clone(), source })
    }
}

/// What a kind sets before the keys.
fn kind_settings(kind: Kind, name: &str) -> Vec<Setting> {
    let source = format!("{name}, kind = \"passive\"");
    let set = |parameter: &str, value: &str| Setting {
        parameter: parameter.into(),
        value: value.into(),
        source: source.clone(),
    };
    match kind {
        Kind::SemiActive => Vec::new(),
        // no proportional valve: held shut without leakage or relief, no controller (physics.md §4.6)
        Kind::Passive => vec![
            set("control_mode", "2"),
            set("x_spool_start", "0"),
            set("A_valve_leak", "0"),
            set("A_relief", "0"),
            set("effect_flow_forces", "false"),
            set("effect_amplifier_delay", "false"),
        ],
    }
}

/// The settings of `[section] key = value`.
fn setting(section: &str, key: &str, value: &toml::Value, place: &Place) -> Result<Vec<Setting>, Error> {
    let at = |parameter: &str, value: String| Setting { parameter: parameter.into(), value, source: place.to_string() };
    let problem = |problem: String| Error::InFile { at: place.clone(), problem };
    if section == "parameters" {
        let param = lookup(key).map_err(|e| e.at(place.clone()))?;
        let text = match (param, value) {
            (Param::Real(v), _) => format!("{}", si_value(value, v.unit(), place, Convert::Same)?),
            (_, toml::Value::Boolean(b)) => b.to_string(),
            (_, toml::Value::Integer(i)) => i.to_string(),
            (_, other) => return Err(problem(format!("{other} is not a value of {key}"))),
        };
        return Ok(vec![at(key, text)]);
    }
    let Some(k) = KEYS.iter().find(|k| k.section == section && k.key == key) else {
        let keys = KEYS.iter().filter(|k| k.section == section).map(|k| k.key);
        let listed: Vec<&str> = KEYS.iter().filter(|k| k.section == section).map(|k| k.key).collect();
        return Err(problem(format!("unknown key{} (keys of [{section}]: {})", closest(key, keys), listed.join(", "))));
    };
    let unit = match lookup(k.parameter).map_err(|e| e.at(place.clone()))? {
        Param::Real(v) => v.unit(),
        _ => unreachable!("the description's keys are Real parameters"),
    };
    let x = si_value(value, unit, place, k.convert)?;
    let mut out = vec![at(k.parameter, format!("{x}"))];
    // a part given with its size zero is absent (seal friction "0 N")
    if let Some(switch) = k.switch.filter(|_| x > 0.0 || !matches!(k.key, "friction" | "viscous_friction")) {
        out.push(at(switch, "true".into()));
    }
    Ok(out)
}

/// The SI value of `value` (a number in SI, or a string with a unit) for a parameter in `unit`,
/// through `convert`; the unit's dimension must be the parameter's (a length for a diameter).
fn si_value(value: &toml::Value, unit: &str, place: &Place, convert: Convert) -> Result<f64, Error> {
    let problem = |problem: String| Error::InFile { at: place.clone(), problem };
    let target =
        parse_unit(unit).map_err(|e| e.context(format!("the model's unit {unit}")).at(place.clone()))?.dimension;
    let wanted = match convert {
        Convert::CircleArea => parse_unit("m").expect("metre").dimension,
        _ => target,
    };
    let (x, dimension) = match value {
        toml::Value::Float(x) => (*x, wanted),
        toml::Value::Integer(i) => (*i as f64, wanted),
        toml::Value::String(s) => parse_quantity(s).map_err(|e| e.at(place.clone()))?,
        other => return Err(problem(format!("{other} is not a quantity (a number in SI, or \"36 mm\")"))),
    };
    if dimension != wanted {
        return Err(problem(format!(
            "{value} is {} but {} is wanted{}",
            describe(dimension),
            describe(wanted),
            if matches!(convert, Convert::CircleArea) { " (a diameter)" } else { "" }
        )));
    }
    Ok(match convert {
        Convert::Same => x,
        Convert::Half => 0.5 * x,
        Convert::CircleArea => PI / 4.0 * x * x,
    })
}

fn describe(d: Dimension) -> String {
    format!("of dimension {d}")
}

/// Writes `TEMPLATE` to `path`, refusing to overwrite a file.
pub fn write_template(path: &Path) -> Result<(), Error> {
    if path.exists() {
        return Err(Error::Exists { path: path.to_path_buf() });
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| Error::CreateDir { path: dir.to_path_buf(), source })?;
    }
    std::fs::write(path, TEMPLATE).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn applied(text: &str) -> Result<Parameters, Error> {
        let mut p = Parameters::default();
        Description::parse("d.toml", text)?.apply(&mut p)?;
        Ok(p)
    }

    #[test]
    fn the_template_describes_a_valid_passive_damper() {
        let p = applied(TEMPLATE).unwrap();
        assert_eq!(p.control_mode, 2);
        assert_eq!(p.d_piston, 0.036);
        assert!((p.l_half_stroke - 0.05).abs() < 1e-15);
        assert!((p.a_bleed_reb - 0.6e-6).abs() < 1e-18);
        assert_eq!(p.p_open_reb, 12e5);
        assert!((p.t_ref - 293.15).abs() < 1e-12);
        assert!(p.effect_rebound_valve && p.effect_compression_valve && p.effect_end_stops && p.effect_seal_friction);
        assert!(!p.effect_flow_forces && !p.effect_viscous_friction);
    }

    #[test]
    fn a_diameter_gives_an_area() {
        let p = applied("[rebound_valve]\nbleed_diameter = \"1 mm\"\n").unwrap();
        assert!((p.a_bleed_reb - PI / 4.0 * 1e-6).abs() < 1e-18);
        assert!(p.effect_rebound_valve);
    }

    #[test]
    fn a_saturation_pressure_lets_gas_out_of_solution() {
        assert!(!applied(TEMPLATE).unwrap().effect_gas_release);
        let p = applied("[oil]\nsaturation_pressure = \"8 bar\"\n").unwrap();
        assert!(p.effect_gas_release);
        assert_eq!((p.p_saturation, p.gas_solubility), (8e5, Parameters::default().gas_solubility));
    }

    #[test]
    fn every_problem_names_the_file_the_line_and_the_key() {
        let cases = [
            ("[cylinder]\npiston_diameter = \"36 bar\"\n", "d.toml, line 2, [cylinder] piston_diameter"),
            ("[cylinder]\npiston_diameter = \"36 bar\"\n", "but of dimension m is wanted"),
            ("[cylinder]\npiston_diamter = \"36 mm\"\n", "did you mean piston_diameter?"),
            ("[cylindre]\n", "line 1: unknown section [cylindre]; did you mean cylinder?"),
            ("kind = \"active\"\n", "line 1, kind: 'active' is not a kind"),
            ("[gas]\nprecharge = \"8 furlong\"\n", "line 2, [gas] precharge: unknown unit 'furlong'"),
            ("[parameters]\nair_fracton = 0.01\n", "did you mean air_fraction?"),
            ("[parameters]\nair_fraction = 0.9\n", "out of the model's range"),
            ("[cylinder]\nrod_diameter = \"80 mm\"\n", "D_rod must be smaller than D_piston"),
            ("[cylinder\n", "d.toml, line 1: not TOML"),
        ];
        for (text, expected) in cases {
            let e = applied(text).unwrap_err().to_string();
            assert!(e.contains(expected), "{text:?}: {e}");
        }
    }
}
