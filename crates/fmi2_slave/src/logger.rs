//! Logging through the importer's callback, with the categories of `modelDescription.xml`.
//! Messages are formatted into a stack buffer: logging never allocates, so it is safe inside
//! fmi2DoStep. Messages of status Warning and worse are always passed on; `logEvents` messages only
//! when the importer switched that category on.

use crate::fmi2::{fmi2CallbackLogger, fmi2ComponentEnvironment, fmi2Status, fmi2Status_fmi2OK};
use std::ffi::{c_char, CStr, CString};
use std::fmt::{self, Write};

/// The log categories, in the order of `<LogCategories>`.
pub const CATEGORIES: [&CStr; 6] =
    [c"logEvents", c"logStatusWarning", c"logStatusDiscard", c"logStatusError", c"logStatusFatal", c"logAll"];

/// Category index of `logEvents`.
pub const LOG_EVENTS: usize = 0;

const BUFFER: usize = 1024;

/// Formats into a fixed buffer, truncating, escaping '%' (the message is the callback's format
/// string) and keeping room for the terminating NUL.
struct StackText {
    bytes: [u8; BUFFER],
    len: usize,
}

impl Write for StackText {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for &b in s.as_bytes() {
            let escaped: &[u8] = if b == b'%' {
                b"%%"
            } else if b == 0 {
                b"?"
            } else {
                std::slice::from_ref(&b)
            };
            if self.len + escaped.len() >= BUFFER {
                return Ok(());
            }
            self.bytes[self.len..self.len + escaped.len()].copy_from_slice(escaped);
            self.len += escaped.len();
        }
        Ok(())
    }
}

/// The importer's logger and what it wants to see.
pub struct Logger {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    /// Debug logging switched on, per category.
    enabled: [bool; CATEGORIES.len()],
}

impl Logger {
    pub fn new(callback: fmi2CallbackLogger, environment: fmi2ComponentEnvironment, name: CString, on: bool) -> Self {
        Logger { callback, environment, instance_name: name, enabled: [on; CATEGORIES.len()] }
    }

    /// fmi2SetDebugLogging: all categories when `names` is empty, else the named ones.
    pub fn set_debug_logging(&mut self, on: bool, names: &[&CStr]) -> Result<(), crate::Refusal> {
        if names.is_empty() {
            self.enabled = [on; CATEGORIES.len()];
            return Ok(());
        }
        for name in names {
            let k = CATEGORIES
                .iter()
                .position(|c| c == name)
                .ok_or_else(|| crate::Refusal::LogCategory(name.to_string_lossy().into_owned()))?;
            self.enabled[k] = on;
        }
        Ok(())
    }

    pub fn instance_name(&self) -> &CStr {
        &self.instance_name
    }

    /// Sends a message of `status` in category `category` (index into [`CATEGORIES`]).
    pub fn log(&self, status: fmi2Status, category: usize, args: fmt::Arguments) {
        let Some(callback) = self.callback else { return };
        let wanted = status != fmi2Status_fmi2OK || self.enabled[category] || self.enabled[CATEGORIES.len() - 1];
        if !wanted {
            return;
        }
        let mut text = StackText { bytes: [0; BUFFER], len: 0 };
        let _ = text.write_fmt(args);
        text.bytes[text.len] = 0;
        // SAFETY: the callback was supplied by the importer for this instance; all strings are
        // NUL-terminated and live for the call; the message contains no unescaped '%'.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                CATEGORIES[category].as_ptr(),
                text.bytes.as_ptr() as *const c_char,
            );
        }
    }
}
