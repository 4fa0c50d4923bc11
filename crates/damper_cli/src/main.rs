fn main() {
    std::process::exit(damper_cli::cli::main(std::env::args_os().skip(1)));
}
