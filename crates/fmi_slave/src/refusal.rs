//! Why a call into a [`Model`](crate::Model) is refused: one enum for the FMI layer and the
//! models' slaves, displayed as the message the master's log receives. Every variant but
//! [`Refusal::Model`] and [`Refusal::Restored`] is built without allocating, so a refused
//! `fmi2SetReal` or `fmi3SetFloat64` inside a simulation loop costs no heap.

use std::error::Error;

/// A refused call: the message a master's log receives, mostly built without allocating.
#[derive(Debug, thiserror::Error)]
pub enum Refusal {
    #[error("unknown value reference {0}")]
    UnknownReference(u32),
    #[error("{name} = {value} refused: not a finite number")]
    NotFinite { name: &'static str, value: f64 },
    #[error("{name} = {value} refused: outside [{lo}, {hi}]")]
    OutOfRange { name: &'static str, value: f64, lo: f64, hi: f64 },
    #[error("{name} = {value} refused: outside [{lo}, {hi}]")]
    IntegerOutOfRange { name: &'static str, value: i32, lo: i32, hi: i32 },
    #[error("{0} is an output and cannot be set")]
    Output(&'static str),
    #[error("{0} cannot be set")]
    NotSettable(&'static str),
    /// An output the model cannot compute at the present inputs.
    #[error("{name} = {value} is not finite (inputs out of the model's reach)")]
    OutputNotFinite { name: &'static str, value: f64 },
    #[error("canInterpolateInputs is false")]
    NoInputDerivatives,
    #[error("{name}: derivative of order {order} refused: inputs move along ramps (order 1)")]
    DerivativeOrder { name: &'static str, order: i32 },
    #[error("{name}: derivative {value} refused: not a finite number")]
    DerivativeNotFinite { name: &'static str, value: f64 },
    /// An input whose derivative the model does not take, with why.
    #[error("{name}: no derivative taken ({why})")]
    NoDerivative { name: &'static str, why: &'static str },
    #[error("tolerance {0} refused: a relative tolerance must be a positive number")]
    Tolerance(f64),
    #[error("unknown log category {0:?}")]
    LogCategory(String),
    /// A serialised FMU state that [`snapshot::from_bytes`](crate::snapshot::from_bytes) cannot read.
    #[error("serialized FMU state rejected: {0}")]
    Unreadable(#[from] Unreadable),
    /// A state that reads but is not one the model could have made.
    #[error("serialized FMU state rejected: {0}")]
    Restored(Box<Refusal>),
    /// A number of the state, or the time, that is not finite.
    #[error("{0} is not finite")]
    StateNotFinite(&'static str),
    /// Parts of a state that do not agree with its parameters.
    #[error("{0} do not match the parameters")]
    Inconsistent(&'static str),
    /// The model's own error (parameters that do not go together, an unstable integration), with
    /// its own message.
    #[error(transparent)]
    Model(Box<dyn Error + Send + Sync>),
}

impl Refusal {
    /// The model's own error `e`.
    pub fn model(e: impl Error + Send + Sync + 'static) -> Self {
        Refusal::Model(Box::new(e))
    }

    /// `self` as the reason a restored state is rejected.
    pub fn restored(self) -> Self {
        Refusal::Restored(Box::new(self))
    }
}

/// Why [`snapshot::from_bytes`](crate::snapshot::from_bytes) refuses a byte string.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Unreadable {
    #[error("shorter than its header")]
    ShorterThanHeader,
    #[error("not a state of this model (bad magic)")]
    BadMagic,
    #[error("unknown format version")]
    FormatVersion,
    #[error("made by a model with another GUID")]
    OtherGuid,
    #[error("payload length does not match")]
    PayloadLength,
    #[error("payload does not match this model's state layout")]
    Layout,
    #[error("a field is not in its type's range (Boolean not 0 or 1, integer overflow)")]
    FieldRange,
}

/// Refuses a non-finite `value` for the Real variable `name`, or one outside the model
/// description's [`min`, `max`].
pub fn check_real(name: &'static str, value: f64, min: Option<f64>, max: Option<f64>) -> Result<(), Refusal> {
    if !value.is_finite() {
        return Err(Refusal::NotFinite { name, value });
    }
    let (lo, hi) = (min.unwrap_or(f64::NEG_INFINITY), max.unwrap_or(f64::INFINITY));
    if value < lo || value > hi {
        return Err(Refusal::OutOfRange { name, value, lo, hi });
    }
    Ok(())
}

/// Refuses a `value` for the Integer variable `name` outside the model description's [`min`, `max`].
pub fn check_integer(name: &'static str, value: i32, min: Option<i32>, max: Option<i32>) -> Result<(), Refusal> {
    let (lo, hi) = (min.unwrap_or(i32::MIN), max.unwrap_or(i32::MAX));
    if value < lo || value > hi {
        return Err(Refusal::IntegerOutOfRange { name, value, lo, hi });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_messages_name_the_variable_and_the_range() {
        assert_eq!(
            check_real("k", f64::NAN, None, None).unwrap_err().to_string(),
            "k = NaN refused: not a finite number"
        );
        assert_eq!(
            check_real("k", 3.0, Some(0.0), Some(2.0)).unwrap_err().to_string(),
            "k = 3 refused: outside [0, 2]"
        );
        assert_eq!(check_integer("m", 4, Some(0), Some(3)).unwrap_err().to_string(), "m = 4 refused: outside [0, 3]");
        let restored = Refusal::from(Unreadable::BadMagic);
        assert_eq!(restored.to_string(), "serialized FMU state rejected: not a state of this model (bad magic)");
        let nested = Refusal::Inconsistent("the delay line").restored().to_string();
        assert_eq!(nested, "serialized FMU state rejected: the delay line do not match the parameters");
    }
}
