//! The generated `Inputs` struct: the model's inputs as fields named like the variables, an array
//! per name of structured inputs (`front_left.z_road`, `front_right.z_road`, … → `z_road`), with
//! their start values, access by variable and the FMU state's layout. A model then holds its
//! inputs in this struct, so an input added to the XML is a field without a hand-written mapping.

use crate::emit::{doc_text, literal};
use crate::parse::Var;
use crate::{camel, field};
use std::fmt::Write as _;

/// One field of `Inputs`: a scalar input, or the inputs of one name under several parts
/// of a structured name (`front_left.z_road`, `front_right.z_road`, …), an array in XML order.
struct InputField<'a> {
    name: String,
    elements: Vec<&'a Var>,
    array: bool,
}

/// The inputs grouped into fields: by name, or by the last part of a structured name.
fn input_fields(vars: &[Var]) -> Vec<InputField<'_>> {
    let mut fields: Vec<InputField<'_>> = Vec::new();
    for v in vars.iter().filter(|v| v.causality == "input") {
        let (array, leaf) = match v.name.rsplit_once('.') {
            Some((_, leaf)) => (true, leaf),
            None => (false, v.name.as_str()),
        };
        let name = field(leaf);
        match fields.iter_mut().find(|f| f.name == name) {
            Some(f) if f.array && array => f.elements.push(v),
            Some(_) => crate::fail(v.line, format!("input {}: its field {name} is another input's too", v.name)),
            None => fields.push(InputField { name, elements: vec![v], array }),
        }
    }
    fields
}

/// The `Inputs` struct: a field per Real input, named like the variable in lower case (an array per
/// name of structured inputs, `part.name`, one element per part in XML order), `START` and
/// `Default` from the start values, access by variable, and the FMU state's layout of the inputs.
pub fn emit(out: &mut String, vars: &[Var]) {
    let fields = input_fields(vars);
    let count: usize = fields.iter().map(|f| f.elements.len()).sum();
    let _ = writeln!(
        out,
        "\n/// Every input of `modelDescription.xml`, its field named like the variable in lower case (the"
    );
    let _ = writeln!(out, "/// inputs `part.name` of a structured name: the array `name`, an element per part in XML");
    let _ = writeln!(out, "/// order), in SI units. `Default` gives the start values.");
    let _ = writeln!(out, "#[derive(Clone, Copy, Debug, PartialEq)]\npub struct Inputs {{");
    for f in &fields {
        let v = f.elements[0];
        let unit = v.unit.as_ref().map_or(String::new(), |u| format!(" (`{u}`)"));
        let description = doc_text(v.description.as_deref().unwrap_or(""));
        if f.array {
            let parts: Vec<&str> = f.elements.iter().map(|e| e.name.rsplit_once('.').map_or("", |p| p.0)).collect();
            let leaf = v.name.rsplit_once('.').map_or("", |p| p.1);
            let _ = writeln!(
                out,
                "    /// `<part>.{leaf}`{unit} for the parts {} in this order; `{}`: {description}",
                parts.join(", "),
                v.name
            );
        } else {
            let _ = writeln!(out, "    /// `{}`{unit}: {description}", v.name);
        }
        let ty = if f.array { format!("[f64; {}]", f.elements.len()) } else { "f64".into() };
        let _ = writeln!(out, "    pub {}: {ty},", f.name);
    }
    let _ =
        writeln!(out, "}}\n\n#[allow(dead_code, unreachable_patterns, clippy::match_single_binding)]\nimpl Inputs {{");
    let _ = writeln!(out, "    /// The start values of `modelDescription.xml`.");
    let _ = writeln!(out, "    pub const START: Inputs = Inputs {{");
    for f in &fields {
        let starts: Vec<String> =
            f.elements.iter().map(|e| literal("Real", e.start.as_deref().expect("checked"))).collect();
        let value = if f.array { format!("[{}]", starts.join(", ")) } else { starts.join("") };
        let _ = writeln!(out, "        {}: {value},", f.name);
    }
    let _ = writeln!(out, "    }};");
    let place = |f: &InputField<'_>, k: usize| if f.array { format!("{}[{k}]", f.name) } else { f.name.clone() };
    for (signature, take) in [
        ("    /// The field of an input; `None` for a variable that is not one.\n    pub fn real_mut(&mut self, v: RealVar) -> Option<&mut f64>", "&mut self."),
        ("    /// The value of an input; `None` for a variable that is not one.\n    pub fn real(&self, v: RealVar) -> Option<f64>", "self."),
    ] {
        let _ = writeln!(out, "{signature} {{\n        match v {{");
        for f in &fields {
            for (k, e) in f.elements.iter().enumerate() {
                let _ = writeln!(out, "            RealVar::{} => Some({take}{}),", camel(&e.name), place(f, k));
            }
        }
        let _ = writeln!(out, "            _ => None,\n        }}\n    }}");
    }
    let _ = writeln!(
        out,
        "    /// Every input's field: field by field, an array's elements in order (the FMU state's layout)."
    );
    let _ = writeln!(out, "    pub fn fields_mut(&mut self) -> [&mut f64; {count}] {{");
    // destructured: the borrow checker takes disjoint fields, not the elements of an indexed array
    let binding = |f: &InputField<'_>, k: usize| if f.array { format!("{}_{k}", f.name) } else { f.name.clone() };
    let pattern: Vec<String> = fields
        .iter()
        .map(|f| match f.array {
            true => {
                format!("{}: [{}]", f.name, (0..f.elements.len()).map(|k| binding(f, k)).collect::<Vec<_>>().join(", "))
            }
            false => f.name.clone(),
        })
        .collect();
    let list: Vec<String> = fields.iter().flat_map(|f| (0..f.elements.len()).map(move |k| binding(f, k))).collect();
    let _ = writeln!(
        out,
        "        let Inputs {{ {} }} = self;\n        [{}]\n    }}\n}}",
        pattern.join(", "),
        list.join(", ")
    );
    let _ =
        writeln!(out, "\nimpl Default for Inputs {{\n    fn default() -> Self {{\n        Inputs::START\n    }}\n}}");
    let _ = writeln!(out, "\n/// The FMU state's layout of the inputs: [`Inputs::fields_mut`].");
    let _ = writeln!(out, "impl fmi_slave::snapshot::Visit for Inputs {{");
    let _ = writeln!(out, "    fn visit<V: fmi_slave::snapshot::Visitor>(&mut self, v: &mut V) {{");
    let _ = writeln!(out, "        for x in self.fields_mut() {{\n            v.real(x);\n        }}\n    }}\n}}");
}
