fn main() {
    reset_sigpipe();
    std::process::exit(damper_cli::cli::main(std::env::args_os().skip(1)));
}

/// `damper compare … | head` should end quietly, as a Unix tool does, instead of panicking in
/// `print!` on the closed pipe: Rust ignores SIGPIPE by default, so restore the default action.
#[allow(unsafe_code)]
fn reset_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in main, before any thread exists; SIG_DFL is a valid handler.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
