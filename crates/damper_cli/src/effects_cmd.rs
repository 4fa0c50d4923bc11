//! `damper effects`: the effect catalog as a table, or (`--json`) as the one export that other
//! tools read (the Python generators and scorers), so that nothing parses `src/effects/*.rs`.

use damper_engine::parameters::{effects, Candidacy, Effect as EffectInfo, EffectExt, FittedParameter, Start};
use serde_json::{json, Value};

/// The catalog as an aligned table: key, switch, default, parameters, meaning.
pub fn table() -> String {
    let rows: Vec<[String; 5]> = effects()
        .map(|e| {
            [
                e.key.to_string(),
                e.switch(),
                if e.default_on() { "on" } else { "off" }.to_string(),
                e.parameter_names().join(", "),
                e.meaning.to_string(),
            ]
        })
        .collect();
    let header = ["effect", "switch", "default", "parameters", "meaning"].map(String::from);
    let width = |k: usize| rows.iter().chain([&header]).map(|r| r[k].chars().count()).max().unwrap_or(0) + 2;
    let widths = [width(0), width(1), width(2), width(3)];
    let line = |r: &[String; 5]| {
        let mut s = String::new();
        for (cell, w) in r.iter().zip(widths) {
            s.push_str(&format!("{cell:<w$}"));
        }
        s.push_str(&r[4]);
        s + "\n"
    };
    std::iter::once(&header).chain(&rows).map(line).collect()
}

/// The catalog as JSON: every field of each effect's [`EffectInfo`].
pub fn json() -> String {
    let list: Vec<Value> = effects().map(effect_json).collect();
    serde_json::to_string_pretty(&list).expect("plain JSON") + "\n"
}

fn effect_json(e: &'static EffectInfo) -> Value {
    json!({
        "key": e.key,
        "switch": e.switch(),
        "default_on": e.default_on(),
        "meaning": e.meaning,
        "equation": e.equation,
        "code": { "file": e.code.file, "function": e.code.function },
        "fitted": e.fitted.iter().map(parameter_json).collect::<Vec<_>>(),
        "secondary": e.secondary.iter().map(parameter_json).collect::<Vec<_>>(),
        "other": e.other,
        "size_parameter": e.size_parameter(),
        "hidden_range": [e.hidden_range.0, e.hidden_range.1],
        "hide_with": {
            "set": e.hide_with.set.iter().map(|(n, v)| (n.to_string(), json!(v))).collect::<serde_json::Map<_, _>>(),
            "temperature_rise_K": e.hide_with.temperature_rise,
        },
        "candidacy": match e.candidacy {
            Candidacy::Always => "always",
            Candidacy::WhenOn => "when_on",
            Candidacy::WithTemperature => "with_temperature",
            Candidacy::Controlled => "controlled",
        },
        "signature": e.signature,
    })
}

fn parameter_json(f: &FittedParameter) -> Value {
    json!({
        "name": f.name,
        "search": [f.search.0, f.search.1],
        "log": f.log,
        "plausible": [f.plausible.0, f.plausible.1],
        "start": match f.start {
            Start::Model => json!("model"),
            Start::OfLargestStroke(share) => json!({ "of_largest_stroke": share }),
            Start::SameAs(name) => json!({ "same_as": name }),
        },
    })
}
