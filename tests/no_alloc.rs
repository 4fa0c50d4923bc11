//! fmi2DoStep, the getters and setters used every step, and the logging of a refused call never
//! touch the heap.
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
// A counting global allocator and the FMU's C API through raw pointers: the crate denies unsafe
// code (Cargo.toml), this file needs it.
#![allow(unsafe_code)]
mod common;

use common::*;
use fmi_slave::fmi2::{fmi2ComponentEnvironment, fmi2Status, fmi2String};
use semi_active_damper::model_description::RealVar;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Counts allocations per thread, so parallel tests do not disturb each other.
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: alloc and dealloc forward to System unchanged; the counter allocates nothing.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: the caller upholds GlobalAlloc::alloc's contract, which is System's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller upholds GlobalAlloc::dealloc's contract: ptr came from System.alloc with layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

static MESSAGES: AtomicUsize = AtomicUsize::new(0);

/// A logger that only counts (it must not allocate itself).
unsafe extern "C" fn counting_logger(
    _: fmi2ComponentEnvironment,
    _: fmi2String,
    _: fmi2Status,
    _: fmi2String,
    _: fmi2String,
) {
    MESSAGES.fetch_add(1, Ordering::Relaxed);
}

#[test]
fn do_step_does_not_allocate() {
    let f = Fmu::with_logger("no-alloc", counting_logger);
    f.initialise();
    let before = ALLOCATIONS.with(|n| n.get());
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        f.set(RealVar::VDamper, 0.4 * (15.0 * t).sin());
        f.set(RealVar::FDemand, 10e3 * (3.0 * t).sin());
        assert_eq!(f.step(t, 1e-3), OK);
        let _ = f.get(RealVar::FDamper);
    }
    let logged_before = MESSAGES.load(Ordering::Relaxed);
    assert_eq!(f.step(0.5, 1e-3), ERROR, "wrong communication point, logged");
    assert!(MESSAGES.load(Ordering::Relaxed) > logged_before);
    assert_eq!(ALLOCATIONS.with(|n| n.get()) - before, 0);
}
