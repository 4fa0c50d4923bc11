//! Reading `modelDescription.xml` into [`ModelDescription`]: the variables with their attributes and
//! the XML line each came from, for the checks' messages.

use crate::fail;
use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};
use std::collections::{BTreeMap, BTreeSet};

/// One `ScalarVariable`.
#[derive(Debug, Clone)]
pub struct Var {
    /// 1-based index in `ModelVariables` (the index of `ModelStructure`).
    pub index: usize,
    /// XML line of the `ScalarVariable` element.
    pub line: usize,
    pub name: String,
    pub vr: u32,
    pub causality: String,
    pub variability: String,
    pub initial: Option<String>,
    pub description: Option<String>,
    /// `Real`, `Integer` or `Boolean`.
    pub ty: String,
    pub start: Option<String>,
    pub min: Option<String>,
    pub max: Option<String>,
    pub unit: Option<String>,
}

/// What the generator needs of a model description.
#[derive(Debug)]
pub struct ModelDescription {
    pub guid: String,
    pub model_identifier: String,
    pub can_interpolate_inputs: bool,
    pub units: BTreeSet<String>,
    pub vars: Vec<Var>,
    /// `ModelStructure/Outputs`: (index, XML line).
    pub outputs: Vec<(usize, usize)>,
    /// `ModelStructure/InitialUnknowns`: indices.
    pub initial_unknowns: Vec<usize>,
}

fn attrs(e: &BytesStart, line: usize) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for a in e.attributes() {
        let a = a.unwrap_or_else(|err| fail(line, format!("bad attribute: {err}")));
        let key = a.key.into_inner().to_string();
        let value = a
            .normalized_value(XmlVersion::Implicit1_0)
            .unwrap_or_else(|err| fail(line, format!("bad value of {key}: {err}")))
            .into_owned();
        map.insert(key, value);
    }
    map
}

fn line_of(src: &str, pos: usize) -> usize {
    src[..pos.min(src.len())].bytes().filter(|&b| b == b'\n').count() + 1
}

/// The partly read description, as the parser goes.
#[derive(Default)]
struct Builder {
    guid: Option<String>,
    model_identifier: Option<String>,
    can_interpolate_inputs: bool,
    units: BTreeSet<String>,
    vars: Vec<Var>,
    current: Option<Var>,
    outputs: Vec<(usize, usize)>,
    initial_unknowns: Vec<usize>,
    section: String,
}

impl Builder {
    fn start(&mut self, tag: &str, a: &BTreeMap<String, String>, line: usize, empty: bool) {
        match tag {
            "fmiModelDescription" => {
                if a.get("fmiVersion").map(String::as_str) != Some("2.0") {
                    fail(line, "fmiVersion must be 2.0");
                }
                self.guid = a.get("guid").cloned();
            }
            "CoSimulation" => {
                self.model_identifier = a.get("modelIdentifier").cloned();
                self.can_interpolate_inputs = a.get("canInterpolateInputs").is_some_and(|v| v == "true" || v == "1");
            }
            "Unit" => {
                self.units.insert(a.get("name").cloned().unwrap_or_else(|| fail(line, "Unit without name")));
            }
            "ScalarVariable" => self.variable(a, line, empty),
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" => self.type_element(tag, a, line),
            "Outputs" | "InitialUnknowns" => self.section = tag.to_string(),
            "Unknown" => {
                let index: usize = a
                    .get("index")
                    .and_then(|v| v.parse().ok())
                    .unwrap_or_else(|| fail(line, "Unknown without a valid index"));
                match self.section.as_str() {
                    "Outputs" => self.outputs.push((index, line)),
                    "InitialUnknowns" => self.initial_unknowns.push(index),
                    _ => {}
                }
            }
            _ => {}
        }
    }

    fn variable(&mut self, a: &BTreeMap<String, String>, line: usize, empty: bool) {
        let get = |k: &str| a.get(k).cloned();
        let name = get("name").unwrap_or_else(|| fail(line, "ScalarVariable without name"));
        let vr = get("valueReference")
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| fail(line, format!("{name}: missing or bad valueReference")));
        if empty {
            fail(line, format!("{name}: ScalarVariable without a type element"));
        }
        self.current = Some(Var {
            index: self.vars.len() + 1,
            line,
            name,
            vr,
            causality: get("causality").unwrap_or_else(|| "local".into()),
            variability: get("variability").unwrap_or_else(|| "continuous".into()),
            initial: get("initial"),
            description: get("description"),
            ty: String::new(),
            start: None,
            min: None,
            max: None,
            unit: None,
        });
    }

    fn type_element(&mut self, tag: &str, a: &BTreeMap<String, String>, line: usize) {
        let var = self.current.as_mut().unwrap_or_else(|| fail(line, format!("<{tag}> outside a ScalarVariable")));
        if tag == "String" || tag == "Enumeration" {
            fail(line, format!("{}: type {tag} is not supported by this FMU", var.name));
        }
        var.ty = tag.to_string();
        var.start = a.get("start").cloned();
        var.min = a.get("min").cloned();
        var.max = a.get("max").cloned();
        var.unit = a.get("unit").cloned();
    }

    fn end(&mut self, tag: &str, line: usize) {
        if tag == "ScalarVariable" {
            let var = self.current.take().unwrap_or_else(|| fail(line, "stray </ScalarVariable>"));
            self.vars.push(var);
        }
        if tag == "Outputs" || tag == "InitialUnknowns" {
            self.section.clear();
        }
    }
}

/// Parses the XML text `src`; a malformed file fails the build with its line.
pub fn parse(src: &str) -> ModelDescription {
    let mut reader = Reader::from_str(src);
    let mut b = Builder::default();
    loop {
        let line = line_of(src, reader.buffer_position() as usize);
        let event = reader.read_event().unwrap_or_else(|e| fail(line, format!("XML error: {e}")));
        match &event {
            Event::Start(e) | Event::Empty(e) => {
                let tag = e.name().into_inner().to_string();
                b.start(&tag, &attrs(e, line), line, matches!(event, Event::Empty(_)));
            }
            Event::End(e) => b.end(e.name().into_inner(), line),
            Event::Eof => break,
            _ => {}
        }
    }
    ModelDescription {
        guid: b.guid.unwrap_or_else(|| fail(1, "no guid")),
        model_identifier: b.model_identifier.unwrap_or_else(|| fail(1, "no CoSimulation/@modelIdentifier")),
        can_interpolate_inputs: b.can_interpolate_inputs,
        units: b.units,
        vars: b.vars,
        outputs: b.outputs,
        initial_unknowns: b.initial_unknowns,
    }
}
