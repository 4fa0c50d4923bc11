//! The effect catalog (`src/effects/`) and `modelDescription.xml` agree: every effect's switch
//! `effect_<key>` is a Boolean parameter that `is_on` reads, its parameters are Real parameters of
//! the XML, and its ranges nest (hidden values ⊂ plausible ⊂ search ⊂ the XML's min/max). An effect
//! added to the catalog but not to the XML (or the reverse) fails here with its name. Each effect
//! names the function that holds its equation, and the effect table of the docs is rendered from
//! the catalog, so neither can drift from the code.
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]

use semi_active_damper::effects::{ActiveEffects, PlantSignals, CATALOG};
use semi_active_damper::model_description::{BooleanVar, Causality, RealVar};
use semi_active_damper::physics::params::Parameters;

fn real_parameter(name: &str) -> RealVar {
    let v = RealVar::ALL.into_iter().find(|v| v.name() == name);
    let v = v.unwrap_or_else(|| panic!("{name} is not a variable of modelDescription.xml"));
    assert_eq!(v.causality(), Causality::Parameter, "{name}");
    v
}

#[test]
fn every_effect_has_its_switch_and_parameters_in_the_model_description() {
    let mut keys = Vec::new();
    for e in CATALOG {
        let info = e.info();
        assert!(!keys.contains(&info.key), "{} listed twice", info.key);
        keys.push(info.key);
        let switch = format!("effect_{}", info.key);
        let var = BooleanVar::ALL.into_iter().find(|v| v.name() == switch);
        let var = var.unwrap_or_else(|| panic!("{switch} is not in modelDescription.xml"));
        let mut p = Parameters::default();
        for on in [true, false] {
            *p.boolean_mut(var).expect("a parameter") = on;
            assert_eq!(e.is_on(&p), on, "{}: is_on does not read {switch}", info.key);
        }
        assert!(!info.fitted.is_empty() && info.fitted.len() <= 2, "{}: one or two fitted parameters", info.key);
        for f in info.fitted.iter().chain(info.secondary) {
            let v = real_parameter(f.name);
            let (lo, hi) = (v.min().unwrap_or(f64::NEG_INFINITY), v.max().unwrap_or(f64::INFINITY));
            assert!(lo <= f.search.0 && f.search.1 <= hi, "{}: search range outside the XML's", f.name);
            assert!(f.search.0 <= f.plausible.0 && f.plausible.1 <= f.search.1, "{}: plausible ⊄ search", f.name);
            assert!(!f.log || f.search.0 > 0.0, "{}: a log search needs a positive range", f.name);
        }
        let size = info.fitted[0];
        let (h0, h1) = info.hidden_range;
        assert!(size.plausible.0 <= h0 && h0 < h1 && h1 <= size.plausible.1, "{}: hidden ⊄ plausible", info.key);
        for name in info.other {
            real_parameter(name);
        }
    }
    // and the reverse: every effect switch of the XML has its file
    for v in BooleanVar::ALL {
        if let Some(key) = v.name().strip_prefix("effect_") {
            assert!(keys.contains(&key), "modelDescription.xml has {} but src/effects/ has no {key}", v.name());
        }
    }
}

/// Signals across the plant's regimes: velocities of both signs and near zero, strokes out to
/// ±0.9 m (an effect may act only beyond a stroke: an end stop, a dead band), both chambers
/// pressurised in turn, the oil cold and hot.
fn signal_grid() -> Vec<PlantSignals> {
    let mut grid = Vec::new();
    for v_damper in [-1.0, -0.05, 0.0, 0.05, 1.0] {
        for x_damper in [-0.9, -0.3, -0.03, 0.0, 0.03, 0.3, 0.9] {
            for (p_ext, p_comp, p_reservoir) in [(40e5, 5e5, 5e5), (3e5, 90e5, 6e5), (5e5, 5e5, 5e5)] {
                for (temperature, viscosity_ratio) in [(293.15, 1.0), (350.0, 0.14)] {
                    let x_spool = 1e-3;
                    grid.push(PlantSignals {
                        v_damper,
                        x_damper,
                        p_ext,
                        p_comp,
                        p_reservoir,
                        x_spool,
                        temperature,
                        viscosity_ratio,
                    });
                }
            }
        }
    }
    grid
}

#[test]
fn switched_off_effects_add_nothing() {
    let mut p = Parameters::default();
    for e in CATALOG {
        let var = BooleanVar::ALL.into_iter().find(|v| v.name() == format!("effect_{}", e.info().key)).unwrap();
        *p.boolean_mut(var).unwrap() = false;
    }
    let active = ActiveEffects::of(&p);
    for s in signal_grid() {
        assert_eq!(active.force(&p, &s), 0.0);
        assert_eq!(active.bypass_flow(&p, &s), 0.0);
        assert_eq!(active.base_flow(&p, &s), 0.0);
    }
    // friction opposes the motion: in tension when extending
    p.effect_seal_friction = true;
    p.effect_viscous_friction = true;
    let s = PlantSignals { v_damper: 0.4, temperature: 293.15, viscosity_ratio: 1.0, ..PlantSignals::ZERO };
    let f = ActiveEffects::of(&p).force(&p, &s);
    assert!((f - (p.f_coulomb * (0.4 / p.v_friction).tanh() + p.c_viscous * 0.4)).abs() < 1e-9, "{f}");
}

/// The plant calls an effect's force or flows only when its `terms` say it adds them: an effect
/// that writes one must declare it, or the plant would drop it; and one it declares must act
/// somewhere in the plant's regimes (at some signals of [`signal_grid`]).
/// An effect's force or flow at some signals.
type Hook<'a> = dyn Fn(&PlantSignals) -> f64 + 'a;

#[test]
fn an_effect_adds_only_the_terms_it_declares() {
    let mut p = Parameters::default();
    let grid = signal_grid();
    for e in CATALOG {
        let var = BooleanVar::ALL.into_iter().find(|v| v.name() == format!("effect_{}", e.info().key)).unwrap();
        *p.boolean_mut(var).unwrap() = true;
        let (key, terms, active) = (e.info().key, e.terms(), ActiveEffects::of(&p));
        let hooks: [(&str, bool, &Hook); 3] = [
            ("a force", terms.force, &|s| e.force(&p, s)),
            ("a bypass flow", terms.bypass_flow, &|s| e.bypass_flow(&p, s)),
            ("a base flow", terms.base_flow, &|s| e.base_flow(&p, s)),
        ];
        for (what, declared, hook) in hooks {
            let acts = grid.iter().any(|s| hook(s) != 0.0);
            assert_eq!(acts, declared, "{key}: declares {what}: {declared}, adds one at some signals: {acts}");
        }
        let listed = format!("{active:?}");
        let adds = terms.force || terms.bypass_flow || terms.base_flow;
        assert_eq!(listed.contains(&format!("\"{key}\"")), adds, "{listed}");
        *p.boolean_mut(var).unwrap() = false;
    }
}

#[test]
fn the_worked_example_in_the_docs_is_the_file() {
    let docs = include_str!("../docs/effects.md");
    let file = include_str!("../src/effects/viscous_friction.rs");
    assert!(docs.contains(file), "docs/effects.md must show src/effects/viscous_friction.rs verbatim");
}

/// `(name, is_method_of)` for every `fn` of a Rust source: `Some(type)` inside `impl … Type {`,
/// `None` at the top level. Line-based: enough for this crate's rustfmt-formatted files.
fn functions(src: &str) -> Vec<(String, Option<String>)> {
    let mut out = Vec::new();
    let mut impl_type = None;
    for line in src.lines() {
        if line.starts_with("impl") {
            // `impl Effect for SealFriction {` and `impl CubicMount {`: the type is the last word
            let head = line.trim_end_matches('{').trim_end();
            impl_type = head.rsplit(' ').next().map(str::to_string);
        } else if line.starts_with('}') {
            impl_type = None;
        }
        let trimmed = line.trim_start();
        let decl = trimmed.strip_prefix("pub ").unwrap_or(trimmed);
        if let Some(rest) = decl.strip_prefix("fn ") {
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let top_level = !line.starts_with(' ');
            out.push((name, if top_level { None } else { impl_type.clone() }));
        }
    }
    out
}

#[test]
fn every_effect_names_the_function_that_holds_its_equation() {
    for e in CATALOG {
        let info = e.info();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(info.code.file);
        let src = std::fs::read_to_string(&path)
            .unwrap_or_else(|err| panic!("{}: code.file {} cannot be read: {err}", info.key, info.code.file));
        let wanted = match info.code.function.split_once("::") {
            Some((ty, method)) => (method.to_string(), Some(ty.to_string())),
            None => (info.code.function.to_string(), None),
        };
        let found = functions(&src);
        assert!(
            found.contains(&wanted),
            "{}: {} has no function {} (its functions: {found:?})",
            info.key,
            info.code.file,
            info.code.function
        );
    }
}

#[test]
fn the_function_finder_tells_methods_from_free_functions() {
    let src = "pub fn free(x: f64) -> f64 {\n    x\n}\n\nimpl Effect for Thing {\n    fn force(&self) -> f64 {\n        0.0\n    }\n}\n";
    let found = functions(src);
    assert_eq!(found, [("free".to_string(), None), ("force".to_string(), Some("Thing".to_string()))]);
}

// --- the effect table of docs/effects.md and docs/physics.md §8, rendered from the catalog ------

const TABLE_START: &str = "<!-- effect table: rendered from src/effects/ by tests/effects.rs, do not edit -->";
const TABLE_END: &str = "<!-- end of the effect table -->";

/// A value in the unit a reader expects (ms, bar, mm/s, degrees), with four significant digits.
fn quantity(x: f64, unit: &str) -> String {
    let (factor, shown) = match unit {
        "s" => (1e3, "ms"),
        "Pa" => (1e-5, "bar"),
        "m/s" => (1e3, "mm/s"),
        "rad" => (180.0 / std::f64::consts::PI, "°"),
        "1" => (1.0, ""),
        "N.s/m" => (1.0, "N·s/m"),
        "N/m3" => (1.0, "N/m³"),
        "m3/(s.Pa)" => (1.0, "m³/(s·Pa)"),
        other => (1.0, other),
    };
    let value = format!("{:.3e}", x * factor).parse::<f64>().unwrap();
    let number = if value != 0.0 && (value.abs() >= 1e5 || value.abs() < 1e-3) {
        format!("{value:e}")
    } else {
        format!("{value}")
    };
    match shown {
        "" => number,
        "°" => format!("{number}°"),
        _ => format!("{number} {shown}"),
    }
}

/// `lo–hi unit` for a range in `unit`.
fn range(lo: f64, hi: f64, unit: &str) -> String {
    let (lo, hi) = (quantity(lo, unit), quantity(hi, unit));
    // the unit once, after the upper bound
    let lo = lo.split(' ').next().unwrap().trim_end_matches('°').to_string();
    format!("{lo}–{hi}")
}

fn render_effect_table() -> String {
    let mut out = String::from(TABLE_START);
    out.push_str(
        "\n| key | default | equation | code | fitted parameters: plausible range (default) | held | signature of the missing effect in r |\n|---|---|---|---|---|---|---|\n",
    );
    for e in CATALOG {
        let info = e.info();
        let switch = format!("effect_{}", info.key);
        let on = BooleanVar::ALL.into_iter().find(|v| v.name() == switch).and_then(|v| v.start()).unwrap();
        let fitted: Vec<String> = info
            .fitted
            .iter()
            .map(|f| (f, ""))
            .chain(info.secondary.iter().map(|f| (f, ", once kept")))
            .map(|(f, when)| {
                let v = real_parameter(f.name);
                let default = quantity(v.start().unwrap(), v.unit());
                format!("`{}` {} ({default}{when})", f.name, range(f.plausible.0, f.plausible.1, v.unit()))
            })
            .collect();
        let held: Vec<String> = info
            .other
            .iter()
            .map(|name| {
                let v = real_parameter(name);
                format!("`{name}` {}", quantity(v.start().unwrap(), v.unit()))
            })
            .collect();
        out.push_str(&format!(
            "| `{}` | {} | {} | `{}` in `{}` | {} | {} | {} |\n",
            info.key,
            if on { "on" } else { "off" },
            info.equation,
            info.code.function,
            info.code.file,
            fitted.join("; "),
            if held.is_empty() { "–".to_string() } else { held.join("; ") },
            info.signature
        ));
    }
    out.push_str(TABLE_END);
    out
}

/// The docs' effect tables are rendered from the catalog: with `UPDATE_DOCS=1` in the environment
/// this test writes the rendered block into both files (after a new effect, or a changed
/// `info()`), otherwise it fails where they differ.
#[test]
fn the_effect_tables_of_the_docs_are_the_catalog() {
    let rendered = render_effect_table();
    let update = std::env::var_os("UPDATE_DOCS").is_some_and(|v| v == "1");
    for file in ["docs/effects.md", "docs/physics.md"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let start = text.find(TABLE_START).unwrap_or_else(|| panic!("{file} has no line {TABLE_START}"));
        let end = text[start..].find(TABLE_END).unwrap_or_else(|| panic!("{file} has no line {TABLE_END}"));
        let block = &text[start..start + end + TABLE_END.len()];
        if update && block != rendered {
            std::fs::write(&path, text.replace(block, &rendered)).unwrap_or_else(|e| panic!("{file}: {e}"));
            continue;
        }
        assert!(
            block == rendered,
            "{file}'s effect table differs from src/effects/: run `UPDATE_DOCS=1 cargo test --release --test integration effects::` \
             to write it, or replace its block with:\n\n{rendered}\n"
        );
    }
}

#[test]
fn quantities_are_shown_in_the_readers_units() {
    assert_eq!(quantity(0.006, "s"), "6 ms");
    assert_eq!(quantity(0.85e5, "Pa"), "0.85 bar");
    assert_eq!(quantity(5e-4, "m/s"), "0.5 mm/s");
    assert_eq!(quantity(1.2042771838760873, "rad"), "69°");
    assert_eq!(quantity(1e7, "N/m"), "1e7 N/m");
    assert_eq!(quantity(5e-14, "m3/(s.Pa)"), "5e-14 m³/(s·Pa)");
    assert_eq!(quantity(0.025, "1"), "0.025");
    assert_eq!(range(50.0, 600.0, "N"), "50–600 N");
    assert_eq!(range(0.001, 0.006, "s"), "1–6 ms");
}

/// The model's sources outside their test modules (everything before a file's `#[cfg(test)]`).
fn model_sources() -> Vec<(std::path::PathBuf, String)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<(std::path::PathBuf, String)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let src = std::fs::read_to_string(&path).unwrap();
                let code = src.split("#[cfg(test)]").next().unwrap_or("").to_string();
                out.push((path, code));
            }
        }
    }
    let mut out = vec![];
    walk(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut out);
    out
}

/// Whether `code` calls the function `name` (`name(` or `.name(` not in its `fn` line).
fn calls(code: &str, name: &str) -> bool {
    code.lines().any(|line| {
        let line = line.split("//").next().unwrap_or("");
        line.match_indices(&format!("{name}(")).any(|(i, _)| {
            let before = &line[..i];
            let word_start = !before.ends_with(|c: char| c.is_alphanumeric() || c == '_');
            word_start && !before.trim_end().ends_with("fn")
        })
    })
}

#[test]
fn the_model_runs_the_function_each_effect_names() {
    // the catalog's reference is where a reader finds the equation: the model must run that very
    // function, not a copy of its formula (the flow force was once written out again in the plant)
    let sources = model_sources();
    assert!(sources.len() > 20, "the model's sources: {}", sources.len());
    for e in CATALOG {
        let info = e.info();
        let name = info.code.function.rsplit("::").next().unwrap();
        let callers: Vec<_> = sources.iter().filter(|(_, code)| calls(code, name)).map(|(p, _)| p).collect();
        assert!(!callers.is_empty(), "{}: nothing in src/ calls {}", info.key, info.code.function);
    }
    assert!(calls("let f = flow_force(g, a, dp);", "flow_force"));
    assert!(calls("x.push(1.0)", "push") && !calls("pub fn flow_force(g: f64) -> f64 {", "flow_force"));
    assert!(!calls("let g = flow_force_gain(a, b, c);", "flow_force") && !calls("// flow_force(a)", "flow_force"));
}
