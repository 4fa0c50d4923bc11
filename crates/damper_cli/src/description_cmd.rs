//! `damper describe`: what a damper description sets, printed, and as an SSP parameter set.

use damper_engine::description::Description;
use damper_engine::parameters::{get_parameter, lookup, Param, Value};
use damper_engine::ssv::Written;
use damper_engine::Error;
use std::path::Path;

/// The description of `path` and the parameters it sets, at their values after it is applied
/// (the last setting of a parameter wins), in the order first set.
pub fn described(path: &Path) -> Result<(Description, Vec<Written>), Error> {
    let d = Description::read(path)?;
    let mut p = Default::default();
    d.apply(&mut p)?;
    let mut written: Vec<Written> = Vec::new();
    for s in &d.settings {
        if written.iter().any(|w| w.name == s.parameter) {
            continue;
        }
        let unit = match lookup(&s.parameter)? {
            Param::Real(v) => v.unit().to_string(),
            _ => String::new(),
        };
        let value = get_parameter(&p, &s.parameter)?;
        written.push(Written {
            name: s.parameter.clone(),
            value,
            unit,
            uncertainty: None,
            status: format!("given ({})", s.source),
            start: None,
        });
    }
    Ok((d, written))
}

/// The terminal table: each parameter, its value and unit, where it comes from.
pub fn print(d: &Description, written: &[Written], ssv: Option<&Path>) {
    let name = if d.name.is_empty() { String::new() } else { format!(" ({})", d.name) };
    println!("damper describe {}{name}: {} parameters", d.path, written.len());
    println!("{:<26}{:>14}  {:<12}from", "parameter", "value", "unit");
    for w in written {
        let value = match w.value {
            Value::Real(x) => format!("{x:.5e}"),
            other => other.to_string(),
        };
        let from = w.status.trim_start_matches("given (").trim_end_matches(')');
        println!("{:<26}{:>14}  {:<12}{from}", w.name, value, w.unit);
    }
    if let Some(path) = ssv {
        println!("→ {} (SSP 1.0 parameter set: --params, or an FMI master's start values)", path.display());
    }
}
