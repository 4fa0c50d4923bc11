//! The command line's integration tests.
//!
//! One test program for the crate's integration tests, each file below a module with its own
//! concern (see its docs). One program, not one per file: each program is linked with the release
//! profile's link-time optimisation, and one per file cost CI several minutes. Run one module with
//! a filter: `cargo test --release --test integration MODULE::`.
mod common;

mod calibrate_cmd;
mod cli;
mod cli_docs;
mod constant_channels;
mod csv_errors;
mod fmu_backend;
mod json_files;
mod passive;
mod rig_export_example;
mod round_trip;
mod unit_mapping;
