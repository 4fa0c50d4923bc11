//! For an FMU crate's `build.rs`: reads its `modelDescription.xml` (the single source of truth for
//! the FMU's variables) with quick-xml, checks it, and generates `$OUT_DIR/model_description.rs`:
//!
//! - the GUID and the model identifier;
//! - one enum per FMI type (`RealVar`, `IntegerVar`, `BooleanVar`) with value reference, name,
//!   causality, start, min and max of every variable (and the unit of every Real);
//! - `Parameters`: one field per parameter, named like the variable in lower case and documented
//!   with its description and unit, `Default` from the start values, access by variable
//!   (`real_mut`, `real`, …) and every field of a type at once (`real_fields_mut`, the FMU
//!   state's layout). A new parameter is then one XML edit.
//!
//! The FMU crate maps the inputs and outputs in exhaustive `match`es, so a variable added to or
//! removed from the XML does not compile until the code handles it. The GUID must equal a
//! fingerprint of the variable table, so an interface change cannot keep a stale GUID. The
//! generated code refers to `Causality` and `VarInfo`, which the including module must bring into
//! scope (from `fmi2_slave`).

mod checks;
mod emit;
mod parse;

use std::path::PathBuf;

const XML: &str = "modelDescription.xml";

fn fail(line: usize, msg: impl AsRef<str>) -> ! {
    panic!("{XML}:{line}: {}", msg.as_ref());
}

/// The Rust identifier of a variable's enum variant: `D_piston` → `DPiston`.
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

/// The field of a parameter in `Parameters`: `D_piston` → `d_piston`.
fn field(name: &str) -> String {
    name.to_ascii_lowercase().replace(|c: char| !c.is_ascii_alphanumeric(), "_")
}

/// Checks `modelDescription.xml` in the crate's directory and writes `$OUT_DIR/model_description.rs`.
/// Panics (failing the build) with `modelDescription.xml:LINE: what is wrong`.
pub fn generate() {
    println!("cargo:rerun-if-changed={XML}");
    let src = std::fs::read_to_string(XML).unwrap_or_else(|e| panic!("{XML}: cannot read: {e}"));
    let md = parse::parse(&src);
    checks::check(&md);
    checks::check_guid(&md);
    let path = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("model_description.rs");
    std::fs::write(path, emit::emit(&md)).expect("OUT_DIR is writable");
}
