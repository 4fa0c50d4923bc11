//! The checks of a model description that the FMU's code relies on, and the GUID as a fingerprint
//! of its variable table.

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
        check_type(v, &md.units);
    }
    check_structure(md);
}

fn check_causality(v: &Var) {
    match (v.causality.as_str(), v.variability.as_str()) {
        ("parameter", "fixed" | "tunable") | ("input", "continuous" | "discrete") => {
            if v.start.is_none() {
                fail(v.line, format!("{}: {} needs a start value", v.name, v.causality));
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

fn check_type(v: &Var, units: &BTreeSet<String>) {
    if let Some(u) = &v.unit {
        if !units.contains(u) {
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

fn check_structure(md: &ModelDescription) {
    let output_indices: Vec<usize> = md.vars.iter().filter(|v| v.causality == "output").map(|v| v.index).collect();
    let listed: Vec<usize> = md.outputs.iter().map(|o| o.0).collect();
    if listed != output_indices {
        fail(
            md.outputs.first().map_or(1, |o| o.1),
            format!("ModelStructure/Outputs lists {listed:?}, the outputs are {output_indices:?}"),
        );
    }
    if md.initial_unknowns != output_indices {
        fail(
            1,
            format!(
                "ModelStructure/InitialUnknowns lists {:?}, the outputs are {output_indices:?}",
                md.initial_unknowns
            ),
        );
    }
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

/// Fails the build unless the XML's GUID is the variable table's fingerprint, giving the GUID to set.
pub fn check_guid(md: &ModelDescription) {
    let expected = fingerprint(md);
    if md.guid != expected {
        fail(
            2,
            format!(
                "guid is {} but the variable table's fingerprint is {expected}: set guid=\"{expected}\" (the interface changed, so must the GUID)",
                md.guid
            ),
        );
    }
}
