//! The steady force–velocity law of a passive damper (docs/physics.md §3.8, "In steady motion"),
//! and its fit on the quasi-steady samples of records: the static stages of a calibration that
//! bring the model from a datasheet's values to a real damper's before the dynamic fit.
//!
//! ```text
//! extension (v > 0):   Q_reb(Δp) − Q_cv1(−Δp) = A_a v,   Q_cv2(δ) − Q_comp(−δ) = A_r v,   p_B = p_r − δ
//!                      F = Δp A_a − p_B A_r + F_e
//! compression (v < 0): Q_cv1(δ) − Q_reb(−δ) = A_a |v|,  Q_comp(Δp) − Q_cv2(−Δp) = A_r |v|,  p_B = p_r + Δp
//!                      F = −p_B A_r − δ A_a + F_e
//! ```
//! p_r is the gas at V_gas0 + A_r x and the oil's temperature, F_e the effects' forces (friction,
//! end stops) at (v, x). The oil and the mount do not enter a steady state: the samples used are
//! those where the velocity changes slowly against the oil column's time constant, away from
//! reversals ([`steady_points`]).

use crate::error::Error;
use crate::lm::{self, Bound};
use crate::model::Drive;
use crate::parameters::real;
use crate::settings::{apply, Entry};
use semi_active_damper::effects::PlantSignals;
use semi_active_damper::physics::fluid::{orifice_flow, viscosity_ratio};
use semi_active_damper::physics::hydraulics::check_valve_area;
use semi_active_damper::physics::params::{Derived, Parameters};
use semi_active_damper::physics::passive_valve::PassiveValve;
use semi_active_damper::physics::plant::Plant;

/// A sample the steady law explains: velocity (m/s), stroke (m), oil temperature (K), the
/// measured force (N) and the setting of the damper it was taken at ([`crate::settings`]).
#[derive(Clone, Copy, Debug)]
pub struct SteadyPoint {
    pub v: f64,
    pub x: f64,
    pub t_oil: f64,
    pub force: f64,
    pub setting: usize,
}

/// The oil column's time constant the quasi-steady test allows for (s): the passive dampers'
/// force settles within a few ms after a change of velocity (c_t/k of §3.4 with their valves).
pub const SETTLING: f64 = 0.01;
/// A sample is quasi-steady where |a|·SETTLING is at most this share of |v|.
pub const STEADY_SHARE: f64 = 0.05;
/// ... and |v| at least this (m/s): near a reversal the check valves switch and the oil relaxes.
pub const MIN_STEADY_VELOCITY: f64 = 2e-3;

/// Whether the steady law of this module describes `p`: a passive damper (the valve held shut,
/// no relief valve).
pub fn is_passive(p: &Parameters) -> bool {
    let d = p.derive();
    p.control_mode == 2 && d.ports.area(p.x_spool_start) + p.a_valve_leak == 0.0 && p.a_relief == 0.0
}

/// The pressure drop (Pa) at which the increasing `flow` passes `target` (m³/s) > 0.
fn drop_for(flow: impl Fn(f64) -> f64, target: f64) -> Option<f64> {
    let (mut lo, mut hi) = (0.0, 1e4);
    while flow(hi) < target {
        hi *= 4.0;
        if hi > 1e10 {
            return None;
        }
    }
    // Illinois regula falsi: converges superlinearly on these smooth monotone laws
    let (mut f_lo, mut f_hi) = (flow(lo) - target, flow(hi) - target);
    for _ in 0..100 {
        let mid = hi - f_hi * (hi - lo) / (f_hi - f_lo);
        let f_mid = flow(mid) - target;
        if f_mid.abs() <= 1e-12 * target || (hi - lo) <= 1e-9 * hi {
            return Some(mid);
        }
        if (f_mid > 0.0) == (f_hi > 0.0) {
            hi = mid;
            f_hi = f_mid;
            f_lo *= 0.5;
        } else {
            lo = mid;
            f_lo = f_mid;
            f_hi *= 0.5;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The steady load-cell force (N) of the passive damper `p` (derived `d`) at the point's
/// velocity, stroke and temperature; None where no pressure drop passes the flow.
pub fn steady_force(p: &Parameters, d: &Derived, pt: &SteadyPoint) -> Option<f64> {
    let cyl = &d.cylinder;
    let plant = Plant { p, d, v_damper: 0.0, i_command: 0.0, t_oil: pt.t_oil, a_damper: 0.0 };
    let p_r = plant.rest_state(pt.x, p.x_spool_start)[0];
    let mu = if p.effect_oil_temperature { viscosity_ratio(p.visc_temp_coeff, pt.t_oil, p.t_ref) } else { 1.0 };
    let orifice = |cd: f64, area: f64, dp: f64| orifice_flow(cd, area, dp, p.rho, p.p_transition);
    let check =
        |dp: f64| orifice(p.cd_cv, check_valve_area(p.a_cv_leak, p.a_cv_max, d.p_cv_crack, p.p_cv_full, dp), dp);
    let valve = |on: bool, v: PassiveValve, dp: f64| if on { v.flow(dp, mu, p.rho, p.p_transition).0 } else { 0.0 };
    let rebound = |dp: f64| valve(p.effect_rebound_valve, PassiveValve::rebound(p), dp);
    let compression = |dp: f64| valve(p.effect_compression_valve, PassiveValve::compression(p), dp);
    let signals = PlantSignals {
        v_damper: pt.v,
        x_damper: pt.x,
        p_reservoir: p_r,
        temperature: pt.t_oil,
        viscosity_ratio: mu,
        ..PlantSignals::ZERO
    };
    let f_e = d.effects.force(p, &signals);
    if pt.v > 0.0 {
        let dp = drop_for(|dp| rebound(dp) - check(-dp), cyl.a_annulus * pt.v)?;
        let refill = drop_for(|dp| check(dp) - compression(-dp), cyl.a_rod * pt.v)?;
        Some(dp * cyl.a_annulus - (p_r - refill) * cyl.a_rod + f_e)
    } else if pt.v < 0.0 {
        let cv1 = drop_for(|dp| check(dp) - rebound(-dp), -cyl.a_annulus * pt.v)?;
        let dp = drop_for(|dp| compression(dp) - check(-dp), -cyl.a_rod * pt.v)?;
        Some(-(p_r + dp) * cyl.a_rod - cv1 * cyl.a_annulus + f_e)
    } else {
        Some(-p_r * cyl.a_rod + f_e)
    }
}

/// The quasi-steady samples of a record taken at `setting`: the stroke integrated from `x_start`
/// (m) along the drive's velocity, the acceleration from central differences.
pub fn steady_points(drive: &Drive, x_start: f64, measured: &[f64], setting: usize) -> Vec<SteadyPoint> {
    let (t, v) = (&drive.time, &drive.v_damper);
    let a = crate::dsp::smooth_rate(t, v, 2);
    let stroke = crate::dsp::integrate(t, v, x_start);
    let mut out = Vec::new();
    for (k, &x) in stroke.iter().enumerate() {
        let t_oil = drive.t_oil.as_ref().map_or(semi_active_damper::damper::T_OIL_START, |t| t[k]);
        if v[k].abs() >= MIN_STEADY_VELOCITY && a[k].abs() * SETTLING <= STEADY_SHARE * v[k].abs() {
            out.push(SteadyPoint { v: v[k], x, t_oil, force: measured[k], setting });
        }
    }
    out
}

/// The result of [`fit_steady`].
#[derive(Clone, Debug)]
pub struct SteadyFit {
    /// (entry, start, fitted) of each parameter fitted.
    pub fitted: Vec<(Entry, f64, f64)>,
    /// RMS force residual of the steady law over the points (N), before and after.
    pub rms_before: f64,
    pub rms_after: f64,
    /// Points used, and starts tried.
    pub points: usize,
    pub starts: usize,
}

/// Residuals of the steady law with `entries` = `x` on top of `p`, each point at its setting.
fn residuals(p: &Parameters, entries: &[Entry], x: &[f64], points: &[SteadyPoint]) -> Result<Vec<f64>, Error> {
    let settings = points.iter().map(|pt| pt.setting + 1).max().unwrap_or(1);
    let per_setting: Vec<(Parameters, Derived)> = (0..settings)
        .map(|s| {
            let mut q = *p;
            apply(&mut q, entries, x, s)?;
            q.validate()?;
            let d = q.derive();
            Ok((q, d))
        })
        .collect::<Result<_, Error>>()?;
    points
        .iter()
        .map(|pt| {
            let (q, d) = &per_setting[pt.setting];
            steady_force(q, d, pt).map(|f| f - pt.force).ok_or(Error::NoPressureDrop { v: pt.v })
        })
        .collect()
}

/// The most points a steady fit uses (evenly spread over the record): more add time, not
/// information, to a law of a dozen parameters.
pub const MAX_POINTS: usize = 1500;

/// Fits `entries` of `p` to the steady points, from several starts (each blow-off preload at a
/// third, once and three times its start, the others at theirs); the best wins. Each parameter is
/// searched over [start/30, 30·start] within the model's range: a datasheet's value may be far
/// from a real valve's.
pub fn fit_steady(
    p: &Parameters,
    entries: &[Entry],
    points: &[SteadyPoint],
    pool: &rayon::ThreadPool,
) -> Result<SteadyFit, Error> {
    if points.len() < 4 * entries.len() {
        return Err(Error::TooFewSamples { samples: points.len(), parameters: entries.len() });
    }
    let stride = points.len().div_ceil(MAX_POINTS);
    let points: Vec<SteadyPoint> = points.iter().step_by(stride).copied().collect();
    let points = points.as_slice();
    let starts: Vec<f64> = entries.iter().map(|e| real(p, e.name)).collect::<Result<_, _>>()?;
    let bounds: Vec<Bound> =
        entries.iter().zip(&starts).map(|(e, &s)| wide_box(e.name, s)).collect::<Result<_, _>>()?;
    let rms = |r: &[f64]| (r.iter().map(|x| x * x).sum::<f64>() / r.len() as f64).sqrt();
    let rms_before = rms(&residuals(p, entries, &starts, points)?);
    let f = |x: &[f64]| residuals(p, entries, x, points);
    let mut best: Option<lm::Solution> = None;
    // the blow-off preloads are shared: a setting's own would multiply the starts
    let varied: Vec<usize> =
        (0..entries.len()).filter(|&i| entries[i].name.starts_with("p_open") && entries[i].setting.is_none()).collect();
    let combos = 3usize.pow(varied.len() as u32);
    for combo in 0..combos {
        let mut x0 = starts.clone();
        let mut c = combo;
        for &i in &varied {
            x0[i] = bounds[i].clamp(starts[i] * [1.0, 1.0 / 3.0, 3.0][c % 3]);
            c /= 3;
        }
        let opts = lm::Options { max_iterations: 25, step: 1e-3, tolerance: 1e-6 };
        if let Ok(s) = lm::solve(&f, &x0, &bounds, pool, opts, &[]) {
            if best.as_ref().is_none_or(|b| s.cost < b.cost) {
                best = Some(s);
            }
        }
    }
    let best = best.ok_or(Error::SteadyFitFailed)?;
    Ok(SteadyFit {
        fitted: entries.iter().zip(&starts).zip(&best.x).map(|((&e, &s), &x)| (e, s, x)).collect(),
        rms_before,
        rms_after: (best.cost / points.len() as f64).sqrt(),
        points: points.len(),
        starts: combos,
    })
}

/// [start/30, 30·start] within the model's range, on a log scale; a linear box for a start of 0.
fn wide_box(name: &str, start: f64) -> Result<Bound, Error> {
    let v = match crate::parameters::lookup(name)? {
        crate::parameters::Param::Real(v) => v,
        _ => return Err(Error::NotOfKind { name: name.to_string(), kind: "Real parameter", is: None }),
    };
    let (min, max) = (v.min().unwrap_or(f64::NEG_INFINITY), v.max().unwrap_or(f64::INFINITY));
    if start > 0.0 {
        let (lo, hi) = ((start / 30.0).max(min).max(1e-300), (start * 30.0).min(max));
        if lo < hi {
            return Ok(Bound { lo, hi, log: true });
        }
    }
    Err(Error::NoPositiveStart { name: name.to_string(), start })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::description::{Description, TEMPLATE};

    fn template() -> Parameters {
        let mut p = Parameters::default();
        Description::parse("template", TEMPLATE).unwrap().apply(&mut p).unwrap();
        p
    }

    /// The steady law against the dynamic model held at constant velocity: the force settles on
    /// it. The gas volume is a thousand times the template's, so that the gas pressure stays
    /// constant along the stroke: with the template's, the chambers' pressures follow the gas
    /// spring with the oil column's lag (0.25 % of the force at −0.1 m/s), which a steady law
    /// leaves out.
    #[test]
    fn the_dynamic_model_settles_on_the_steady_law() {
        let p = Parameters { rtol: 1e-7, v_gas0: 1e3 * template().v_gas0, ..template() };
        let d = p.derive();
        for v in [-0.5, -0.1, -0.01, 0.01, 0.1, 0.5] {
            let n = 400;
            let time: Vec<f64> = (0..n).map(|k| k as f64 * 1e-3).collect();
            let drive = Drive {
                time,
                v_damper: vec![v; n],
                demand: crate::model::Demand::Held,
                t_oil: None,
                x_damper_start: None,
            };
            let run = crate::model::Model::new(p).run(&drive).unwrap();
            let x = run.x_damper[n - 1];
            let pt = SteadyPoint { v, x, t_oil: semi_active_damper::damper::T_OIL_START, force: 0.0, setting: 0 };
            let steady = steady_force(&p, &d, &pt).unwrap();
            let dynamic = run.f_damper[n - 1];
            assert!(
                (steady - dynamic).abs() <= 2e-4 * steady.abs().max(10.0),
                "v {v}: steady {steady}, dynamic {dynamic}"
            );
        }
    }

    /// From a datasheet's values three times off, the steady fit finds the valves of a damper
    /// whose steady points it is given, taken at two settings of its rebound adjuster: the
    /// rebound bleed of each setting, the rest shared.
    #[test]
    fn the_steady_fit_reaches_valves_far_from_the_start() {
        let truth = template();
        let opened = Parameters { a_bleed_reb: 1.7 * truth.a_bleed_reb, ..truth };
        let mut points = Vec::new();
        for k in 0..300 {
            let v = if k % 2 == 0 { 1.0 } else { -1.0 } * (0.003 + 0.6 * (k as f64 / 300.0));
            let x = 0.02 * ((k % 7) as f64 / 3.0 - 1.0);
            let setting = k / 2 % 2;
            let mut pt = SteadyPoint { v, x, t_oil: semi_active_damper::damper::T_OIL_START, force: 0.0, setting };
            let p = [&truth, &opened][setting];
            pt.force = steady_force(p, &p.derive(), &pt).unwrap();
            points.push(pt);
        }
        let mut start = truth;
        start.a_bleed_reb *= 3.0;
        start.p_open_reb /= 3.0;
        start.a_bleed_comp /= 3.0;
        start.p_open_comp *= 2.5;
        let shared = |name| Entry { name, setting: None };
        let own = |setting| Entry { name: "A_bleed_reb", setting: Some(setting) };
        let entries = [own(0), own(1), shared("p_open_reb"), shared("A_bleed_comp"), shared("p_open_comp")];
        // (the bleeds from three times off, the preloads from the starts tried)
        let pool = crate::model::thread_pool(1).unwrap();
        let fit = fit_steady(&start, &entries, &points, &pool).unwrap();
        for (e, _, x) in &fit.fitted {
            let t = real([&truth, &opened][e.setting.unwrap_or(0)], e.name).unwrap();
            assert!((x - t).abs() <= 1e-3 * t, "{e:?}: {x} against {t}");
        }
        assert!(fit.rms_after < 1e-2 && fit.rms_before > 30.0, "{fit:?}");
    }
}
