//! Checks `modelDescription.xml` and generates the variable enums and GUID from it.
fn main() {
    fmi_codegen::generate();
}
