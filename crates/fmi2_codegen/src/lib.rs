//! For an FMU crate's `build.rs`: reads its `modelDescription.xml` (the single source of truth for
//! the FMU's variables) with quick-xml, checks it, and generates `$OUT_DIR/model_description.rs`:
//! the GUID, the model identifier and one enum per FMI type (`RealVar`, `IntegerVar`, `BooleanVar`)
//! with value reference, name, causality, start, min and max of every variable (and the unit of
//! every Real).
//!
//! The FMU crate maps every variant in exhaustive `match`es, so a variable added to or removed from
//! the XML does not compile until the code handles it. The GUID must equal a fingerprint of the
//! variable table, so an interface change cannot keep a stale GUID. The generated code refers to
//! `Causality` and `VarInfo`, which the including module must bring into scope (from `fmi2_slave`).

use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::PathBuf;

const XML: &str = "modelDescription.xml";

#[derive(Debug, Clone)]
struct Var {
    index: usize,
    line: usize,
    name: String,
    vr: u32,
    causality: String,
    variability: String,
    initial: Option<String>,
    ty: String,
    start: Option<String>,
    min: Option<String>,
    max: Option<String>,
    unit: Option<String>,
}

fn fail(line: usize, msg: impl AsRef<str>) -> ! {
    panic!("{XML}:{line}: {}", msg.as_ref());
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

/// FNV-1a, 64 bit: stable across Rust versions (std's hashers are not).
fn fnv1a(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn camel(name: &str) -> String {
    let mut out = String::new();
    for part in name.split(|c: char| !c.is_ascii_alphanumeric()).filter(|p| !p.is_empty()) {
        let mut chars = part.chars();
        if let Some(c) = chars.next() {
            out.push(c.to_ascii_uppercase());
            out.extend(chars);
        }
    }
    out
}

/// Checks `modelDescription.xml` in the crate's directory and writes `$OUT_DIR/model_description.rs`.
/// Panics (failing the build) with `modelDescription.xml:LINE: what is wrong`.
pub fn generate() {
    println!("cargo:rerun-if-changed={XML}");
    let src = std::fs::read_to_string(XML).unwrap_or_else(|e| panic!("{XML}: cannot read: {e}"));
    let mut reader = Reader::from_str(&src);
    let mut guid = None;
    let mut model_identifier = None;
    let mut can_interpolate_inputs = false;
    let mut units = BTreeSet::new();
    let mut vars: Vec<Var> = Vec::new();
    let mut current: Option<Var> = None;
    let mut outputs: Vec<(usize, usize)> = Vec::new();
    let mut initial_unknowns: Vec<usize> = Vec::new();
    let mut section = String::new();
    loop {
        let pos = reader.buffer_position() as usize;
        let line = line_of(&src, pos);
        let event = reader.read_event().unwrap_or_else(|e| fail(line, format!("XML error: {e}")));
        let (e, empty) = match &event {
            Event::Start(e) => (e.clone(), false),
            Event::Empty(e) => (e.clone(), true),
            Event::End(e) => {
                let name = e.name().into_inner().to_string();
                if name == "ScalarVariable" {
                    vars.push(current.take().unwrap_or_else(|| fail(line, "stray </ScalarVariable>")));
                }
                if name == "Outputs" || name == "InitialUnknowns" {
                    section.clear();
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let tag = e.name().into_inner().to_string();
        let a = attrs(&e, line);
        match tag.as_str() {
            "fmiModelDescription" => {
                if a.get("fmiVersion").map(String::as_str) != Some("2.0") {
                    fail(line, "fmiVersion must be 2.0");
                }
                guid = a.get("guid").cloned();
            }
            "CoSimulation" => {
                model_identifier = a.get("modelIdentifier").cloned();
                can_interpolate_inputs = a.get("canInterpolateInputs").is_some_and(|v| v == "true" || v == "1");
            }
            "Unit" => {
                units.insert(a.get("name").cloned().unwrap_or_else(|| fail(line, "Unit without name")));
            }
            "ScalarVariable" => {
                let get = |k: &str| a.get(k).cloned();
                let name = get("name").unwrap_or_else(|| fail(line, "ScalarVariable without name"));
                let vr = get("valueReference")
                    .and_then(|v| v.parse().ok())
                    .unwrap_or_else(|| fail(line, format!("{name}: missing or bad valueReference")));
                let var = Var {
                    index: vars.len() + 1,
                    line,
                    name,
                    vr,
                    causality: get("causality").unwrap_or_else(|| "local".into()),
                    variability: get("variability").unwrap_or_else(|| "continuous".into()),
                    initial: get("initial"),
                    ty: String::new(),
                    start: None,
                    min: None,
                    max: None,
                    unit: None,
                };
                if empty {
                    fail(line, format!("{}: ScalarVariable without a type element", var.name));
                }
                current = Some(var);
            }
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" => {
                let var = current.as_mut().unwrap_or_else(|| fail(line, format!("<{tag}> outside a ScalarVariable")));
                if tag == "String" || tag == "Enumeration" {
                    fail(line, format!("{}: type {tag} is not supported by this FMU", var.name));
                }
                var.ty = tag.clone();
                var.start = a.get("start").cloned();
                var.min = a.get("min").cloned();
                var.max = a.get("max").cloned();
                var.unit = a.get("unit").cloned();
            }
            "Outputs" | "InitialUnknowns" => section = tag.clone(),
            "Unknown" => {
                let index: usize = a
                    .get("index")
                    .and_then(|v| v.parse().ok())
                    .unwrap_or_else(|| fail(line, "Unknown without a valid index"));
                match section.as_str() {
                    "Outputs" => outputs.push((index, line)),
                    "InitialUnknowns" => initial_unknowns.push(index),
                    _ => {}
                }
            }
            _ => {}
        }
    }

    let model_identifier = model_identifier.unwrap_or_else(|| fail(1, "no CoSimulation/@modelIdentifier"));
    let guid = guid.unwrap_or_else(|| fail(1, "no guid"));

    // --- checks ---------------------------------------------------------------------------------
    let mut names = BTreeSet::new();
    let mut idents = BTreeSet::new();
    let mut vrs = BTreeSet::new();
    for v in &vars {
        if !names.insert(v.name.clone()) {
            fail(v.line, format!("duplicate variable name {}", v.name));
        }
        if !idents.insert((v.ty.clone(), camel(&v.name))) {
            fail(v.line, format!("{}: its Rust identifier {} collides with another", v.name, camel(&v.name)));
        }
        if !vrs.insert((v.ty.clone(), v.vr)) {
            fail(v.line, format!("{}: valueReference {} used twice for type {}", v.name, v.vr, v.ty));
        }
        match (v.causality.as_str(), v.variability.as_str()) {
            ("parameter", "fixed" | "tunable") | ("input", "continuous" | "discrete") => {
                if v.start.is_none() {
                    fail(v.line, format!("{}: {} needs a start value", v.name, v.causality));
                }
            }
            ("output", "continuous" | "discrete") => {
                if v.initial.as_deref() != Some("calculated") || v.start.is_some() {
                    fail(v.line, format!("{}: outputs are initial=\"calculated\" without start", v.name));
                }
            }
            (c, va) => fail(v.line, format!("{}: causality {c} with variability {va} is not used here", v.name)),
        }
        if let Some(u) = &v.unit {
            if !units.contains(u) {
                fail(v.line, format!("{}: unit {u} is not in UnitDefinitions", v.name));
            }
        }
        if v.ty == "Real" && v.unit.is_none() {
            fail(v.line, format!("{}: a Real needs a unit", v.name));
        }
        if v.ty == "Boolean" {
            if v.start.as_deref().is_some_and(|s| !matches!(s, "true" | "false" | "1" | "0")) {
                fail(v.line, format!("{}: Boolean start must be true or false", v.name));
            }
            continue;
        }
        let num = |s: &Option<String>| {
            s.as_ref()
                .map(|x| x.parse::<f64>().unwrap_or_else(|_| fail(v.line, format!("{}: {x} is not a number", v.name))))
        };
        if let (Some(s), Some(lo)) = (num(&v.start), num(&v.min)) {
            if s < lo {
                fail(v.line, format!("{}: start {s} below min {lo}", v.name));
            }
        }
        if let (Some(s), Some(hi)) = (num(&v.start), num(&v.max)) {
            if s > hi {
                fail(v.line, format!("{}: start {s} above max {hi}", v.name));
            }
        }
    }
    let output_indices: Vec<usize> = vars.iter().filter(|v| v.causality == "output").map(|v| v.index).collect();
    let listed: Vec<usize> = outputs.iter().map(|o| o.0).collect();
    if listed != output_indices {
        fail(
            outputs.first().map_or(1, |o| o.1),
            format!("ModelStructure/Outputs lists {listed:?}, the outputs are {output_indices:?}"),
        );
    }
    if initial_unknowns != output_indices {
        fail(
            1,
            format!("ModelStructure/InitialUnknowns lists {initial_unknowns:?}, the outputs are {output_indices:?}"),
        );
    }

    // GUID = fingerprint of the interface (names, types, value references, causality, variability).
    let mut table = model_identifier.clone();
    for v in &vars {
        let _ = write!(table, "|{}:{}:{}:{}:{}", v.name, v.ty, v.vr, v.causality, v.variability);
    }
    let (h1, h2) = (fnv1a(table.as_bytes(), 0), fnv1a(table.as_bytes(), 0x9e37_79b9_7f4a_7c15));
    let expected = format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        h1 >> 32,
        (h1 >> 16) & 0xffff,
        h1 & 0xffff,
        h2 >> 48,
        h2 & 0xffff_ffff_ffff
    );
    if guid != expected {
        fail(2, format!("guid is {guid} but the variable table's fingerprint is {expected}: set guid=\"{expected}\" (the interface changed, so must the GUID)"));
    }

    // --- code generation ------------------------------------------------------------------------
    let mut out = String::new();
    let _ = writeln!(out, "/// GUID of `modelDescription.xml` (fingerprint of its variable table).");
    let _ = writeln!(out, "pub const GUID: &str = {guid:?};");
    let _ = writeln!(out, "/// `CoSimulation/@modelIdentifier`: the shared library's file name.");
    let _ = writeln!(out, "pub const MODEL_IDENTIFIER: &str = {model_identifier:?};");
    let _ =
        writeln!(out, "/// `CoSimulation/@canInterpolateInputs`: whether fmi2SetRealInputDerivatives is supported.");
    let _ = writeln!(out, "pub const CAN_INTERPOLATE_INPUTS: bool = {can_interpolate_inputs};");
    for ty in ["Real", "Integer", "Boolean"] {
        let (rust_ty, enum_name) = match ty {
            "Real" => ("f64", "RealVar"),
            "Integer" => ("i32", "IntegerVar"),
            _ => ("bool", "BooleanVar"),
        };
        let vs: Vec<&Var> = vars.iter().filter(|v| v.ty == ty).collect();
        let lit = |s: &Option<String>| -> String {
            match s {
                None => "None".into(),
                Some(x) if ty == "Boolean" => format!("Some({})", x == "true" || x == "1"),
                Some(x) if ty == "Real" => format!("Some({:?}f64)", x.parse::<f64>().unwrap()),
                Some(x) => format!("Some({}i32)", x.parse::<i32>().unwrap()),
            }
        };
        let _ = writeln!(out, "\n/// The {ty} variables of `modelDescription.xml`.");
        let _ = writeln!(out, "#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]\npub enum {enum_name} {{");
        for v in &vs {
            // The unit goes in backticks: bare `[N]` or `[m/s]` would be read as intra-doc links.
            let unit = v.unit.as_ref().map_or(String::new(), |u| format!(", `{u}`"));
            let _ = writeln!(out, "    /// `{}` (vr {}, {}, {}{unit})", v.name, v.vr, v.causality, v.variability);
            let _ = writeln!(out, "    {},", camel(&v.name));
        }
        let _ = writeln!(out, "}}\n\n#[allow(dead_code, unreachable_patterns, clippy::approx_constant, clippy::match_single_binding)]\nimpl {enum_name} {{");
        let _ = writeln!(out, "    /// Every variable of this type, in XML order.");
        let _ = write!(out, "    pub const ALL: [{enum_name}; {}] = [", vs.len());
        for v in &vs {
            let _ = write!(out, "{enum_name}::{}, ", camel(&v.name));
        }
        let _ = writeln!(out, "];");
        let gen_fn = |out: &mut String, fname: &str, ret: &str, f: &dyn Fn(&Var) -> String| {
            let _ = writeln!(out, "    pub const fn {fname}(self) -> {ret} {{\n        match self {{");
            for v in &vs {
                let _ = writeln!(out, "            {enum_name}::{} => {},", camel(&v.name), f(v));
            }
            let _ = writeln!(out, "            _ => unreachable!(),\n        }}\n    }}");
        };
        gen_fn(&mut out, "vr", "u32", &|v| v.vr.to_string());
        gen_fn(&mut out, "name", "&'static str", &|v| format!("{:?}", v.name));
        gen_fn(&mut out, "causality", "Causality", &|v| format!("Causality::{}", camel(&v.causality)));
        let _ = writeln!(out, "    /// Name and causality, for the FMI layer.");
        let _ = writeln!(
            out,
            "    pub const fn info(self) -> VarInfo {{\n        VarInfo {{ name: self.name(), causality: self.causality() }}\n    }}"
        );
        gen_fn(&mut out, "start", &format!("Option<{rust_ty}>"), &|v| lit(&v.start));
        if ty == "Real" {
            // the checks above made every Real carry a unit of UnitDefinitions
            gen_fn(&mut out, "unit", "&'static str", &|v| format!("{:?}", v.unit.as_deref().unwrap_or_default()));
        }
        if ty != "Boolean" {
            gen_fn(&mut out, "min", &format!("Option<{rust_ty}>"), &|v| lit(&v.min));
            gen_fn(&mut out, "max", &format!("Option<{rust_ty}>"), &|v| lit(&v.max));
        }
        let _ = writeln!(out, "    /// The variable with this value reference, if any.");
        let _ = writeln!(out, "    pub const fn from_vr(vr: u32) -> Option<Self> {{\n        match vr {{");
        for v in &vs {
            let _ = writeln!(out, "            {} => Some({enum_name}::{}),", v.vr, camel(&v.name));
        }
        let _ = writeln!(out, "            _ => None,\n        }}\n    }}\n}}");
    }
    let path = PathBuf::from(std::env::var("OUT_DIR").unwrap()).join("model_description.rs");
    std::fs::write(path, out).unwrap();
}
