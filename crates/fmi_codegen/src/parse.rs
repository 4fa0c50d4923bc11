//! Reading `modelDescription.xml` into [`ModelDescription`]: the variables with their attributes and
//! the XML line each came from (for the checks' messages), the model structure, and what the FMI
//! 3.0 description repeats (header, units, log categories, default experiment).

use crate::fail;
use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};
use std::collections::BTreeMap;

/// An element's attributes, by name.
pub type Attributes = BTreeMap<String, String>;

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

/// One `Unknown` of `ModelStructure`.
#[derive(Debug, Clone)]
pub struct Unknown {
    pub index: usize,
    pub line: usize,
    /// The `dependencies` indices; `None` when the attribute is absent ("depends on every known").
    pub dependencies: Option<Vec<usize>>,
    pub dependencies_kind: Option<String>,
}

/// One `Unit` of `UnitDefinitions`: its name, its `BaseUnit` exponents and its `DisplayUnit`s.
#[derive(Debug, Clone, Default)]
pub struct Unit {
    pub name: String,
    pub base: Attributes,
    pub display: Vec<Attributes>,
}

/// What the generator needs of a model description.
#[derive(Debug, Default)]
pub struct ModelDescription {
    pub guid: String,
    pub model_identifier: String,
    pub can_interpolate_inputs: bool,
    /// The attributes of `fmiModelDescription` and of `CoSimulation`.
    pub header: Attributes,
    pub co_simulation: Attributes,
    pub units: Vec<Unit>,
    /// `LogCategories`: each category's attributes.
    pub log_categories: Vec<Attributes>,
    pub default_experiment: Option<Attributes>,
    /// `VendorAnnotations/Tool[@name="fmi_codegen"]/FMI3`: what the FMI 3.0 description adds.
    pub fmi3: Attributes,
    pub vars: Vec<Var>,
    pub outputs: Vec<Unknown>,
    pub initial_unknowns: Vec<Unknown>,
}

impl ModelDescription {
    /// Whether `name` is a unit of `UnitDefinitions`.
    pub fn has_unit(&self, name: &str) -> bool {
        self.units.iter().any(|u| u.name == name)
    }

    /// The variable of a `ModelStructure` index.
    pub fn by_index(&self, index: usize) -> Option<&Var> {
        index.checked_sub(1).and_then(|i| self.vars.get(i))
    }
}

fn attrs(e: &BytesStart, line: usize) -> Attributes {
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
    md: ModelDescription,
    current: Option<Var>,
    /// The innermost section whose children are read: `Outputs`, `InitialUnknowns`, `Tool`.
    section: String,
    tool: Option<String>,
}

fn unknown(a: &Attributes, line: usize) -> Unknown {
    let index =
        a.get("index").and_then(|v| v.parse().ok()).unwrap_or_else(|| fail(line, "Unknown without a valid index"));
    let dependencies = a.get("dependencies").map(|list| {
        list.split_whitespace()
            .map(|d| d.parse().unwrap_or_else(|_| fail(line, format!("dependencies: {d} is not an index"))))
            .collect()
    });
    Unknown { index, line, dependencies, dependencies_kind: a.get("dependenciesKind").cloned() }
}

impl Builder {
    fn start(&mut self, tag: &str, a: Attributes, line: usize, empty: bool) {
        match tag {
            "fmiModelDescription" => {
                if a.get("fmiVersion").map(String::as_str) != Some("2.0") {
                    fail(line, "fmiVersion must be 2.0");
                }
                self.md.guid = a.get("guid").cloned().unwrap_or_else(|| fail(line, "no guid"));
                self.md.header = a;
            }
            "CoSimulation" => {
                self.md.model_identifier =
                    a.get("modelIdentifier").cloned().unwrap_or_else(|| fail(line, "no CoSimulation/@modelIdentifier"));
                self.md.can_interpolate_inputs = a.get("canInterpolateInputs").is_some_and(|v| v == "true" || v == "1");
                self.md.co_simulation = a;
            }
            "Unit" => {
                let name = a.get("name").cloned().unwrap_or_else(|| fail(line, "Unit without name"));
                self.md.units.push(Unit { name, ..Unit::default() });
            }
            "BaseUnit" => self.unit(line, tag).base = a,
            "DisplayUnit" => self.unit(line, tag).display.push(a),
            "Category" => self.md.log_categories.push(a),
            "DefaultExperiment" => self.md.default_experiment = Some(a),
            "Tool" => self.tool = a.get("name").cloned(),
            "FMI3" if self.tool.as_deref() == Some("fmi_codegen") => self.md.fmi3 = a,
            "ScalarVariable" => self.variable(&a, line, empty),
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" => self.type_element(tag, &a, line),
            "Outputs" | "InitialUnknowns" => self.section = tag.to_string(),
            "Unknown" => match self.section.as_str() {
                "Outputs" => self.md.outputs.push(unknown(&a, line)),
                "InitialUnknowns" => self.md.initial_unknowns.push(unknown(&a, line)),
                _ => {}
            },
            _ => {}
        }
    }

    /// The unit a `BaseUnit` or `DisplayUnit` belongs to.
    fn unit(&mut self, line: usize, tag: &str) -> &mut Unit {
        self.md.units.last_mut().unwrap_or_else(|| fail(line, format!("<{tag}> outside a Unit")))
    }

    fn variable(&mut self, a: &Attributes, line: usize, empty: bool) {
        let get = |k: &str| a.get(k).cloned();
        let name = get("name").unwrap_or_else(|| fail(line, "ScalarVariable without name"));
        let vr = get("valueReference")
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| fail(line, format!("{name}: missing or bad valueReference")));
        if empty {
            fail(line, format!("{name}: ScalarVariable without a type element"));
        }
        self.current = Some(Var {
            index: self.md.vars.len() + 1,
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

    fn type_element(&mut self, tag: &str, a: &Attributes, line: usize) {
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
        match tag {
            "ScalarVariable" => {
                let var = self.current.take().unwrap_or_else(|| fail(line, "stray </ScalarVariable>"));
                self.md.vars.push(var);
            }
            "Outputs" | "InitialUnknowns" => self.section.clear(),
            "Tool" => self.tool = None,
            _ => {}
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
                b.start(&tag, attrs(e, line), line, matches!(event, Event::Empty(_)));
            }
            Event::End(e) => b.end(e.name().into_inner(), line),
            Event::Eof => break,
            _ => {}
        }
    }
    if b.md.guid.is_empty() {
        fail(1, "no fmiModelDescription with a guid");
    }
    b.md
}
