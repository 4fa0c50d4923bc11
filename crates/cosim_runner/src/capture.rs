//! The FMUs' log messages, kept on the thread that made the call: rust-fmi passes each message of
//! an FMU's logger callback to the `log` facade (target: the instance name), and a refused call's
//! error then carries the FMU's own reason. An FMU calls its logger on the caller's thread, inside
//! the call, so runs on several threads keep their messages apart.

use std::cell::RefCell;

/// Messages kept per thread (the newest; a run reads them right after the refused call).
const KEPT: usize = 16;

thread_local! {
    static MESSAGES: RefCell<Vec<(String, String)>> = const { RefCell::new(Vec::new()) };
}

struct Capture;

impl log::Log for Capture {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }

    fn log(&self, record: &log::Record) {
        // rust-fmi's own tracing (module fmi::…) is not an FMU's message
        if record.module_path() != Some("logger") || record.level() > log::Level::Warn {
            return;
        }
        MESSAGES.with_borrow_mut(|m| {
            if m.len() == KEPT {
                m.remove(0);
            }
            m.push((record.target().to_owned(), record.args().to_string()));
        });
    }

    fn flush(&self) {}
}

static CAPTURE: Capture = Capture;

/// Installs the capture as the process's logger, once; where another logger came first, the
/// refusals carry no FMU message.
pub fn install() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if log::set_logger(&CAPTURE).is_ok() {
            log::set_max_level(log::LevelFilter::Warn);
        }
    });
}

/// Forgets this thread's messages (at the start of a run).
pub fn clear() {
    MESSAGES.with_borrow_mut(Vec::clear);
}

/// The newest message `instance` logged on this thread.
pub fn last(instance: &str) -> Option<String> {
    MESSAGES.with_borrow(|m| m.iter().rev().find(|(who, _)| who == instance).map(|(_, msg)| msg.clone()))
}
