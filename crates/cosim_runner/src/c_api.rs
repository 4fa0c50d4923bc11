//! The C ABI damper_tools.runner calls through ctypes: a job in, the record out; and the tracking
//! fit's grid of squared errors. Nothing here panics into the caller: a panic is caught and reported
//! as status 3.
#![allow(unsafe_code, reason = "the caller's pointers are read here, and only here")]

use crate::tracking_fit::{first_order_lags, squared_errors, Direction};
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

/// The caller's `len` values at `p`, for the call: empty when `len` is 0 (whatever `p` is).
///
/// # Safety
///
/// Unless `len` is 0, `p` is non-null and points to `len` readable values, not written during the call.
unsafe fn caller_slice<'a, T>(p: *const T, len: usize) -> &'a [T] {
    if len == 0 {
        return &[];
    }
    // SAFETY: non-null and `len` readable values (the contract above).
    unsafe { std::slice::from_raw_parts(p, len) }
}

/// [`caller_slice`] for values the call writes.
///
/// # Safety
///
/// Unless `len` is 0, `p` is non-null and points to `len` writable values, not aliased during the call.
unsafe fn caller_slice_mut<'a, T>(p: *mut T, len: usize) -> &'a mut [T] {
    if len == 0 {
        return &mut [];
    }
    // SAFETY: non-null and `len` writable, unaliased values (the contract above).
    unsafe { std::slice::from_raw_parts_mut(p, len) }
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
        // SAFETY: the pointers are non-null where their counts are not 0 (checked above) and, by the
        // contract, point to n_inputs pointers and record_len unaliased writable doubles.
        let (pointers, out) = unsafe { (caller_slice(inputs, n_inputs), caller_slice_mut(record, record_len)) };
        let series: Vec<&[f64]> = pointers
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                if p.is_null() {
                    return Err(RunError::Inputs(format!("series {i} is a null pointer")));
                }
                // SAFETY: non-null, and each series has input_len doubles (the contract).
                Ok(unsafe { caller_slice(p, input_len) })
            })
            .collect::<Result<_, _>>()?;
        run(&job, &series, out)
    }));
    report(outcome, message, message_capacity)
}

/// The status of a call and its reason, written to the caller's `message` buffer.
fn report(outcome: std::thread::Result<Result<(), RunError>>, message: *mut c_char, message_capacity: usize) -> i32 {
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

/// The tracking fit's grid ([`squared_errors`]): `lags` holds `n_bandwidths` rows of `n_samples`
/// doubles, `force` `n_samples` doubles, `samples` `n_indices` sample indices; `extension` is 1 for
/// the extension samples (the model max(lag, 0)) and 0 for compression (min(lag, 0)); the sums are
/// written to `out`, `n_bandwidths` × `n_delays` doubles row by row. Returns [`OK`], [`BAD_JOB`]
/// (shapes or indices wrong, the reason in `message`) or [`INTERNAL`].
///
/// # Safety
///
/// Each pointer points to as many readable (for `out`, writable) values as its count says, and
/// `message` to `message_capacity` writable bytes or is null; none is touched after the call returns.
#[no_mangle]
pub unsafe extern "C" fn cosim_runner_tracking_sse(
    lags: *const f64,
    n_bandwidths: usize,
    n_samples: usize,
    force: *const f64,
    samples: *const usize,
    n_indices: usize,
    n_delays: usize,
    extension: i32,
    out: *mut f64,
    message: *mut c_char,
    message_capacity: usize,
) -> i32 {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if lags.is_null() || force.is_null() || out.is_null() || (n_indices > 0 && samples.is_null()) {
            return Err(RunError::TrackingFit("a null pointer".into()));
        }
        let n_lags = n_bandwidths.checked_mul(n_samples);
        let n_out = n_bandwidths.checked_mul(n_delays);
        let (Some(n_lags), Some(n_out)) = (n_lags, n_out) else {
            return Err(RunError::TrackingFit("sizes overflow".into()));
        };
        // SAFETY: each pointer is non-null where its count is not 0 (checked above) and points to as
        // many values as its count says (the contract); `out` is not aliased.
        let (lags, force, samples, out) = unsafe {
            (
                caller_slice(lags, n_lags),
                caller_slice(force, n_samples),
                caller_slice(samples, n_indices),
                caller_slice_mut(out, n_out),
            )
        };
        let direction = if extension != 0 { Direction::Extension } else { Direction::Compression };
        squared_errors(lags, force, samples, n_delays, direction, out)
    }));
    report(outcome, message, message_capacity)
}

/// The tracking fit's lags ([`first_order_lags`]): `demand` holds `n_samples` doubles, `poles`
/// `n_poles`; `out` receives `n_poles` rows of `n_samples` doubles. Returns [`OK`], [`BAD_JOB`] (the
/// reason in `message`) or [`INTERNAL`].
///
/// # Safety
///
/// Each pointer points to as many readable (for `out`, writable) values as its count says, and
/// `message` to `message_capacity` writable bytes or is null; none is touched after the call returns.
#[no_mangle]
pub unsafe extern "C" fn cosim_runner_first_order_lags(
    demand: *const f64,
    n_samples: usize,
    poles: *const f64,
    n_poles: usize,
    out: *mut f64,
    message: *mut c_char,
    message_capacity: usize,
) -> i32 {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        if demand.is_null() || poles.is_null() || out.is_null() {
            return Err(RunError::TrackingFit("a null pointer".into()));
        }
        let Some(n_out) = n_poles.checked_mul(n_samples) else {
            return Err(RunError::TrackingFit("sizes overflow".into()));
        };
        // SAFETY: each pointer is non-null (checked above) and points to as many values as its count
        // says (the contract); `out` is not aliased.
        let (demand, poles, out) =
            unsafe { (caller_slice(demand, n_samples), caller_slice(poles, n_poles), caller_slice_mut(out, n_out)) };
        first_order_lags(demand, poles, out)
    }));
    report(outcome, message, message_capacity)
}
