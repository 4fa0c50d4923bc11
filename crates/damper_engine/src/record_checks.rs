//! Records that cannot be compared with the model, caught before a model run: a constant (dead)
//! force channel, a damper that does not move, velocities beyond the model's range, and a time
//! column whose unit cannot be the one its header says.

use crate::dsp::std;
use crate::error::{Error, Place};
use crate::measurement::Measurement;
use crate::units::Column;
use semi_active_damper::model_description::RealVar;

/// Below this largest |v_damper| (m/s) the record shows nothing of the damper's dynamics: about
/// ten times a rig velocity sensor's noise.
pub const MIN_MOTION: f64 = 1e-3;
/// Sample rates (Hz) a damper record can have: below, the force's dynamics are not resolved;
/// above, the time column is probably in another unit than its header says.
pub const RATE_RANGE: (f64, f64) = (20.0, 200e3);

/// Checks `m` (split into train and validation parts at sample `split`); the error names the
/// file, the line and the column.
pub fn check(m: &Measurement, split: usize) -> Result<(), Error> {
    let problem = |line: Option<usize>, problem: String| Error::InFile {
        at: Place { file: m.path.clone(), line, field: None },
        problem,
    };
    let line = |k: usize| m.lines.get(k).copied().unwrap_or(k + 1);
    let header =
        |c: Column| m.sources.iter().find(|s| s.column == c).map_or(c.name().to_string(), |s| s.header.clone());
    let dt = m.median_interval();
    let rate = 1.0 / dt;
    if !(RATE_RANGE.0..=RATE_RANGE.1).contains(&rate) {
        let time = m.sources.iter().find(|s| s.column == Column::Time);
        return Err(problem(None, format!(
            "the time column '{}' read in {} gives a sample interval of {dt:.3e} s ({rate:.3e} Hz), implausible for a damper record ({}–{} Hz): is it in another unit? Write it in the header (e.g. 'time [ms]') or map it (--map 'time=time:ms')",
            header(Column::Time),
            time.map_or("s", |s| s.unit.as_str()),
            RATE_RANGE.0,
            RATE_RANGE.1
        )));
    }
    if let Some(f) = m.get(Column::FDamper) {
        for (part, range) in [("the record", 0..f.len()), ("the validation part", split..f.len())] {
            if std(&f[range.clone()]) == 0.0 {
                return Err(problem(None, format!(
                    "column '{}' (F_damper) is constant at {} N over {part} (lines {}–{}): a dead or disconnected load cell? There is nothing to compare the model with",
                    header(Column::FDamper),
                    f[range.start],
                    line(range.start),
                    line(range.end - 1)
                )));
            }
        }
    }
    if let Some(v) = m.get(Column::VDamper) {
        let largest = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        if largest < MIN_MOTION {
            return Err(problem(None, format!(
                "the damper does not move: the largest |v_damper| in column '{}' is {largest:.2e} m/s (less than {MIN_MOTION} m/s); a record must move the damper to show its dynamics",
                header(Column::VDamper)
            )));
        }
        let limit = RealVar::VDamper.max().unwrap_or(f64::INFINITY);
        if let Some(k) = v.iter().position(|x| x.abs() > limit) {
            return Err(problem(Some(line(k)), format!(
                "v_damper = {} m/s (column '{}') is beyond the model's range of ±{limit} m/s; is the column in another unit (e.g. 'v_damper [mm/s]', or --map)?",
                v[k],
                header(Column::VDamper)
            )));
        }
    }
    Ok(())
}
