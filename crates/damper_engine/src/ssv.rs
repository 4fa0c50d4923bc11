//! SSP 1.0 parameter-set files (`.ssv`, SystemStructureParameterValues): the standard file that
//! SSP importers (fmpy, OMSimulator, libcosim) apply as start values. `damper calibrate` writes
//! one; `--params FILE.ssv` applies one to the model's defaults.
//!
//! ```xml
//! <ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="…">
//!   <ssv:Parameters>
//!     <ssv:Parameter name="r_port" description="calibrated: 3.1e-3 ± 2.0e-5 m">
//!       <ssv:Real value="0.0031" unit="m"/>
//!     </ssv:Parameter>
//!   </ssv:Parameters>
//!   <ssv:Units> <ssc:Unit name="m"><ssc:BaseUnit m="1"/></ssc:Unit> … </ssv:Units>
//! </ssv:ParameterSet>
//! ```
//! Reading accepts `Real`, `Integer` and `Boolean` values; every error names the file, the line
//! and the parameter or attribute.

use crate::error::{Error, Place};
use crate::parameters::{lookup, set_parameter, Param, Value};
use quick_xml::events::{BytesDecl, BytesStart, BytesText, Event};
use quick_xml::{Reader, Writer};
use semi_active_damper::physics::params::Parameters;
use std::path::Path;

/// The SSV namespace of SSP 1.0.
pub const SSV_NAMESPACE: &str = "http://ssp-standard.org/SSP1/SystemStructureParameterValues";
/// The SSC (common) namespace of SSP 1.0.
pub const SSC_NAMESPACE: &str = "http://ssp-standard.org/SSP1/SystemStructureCommon";
/// The namespace of this program's calibration annotation.
pub const CALIBRATION_NAMESPACE: &str = "urn:semi-active-damper:calibration";

/// The model's unit definitions (the base-unit exponents written into `ssv:Units`).
const MODEL_DESCRIPTION: &str = include_str!("../../../modelDescription.xml");

/// One parameter of a file as read.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub name: String,
    pub value: Value,
    /// The `unit` attribute, if any.
    pub unit: Option<String>,
    /// Line of the `ssv:Parameter` element (1-based).
    pub line: usize,
}

/// A parameter to write, with what the calibration knows of it.
#[derive(Clone, Debug)]
pub struct Written {
    pub name: String,
    pub value: Value,
    /// The model's unit of a Real parameter ("1": dimensionless; empty for Integer and Boolean).
    pub unit: String,
    /// Standard uncertainty (same unit); None: not known (held, not fitted).
    pub uncertainty: Option<f64>,
    /// "fitted", "held: WHY" or "given".
    pub status: String,
    /// The value the calibration started from (Real parameters it fitted or held).
    pub start: Option<f64>,
}

fn line_at(text: &str, offset: usize) -> usize {
    let offset = offset.min(text.len());
    // the element starts at the first non-blank character after the previous event
    let skip = text[offset..].len() - text[offset..].trim_start().len();
    text[..offset + skip].matches('\n').count() + 1
}

fn attr(e: &BytesStart<'_>, name: &str, at: &Place) -> Result<Option<String>, Error> {
    for a in e.attributes() {
        let a = a.map_err(|source| Error::BadAttribute { at: at.clone(), source })?;
        if a.key.local_name().as_ref() == name && a.key.prefix().is_none() {
            #[allow(deprecated)]
            let v = a.unescape_value().map_err(|source| Error::AttributeValue {
                at: at.clone(),
                name: name.to_string(),
                source: Box::new(source),
            })?;
            return Ok(Some(v.into_owned()));
        }
    }
    Ok(None)
}

fn has_ssv_namespace(e: &BytesStart<'_>) -> bool {
    e.attributes().flatten().any(|a| {
        let key = a.key.as_ref();
        (key == "xmlns" || key.starts_with("xmlns:")) && a.value.as_ref() == SSV_NAMESPACE
    })
}

/// Reads the parameters of an .ssv file (the text of `path`).
pub fn parse(path: &str, text: &str) -> Result<Vec<Entry>, Error> {
    let mut reader = Reader::from_str(text);
    reader.config_mut().trim_text(true);
    let mut entries: Vec<Entry> = Vec::new();
    let mut stack: Vec<String> = Vec::new();
    let mut current: Option<(String, usize, bool)> = None; // (name, line, has a value)
    loop {
        let before = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|source| Error::Xml {
            file: path.to_string(),
            line: line_at(text, reader.error_position() as usize),
            source,
        })?;
        let line = line_at(text, before);
        let problem = |at: Place, problem: String| Error::InFile { at, problem };
        let (e, empty) = match &event {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                if stack.pop().as_deref() == Some("Parameter") {
                    if let Some((name, l, false)) = current.take() {
                        return Err(no_value(path, l, &name));
                    }
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let local = e.local_name().as_ref().to_string();
        if stack.is_empty() {
            if local != "ParameterSet" || !has_ssv_namespace(e) {
                return Err(problem(
                    Place::line(path, line),
                    format!(
                        "the root element is <{}>, not an ssv:ParameterSet of the namespace {SSV_NAMESPACE} (SSP 1.0)",
                        e.name().as_ref()
                    ),
                ));
            }
        } else if local == "Parameter" && stack.last().map(String::as_str) == Some("Parameters") {
            let at = Place::field(path, line, "ssv:Parameter");
            let name = attr(e, "name", &at)?.ok_or_else(|| problem(at, "no name attribute".into()))?;
            if let Some(prev) = entries.iter().find(|x| x.name == name) {
                return Err(problem(
                    Place::field(path, line, format!("parameter {name}")),
                    format!("given twice (first at line {})", prev.line),
                ));
            }
            current = Some((name, line, false));
        } else if let (Some("Parameter"), Some((name, pline, seen))) =
            (stack.last().map(String::as_str), current.as_mut())
        {
            let at = Place::field(path, line, format!("parameter {name}"));
            let kind = match local.as_str() {
                "Real" | "Integer" | "Boolean" => local.as_str(),
                "Annotations" => {
                    push(&mut stack, &local, empty);
                    continue;
                }
                other => {
                    return Err(problem(
                        at,
                        format!("the value is an ssv:{other}; this model takes Real, Integer or Boolean parameters"),
                    ))
                }
            };
            if *seen {
                return Err(problem(at, format!("a second value (the first at line {pline})")));
            }
            let text_value = attr(e, "value", &at)?
                .ok_or_else(|| problem(at.and(format!("ssv:{kind}")), "no value attribute".into()))?;
            let bad = |kind: &str, expected: &str| {
                problem(at.and(format!("ssv:{kind} value=\"{text_value}\"")), expected.to_string())
            };
            let value = match kind {
                "Real" => Value::Real(text_value.trim().parse().map_err(|_| bad("Real", "not a number"))?),
                "Integer" => Value::Integer(text_value.trim().parse().map_err(|_| bad("Integer", "not an integer"))?),
                _ => Value::Boolean(match text_value.trim() {
                    "true" | "1" => true,
                    "false" | "0" => false,
                    _ => return Err(bad("Boolean", "expected true or false")),
                }),
            };
            let unit = attr(e, "unit", &at)?;
            *seen = true;
            entries.push(Entry { name: name.clone(), value, unit, line: *pline });
        }
        push(&mut stack, &local, empty);
    }
    if let Some((name, l, false)) = current {
        return Err(no_value(path, l, &name));
    }
    Ok(entries)
}

fn no_value(path: &str, line: usize, name: &str) -> Error {
    Error::InFile {
        at: Place::field(path, line, format!("parameter {name}")),
        problem: "no Real, Integer or Boolean value".into(),
    }
}

fn push(stack: &mut Vec<String>, local: &str, empty: bool) {
    if !empty {
        stack.push(local.to_string());
    }
}

/// Reads an .ssv file.
pub fn read(path: &Path) -> Result<Vec<Entry>, Error> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read { path: path.to_path_buf(), source })?;
    parse(&path.display().to_string(), &text)
}

/// Applies the parameters of an .ssv file to `p`: every name must be a parameter of the model, of
/// the file's type, in the model's range and unit.
pub fn apply(p: &mut Parameters, path: &Path) -> Result<Vec<Entry>, Error> {
    let entries = read(path)?;
    for e in &entries {
        let at = Place::field(path.display().to_string(), e.line, format!("parameter {}", e.name));
        let param = lookup(&e.name).map_err(|err| err.at(at.clone()))?;
        let type_ok = matches!(
            (param, e.value),
            (Param::Real(_), Value::Real(_))
                | (Param::Integer(_), Value::Integer(_))
                | (Param::Boolean(_), Value::Boolean(_))
        );
        // an integer value for a Real parameter is read as that number, as importers do
        let text = match (param, e.value) {
            (Param::Real(_), Value::Integer(i)) => i.to_string(),
            _ if type_ok => e.value.to_string(),
            (param, value) => {
                return Err(Error::InFile {
                    at,
                    problem: format!(
                        "the file gives {} {value}, the model's parameter is {}",
                        kind(value),
                        param_kind(param)
                    ),
                })
            }
        };
        if let (Param::Real(v), Some(unit)) = (param, &e.unit) {
            if unit != v.unit() && !(unit.is_empty() && v.unit() == "1") {
                return Err(Error::InFile {
                    at,
                    problem: format!("unit \"{unit}\", the model's unit is \"{}\"", v.unit()),
                });
            }
        }
        set_parameter(p, &e.name, &text).map_err(|err| err.at(at))?;
    }
    Ok(entries)
}

fn kind(v: Value) -> &'static str {
    match v {
        Value::Real(_) => "a Real",
        Value::Integer(_) => "an Integer",
        Value::Boolean(_) => "a Boolean",
    }
}

fn param_kind(p: Param) -> &'static str {
    match p {
        Param::Real(_) => "a Real",
        Param::Integer(_) => "an Integer",
        Param::Boolean(_) => "a Boolean",
    }
}

/// The base-unit exponents of `unit` from the model's UnitDefinitions: (attribute, exponent).
fn base_unit(unit: &str) -> Vec<(String, String)> {
    let mut reader = Reader::from_str(MODEL_DESCRIPTION);
    let mut inside = false;
    loop {
        match reader.read_event() {
            Ok(Event::Start(e)) | Ok(Event::Empty(e)) if e.local_name().as_ref() == "Unit" => {
                inside = attr(&e, "name", &Place::line("", 0)).ok().flatten().as_deref() == Some(unit);
            }
            Ok(Event::Start(e)) | Ok(Event::Empty(e)) if inside && e.local_name().as_ref() == "BaseUnit" => {
                return e
                    .attributes()
                    .flatten()
                    .map(|a| (a.key.as_ref().to_string(), a.value.as_ref().to_string()))
                    .collect();
            }
            Ok(Event::End(e)) if inside && e.local_name().as_ref() == "Unit" => return Vec::new(),
            Ok(Event::Eof) | Err(_) => return Vec::new(),
            _ => {}
        }
    }
}

/// Shortest text that reads back as the same f64.
fn number(x: f64) -> String {
    format!("{x:e}").parse::<f64>().map_or_else(|_| x.to_string(), |_| format!("{x:e}"))
}

/// The text of an .ssv file named `name` with `params` (`note`: the set's description).
pub fn to_string(name: &str, note: &str, params: &[Written]) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let io = |r: std::io::Result<()>| r.expect("writing to memory");
    io(w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None))));
    let mut root = BytesStart::new("ssv:ParameterSet");
    root.push_attribute(("xmlns:ssv", SSV_NAMESPACE));
    root.push_attribute(("xmlns:ssc", SSC_NAMESPACE));
    root.push_attribute(("xmlns:cal", CALIBRATION_NAMESPACE));
    root.push_attribute(("version", "1.0"));
    root.push_attribute(("name", name));
    root.push_attribute(("description", note));
    let mut units: Vec<&str> = params.iter().map(|p| p.unit.as_str()).filter(|u| !u.is_empty()).collect();
    units.sort();
    units.dedup();
    let r =
        w.create_element("ssv:ParameterSet").with_attributes(root.attributes().flatten()).write_inner_content(|w| {
            w.create_element("ssv:Parameters").write_inner_content(|w| {
                for p in params {
                    let description = match p.uncertainty {
                        Some(u) => {
                            format!("{}: {} ± {} {} (standard uncertainty)", p.status, p.value, number(u), p.unit)
                        }
                        None => format!("{}: {} {}", p.status, p.value, p.unit).trim_end().to_string(),
                    };
                    w.create_element("ssv:Parameter")
                        .with_attribute(("name", p.name.as_str()))
                        .with_attribute(("description", description.as_str()))
                        .write_inner_content(|w| {
                            match p.value {
                                Value::Real(x) => w
                                    .create_element("ssv:Real")
                                    .with_attribute(("value", number(x).as_str()))
                                    .with_attribute(("unit", p.unit.as_str()))
                                    .write_empty()?,
                                Value::Integer(i) => w
                                    .create_element("ssv:Integer")
                                    .with_attribute(("value", i.to_string().as_str()))
                                    .write_empty()?,
                                Value::Boolean(b) => w
                                    .create_element("ssv:Boolean")
                                    .with_attribute(("value", if b { "true" } else { "false" }))
                                    .write_empty()?,
                            };
                            w.create_element("ssc:Annotations").write_inner_content(|w| {
                                w.create_element("ssc:Annotation")
                                    .with_attribute(("type", CALIBRATION_NAMESPACE))
                                    .write_inner_content(|w| {
                                        let mut c = w
                                            .create_element("cal:Calibration")
                                            .with_attribute(("status", p.status.as_str()));
                                        if let Some(s) = p.start {
                                            c = c.with_attribute(("start", number(s).as_str()));
                                        }
                                        if let (Some(u), Value::Real(x)) = (p.uncertainty, p.value) {
                                            c = c.with_attribute(("standardUncertainty", number(u).as_str()));
                                            if x != 0.0 {
                                                c = c.with_attribute((
                                                    "relativeUncertainty",
                                                    number(u / x.abs()).as_str(),
                                                ));
                                            }
                                        }
                                        c.write_empty()?;
                                        Ok(())
                                    })?;
                                Ok(())
                            })?;
                            Ok(())
                        })?;
                }
                Ok(())
            })?;
            w.create_element("ssv:Units").write_inner_content(|w| {
                for u in &units {
                    let base = base_unit(u);
                    let unit = w.create_element("ssc:Unit").with_attribute(("name", *u));
                    unit.write_inner_content(|w| {
                        w.create_element("ssc:BaseUnit")
                            .with_attributes(base.iter().map(|(k, v)| (k.as_str(), v.as_str())))
                            .write_empty()?;
                        Ok(())
                    })?;
                }
                Ok(())
            })?;
            Ok(())
        });
    io(r.map(|_| ()));
    io(w.write_event(Event::Text(BytesText::new("\n"))));
    String::from_utf8(w.into_inner()).expect("UTF-8")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written() -> Vec<Written> {
        vec![
            Written {
                name: "r_port".into(),
                value: Value::Real(3.1e-3),
                unit: "m".into(),
                uncertainty: Some(2e-5),
                status: "fitted".into(),
                start: Some(3e-3),
            },
            Written {
                name: "air_fraction".into(),
                value: Value::Real(0.03),
                unit: "1".into(),
                uncertainty: None,
                status: "held: not identifiable".into(),
                start: Some(0.025),
            },
            Written {
                name: "n_ports".into(),
                value: Value::Integer(3),
                unit: String::new(),
                uncertainty: None,
                status: "given".into(),
                start: None,
            },
        ]
    }

    #[test]
    fn round_trip_with_units_and_the_uncertainty() {
        let text = to_string("damper", "calibrated", &written());
        assert!(text.contains(SSV_NAMESPACE) && text.contains("<ssc:BaseUnit m=\"1\"/>"), "{text}");
        let entries = parse("x.ssv", &text).unwrap();
        assert_eq!(entries.len(), 3);
        assert_eq!(entries[2].value, Value::Integer(3));
        assert_eq!(entries[0].value, Value::Real(3.1e-3));
        assert_eq!(entries[0].unit.as_deref(), Some("m"));
        assert_eq!(entries[1].name, "air_fraction");
        let dir = std::env::temp_dir().join(format!("ssv_round_trip_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("p.ssv");
        std::fs::write(&f, &text).unwrap();
        let mut p = Parameters::default();
        apply(&mut p, &f).unwrap();
        assert_eq!((p.r_port, p.air_fraction, p.n_ports), (3.1e-3, 0.03, 3));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn integer_and_boolean_values_and_errors_with_line_and_field() {
        let head = format!("<?xml version=\"1.0\"?>\n<ssv:ParameterSet xmlns:ssv=\"{SSV_NAMESPACE}\" version=\"1.0\" name=\"p\">\n<ssv:Parameters>\n");
        let good = format!("{head}<ssv:Parameter name=\"n_ports\"><ssv:Integer value=\"3\"/></ssv:Parameter>\n<ssv:Parameter name=\"tare_load_cell\"><ssv:Boolean value=\"true\"/></ssv:Parameter>\n</ssv:Parameters></ssv:ParameterSet>\n");
        let e = parse("g.ssv", &good).unwrap();
        assert_eq!((e[0].value, e[0].line, e[1].value, e[1].line), (Value::Integer(3), 4, Value::Boolean(true), 5));
        let bad = format!("{head}<ssv:Parameter name=\"r_port\">\n  <ssv:Real value=\"abc\"/>\n</ssv:Parameter>\n</ssv:Parameters></ssv:ParameterSet>\n");
        let err = parse("b.ssv", &bad).unwrap_err().to_string();
        assert!(err.starts_with("b.ssv, line 5, parameter r_port, ssv:Real value=\"abc\""), "{err}");
        let err = parse("r.ssv", "<a/>").unwrap_err().to_string();
        assert!(err.contains("r.ssv, line 1") && err.contains("not an ssv:ParameterSet"), "{err}");
        let err =
            parse("x.ssv", &format!("{head}<ssv:Parameter name=\"r_port\"><ssv:Real value=\"1\"></ssv:Parameter>"))
                .unwrap_err()
                .to_string();
        assert!(err.contains("x.ssv, line 4: not well-formed"), "{err}");
    }
}
