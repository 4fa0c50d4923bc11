//! The checks of a model description that the FMU's code relies on, and the GUID as a fingerprint
//! of its variable table.

use crate::parse::Unknown;
use crate::parse::{ModelDescription, Var};
use crate::{camel, fail, field};
use std::collections::BTreeSet;
use std::fmt::Write as _;

/// Fails the build, naming the line, unless every variable is well-formed and the model structure
/// lists the outputs.
pub fn check(md: &ModelDescription) {
    let mut names = BTreeSet::new();
    let mut idents = BTreeSet::new();
    let mut fields = BTreeSet::new();
    let mut vrs = BTreeSet::new();
    for v in &md.vars {
        if !names.insert(v.name.clone()) {
            fail(v.line, format!("duplicate variable name {}", v.name));
        }
        if !idents.insert((v.ty.clone(), camel(&v.name))) {
            fail(v.line, format!("{}: its Rust identifier {} collides with another", v.name, camel(&v.name)));
        }
        if v.causality == "parameter" && !fields.insert(field(&v.name)) {
            fail(v.line, format!("{}: its field name {} collides with another parameter's", v.name, field(&v.name)));
        }
        if !vrs.insert((v.ty.clone(), v.vr)) {
            fail(v.line, format!("{}: valueReference {} used twice for type {}", v.name, v.vr, v.ty));
        }
        check_causality(v);
        check_type(v, md);
    }
    check_structure(md);
}

fn check_causality(v: &Var) {
    match (v.causality.as_str(), v.variability.as_str()) {
        ("parameter", "fixed" | "tunable") | ("input", "continuous" | "discrete") => {
            if v.start.is_none() {
                fail(v.line, format!("{}: {} needs a start value", v.name, v.causality));
            }
            // the generated `Inputs` holds Reals (the models' inputs are signals)
            if v.causality == "input" && v.ty != "Real" {
                fail(v.line, format!("{}: inputs are Real here", v.name));
            }
        }
        ("output", "continuous" | "discrete") => {
            if v.initial.as_deref() != Some("calculated") || v.start.is_some() {
                fail(v.line, format!("{}: outputs are initial=\"calculated\" without start", v.name));
            }
        }
        (c, va) => fail(v.line, format!("{}: causality {c} with variability {va} is not used here", v.name)),
    }
}

fn check_type(v: &Var, md: &ModelDescription) {
    if let Some(u) = &v.unit {
        if !md.has_unit(u) {
            fail(v.line, format!("{}: unit {u} is not in UnitDefinitions (add <Unit name=\"{u}\">)", v.name));
        }
    }
    if v.ty == "Real" && v.unit.is_none() {
        fail(v.line, format!("{}: a Real needs a unit", v.name));
    }
    if v.ty == "Boolean" {
        if v.start.as_deref().is_some_and(|s| !matches!(s, "true" | "false" | "1" | "0")) {
            fail(v.line, format!("{}: Boolean start must be true or false", v.name));
        }
        return;
    }
    let num = |s: &Option<String>| {
        s.as_ref()
            .map(|x| x.parse::<f64>().unwrap_or_else(|_| fail(v.line, format!("{}: {x} is not a number", v.name))))
    };
    if v.ty == "Integer" {
        for s in [&v.start, &v.min, &v.max].into_iter().flatten() {
            if s.parse::<i32>().is_err() {
                fail(v.line, format!("{}: {s} is not a 32-bit integer", v.name));
            }
        }
    }
    if let (Some(s), Some(lo)) = (num(&v.start), num(&v.min)) {
        if s < lo {
            fail(v.line, format!("{}: start {s} below min {lo}", v.name));
        }
    }
    if let (Some(s), Some(hi)) = (num(&v.start), num(&v.max)) {
        if s > hi {
            fail(v.line, format!("{}: start {s} above max {hi}", v.name));
        }
    }
}

/// Fails unless `ModelStructure` lists every output, in order, under `Outputs` and
/// `InitialUnknowns`, each with its `dependencies` declared (absent, they would mean "depends on
/// every known", an algebraic loop for masters that is not there): an output's on inputs alone;
/// an initial unknown's on inputs and parameters (the knowns of Initialization Mode; that every
/// parameter is listed, [`fixes`] checks: the outputs at rest follow from most parameters, and a
/// parameter closes no loop; which inputs, `tests/python/test_conformance.py` probes).
fn check_structure(md: &ModelDescription) {
    let output_indices: Vec<usize> = md.vars.iter().filter(|v| v.causality == "output").map(|v| v.index).collect();
    for (section, unknowns) in [("Outputs", &md.outputs), ("InitialUnknowns", &md.initial_unknowns)] {
        let listed: Vec<usize> = unknowns.iter().map(|o| o.index).collect();
        if listed != output_indices {
            fail(
                unknowns.first().map_or(1, |o| o.line),
                format!("ModelStructure/{section} lists {listed:?}, the outputs are {output_indices:?}"),
            );
        }
    }
    for u in &md.outputs {
        check_dependencies(md, u, &["input"]);
    }
    for u in &md.initial_unknowns {
        check_dependencies(md, u, &["input", "parameter"]);
    }
}

/// The parameters' indices that some initial unknown does not list among its dependencies.
fn undeclared_parameters(md: &ModelDescription) -> Vec<usize> {
    let declared = |u: &Unknown, p: usize| u.dependencies.as_ref().is_some_and(|d| d.contains(&p));
    let parameters = md.vars.iter().filter(|v| v.causality == "parameter").map(|v| v.index);
    parameters.filter(|&p| md.initial_unknowns.iter().any(|u| !declared(u, p))).collect()
}

/// What the author of the XML must write after an interface change, each said as the edit to make:
/// a new parameter's index in every initial unknown's dependencies, and the GUID of the new table.
/// Reported together, so that adding variables stops the build once.
pub fn fixes(md: &ModelDescription) -> Vec<String> {
    let mut fixes = Vec::new();
    let missing = undeclared_parameters(md);
    if !missing.is_empty() {
        let list = missing.iter().map(usize::to_string).collect::<Vec<_>>().join(" ");
        fixes.push(format!(
            "every initial unknown depends on every parameter (a known of Initialization Mode): append \"{list}\" to \
             the dependencies of each Unknown of ModelStructure/InitialUnknowns, in index order"
        ));
    }
    let expected = fingerprint(md);
    if md.guid != expected {
        fixes.push(format!(
            "guid is {} but the variable table's fingerprint is {expected}: set guid=\"{expected}\" (the interface \
             changed, so must the GUID)",
            md.guid
        ));
    }
    fixes
}

/// The declared dependencies of `u`, failing unless they are present, ascending and of variables
/// whose causality is one of `knowns`, with a `dependenciesKind` per dependency if any.
fn check_dependencies<'a>(md: &ModelDescription, u: &'a Unknown, knowns: &[&str]) -> &'a [usize] {
    let Some(deps) = &u.dependencies else {
        fail(u.line, format!("Unknown index {}: declare its dependencies (absent means \"on every known\")", u.index));
    };
    if !deps.windows(2).all(|w| w[0] < w[1]) {
        fail(u.line, format!("Unknown index {}: dependencies must be ascending, without repeats", u.index));
    }
    for d in deps {
        match md.by_index(*d) {
            Some(v) if knowns.contains(&v.causality.as_str()) => {}
            Some(v) => fail(
                u.line,
                format!(
                    "Unknown index {}: dependency {d} is {} ({}), not one of {knowns:?}",
                    u.index, v.name, v.causality
                ),
            ),
            None => fail(u.line, format!("Unknown index {}: dependency {d} is no variable's index", u.index)),
        }
    }
    if let Some(kinds) = &u.dependencies_kind {
        if kinds.split_whitespace().count() != deps.len() {
            fail(u.line, format!("Unknown index {}: one dependenciesKind per dependency", u.index));
        }
    }
    deps
}

/// FNV-1a, 64 bit: stable across Rust versions (std's hashers are not).
fn fnv1a(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The GUID the variable table gives: a fingerprint of the names, types, value references,
/// causalities and variabilities (not of descriptions or start values).
pub fn fingerprint(md: &ModelDescription) -> String {
    let mut table = md.model_identifier.clone();
    for v in &md.vars {
        let _ = write!(table, "|{}:{}:{}:{}:{}", v.name, v.ty, v.vr, v.causality, v.variability);
    }
    let (h1, h2) = (fnv1a(table.as_bytes(), 0), fnv1a(table.as_bytes(), 0x9e37_79b9_7f4a_7c15));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        h1 >> 32,
        (h1 >> 16) & 0xffff,
        h1 & 0xffff,
        h2 >> 48,
        h2 & 0xffff_ffff_ffff
    )
}

/// Fails the build, naming each edit to make, unless the XML needs none ([`fixes`]).
pub fn check_fixes(md: &ModelDescription) {
    let fixes = fixes(md);
    if !fixes.is_empty() {
        fail(2, fixes.join("; and "));
    }
}
