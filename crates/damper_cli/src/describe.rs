//! One-line descriptions the terminal summary and the report share.

use damper_engine::comparison::ModelSetup;
use damper_engine::parameters::{effects, EffectExt};

/// One line: effects off/on against the default, changed parameters, tare, filter and backend.
pub fn describe_model(setup: &ModelSetup) -> String {
    let defaults: Vec<(&str, bool)> = effects().map(|e| (e.key, e.default_on())).collect();
    let mut parts = Vec::new();
    for ((k, on), (_, d)) in setup.effects.iter().zip(&defaults) {
        if on != d {
            parts.push(format!("{}{}", if *on { "+" } else { "−" }, k));
        }
    }
    let on: Vec<&str> = setup.effects.iter().filter(|e| e.1).map(|e| e.0).collect();
    let mut s = if parts.is_empty() {
        format!("default effects ({})", on.join(", "))
    } else {
        format!("default {} → effects on: {}", parts.join(" "), on.join(", "))
    };
    let changed: Vec<String> = setup
        .changed
        .iter()
        .filter(|(n, _)| !n.starts_with("effect_") && *n != "control_mode" && *n != "tare_load_cell")
        .map(|(n, v)| format!("{n}={v}"))
        .collect();
    if !changed.is_empty() {
        s += &format!("; {}", changed.join(", "));
    }
    s += &format!("; tare_load_cell {}", setup.model.params.tare_load_cell);
    if let Some(fc) = setup.model.load_cell_lowpass_hz {
        s += &format!("; load-cell low-pass {fc} Hz");
    }
    s += &format!("; {}", setup.backend.describe());
    s
}
