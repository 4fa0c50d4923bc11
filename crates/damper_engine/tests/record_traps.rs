//! Each trap of a real record with a record that falls into it: the sign convention reversed, a
//! force clipped at its rail, a velocity clipped, a stated sample rate the time column
//! contradicts, a drifting force zero. A passive damper (damper init's template) on a dyno program
//! with rests, made with the model, is the good record each one spoils.

#[allow(dead_code, reason = "the shared helpers: this file uses scratch() only")]
use crate::common;

use damper_engine::comparison::{compare, CompareOptions};
use damper_engine::description::{Description, TEMPLATE};
use damper_engine::model::{Demand, Drive, Model};
use damper_engine::units::Column;
use semi_active_damper::physics::params::Parameters;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A dyno program: sine cycles at 1.5 Hz and 25 mm, each followed by a 0.3 s rest, 1 kHz; the
/// template damper's force with 3 N of noise. (time, velocity, force).
fn record() -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut p = Parameters::default();
    Description::parse("template", TEMPLATE).unwrap().apply(&mut p).unwrap();
    let (dt, w) = (1e-3, 2.0 * std::f64::consts::PI * 1.5);
    let mut v = Vec::new();
    for _ in 0..6 {
        v.extend((0..667).map(|k| 0.025 * w * libm::sin(w * k as f64 * dt)));
        v.extend(std::iter::repeat_n(0.0, 300));
    }
    let time: Vec<f64> = (0..v.len()).map(|k| k as f64 * dt).collect();
    let drive =
        Drive { time: time.clone(), v_damper: v.clone(), demand: Demand::Held, t_oil: None, x_damper_start: None };
    let force = Model::new(p).run(&drive).unwrap().f_damper;
    let mut seed = 3u64;
    let noisy = force
        .iter()
        .map(|f| {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            (f + 3.0 * 12f64.sqrt() * u).round()
        })
        .collect();
    (time, v, noisy)
}

fn write(dir: &Path, name: &str, comments: &str, t: &[f64], v: &[f64], f: &[f64]) -> PathBuf {
    let mut s = String::from(comments);
    s += "time,v_damper,F_damper\n";
    for k in 0..t.len() {
        let _ = writeln!(s, "{},{},{}", t[k], v[k], f[k]);
    }
    let path = dir.join(name);
    std::fs::write(&path, s).unwrap();
    path
}

fn options(dir: &Path, path: &Path) -> CompareOptions {
    let template = dir.join("damper.toml");
    std::fs::write(&template, TEMPLATE).unwrap();
    CompareOptions { damper_file: Some(template), ..CompareOptions::new(path) }
}

#[test]
fn the_good_record_passes_every_check() {
    let dir = common::scratch("traps_good");
    let (t, v, f) = record();
    let path = write(&dir, "good.csv", "# Sample rate: 1000 Hz\n", &t, &v, &f);
    let c = compare(&options(&dir, &path)).unwrap();
    assert!(!c.warnings.iter().any(|w| w.contains("clipped") || w.contains("drifts")), "{:?}", c.warnings);
    assert!(c.analysis.force().validation.nrmse < 1.3 * c.analysis.noise_floor_estimate);
}

#[test]
fn a_reversed_sign_is_refused_and_the_flag_flips_it() {
    let dir = common::scratch("traps_sign");
    let (t, v, f) = record();
    let negated: Vec<f64> = f.iter().map(|x| -x).collect();
    let path = write(&dir, "sign.csv", "", &t, &v, &negated);
    let e = compare(&options(&dir, &path)).unwrap_err().to_string();
    assert!(e.contains("opposes its motion") && e.contains("--flip F_damper"), "{e}");
    let c = compare(&CompareOptions { flips: vec![Column::FDamper], ..options(&dir, &path) }).unwrap();
    assert!(c.warnings.iter().any(|w| w.contains("F_damper negated")));
    assert!(c.analysis.force().validation.nrmse < 1.3 * c.analysis.noise_floor_estimate);
}

#[test]
fn a_clipped_force_is_left_out_and_reported() {
    let dir = common::scratch("traps_clipped");
    let (t, v, f) = record();
    let rail = 0.7 * f.iter().fold(0.0f64, |a, x| a.max(*x));
    let clipped: Vec<f64> = f.iter().map(|x| x.min(rail.round())).collect();
    let path = write(&dir, "clipped.csv", "", &t, &v, &clipped);
    let c = compare(&options(&dir, &path)).unwrap();
    let said = c.warnings.join("\n");
    assert!(said.contains("clipped at the load cell's rail") && said.contains("left out"), "{said}");
    assert!(c.measurement.excluded.iter().any(|&e| e));
    // the samples left out, the rest is at the noise (3 N)
    let rmse = c.analysis.force().validation.rmse;
    assert!(rmse < 1.2 * 3.0, "RMS error {rmse} N");
}

#[test]
fn a_clipped_velocity_is_refused() {
    let dir = common::scratch("traps_velocity");
    let (t, v, f) = record();
    let rail = 0.8 * v.iter().fold(0.0f64, |a, x| a.max(*x));
    let clipped: Vec<f64> = v.iter().map(|x| x.min(rail)).collect();
    let path = write(&dir, "clipped_v.csv", "", &t, &clipped, &f);
    let e = compare(&options(&dir, &path)).unwrap_err().to_string();
    assert!(e.contains("v_damper") && e.contains("clipped at its amplifier's rail") && e.contains("lines"), "{e}");
}

#[test]
fn a_stated_rate_the_time_column_contradicts_is_refused() {
    let dir = common::scratch("traps_rate");
    let (t, v, f) = record();
    let path = write(&dir, "rate.csv", "# Logger: dyno 4\n# Sample rate: 500 Hz\n", &t, &v, &f);
    let e = compare(&options(&dir, &path)).unwrap_err().to_string();
    assert!(e.contains("line 2") && e.contains("500 Hz") && e.contains("--trust-time-column"), "{e}");
    compare(&CompareOptions { trust_time_column: true, ..options(&dir, &path) }).unwrap();
}

#[test]
fn a_drifting_zero_is_reported() {
    let dir = common::scratch("traps_drift");
    let (t, v, f) = record();
    let drifting: Vec<f64> = f.iter().zip(&t).map(|(x, t)| x + 20.0 * t).collect();
    let path = write(&dir, "drift.csv", "", &t, &v, &drifting);
    let c = compare(&options(&dir, &path)).unwrap();
    let said = c.warnings.join("\n");
    assert!(said.contains("the force at rest drifts by +1") && said.contains("N/s"), "{said}");
}

/// A record of the template damper at rest in its end stop (free stroke 45 mm) and at mid-stroke in
/// turn: six half-sine moves out to `ends[k]` (m) and back, 0.5 s each, each followed by a 0.3 s
/// rest, 1 kHz, 3 N of noise, plus `drift` N/s. (time, velocity, force).
fn end_stop_record(ends: &[f64], drift: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut p = Parameters::default();
    Description::parse("template", TEMPLATE).unwrap().apply(&mut p).unwrap();
    let (dt, period) = (1e-3, 0.5);
    let half_sine = |to: f64| -> Vec<f64> {
        let peak = std::f64::consts::PI * to / (2.0 * period);
        (0..500).map(|k| peak * libm::sin(std::f64::consts::PI * (k as f64 + 0.5) * dt / period)).collect()
    };
    let mut v = vec![0.0; 300];
    for &end in ends {
        v.extend(half_sine(end));
        v.extend(std::iter::repeat_n(0.0, 300));
        v.extend(half_sine(-end));
        v.extend(std::iter::repeat_n(0.0, 300));
    }
    let time: Vec<f64> = (0..v.len()).map(|k| k as f64 * dt).collect();
    let drive =
        Drive { time: time.clone(), v_damper: v.clone(), demand: Demand::Held, t_oil: None, x_damper_start: None };
    let force = Model::new(p).run(&drive).unwrap().f_damper;
    let mut rng = damper_engine::rng::Rng::new(7);
    let noisy = force.iter().zip(&time).map(|(f, t)| (f + drift * t + 3.0 * rng.normal()).round()).collect();
    (time, v, noisy)
}

/// Rests in an end stop, the rig's end position creeping out by 8 µm a cycle: the force at those
/// rests rises by about 25 N a cycle with the stroke (3 kN/mm at 3 mm into the stop), which is
/// no drift of the load cell's zero; with the end positions out of step with time, a drift of
/// 20 N/s is still told from the stroke and reported.
#[test]
fn rests_in_an_end_stop_are_no_drift() {
    let dir = common::scratch("traps_end_stop");
    let creeping: Vec<f64> = (0..6).map(|k| 0.048 + 8e-6 * k as f64).collect();
    let (t, v, f) = end_stop_record(&creeping, 0.0);
    let path = write(&dir, "creeping.csv", "# Sample rate: 1000 Hz\n", &t, &v, &f);
    let c = compare(&options(&dir, &path)).unwrap();
    assert!(!c.warnings.iter().any(|w| w.contains("drifts")), "{:?}", c.warnings);
    let shuffled: Vec<f64> = [0.0, 24.0, 8.0, 40.0, 16.0, 32.0].iter().map(|d| 0.048 + d * 1e-6).collect();
    let (t, v, f) = end_stop_record(&shuffled, 20.0);
    let path = write(&dir, "drifting.csv", "# Sample rate: 1000 Hz\n", &t, &v, &f);
    let c = compare(&options(&dir, &path)).unwrap();
    let said = c.warnings.join("\n");
    assert!(said.contains("the force at rest drifts by +") && said.contains("N/s"), "{said}");
}
