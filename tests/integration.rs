//! The FMU crate's integration tests.
//!
//! One test program for the crate's integration tests, each file below a module with its own
//! concern (see its docs). One program, not one per file: each program is linked with the release
//! profile's link-time optimisation, and one per file cost CI several minutes. Run one module with
//! a filter: `cargo test --release --test integration MODULE::`.
// the C API's helpers, as the modules that call the C API allow unsafe code for themselves
#[allow(unsafe_code)]
mod common;
#[allow(unsafe_code)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod fmi_fuzz;

mod call_sequences;
mod effects;
mod fmi2_api;
mod import_fmu;
mod physics;
mod robustness;
mod solver;
