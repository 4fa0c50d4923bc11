//! Checks `modelDescription.xml` and generates the variable enums and GUID from it.
fn main() {
    fmi2_codegen::generate();
}
