//! Step 4's evidence: the model after adding the effects the diagnosis names, run and analysed on
//! the same record as the baseline, and the error in every regime before and after.

use crate::analysis::{analyse, Analysis};
use crate::comparison::Comparison;
use crate::error::Error;
use crate::model::{Model, Prediction};
use semi_active_damper::physics::params::Parameters;

/// The model with the named effects, run and analysed like the baseline.
pub struct After {
    /// The effects added, in the ladder's order.
    pub effects: Vec<&'static str>,
    pub prediction: Prediction,
    pub analysis: Analysis,
}

/// Runs the comparison's model with `params` (the baseline plus the fitted effects).
pub fn after(c: &Comparison, effects: &[&'static str], params: Parameters) -> Result<After, Error> {
    let model = Model { params, ..c.setup.model };
    let prediction = c.setup.backend.run(&model, &c.drive)?;
    let analysis = analyse(&c.measurement, &c.drive, &prediction, c.analysis.split);
    Ok(After { effects: effects.to_vec(), prediction, analysis })
}

/// Per regime: (group, name, time share, RMS before, RMS after), regimes with samples only.
pub fn regime_rows<'a>(b: &'a Analysis, a: &'a Analysis) -> Vec<(&'static str, &'a str, f64, f64, f64)> {
    b.regimes
        .iter()
        .filter(|r| r.samples > 0)
        .filter_map(|r| {
            let ra = a.regimes.iter().find(|x| x.group == r.group && x.name == r.name)?;
            Some((r.group, r.name.as_str(), r.time_share, r.rms, ra.rms))
        })
        .collect()
}
