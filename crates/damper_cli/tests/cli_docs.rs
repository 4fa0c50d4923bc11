//! docs/cli.md is the `damper` help, so that the reference cannot drift from the program: this
//! test renders it from the binary and fails when the file differs. After changing an option,
//! refresh it with `UPDATE_DOCS=1 cargo test --release -p damper_cli --test integration cli_docs::`.

use std::path::Path;
use std::process::Command;

fn help(args: &[&str]) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_damper")).args(args).output().expect("run damper");
    assert_eq!(o.status.code(), Some(0), "damper {args:?}");
    String::from_utf8(o.stdout).expect("UTF-8 help")
}

fn rendered() -> String {
    let mut md = String::from(
        "# The `damper` command line\n\n\
         Generated from `damper --help` and `damper help COMMAND` by `crates/damper_cli/tests/cli_docs.rs`\n\
         (a test fails when this page and the program differ). The method behind the commands is in\n\
         [diagnose.md](diagnose.md), the measurement file rules in\n\
         [../data/measurements/README.md](../data/measurements/README.md).\n",
    );
    let sections: [(&str, &[&str]); 5] = [
        ("damper", &["--help"]),
        ("damper diagnose", &["help", "diagnose"]),
        ("damper compare", &["help", "compare"]),
        ("damper generate", &["help", "generate"]),
        ("damper effects", &["help", "effects"]),
    ];
    for (title, args) in sections {
        md += &format!("\n## `{title}`\n\n```text\n{}```\n", help(args));
    }
    md
}

#[test]
fn docs_cli_md_is_the_program_s_help() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/cli.md");
    let expected = rendered();
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &expected).expect("write docs/cli.md");
    }
    let actual = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        actual == expected,
        "docs/cli.md differs from the program's help; refresh it with \
         UPDATE_DOCS=1 cargo test --release -p damper_cli --test integration cli_docs::"
    );
}
