//! A randomized FMI 2.0 and FMI 3.0 Co-Simulation importer: it loads the FMU binaries with dlopen
//! (one test binary cannot link them all: their exported C symbols have the same names) and drives
//! their C API with random, often illegal, call sequences, checking each answer against an
//! independent transcription of the standard's state table (docs/robustness.md).
#![allow(dead_code, non_upper_case_globals)]

mod calls;
pub mod library;
pub mod mirror;
pub mod model_info;
pub mod report;
pub mod rng;
pub mod sequence;
mod states;
pub mod watchdog;
