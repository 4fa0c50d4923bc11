//! Prints the FMI 3.0 model description generated from an FMU crate's FMI 2.0 one:
//!
//! ```text
//! cargo run --release -p fmi_codegen --bin fmi3-model-description -- crates/quarter_truck/modelDescription.xml
//! ```
//!
//! The packaging scripts (`scripts/package_fmu.py`) put its output into the FMI 3.0 FMUs.
use std::process::ExitCode;

fn main() -> ExitCode {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: fmi3-model-description PATH/modelDescription.xml");
        return ExitCode::from(2);
    };
    match std::fs::read_to_string(&path) {
        Ok(src) => {
            print!("{}", fmi_codegen::fmi3_model_description(&src));
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("fmi3-model-description: {path}: {e}");
            ExitCode::FAILURE
        }
    }
}
