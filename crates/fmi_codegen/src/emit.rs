//! The generated Rust: the GUID and model identifier, one enum per FMI type with every variable's
//! attributes, and the `Parameters` struct with one field per parameter and its accessors (the
//! `Inputs` struct: [`crate::inputs`]).

use crate::parse::{ModelDescription, Var};
use crate::{camel, field};
use std::fmt::Write as _;

/// Boolean parameters named with this prefix are switches: `Parameters::switch(key)` reads them.
const SWITCH_PREFIX: &str = "effect_";

/// The FMI types this generator handles: (XML element, Rust type, enum name).
const TYPES: [(&str, &str, &str); 3] =
    [("Real", "f64", "RealVar"), ("Integer", "i32", "IntegerVar"), ("Boolean", "bool", "BooleanVar")];

/// The whole generated file.
pub fn emit(md: &ModelDescription) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "/// GUID of `modelDescription.xml` (fingerprint of its variable table).");
    let _ = writeln!(out, "pub const GUID: &str = {:?};", md.guid);
    let _ = writeln!(out, "/// `CoSimulation/@modelIdentifier`: the shared library's file name.");
    let _ = writeln!(out, "pub const MODEL_IDENTIFIER: &str = {:?};", md.model_identifier);
    let _ =
        writeln!(out, "/// `CoSimulation/@canInterpolateInputs`: whether fmi2SetRealInputDerivatives is supported.");
    let _ = writeln!(out, "pub const CAN_INTERPOLATE_INPUTS: bool = {};", md.can_interpolate_inputs);
    let _ =
        writeln!(out, "/// Value reference of `time`, the independent variable the FMI 3.0 model description adds.");
    let _ = writeln!(out, "pub const FMI3_TIME_VR: u32 = {};", crate::fmi3::time_vr(md));
    for (ty, rust_ty, enum_name) in TYPES {
        let vs: Vec<&Var> = md.vars.iter().filter(|v| v.ty == ty).collect();
        enum_of(&mut out, ty, rust_ty, enum_name, &vs);
    }
    parameters(&mut out, &md.vars);
    crate::inputs::emit(&mut out, &md.vars);
    out
}

/// A value of type `ty` as a Rust literal.
pub(crate) fn literal(ty: &str, x: &str) -> String {
    match ty {
        "Boolean" => (x == "true" || x == "1").to_string(),
        "Real" => format!("{:?}f64", x.parse::<f64>().expect("checked")),
        _ => format!("{}i32", x.parse::<i32>().expect("checked")),
    }
}

fn optional(ty: &str, s: &Option<String>) -> String {
    s.as_deref().map_or("None".into(), |x| format!("Some({})", literal(ty, x)))
}

/// The enum of one FMI type and its `const fn` attributes.
fn enum_of(out: &mut String, ty: &str, rust_ty: &str, enum_name: &str, vs: &[&Var]) {
    let _ = writeln!(out, "\n/// The {ty} variables of `modelDescription.xml`.");
    let _ = writeln!(out, "#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]\npub enum {enum_name} {{");
    for v in vs {
        // The unit goes in backticks: bare `[N]` or `[m/s]` would be read as intra-doc links.
        let unit = v.unit.as_ref().map_or(String::new(), |u| format!(", `{u}`"));
        let _ = writeln!(out, "    /// `{}` (vr {}, {}, {}{unit})", v.name, v.vr, v.causality, v.variability);
        let _ = writeln!(out, "    {},", camel(&v.name));
    }
    let _ = writeln!(out, "}}\n\n#[allow(dead_code, unreachable_patterns, clippy::approx_constant, clippy::match_single_binding)]\nimpl {enum_name} {{");
    let _ = writeln!(out, "    /// Every variable of this type, in XML order.");
    let _ = write!(out, "    pub const ALL: [{enum_name}; {}] = [", vs.len());
    for v in vs {
        let _ = write!(out, "{enum_name}::{}, ", camel(&v.name));
    }
    let _ = writeln!(out, "];");
    let attribute = |out: &mut String, fname: &str, ret: &str, f: &dyn Fn(&Var) -> String| {
        let _ = writeln!(out, "    pub const fn {fname}(self) -> {ret} {{\n        match self {{");
        for v in vs {
            let _ = writeln!(out, "            {enum_name}::{} => {},", camel(&v.name), f(v));
        }
        let _ = writeln!(out, "            _ => unreachable!(),\n        }}\n    }}");
    };
    attribute(out, "vr", "u32", &|v| v.vr.to_string());
    attribute(out, "name", "&'static str", &|v| format!("{:?}", v.name));
    attribute(out, "causality", "Causality", &|v| format!("Causality::{}", camel(&v.causality)));
    let _ = writeln!(out, "    /// Name and causality, for the FMI layer.");
    let _ = writeln!(
        out,
        "    pub const fn info(self) -> VarInfo {{\n        VarInfo {{ name: self.name(), causality: self.causality() }}\n    }}"
    );
    attribute(out, "start", &format!("Option<{rust_ty}>"), &|v| optional(ty, &v.start));
    if ty == "Real" {
        // the checks made every Real carry a unit of UnitDefinitions
        attribute(out, "unit", "&'static str", &|v| format!("{:?}", v.unit.as_deref().unwrap_or_default()));
    }
    if ty != "Boolean" {
        attribute(out, "min", &format!("Option<{rust_ty}>"), &|v| optional(ty, &v.min));
        attribute(out, "max", &format!("Option<{rust_ty}>"), &|v| optional(ty, &v.max));
    }
    let _ = writeln!(out, "    /// The variable with this value reference, if any.");
    let _ = writeln!(out, "    pub const fn from_vr(vr: u32) -> Option<Self> {{\n        match vr {{");
    for v in vs {
        let _ = writeln!(out, "            {} => Some({enum_name}::{}),", v.vr, camel(&v.name));
    }
    let _ = writeln!(out, "            _ => None,\n        }}\n    }}\n}}");
}

/// A description as doc-comment text: brackets and angle brackets escaped, so that rustdoc reads
/// neither intra-doc links (`[A]`, the source tags) nor HTML tags.
pub(crate) fn doc_text(s: &str) -> String {
    s.replace('\\', "\\\\").replace('[', "\\[").replace(']', "\\]").replace('<', "&lt;").replace('>', "&gt;")
}

/// The `Parameters` struct: a field per parameter (the name in lower case), `Default` from the
/// start values, and access by variable and in bulk for the FMU state.
fn parameters(out: &mut String, vars: &[Var]) {
    let params: Vec<&Var> = vars.iter().filter(|v| v.causality == "parameter").collect();
    let _ = writeln!(
        out,
        "\n/// Every parameter of `modelDescription.xml`, its field named like the variable in lower case,"
    );
    let _ = writeln!(out, "/// in SI units. `Default` gives the start values.");
    let _ = writeln!(out, "#[derive(Clone, Copy, Debug, PartialEq)]\npub struct Parameters {{");
    for v in &params {
        let rust_ty = TYPES.iter().find(|t| t.0 == v.ty).expect("checked").1;
        let unit = v.unit.as_ref().map_or(String::new(), |u| format!(" (`{u}`)"));
        let _ = writeln!(out, "    /// `{}`{unit}: {}", v.name, doc_text(v.description.as_deref().unwrap_or("")));
        let _ = writeln!(out, "    pub {}: {rust_ty},", field(&v.name));
    }
    let _ = writeln!(
        out,
        "}}\n\n#[allow(dead_code, unreachable_patterns, clippy::match_single_binding)]\nimpl Parameters {{"
    );
    let _ = writeln!(out, "    /// The start values of `modelDescription.xml`.");
    let _ = writeln!(out, "    pub const START: Parameters = Parameters {{");
    for v in &params {
        let _ = writeln!(out, "        {}: {},", field(&v.name), literal(&v.ty, v.start.as_deref().expect("checked")));
    }
    let _ = writeln!(out, "    }};");
    for (ty, rust_ty, enum_name) in TYPES {
        let of_type: Vec<&&Var> = params.iter().filter(|v| v.ty == ty).collect();
        let lower = enum_name.trim_end_matches("Var").to_lowercase();
        let _ = writeln!(out, "    /// The field of a {ty} variable; `None` for one that is not a parameter.");
        let _ = writeln!(
            out,
            "    pub fn {lower}_mut(&mut self, v: {enum_name}) -> Option<&mut {rust_ty}> {{\n        match v {{"
        );
        for v in &of_type {
            let _ = writeln!(out, "            {enum_name}::{} => Some(&mut self.{}),", camel(&v.name), field(&v.name));
        }
        let _ = writeln!(out, "            _ => None,\n        }}\n    }}");
        let _ = writeln!(out, "    /// The value of a {ty} parameter; `None` for a variable that is not one.");
        let _ = writeln!(out, "    pub fn {lower}(&self, v: {enum_name}) -> Option<{rust_ty}> {{\n        match v {{");
        for v in &of_type {
            let _ = writeln!(out, "            {enum_name}::{} => Some(self.{}),", camel(&v.name), field(&v.name));
        }
        let _ = writeln!(out, "            _ => None,\n        }}\n    }}");
        let _ = writeln!(out, "    /// Every {ty} parameter's field, in XML order (the FMU state's layout).");
        let _ = writeln!(out, "    pub fn {lower}_fields_mut(&mut self) -> [&mut {rust_ty}; {}] {{", of_type.len());
        let list: Vec<String> = of_type.iter().map(|v| format!("&mut self.{}", field(&v.name))).collect();
        let _ = writeln!(out, "        [{}]\n    }}", list.join(", "));
    }
    let switches: Vec<&&Var> =
        params.iter().filter(|v| v.ty == "Boolean" && v.name.starts_with(SWITCH_PREFIX)).collect();
    let _ = writeln!(out, "    /// The switch `{SWITCH_PREFIX}<key>` (a Boolean parameter) of `key`, if there is one.");
    let _ = writeln!(out, "    pub fn switch(&self, key: &str) -> Option<bool> {{\n        match key {{");
    for v in switches {
        let _ = writeln!(out, "            {:?} => Some(self.{}),", &v.name[SWITCH_PREFIX.len()..], field(&v.name));
    }
    let _ = writeln!(out, "            _ => None,\n        }}\n    }}");
    let _ = writeln!(
        out,
        "}}\n\nimpl Default for Parameters {{\n    fn default() -> Self {{\n        Parameters::START\n    }}\n}}"
    );
    visit(out);
}

/// The parameters' part of the FMU state: Booleans, Integers, then Reals, each in XML order.
fn visit(out: &mut String) {
    let _ = writeln!(
        out,
        "\n/// The FMU state's layout of the parameters: Booleans, Integers, then Reals, each in XML order."
    );
    let _ = writeln!(out, "impl fmi_slave::snapshot::Visit for Parameters {{");
    let _ = writeln!(out, "    fn visit<V: fmi_slave::snapshot::Visitor>(&mut self, v: &mut V) {{");
    let _ = writeln!(
        out,
        "        for b in self.boolean_fields_mut() {{\n            fmi_slave::snapshot::boolean(v, b);\n        }}"
    );
    let _ = writeln!(
        out,
        "        for i in self.integer_fields_mut() {{\n            fmi_slave::snapshot::int32(v, i);\n        }}"
    );
    let _ = writeln!(out, "        for r in self.real_fields_mut() {{\n            v.real(r);\n        }}");
    let _ = writeln!(out, "    }}\n}}");
}
