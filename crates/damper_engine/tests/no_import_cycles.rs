//! No import cycles between the modules of damper_engine or of damper_cli: a module that uses
//! another must not be used by it, directly or through others, so that each can be read, tested
//! and moved on its own. The graph is built from the `crate::` paths in each `src/*.rs`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// The modules of the crate `text` is from that it names: `crate::x::…`, `crate::x` and each
/// top-level name of `crate::{x, y::z}` (here `x` and `y`).
fn used_modules(text: &str) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    for (i, _) in text.match_indices("crate::") {
        // `damper_crate::` or the like is another path, not this crate's
        if text[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let rest = &text[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // the names at depth 0 of the group, up to its closing brace
            let (mut depth, mut start) = (0, true);
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => start = true,
                    c if start && !c.is_whitespace() => {
                        start = false;
                        used.insert(ident(&group[k..]));
                    }
                    _ => {}
                }
            }
        } else {
            used.insert(ident(rest));
        }
    }
    used
}

/// The module graph of the crate at `dir`: module → the other modules it uses.
fn graph(dir: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut g = BTreeMap::new();
    for entry in std::fs::read_dir(dir.join("src")).expect("src") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("rs") {
            continue;
        }
        let name = path.file_stem().and_then(|s| s.to_str()).expect("a file name").to_string();
        let text = std::fs::read_to_string(&path).expect("read");
        // comments may name any module (doc links to the callers, say) without using it
        let code: String = text.lines().map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n");
        let mut used = used_modules(&code);
        used.remove(&name);
        g.insert(name, used);
    }
    g
}

/// A cycle of `g` as the list of its modules, the first repeated at the end; None if it has none.
fn cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        m: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(k) = path.iter().position(|p| p == m) {
            let mut c = path[k..].to_vec();
            c.push(m.to_string());
            return Some(c);
        }
        if done.contains(m) {
            return None;
        }
        path.push(m.to_string());
        for next in g.get(m).into_iter().flatten().filter(|n| g.contains_key(*n)) {
            if let Some(c) = visit(next, g, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    g.keys().find_map(|m| visit(m, g, &mut Vec::new(), &mut done))
}

fn assert_acyclic(krate: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(krate);
    let g = graph(&dir);
    assert!(g.len() > 5, "{krate}: only {} modules found", g.len());
    if let Some(c) = cycle(&g) {
        panic!("{krate}: import cycle {}", c.join(" → "));
    }
}

#[test]
fn damper_engine_has_no_import_cycle() {
    assert_acyclic("damper_engine");
}

#[test]
fn damper_cli_has_no_import_cycle() {
    assert_acyclic("damper_cli");
}

#[test]
fn the_scan_sees_grouped_and_inline_paths_and_the_search_finds_a_cycle() {
    let text = "use crate::{a, b::{x, y}, c::z};\nfn f() { crate::d::g(); }\nuse damper_crate::e;";
    let names: Vec<String> = used_modules(text).into_iter().collect();
    assert_eq!(names, ["a", "b", "c", "d"]);
    let g: BTreeMap<String, BTreeSet<String>> = [("p", "q"), ("q", "r"), ("r", "p")]
        .into_iter()
        .map(|(m, n)| (m.to_string(), BTreeSet::from([n.to_string()])))
        .collect();
    assert_eq!(cycle(&g).map(|c| c.join(" ")), Some("p q r p".into()));
}
