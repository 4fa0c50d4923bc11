//! Model parameters by their FMU names (`--set NAME=VALUE`), and the effect catalog's switches
//! (`--with KEY`, `--without KEY`, `--effect KEY[=VALUE]`).
//!
//! Everything goes through the enums generated from `modelDescription.xml`, so a name the XML does
//! not have is an error here, not a silently ignored setting, and the XML's min/max are checked.

use crate::error::Error;
use semi_active_damper::model_description::{BooleanVar, Causality, IntegerVar, RealVar};
use semi_active_damper::physics::params::Parameters;
use std::fmt;

/// A parameter's value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Real(x) => write!(f, "{x}"),
            Value::Integer(i) => write!(f, "{i}"),
            Value::Boolean(b) => write!(f, "{b}"),
        }
    }
}

/// A parameter of the model, by kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    Real(RealVar),
    Integer(IntegerVar),
    Boolean(BooleanVar),
}

impl Param {
    pub fn name(self) -> &'static str {
        match self {
            Param::Real(v) => v.name(),
            Param::Integer(v) => v.name(),
            Param::Boolean(v) => v.name(),
        }
    }
}

/// Every parameter name of the model.
pub fn parameter_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = Vec::new();
    names.extend(RealVar::ALL.iter().filter(|v| v.causality() == Causality::Parameter).map(|v| v.name()));
    names.extend(IntegerVar::ALL.iter().filter(|v| v.causality() == Causality::Parameter).map(|v| v.name()));
    names.extend(BooleanVar::ALL.iter().filter(|v| v.causality() == Causality::Parameter).map(|v| v.name()));
    names
}

/// Looks up a parameter by its FMU name; the error names the closest names.
pub fn lookup(name: &str) -> Result<Param, Error> {
    if let Some(v) = RealVar::ALL.into_iter().find(|v| v.name() == name) {
        if v.causality() != Causality::Parameter {
            return Err(Error::NotAParameter { name: name.to_string(), causality: v.causality() });
        }
        return Ok(Param::Real(v));
    }
    if let Some(v) = IntegerVar::ALL.into_iter().find(|v| v.name() == name) {
        return Ok(Param::Integer(v));
    }
    if let Some(v) = BooleanVar::ALL.into_iter().find(|v| v.name() == name) {
        return Ok(Param::Boolean(v));
    }
    let mut close: Vec<(usize, &'static str)> =
        parameter_names().into_iter().map(|n| (distance(&n.to_lowercase(), &name.to_lowercase()), n)).collect();
    close.sort();
    let did_you_mean: Vec<&'static str> = close.iter().take(3).filter(|(d, _)| *d <= 4).map(|(_, n)| *n).collect();
    Err(Error::UnknownParameter { name: name.to_string(), did_you_mean, parameters: close.len() })
}

/// The value of a parameter.
pub fn get_parameter(p: &Parameters, name: &str) -> Result<Value, Error> {
    let mut q = *p;
    Ok(match lookup(name)? {
        Param::Real(v) => Value::Real(*q.real_mut(v).expect("parameter")),
        Param::Integer(v) => Value::Integer(*q.integer_mut(v).expect("parameter")),
        Param::Boolean(v) => Value::Boolean(*q.boolean_mut(v).expect("parameter")),
    })
}

/// A Real parameter's value (as [`real`]).
pub fn get_real(p: &Parameters, name: &str) -> Result<f64, Error> {
    real(p, name)
}

/// A Real parameter's value.
pub fn real(p: &Parameters, name: &str) -> Result<f64, Error> {
    match get_parameter(p, name)? {
        Value::Real(x) => Ok(x),
        other => Err(Error::NotOfKind { name: name.to_string(), kind: "Real parameter", is: Some(other.to_string()) }),
    }
}

/// Sets a parameter from text (`0.04`, `3e-3`, `true`/`on`/`1`), checking the XML's range.
pub fn set_parameter(p: &mut Parameters, name: &str, text: &str) -> Result<(), Error> {
    let t = text.trim();
    match lookup(name)? {
        Param::Real(v) => {
            let x: f64 = t.parse().map_err(|_| bad_value(name, text, "not a number"))?;
            set_real_checked(p, v, x)
        }
        Param::Integer(v) => {
            let x: i32 = t.parse().map_err(|_| bad_value(name, text, "not an integer"))?;
            if v.min().is_some_and(|m| x < m) || v.max().is_some_and(|m| x > m) {
                return Err(Error::OutOfRange {
                    name: name.to_string(),
                    value: x.to_string(),
                    min: v.min().map_or("-inf".into(), |m| m.to_string()),
                    max: v.max().map_or("inf".into(), |m| m.to_string()),
                    of_model: false,
                });
            }
            *p.integer_mut(v).expect("parameter") = x;
            Ok(())
        }
        Param::Boolean(v) => {
            let b = parse_bool(t).ok_or_else(|| bad_value(name, text, "expected true/false (or on/off, 1/0)"))?;
            *p.boolean_mut(v).expect("parameter") = b;
            Ok(())
        }
    }
}

/// Sets a Real parameter by name, checking the XML's range.
pub fn set_real(p: &mut Parameters, name: &str, x: f64) -> Result<(), Error> {
    match lookup(name)? {
        Param::Real(v) => set_real_checked(p, v, x),
        _ => Err(Error::NotOfKind { name: name.to_string(), kind: "Real parameter", is: None }),
    }
}

/// Sets a Boolean parameter by name.
pub fn set_bool(p: &mut Parameters, name: &str, b: bool) -> Result<(), Error> {
    match lookup(name)? {
        Param::Boolean(v) => {
            *p.boolean_mut(v).expect("parameter") = b;
            Ok(())
        }
        _ => Err(Error::NotOfKind { name: name.to_string(), kind: "Boolean parameter", is: None }),
    }
}

fn set_real_checked(p: &mut Parameters, v: RealVar, x: f64) -> Result<(), Error> {
    let name = v.name();
    if !x.is_finite() {
        return Err(bad_value(name, &x.to_string(), "not a finite number"));
    }
    if v.min().is_some_and(|m| x < m) || v.max().is_some_and(|m| x > m) {
        return Err(Error::OutOfRange {
            name: name.to_string(),
            value: x.to_string(),
            min: v.min().map_or("-inf".into(), |m| m.to_string()),
            max: v.max().map_or("inf".into(), |m| m.to_string()),
            of_model: true,
        });
    }
    *p.real_mut(v).expect("parameter") = x;
    Ok(())
}

fn bad_value(name: &str, text: &str, expected: &'static str) -> Error {
    Error::BadValue { name: name.to_string(), text: text.to_string(), expected }
}

pub fn parse_bool(t: &str) -> Option<bool> {
    match t.to_ascii_lowercase().as_str() {
        "true" | "on" | "1" | "yes" => Some(true),
        "false" | "off" | "0" | "no" => Some(false),
        _ => None,
    }
}

/// Parses `NAME=VALUE`.
pub fn parse_assignment(text: &str, option: &str) -> Result<(String, String), Error> {
    match text.split_once('=') {
        Some((n, v)) if !n.trim().is_empty() && !v.trim().is_empty() => {
            Ok((n.trim().to_string(), v.trim().to_string()))
        }
        _ => Err(Error::BadAssignment { option: option.to_string(), text: text.to_string() }),
    }
}

/// Levenshtein distance, for "did you mean".
pub fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

pub use semi_active_damper::effects::EffectInfo as Effect;
pub use semi_active_damper::effects::{Candidacy, FittedParameter, Start};

/// What the command line needs of an effect beyond its [`Effect`] description.
pub trait EffectExt {
    /// The name of its switch, `effect_<key>`.
    fn switch(&self) -> String;
    /// Whether the model's default has this effect on.
    fn default_on(&self) -> bool;
    /// The parameter that sets its size (what `--with KEY=VALUE` sets).
    fn size_parameter(&self) -> &'static str;
    /// All its parameters, fitted first.
    fn parameter_names(&self) -> Vec<&'static str>;
}

impl EffectExt for Effect {
    fn switch(&self) -> String {
        format!("effect_{}", self.key)
    }
    fn default_on(&self) -> bool {
        get_parameter(&Parameters::default(), &self.switch()).map(|v| v == Value::Boolean(true)).unwrap_or(false)
    }
    fn size_parameter(&self) -> &'static str {
        self.fitted[0].name
    }
    fn parameter_names(&self) -> Vec<&'static str> {
        self.fitted.iter().chain(self.secondary).map(|f| f.name).chain(self.other.iter().copied()).collect()
    }
}

/// The effect catalog of the model (`semi_active_damper::effects`), in its order.
pub fn effects() -> impl Iterator<Item = &'static Effect> {
    semi_active_damper::effects::CATALOG.into_iter().map(|e| e.info())
}

/// The catalog entry of `key` (with or without the `effect_` prefix).
pub fn effect(key: &str) -> Result<&'static Effect, Error> {
    let k = key.trim().strip_prefix("effect_").unwrap_or(key.trim());
    effects()
        .find(|e| e.key == k)
        .ok_or_else(|| Error::UnknownEffect { key: key.to_string(), catalog: effects().map(|e| e.key).collect() })
}

/// Switches an effect on or off. An effect switched on from off takes the parameters that start
/// at another parameter's value ([`Start::SameAs`]: oil saturated at the reservoir's pre-charge)
/// from that parameter, so that it is added to this damper and not to the default one.
pub fn set_effect(p: &mut Parameters, key: &str, on: bool) -> Result<(), Error> {
    let e = effect(key)?;
    if on && !effect_on(p, e.key)? {
        for f in e.fitted.iter().chain(e.secondary) {
            if let Start::SameAs(source) = f.start {
                set_real(p, f.name, real(p, source)?)?;
            }
        }
    }
    set_bool(p, &e.switch(), on).map_err(|err| Error::NoSwitch {
        switch: e.switch(),
        effect: e.key,
        source: Box::new(err),
    })
}

/// Whether an effect is on.
pub fn effect_on(p: &Parameters, key: &str) -> Result<bool, Error> {
    let e = effect(key)?;
    match get_parameter(p, &e.switch())? {
        Value::Boolean(b) => Ok(b),
        _ => Err(Error::NotOfKind { name: e.switch(), kind: "Boolean", is: None }),
    }
}

/// Parameters whose value differs from the model default, as (name, value).
pub fn changed_parameters(p: &Parameters) -> Vec<(&'static str, Value)> {
    let d = Parameters::default();
    parameter_names()
        .into_iter()
        .filter_map(|n| {
            let (a, b) = (get_parameter(p, n).ok()?, get_parameter(&d, n).ok()?);
            (a != b).then_some((n, a))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_and_get_by_name() {
        let mut p = Parameters::default();
        set_parameter(&mut p, "air_fraction", "0.04").unwrap();
        assert_eq!(p.air_fraction, 0.04);
        set_parameter(&mut p, "control_mode", "1").unwrap();
        assert_eq!(p.control_mode, 1);
        set_parameter(&mut p, "tare_load_cell", "on").unwrap();
        assert!(p.tare_load_cell);
        assert!(set_parameter(&mut p, "air_fraction", "0.9")
            .unwrap_err()
            .to_string()
            .contains("out of the model's range"));
        assert!(set_parameter(&mut p, "air_fracton", "0.1")
            .unwrap_err()
            .to_string()
            .contains("did you mean air_fraction"));
        assert!(set_parameter(&mut p, "F_damper", "1").unwrap_err().to_string().contains("not a parameter"));
        assert!(set_parameter(&mut p, "control_mode", "3").is_err());
        assert_eq!(get_real(&p, "tau_amp").unwrap(), 3e-3);
        let changed: Vec<_> = changed_parameters(&p).into_iter().map(|(n, _)| n).collect();
        assert_eq!(changed, ["air_fraction", "control_mode", "tare_load_cell"]);
    }

    #[test]
    fn an_effect_switched_on_starts_from_the_damper_it_is_added_to() {
        // gas release on a damper charged to 3 bar: its oil is saturated at 3 bar, not at the
        // default's 5 bar; once on, its saturation pressure is its own
        let mut p = Parameters { p_reservoir0: 3e5, ..Default::default() };
        set_effect(&mut p, "gas_release", true).unwrap();
        assert_eq!(p.p_saturation, 3e5);
        p.p_saturation = 2e5;
        set_effect(&mut p, "gas_release", true).unwrap();
        assert_eq!(p.p_saturation, 2e5);
    }

    #[test]
    fn every_effect_has_its_switch_and_parameters() {
        let mut p = Parameters::default();
        for e in effects() {
            let on = effect_on(&p, e.key).unwrap();
            set_effect(&mut p, e.key, !on).unwrap();
            assert_eq!(effect_on(&p, e.key).unwrap(), !on);
            for name in e.parameter_names() {
                get_real(&p, name).unwrap();
            }
        }
        assert!(effect("effect_seal_friction").is_ok());
        assert!(effect("friction").unwrap_err().to_string().contains("seal_friction"));
    }
}
