//! What a diagnosis inherits from its calibration: an effect is fitted on top of calibrated
//! values, and their uncertainty moves the fit as much as the record's noise does. With
//! `damper diagnose --calibration calibration.json` the fitted parameters' uncertainties carry it:
//!
//! ```text
//! s*(θ) = argmin_s |r(s, θ)|²             s: the effect's parameters, θ: the calibrated ones
//! ∂s*/∂θ = −(J_sᵀ J_s)⁻¹ J_sᵀ J_θ          (implicit function theorem at the optimum)
//! Cov(s*) = Cov_fit(s*) + (∂s*/∂θ) Σ_θ (∂s*/∂θ)ᵀ
//! ```
//! J from forward differences of [`STEP`] on the fit's samples; Σ_θ is the calibration's
//! covariance ([`crate::calibrate::Covariance`]) marginalised over the parameters the effect's
//! fit frees (its value no longer matters to the fit).
//!
//! A change's size then carries, e.g., a calibrated laminar bleed's uncertainty into the
//! viscosity's temperature coefficient fitted on a heated record, which the record alone cannot
//! tell from the bleed.

use crate::calibration_file::CalibrationFile;
use crate::candidate::Simulator;
use crate::error::{Error, Place};
use crate::parameters::{lookup, real, set_real, Param};
use nalgebra::DMatrix;
use rayon::prelude::*;
use semi_active_damper::physics::params::Parameters;
use std::path::Path;

/// Relative step of the finite differences: large beside the model's numerical error at
/// [`crate::comparison::ANALYSIS_RTOL`] (a 0.3 % step of a bleed moves the force by about that
/// error), small enough for the fit's linearisation.
pub const STEP: f64 = 0.01;

/// A calibration's covariance, by the model's parameter names.
#[derive(Clone, Debug)]
pub struct CalibrationCovariance {
    pub names: Vec<&'static str>,
    /// In the parameters' units.
    pub matrix: DMatrix<f64>,
}

impl CalibrationCovariance {
    /// Reads `calibration.json`'s covariance: the shared parameters and, with `setting`, that
    /// setting's own values (the parameter set given to the diagnosis must be the same setting's).
    pub fn read(path: &Path, setting: Option<&str>) -> Result<CalibrationCovariance, Error> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        let file: CalibrationFile =
            serde_json::from_str(&text).map_err(|source| Error::Json { path: path.to_path_buf(), source })?;
        let cov = file.covariance.ok_or_else(|| Error::NoCovariance { path: path.to_path_buf() })?;
        let at = Place { file: path.display().to_string(), line: None, field: Some("covariance".into()) };
        let problem = |problem: String| Error::InFile { at: at.clone(), problem };
        let rows: Vec<usize> = (0..cov.parameters.len())
            .filter(|&i| cov.parameters[i].setting.as_deref().is_none_or(|s| Some(s) == setting))
            .collect();
        let names = rows
            .iter()
            .map(|&i| match lookup(&cov.parameters[i].name) {
                Ok(Param::Real(v)) => Ok(v.name()),
                _ => Err(problem(format!("{} is not a Real parameter of the model", cov.parameters[i].name))),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n = cov.matrix.len();
        if n != cov.parameters.len() || cov.matrix.iter().any(|r| r.len() != n || r.iter().any(|x| !x.is_finite())) {
            return Err(problem(format!("not a finite {n}×{n} matrix")));
        }
        let matrix = DMatrix::from_fn(rows.len(), rows.len(), |i, j| cov.matrix[rows[i]][rows[j]]);
        Ok(CalibrationCovariance { names, matrix })
    }

    /// The covariance of the parameters not in `free`.
    fn without(&self, free: &[&str]) -> CalibrationCovariance {
        let keep: Vec<usize> = (0..self.names.len()).filter(|&i| !free.contains(&self.names[i])).collect();
        CalibrationCovariance {
            names: keep.iter().map(|&i| self.names[i]).collect(),
            matrix: DMatrix::from_fn(keep.len(), keep.len(), |i, j| self.matrix[(keep[i], keep[j])]),
        }
    }
}

/// The standard uncertainty each parameter of `fitted` (name, value, the fit's own uncertainty)
/// inherits from the calibration, for the model `model` (the effect on at the fitted values) on
/// the first `train` samples of `measured` where `keep`: None where the fit's own is None or the
/// parameter does not move the force (a delay on its grid).
#[allow(clippy::too_many_arguments)]
pub fn inherited(
    simulate: &Simulator<'_>,
    model: &Parameters,
    measured: &[f64],
    keep: &[bool],
    train: usize,
    fitted: &[(&'static str, f64, Option<f64>)],
    calibration: &CalibrationCovariance,
    pool: &rayon::ThreadPool,
) -> Result<Vec<Option<f64>>, Error> {
    let free: Vec<&str> = fitted.iter().map(|f| f.0).collect();
    let cal = calibration.without(&free);
    let names: Vec<&'static str> = fitted.iter().map(|f| f.0).chain(cal.names.iter().copied()).collect();
    let kept = |force: Vec<f64>| -> Vec<f64> {
        force.iter().zip(&measured[..train]).zip(keep).filter(|(_, k)| **k).map(|((m, y), _)| m - y).collect()
    };
    let base = kept(simulate(model, train)?);
    let columns: Vec<Vec<f64>> = pool.install(|| {
        names
            .par_iter()
            .map(|name| {
                let value = real(model, name)?;
                let h = STEP * value.abs().max(1e-300);
                let mut p = *model;
                set_real(&mut p, name, value + h)?;
                Ok(kept(simulate(&p, train)?).iter().zip(&base).map(|(a, b)| (a - b) / h).collect())
            })
            .collect::<Result<_, Error>>()
    })?;
    let m = base.len();
    let (ns, nt) = (fitted.len(), cal.names.len());
    let moves: Vec<usize> =
        (0..ns).filter(|&j| fitted[j].2.is_some() && columns[j].iter().any(|x| *x != 0.0)).collect();
    let js = DMatrix::from_fn(m, moves.len(), |i, j| columns[moves[j]][i]);
    let jt = DMatrix::from_fn(m, nt, |i, j| columns[ns + j][i]);
    let Some(a) = (js.transpose() * &js).try_inverse() else {
        return Ok(vec![None; ns]);
    };
    let d = -(a * js.transpose() * jt);
    let added = &d * &cal.matrix * d.transpose();
    let mut out = vec![None; ns];
    for (k, &j) in moves.iter().enumerate() {
        out[j] = Some(added[(k, k)].max(0.0).sqrt());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line y = s·t + θ with θ calibrated (σ_θ): fitting s on t ∈ [1, 2] moves s by
    /// −θ·Σt/Σt² per unit of θ, so s inherits σ_θ·Σt/Σt², by hand.
    #[test]
    fn a_calibrated_offset_passes_its_uncertainty_to_a_fitted_slope_by_hand() {
        let n = 101;
        let t: Vec<f64> = (0..n).map(|k| 1.0 + k as f64 / (n - 1) as f64).collect();
        // the slope is F_coulomb (N) and the offset p_reservoir0 (Pa), any two Real parameters
        let line = |p: &Parameters, len: usize| -> Result<Vec<f64>, Error> {
            Ok(t[..len].iter().map(|t| p.f_coulomb * t + p.p_reservoir0).collect())
        };
        let model = Parameters { f_coulomb: 3.0, p_reservoir0: 5.0, ..Parameters::default() };
        let measured = line(&model, n).unwrap();
        let sigma = 0.2;
        let cal =
            CalibrationCovariance { names: vec!["p_reservoir0"], matrix: DMatrix::from_element(1, 1, sigma * sigma) };
        let pool = crate::model::thread_pool(2).unwrap();
        let keep = vec![true; n];
        let got = inherited(&line, &model, &measured, &keep, n, &[("F_coulomb", 3.0, Some(0.0))], &cal, &pool).unwrap();
        let (st, stt): (f64, f64) = (t.iter().sum(), t.iter().map(|t| t * t).sum());
        let hand = sigma * st / stt;
        assert!((got[0].unwrap() - hand).abs() < 1e-6 * hand, "{got:?} against {hand}");
        // a parameter the fit frees inherits nothing of its own calibrated value
        let freed = inherited(
            &line,
            &model,
            &measured,
            &keep,
            n,
            &[("F_coulomb", 3.0, Some(0.0)), ("p_reservoir0", 5.0, Some(0.0))],
            &cal,
            &pool,
        )
        .unwrap();
        assert_eq!(freed, vec![Some(0.0), Some(0.0)]);
    }
}
