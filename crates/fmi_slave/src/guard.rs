//! The boundary helpers: every exported function runs inside [`ffi_guard`], so no panic unwinds
//! into the host; raw pointers become slices only after their null and length checks.

use std::panic::{catch_unwind, AssertUnwindSafe};

/// Runs `f`, turning a panic into `on_panic` (after `f`'s own cleanup by unwinding).
pub fn ffi_guard<T>(on_panic: T, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(on_panic)
}

/// A slice from an importer's (pointer, length) pair; `None` for a null pointer with n > 0.
///
/// # Safety
/// A non-null `ptr` must point to `n` valid, initialised elements that outlive the returned slice.
pub unsafe fn slice<'a, T>(ptr: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        Some(&[])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: non-null, and the caller guarantees n valid elements.
        Some(unsafe { std::slice::from_raw_parts(ptr, n) })
    }
}

/// A mutable slice from an importer's (pointer, length) pair.
///
/// # Safety
/// As [`slice`], and the memory must be writable and not aliased during the call.
pub unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        Some(&mut [])
    } else if ptr.is_null() {
        None
    } else {
        // SAFETY: non-null, and the caller guarantees n valid, writable, unaliased elements.
        Some(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
    }
}
