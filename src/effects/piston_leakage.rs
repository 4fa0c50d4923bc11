//! Laminar leakage through the gap between piston and bore, bypassing the valve.

use super::{Candidacy, CodeRef, Effect, EffectInfo, FittedParameter, HideWith, PlantSignals, Start, Terms};
use crate::physics::params::Parameters;

pub struct PistonLeakage;

static INFO: EffectInfo = EffectInfo {
    key: "piston_leakage",
    meaning: "leakage past the piston G_leak·(p_ext − p_comp) (off: none)",
    equation: "Q = G_leak·(p_ext − p_comp)/μ_r from the annulus to the full bore, bypassing the valve (μ_r: the viscosity over its value at T_ref, 1 unless oil_temperature is on)",
    code: CodeRef { file: "src/effects/piston_leakage.rs", function: "PistonLeakage::bypass_flow" },
    fitted: &[FittedParameter {
        name: "G_leak",
        search: (1e-15, 1e-10),
        log: true,
        plausible: (5e-14, 3e-12),
        grid: None,
        start: Start::Model,
    }],
    secondary: &[],
    other: &[],
    hidden_range: (3e-13, 1e-12),
    hide_with: HideWith::NOTHING,
    candidacy: Candidacy::Always,
    signature:
        "the model too strong at low velocity, roughly proportional to the pressure; lost motion after reversals",
};

impl Effect for PistonLeakage {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn terms(&self) -> Terms {
        Terms::BYPASS_FLOW
    }
    /// Q = G·(p_ext − p_comp)/μ_r: a narrow gap's laminar (Poiseuille) flow is linear in Δp and
    /// inversely proportional to the viscosity.
    fn bypass_flow(&self, p: &Parameters, s: &PlantSignals) -> f64 {
        p.g_leak / s.viscosity_ratio * (s.p_ext - s.p_comp)
    }
    fn bypass_flow_gradient(&self, p: &Parameters, s: &PlantSignals) -> PlantSignals {
        let g = p.g_leak / s.viscosity_ratio;
        PlantSignals { p_ext: g, p_comp: -g, ..PlantSignals::ZERO }
    }
}
