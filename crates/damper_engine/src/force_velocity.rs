//! The force–velocity law of a record, as a reason in physical terms when the model does not fit:
//! per direction, the force above its value at rest (the gas force) fitted by c·|v|ⁿ over the
//! samples moving at 20–100 % of the record's largest speed. n < 0.8 is a degressive law (a
//! blow-off valve open), n ≈ 1 a laminar bleed, n ≈ 2 an orifice.

use crate::dsp::median;

/// The least share of the largest speed a sample must move at to count.
const FAST_SHARE: f64 = 0.2;
/// Speeds below this share of the largest are at rest (the gas force's samples).
const REST_SHARE: f64 = 0.02;
/// Least samples per direction.
const MIN_SAMPLES: usize = 50;

/// F − F_rest ≈ c·|v|ⁿ over one direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerLaw {
    pub exponent: f64,
    /// The law's force above rest at `v_top` (N).
    pub force_at_top: f64,
    /// The direction's largest speed (m/s).
    pub v_top: f64,
}

impl PowerLaw {
    fn kind(&self) -> &'static str {
        match self.exponent {
            n if n < 0.8 => "degressive",
            n if n < 1.3 => "near linear",
            n if n < 1.7 => "progressive",
            _ => "quadratic, an orifice's",
        }
    }
}

/// The power law of `force` against `v` in extension (`extension`) or compression.
pub fn power_law(v: &[f64], force: &[f64], extension: bool) -> Option<PowerLaw> {
    let top = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut rest: Vec<f64> = v.iter().zip(force).filter(|(v, _)| v.abs() < REST_SHARE * top).map(|(_, f)| *f).collect();
    let f_rest = if rest.is_empty() { 0.0 } else { median(&mut rest) };
    let sign = if extension { 1.0 } else { -1.0 };
    let points: Vec<(f64, f64)> = v
        .iter()
        .zip(force)
        .filter(|(v, f)| sign * **v > FAST_SHARE * top && sign * (**f - f_rest) > 0.0)
        .map(|(v, f)| (libm::log(v.abs()), libm::log((f - f_rest).abs())))
        .collect();
    if points.len() < MIN_SAMPLES {
        return None;
    }
    let n = points.len() as f64;
    let (mx, my) = (points.iter().map(|p| p.0).sum::<f64>() / n, points.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = points.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let exponent = sxy / sxx;
    let v_top = v.iter().filter(|x| sign * **x > 0.0).fold(0.0f64, |a, x| a.max(x.abs()));
    let force_at_top = libm::exp(my + exponent * (libm::log(v_top) - mx));
    Some(PowerLaw { exponent, force_at_top, v_top })
}

/// The measured and the model's laws set side by side, per direction, where they differ in kind
/// (exponent by more than 0.4) or size (by more than a factor 1.5); None where they agree.
pub fn contrast(v: &[f64], measured: &[f64], model: &[f64]) -> Option<String> {
    let mut parts = Vec::new();
    for (extension, name) in [(true, "extension"), (false, "compression")] {
        let (Some(m), Some(p)) = (power_law(v, measured, extension), power_law(v, model, extension)) else {
            continue;
        };
        let ratio = p.force_at_top / m.force_at_top;
        if (m.exponent - p.exponent).abs() > 0.4 || !(1.0 / 1.5..=1.5).contains(&ratio) {
            parts.push(format!(
                "in {name} the measured force above rest grows as |v|^{:.2} ({}) to {:.0} N at {:.2} m/s, the model's as |v|^{:.2} ({}) to {:.0} N",
                m.exponent,
                m.kind(),
                m.force_at_top,
                m.v_top,
                p.exponent,
                p.kind(),
                p.force_at_top
            ));
        }
    }
    (!parts.is_empty()).then(|| parts.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_degressive_and_a_quadratic_law_are_told_apart() {
        let v: Vec<f64> = (0..4000).map(|k| 0.5 * libm::sin(k as f64 * 2e-3 * 6.0)).collect();
        let degressive: Vec<f64> = v.iter().map(|v| 300.0 + 800.0 * v.signum() * libm::pow(v.abs(), 0.5)).collect();
        let quadratic: Vec<f64> = v.iter().map(|v| 300.0 + 40e3 * v.signum() * v * v).collect();
        let law = power_law(&v, &degressive, true).unwrap();
        assert!(
            (law.exponent - 0.5).abs() < 0.01 && (law.force_at_top - 800.0 * libm::sqrt(0.5)).abs() < 5.0,
            "{law:?}"
        );
        let text = contrast(&v, &degressive, &quadratic).unwrap();
        assert!(text.contains("degressive") && text.contains("quadratic"), "{text}");
        assert!(contrast(&v, &degressive, &degressive).is_none());
    }
}
