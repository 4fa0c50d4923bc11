//! The C ABI damper_tools.runner calls through ctypes: one function, a job in, the record out.
//! Nothing here panics into the caller: a panic in the run is caught and reported as status 3.
#![allow(unsafe_code, reason = "the caller's pointers are read here, and only here")]

use crate::{job::Job, run, RunError};
use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The run completed; `record` holds it.
pub const OK: i32 = 0;
/// An FMU refused a call: the message is a JSON object of the instance, the call, the time (s) and
/// the FMU's reason.
pub const REFUSED: i32 = 1;
/// The job or the buffers are wrong (the message says which field).
pub const BAD_JOB: i32 = 2;
/// A bug in the runner: a panic, caught.
pub const INTERNAL: i32 = 3;

/// Writes `text` into the caller's buffer of `capacity` bytes, NUL-terminated, cut at a character
/// boundary where it does not fit.
fn write_message(text: &str, message: *mut c_char, capacity: usize) {
    if message.is_null() || capacity == 0 {
        return;
    }
    let mut n = text.len().min(capacity - 1);
    while !text.is_char_boundary(n) {
        n -= 1;
    }
    // SAFETY: the caller gives a writable buffer of `capacity` bytes; n + 1 <= capacity.
    unsafe {
        std::ptr::copy_nonoverlapping(text.as_ptr(), message.cast::<u8>(), n);
        *message.add(n) = 0;
    }
}

/// Runs the job `job_json` (UTF-8, NUL-terminated; the format of [`Job`]) with `n_inputs` input
/// series of `input_len` samples each at `inputs[0..n_inputs]`, writing (n_steps + 1) × recorded
/// values, row by row, to `record[0..record_len]`. Returns [`OK`], [`REFUSED`], [`BAD_JOB`] or
/// [`INTERNAL`]; for the last three the reason is in `message` (`message_capacity` bytes).
///
/// # Safety
///
/// `job_json` is a NUL-terminated string; `inputs` points to `n_inputs` pointers (or is null when
/// `n_inputs` is 0), each to `input_len` readable doubles; `record` to `record_len` writable
/// doubles; `message` to `message_capacity` writable bytes or is null. None of them is touched
/// after the call returns.
#[no_mangle]
pub unsafe extern "C" fn cosim_runner_run(
    job_json: *const c_char,
    inputs: *const *const f64,
    n_inputs: usize,
    input_len: usize,
    record: *mut f64,
    record_len: usize,
    message: *mut c_char,
    message_capacity: usize,
) -> i32 {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if job_json.is_null() || (n_inputs > 0 && inputs.is_null()) || (record_len > 0 && record.is_null()) {
            return Err(RunError::Job("a null pointer for the job, the inputs or the record".into()));
        }
        // SAFETY: the caller passes a NUL-terminated string (checked non-null above).
        let text = unsafe { CStr::from_ptr(job_json) }.to_str().map_err(|e| RunError::Job(e.to_string()))?;
        let job = Job::from_json(text)?;
        let series: Vec<&[f64]> = (0..n_inputs)
            .map(|i| {
                // SAFETY: inputs holds n_inputs pointers, each to input_len doubles (the contract).
                let p = unsafe { *inputs.add(i) };
                if p.is_null() {
                    return Err(RunError::Inputs(format!("series {i} is a null pointer")));
                }
                // SAFETY: as above; the slice lives no longer than this call.
                Ok(unsafe { std::slice::from_raw_parts(p, input_len) })
            })
            .collect::<Result<_, _>>()?;
        let out: &mut [f64] = if record_len == 0 {
            &mut []
        } else {
            // SAFETY: record points to record_len writable doubles, not aliased during the call.
            unsafe { std::slice::from_raw_parts_mut(record, record_len) }
        };
        run(&job, &series, out)
    }));
    let (status, text) = match outcome {
        Ok(Ok(())) => return OK,
        Ok(Err(RunError::Refused { instance, call, time, message })) => {
            let fields = serde_json::json!({"instance": instance, "call": call, "time": time, "message": message});
            (REFUSED, fields.to_string())
        }
        Ok(Err(e)) => (BAD_JOB, e.to_string()),
        Err(panic) => {
            let what =
                panic.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| panic.downcast_ref::<String>().cloned());
            (INTERNAL, format!("cosim_runner panicked: {}", what.unwrap_or_else(|| "(no message)".into())))
        }
    };
    write_message(&text, message, message_capacity);
    status
}
