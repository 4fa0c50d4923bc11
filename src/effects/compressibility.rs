//! Entrained air in the oil: the effective bulk modulus β_e(p) of `physics::fluid`, used for the
//! chamber pressures in `physics::plant`. Off: air-free oil, β_e = β_oil.

use super::{Effect, EffectInfo, FittedParameter};
use crate::physics::params::Parameters;

pub struct Compressibility;

static INFO: EffectInfo = EffectInfo {
    key: "compressibility",
    meaning: "oil with entrained air (off: air-free oil)",
    fitted: &[FittedParameter { name: "air_fraction", search: (1e-4, 0.2), log: true, plausible: (0.002, 0.1), grid: None }],
    other: &["n_polytropic"],
    hidden_range: (0.035, 0.05),
    signature: "error proportional to the force rate during transients, larger at low pressure and in compression, gone in steady state",
};

impl Effect for Compressibility {
    fn info(&self) -> &'static EffectInfo {
        &INFO
    }
    fn is_on(&self, p: &Parameters) -> bool {
        p.effect_compressibility
    }
}
