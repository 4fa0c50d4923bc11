fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    std::process::exit(damper_cli::cli::main(&args));
}
