//! Why a truck's parameters or restored state are refused.

use crate::integration::RK4_STABLE_RADIUS;

/// A truck's parameters or restored state that the integration cannot take.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum SuspensionError {
    /// RK4 with steps of h_max could be unstable: `z` = h_max·|λ|max; `advice` names the
    /// parameters to change.
    #[error("h_max·|λ|max = {z:.3} exceeds RK4's stable {radius}: lower h_max, or {advice}", radius = RK4_STABLE_RADIUS)]
    Unstable { z: f64, advice: &'static str },
    #[error("the demand's past holds a number that is not finite")]
    PastNotFinite,
    #[error("the demand's past has an index beyond its ring")]
    PastIndex,
}
