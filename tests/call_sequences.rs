//! Random FMI call sequences against the FMU binaries of both standards, FMI 2.0 and FMI 3.0
//! (dlopen, in this process): illegal orders,
//! unknown references, NaN, infinite, huge and denormal values, zero, negative and huge steps and
//! times, random and mutated serialized states, states passed to the other FMU, many live
//! instances, resets mid-run. Every status is checked against the standard's state table, every
//! value an OK call returns must be finite, and a call running over 1 s fails the test.
//!
//! The test command runs a fixed set of seeds; a long run is
//!
//! ```text
//! CALL_SEQUENCES=100000 cargo test --release --test integration call_sequences:: -- --nocapture
//! ```
//!
//! (`call_sequences::fmi2` or `call_sequences::fmi3` for one standard).
//!
//! (`CALL_SEQUENCES_SEED` picks another first seed; see docs/robustness.md).
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
// dlopen and the FMUs' C API through raw pointers: the crate denies unsafe code (Cargo.toml),
// this file needs it.
#![allow(unsafe_code)]
use crate::fmi_fuzz;

use fmi_fuzz::library::{fmus, Standard};
use fmi_fuzz::report::Report;
use fmi_fuzz::sequence::Fuzzer;
use fmi_fuzz::watchdog;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Sequences per seed in the test command: the whole test stays well under a minute.
const SEQUENCES_PER_SEED: u64 = 5000;
const SEEDS: [u64; 4] = [1, 2, 3, 4];

fn env(name: &str) -> Option<u64> {
    std::env::var(name).ok().map(|v| v.parse().unwrap_or_else(|_| panic!("{name}={v}: not a count")))
}

/// Runs the seeds on the FMUs of `standard` and fails on any non-standard answer, panic,
/// non-finite value after OK or hang.
fn random_call_sequences(standard: Standard) {
    fmus(standard); // build and load before the clock starts
    let (seeds, per_seed): (Vec<u64>, u64) = match env("CALL_SEQUENCES") {
        Some(n) => (vec![env("CALL_SEQUENCES_SEED").unwrap_or(1)], n),
        None => (SEEDS.to_vec(), SEQUENCES_PER_SEED),
    };
    let started = Instant::now();
    let (report, longest) = watchdog::run(move |dog| {
        let mut total = Report::default();
        for seed in seeds {
            total.add(Fuzzer::new(standard, seed, &dog).run(per_seed));
        }
        (total, dog.longest.load(Ordering::Relaxed))
    });
    println!(
        "{standard:?}: {} in {:.1} s; longest call {:.1} ms; 0 hangs (no call over {:?})",
        report.summary(),
        started.elapsed().as_secs_f64(),
        longest as f64 * 1e-6,
        watchdog::limit()
    );
    assert!(report.is_clean(), "{}\nfirst failures:\n{}", report.summary(), report.failures.join("\n"));
    // the run reached the interesting states, not just refusals
    let s = &report.statuses;
    assert!(s[0] > report.calls / 4 && s[2] > 0 && s[3] > report.calls / 10, "{}", report.summary());
}

#[test]
fn fmi2_random_call_sequences_get_standard_answers_in_bounded_time() {
    random_call_sequences(Standard::Fmi2);
}

#[test]
fn fmi3_random_call_sequences_get_standard_answers_in_bounded_time() {
    random_call_sequences(Standard::Fmi3);
}
