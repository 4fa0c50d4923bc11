//! Logging through the importer's callback, with the categories of `modelDescription.xml`.
//! Messages are formatted into a stack buffer: logging never allocates, so it is safe inside a
//! step. Messages of status Warning and worse are always passed on; `logEvents` messages only when
//! the importer switched that category on.
//!
//! The standards' callbacks differ: FMI 2.0's takes the instance name and reads the message as a
//! printf format string (so `%` is written `%%`); FMI 3.0's takes neither, and reads `#` as the
//! escape of value references (`#12#`), so `#` is written `##`.

use crate::fmi2::{fmi2CallbackLogger, fmi2ComponentEnvironment};
use crate::fmi3::{fmi3InstanceEnvironment, fmi3LogMessageCallback};
use crate::Status;
use std::ffi::{c_char, CStr, CString};
use std::fmt::{self, Write};

/// The log categories, in the order of `<LogCategories>`.
pub const CATEGORIES: [&CStr; 6] =
    [c"logEvents", c"logStatusWarning", c"logStatusDiscard", c"logStatusError", c"logStatusFatal", c"logAll"];

/// Category index of `logEvents`.
pub const LOG_EVENTS: usize = 0;

const BUFFER: usize = 1024;

/// Formats into a fixed buffer, truncating, doubling the callback's escape character and keeping
/// room for the terminating NUL.
struct StackText {
    bytes: [u8; BUFFER],
    len: usize,
    escape: u8,
}

impl Write for StackText {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for &b in s.as_bytes() {
            let doubled = [b, b];
            let escaped: &[u8] = if b == self.escape {
                &doubled
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

/// The importer's callback, as its standard defines it.
#[derive(Clone, Copy)]
pub enum Callback {
    Fmi2 { logger: fmi2CallbackLogger, environment: fmi2ComponentEnvironment },
    Fmi3 { log_message: fmi3LogMessageCallback, environment: fmi3InstanceEnvironment },
}

/// The importer's logger and what it wants to see.
pub struct Logger {
    callback: Callback,
    instance_name: CString,
    /// Debug logging switched on, per category.
    enabled: [bool; CATEGORIES.len()],
}

impl Logger {
    pub fn new(callback: Callback, name: CString, on: bool) -> Self {
        Logger { callback, instance_name: name, enabled: [on; CATEGORIES.len()] }
    }

    /// fmi2SetDebugLogging, fmi3SetDebugLogging: all categories when `names` is empty, else the
    /// named ones.
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
    pub fn log(&self, status: Status, category: usize, args: fmt::Arguments) {
        let wanted = status != Status::Ok || self.enabled[category] || self.enabled[CATEGORIES.len() - 1];
        if !wanted {
            return;
        }
        let escape = match self.callback {
            Callback::Fmi2 { .. } => b'%',
            Callback::Fmi3 { .. } => b'#',
        };
        let mut text = StackText { bytes: [0; BUFFER], len: 0, escape };
        let _ = text.write_fmt(args);
        text.bytes[text.len] = 0;
        let message = text.bytes.as_ptr() as *const c_char;
        let category = CATEGORIES[category].as_ptr();
        match self.callback {
            Callback::Fmi2 { logger: Some(logger), environment } => {
                // SAFETY: the callback was supplied by the importer for this instance; all strings
                // are NUL-terminated and live for the call; the message contains no unescaped '%'.
                unsafe { logger(environment, self.instance_name.as_ptr(), status.code(), category, message) }
            }
            Callback::Fmi3 { log_message: Some(log_message), environment } => {
                // SAFETY: as above; FMI 3.0's callback reads the message as plain text.
                unsafe { log_message(environment, status.code(), category, message) }
            }
            Callback::Fmi2 { logger: None, .. } | Callback::Fmi3 { log_message: None, .. } => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn formatted(escape: u8, args: fmt::Arguments) -> String {
        let mut text = StackText { bytes: [0; BUFFER], len: 0, escape };
        let _ = text.write_fmt(args);
        String::from_utf8(text.bytes[..text.len].to_vec()).unwrap()
    }

    #[test]
    fn each_standard_s_escape_character_is_doubled() {
        assert_eq!(formatted(b'%', format_args!("100 % of #3")), "100 %% of #3");
        assert_eq!(formatted(b'#', format_args!("100 % of #3")), "100 % of ##3");
        assert_eq!(formatted(b'#', format_args!("a\0b")), "a?b");
    }

    #[test]
    fn a_long_message_is_cut_with_room_for_the_nul() {
        let long = "x".repeat(2 * BUFFER);
        assert_eq!(formatted(b'%', format_args!("{long}")).len(), BUFFER - 1);
    }
}
