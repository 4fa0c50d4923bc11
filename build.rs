//! Checks `modelDescription.xml` and generates the variable enums and GUID from it
//! (see `crates/fmi2_codegen`).
fn main() {
    fmi2_codegen::generate();
}
