//! The engine's integration tests.
//!
//! One test program for the crate's integration tests, each file below a module with its own
//! concern (see its docs). One program, not one per file: each program is linked with the release
//! profile's link-time optimisation, and one per file cost CI several minutes. Run one module with
//! a filter: `cargo test --release --test integration MODULE::`.
mod common;

mod calibrate;
mod degenerate_records;
mod diagnose;
mod measurement_formats;
mod no_import_cycles;
mod parallel_runs;
mod record_traps;
