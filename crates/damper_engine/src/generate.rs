//! What `damper generate` makes: measurement-like CSV from the model with effects hidden in it,
//! and the truth in a separate JSON file that `compare` and `diagnose` never read.
//!
//! The truth model is driven over the measurement's own sample grid exactly as `compare` drives
//! its model (the velocity interpolated between samples, the demands held: `crate::model`), so
//! that a model equal to the truth leaves only the measurement chain in the residual. (For data
//! made independently of these numerics, see `python/damper_tools/independent.py`.) The measurement chain, in this order:
//!
//! 1. load cell: first-order low-pass at `lowpass_hz` (default 400 Hz) on the force at the
//!    controller's rate, exact for a force varying linearly between those points (`crate::model`);
//! 2. sensor noise: white, Gaussian, standard deviation per sensor (`Noise`), independent of
//!    everything else (its own random stream);
//! 3. quantisation: rounding to the sensor's resolution (`Noise`, a 16-bit converter over the
//!    sensor's range, in round numbers).
//!
//! Demands are digital: written exactly (after rounding to 0.1 N or 0.1 µm before the run).
//!
//! The velocity: the FMU has one velocity input, used by the hydraulics and by the controller
//! (semi-active clip, direction of the force loop, feedforward). A rig's digital controller works
//! with its measured velocity, so the truth is driven by the velocity as measured (true motion +
//! sensor noise, quantised; or differentiated from the measured displacement), and compare drives
//! its model with the same signal: velocity noise then does not appear in the force residual. With
//! `--errors-in-variables` the truth moves with the true velocity instead. The model is very
//! sensitive to that: near velocity reversals the controller's direction and the semi-active clip
//! follow the sign of the velocity noise, and while the demand is clipped the force-loop
//! integrator is frozen, so a difference made at one reversal can last until the next unclipped
//! stretch. Rig data, 5 s, seeds 1–10, the residual at the floor and white: with the velocity
//! as measured 10 of 10; errors in variables with 0.01 mm/s quantisation only 9 of 10, with
//! 0.1 mm/s noise 5 of 10 (validation NRMSE up to 1.39× the sensor floor, event-like errors of
//! 50–500 N after some reversals).

use crate::dsp::std;
use crate::error::Error;
use crate::model::{Demand, Drive, Model, Prediction};
use crate::parameters::{
    changed_parameters, effect, get_parameter, get_real, set_effect, set_parameter, set_real, EffectExt,
};
use crate::rng::Rng;
use crate::summary::{nan_if_null, ParameterValue};
use crate::units::Column;
use indexmap::IndexMap;
use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::physics::params::Parameters;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The truth model's tolerance (unless `--set rtol=…`): converged (0.02 N RMS force error on
/// `cargo bench`'s input), so that a record carries the effects and the sensors it is told to and
/// not the integrator's error at the FMU's default tolerance (17 N there, 0.86 load-cell σ), which a
/// diagnosis fits: it moved the mount stiffness fitted from a 60 s record by 4.3 standard errors.
const TRUTH_RTOL: f64 = 1e-6;

/// How the damper is driven.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputStyle {
    /// Test rig: constant-velocity blocks with demand steps, a sine sweep, random velocity.
    Rig,
    /// Hardware-in-the-loop: the quarter truck on a random road, clipped Modified Skyhook demand.
    Hil,
}

/// Sensor noise (standard deviation) and resolution, SI.
#[derive(Clone, Copy, Debug)]
pub struct Sensor {
    pub noise: f64,
    pub quantum: f64,
}

/// The sensors of the generated measurement.
#[derive(Clone, Copy, Debug)]
pub struct Noise {
    pub f_damper: Sensor,
    pub v_damper: Sensor,
    pub x_damper: Sensor,
    pub x_spool: Sensor,
    pub i_sol: Sensor,
    pub pressure: Sensor,
    pub t_oil: Sensor,
}

impl Default for Noise {
    /// A 50 kN load cell with 20 N noise and 1 N resolution; a velocity transducer with 0.1 mm/s
    /// noise and 0.01 mm/s resolution (or an LVDT, 2 µm and 1 µm); spool LVDT 1 µm / 0.1 µm;
    /// current 5 mA / 1 mA; pressure transducers 0.1 bar / 0.01 bar; a thermocouple 0.2 K / 0.1 K.
    fn default() -> Noise {
        Noise {
            f_damper: Sensor { noise: 20.0, quantum: 1.0 },
            v_damper: Sensor { noise: 1e-4, quantum: 1e-5 },
            x_damper: Sensor { noise: 2e-6, quantum: 1e-6 },
            x_spool: Sensor { noise: 1e-6, quantum: 1e-7 },
            i_sol: Sensor { noise: 5e-3, quantum: 1e-3 },
            pressure: Sensor { noise: 1e4, quantum: 1e3 },
            t_oil: Sensor { noise: 0.2, quantum: 0.1 },
        }
    }
}

impl Noise {
    /// Sets one sensor from `NAME=NOISE[:QUANTUM]` (SI), NAME one of F_damper, v_damper,
    /// x_damper, x_spool, i_sol, p_ext/p_comp (both pressure transducers).
    pub fn set(&mut self, text: &str) -> Result<(), Error> {
        let bad = |problem: String| Error::BadOption { option: format!("--sensor {text}"), problem };
        let usage = || bad("expected NAME=NOISE[:QUANTUM] in SI units, e.g. v_damper=1e-4:1e-5".into());
        let (name, rest) = text.split_once('=').ok_or_else(usage)?;
        let (noise, quantum) = match rest.split_once(':') {
            Some((a, b)) => (a, Some(b)),
            None => (rest, None),
        };
        let noise: f64 = noise.trim().parse().map_err(|_| usage())?;
        let quantum: Option<f64> = quantum.map(|q| q.trim().parse()).transpose().map_err(|_| usage())?;
        if noise.is_nan() || noise < 0.0 || quantum.is_some_and(|q| q.is_nan() || q <= 0.0) {
            return Err(bad("the noise must be ≥ 0 and the quantum > 0".into()));
        }
        let s = match name.trim() {
            "F_damper" => &mut self.f_damper,
            "v_damper" => &mut self.v_damper,
            "x_damper" => &mut self.x_damper,
            "x_spool" => &mut self.x_spool,
            "i_sol" => &mut self.i_sol,
            "p_ext" | "p_comp" => &mut self.pressure,
            "T_oil" => &mut self.t_oil,
            other => {
                return Err(bad(format!(
                    "unknown sensor '{other}' (F_damper, v_damper, x_damper, x_spool, i_sol, p_ext, p_comp, T_oil)"
                )))
            }
        };
        s.noise = noise;
        if let Some(q) = quantum {
            s.quantum = q;
        }
        Ok(())
    }

    /// Every noise level times `k` (resolutions unchanged).
    pub fn scaled(mut self, k: f64) -> Noise {
        for s in [
            &mut self.f_damper,
            &mut self.v_damper,
            &mut self.x_damper,
            &mut self.x_spool,
            &mut self.i_sol,
            &mut self.pressure,
            &mut self.t_oil,
        ] {
            s.noise *= k;
        }
        self
    }
}

/// Options of `damper generate`.
#[derive(Clone, Debug)]
pub struct GenerateOptions {
    pub out: PathBuf,
    pub truth: PathBuf,
    /// `KEY`, `KEY=VALUE` or `KEY=off`.
    pub effects: Vec<String>,
    pub sets: Vec<(String, String)>,
    /// `--damper FILE.toml`: the truth damper's description, applied to the defaults first.
    pub damper_file: Option<PathBuf>,
    /// `--params FILE.ssv`: an SSP parameter set applied after the description, before the
    /// effects and `--set`.
    pub params_file: Option<PathBuf>,
    pub seed: u64,
    pub input: InputStyle,
    pub duration: f64,
    pub rate: f64,
    /// Spool-position control: write `x_spool_demand` and no `F_demand` (rig only).
    pub spool_control: bool,
    /// Write the displacement `x_damper` instead of `v_damper`.
    pub displacement: bool,
    /// Only the required columns (no spool, current, pressures).
    pub minimal: bool,
    /// Drive the truth with the true velocity, not the measured one (see the module's
    /// documentation, "The velocity").
    pub errors_in_variables: bool,
    /// Load-cell low-pass (Hz); None: no filter.
    pub lowpass_hz: Option<f64>,
    pub noise: Noise,
    /// Default: false for rig data (raw load cell), true for HiL data (as the HiL runs).
    pub tare_load_cell: Option<bool>,
    /// ISO 8608 class A–H or motorway/major/minor (HiL).
    pub road: String,
    /// Vehicle speed (m/s) (HiL).
    pub speed: f64,
    /// The oil temperature's rise over the record (K), from `T_ref`, written as a `T_oil` column:
    /// None takes the largest of the hidden effects' (their `hide_with`), and writes no column
    /// when that is 0.
    pub heating: Option<f64>,
}

impl GenerateOptions {
    pub fn new(out: impl Into<PathBuf>, truth: impl Into<PathBuf>) -> GenerateOptions {
        GenerateOptions {
            out: out.into(),
            truth: truth.into(),
            effects: Vec::new(),
            sets: Vec::new(),
            damper_file: None,
            params_file: None,
            seed: 1,
            input: InputStyle::Rig,
            duration: 10.0,
            rate: 1000.0,
            spool_control: false,
            displacement: false,
            minimal: false,
            errors_in_variables: false,
            lowpass_hz: Some(400.0),
            noise: Noise::default(),
            tare_load_cell: None,
            road: "minor".into(),
            speed: 14.0,
            heating: None,
        }
    }
}

/// What the generator made.
#[derive(Clone, Debug)]
pub struct Generated {
    pub params: Parameters,
    pub time: Vec<f64>,
    /// Columns as written (SI).
    pub columns: Vec<(Column, Vec<f64>)>,
    /// The truth model's outputs on the true inputs.
    pub clean: Prediction,
    pub truth: Truth,
    /// Validation NRMSE of F_damper the sensor noise and quantisation alone give (split 0.7).
    pub expected_floor: f64,
    /// Validation NRMSE of the truth model (with the load-cell filter) driven by the measured
    /// inputs: the best any model can do on these data.
    pub oracle_nrmse: f64,
}

/// The truth file: what was hidden in the data and how they were measured. SI units unless the
/// name says otherwise.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Truth {
    /// `damper generate` and its version.
    pub generator: String,
    pub note: String,
    /// The CSV written.
    pub measurement: String,
    /// The seed of the random streams (effects, inputs, noise).
    pub seed: u64,
    pub samples: usize,
    /// Sample rate (Hz).
    pub rate_hz: f64,
    /// Record length (s).
    pub duration_s: f64,
    /// The truth model's control_mode: 0 force, 1 spool position.
    pub control_mode: i64,
    /// The truth model's force has its rest offset removed (as a tared load cell).
    pub tare_load_cell: bool,
    /// Which velocity drives the truth model.
    pub velocity_driving_the_truth: String,
    pub inputs: TruthInputs,
    /// The effects of `--effect`, in the order given.
    pub effects: Vec<TruthEffect>,
    /// The parameters of `--set` as the truth has them; null: not readable back.
    pub set: IndexMap<String, Option<ParameterValue>>,
    /// Every parameter of the truth that differs from the model's defaults.
    pub changed_parameters: IndexMap<String, ParameterValue>,
    pub sensors: TruthSensors,
    pub noise_floor: TruthNoiseFloor,
}

/// The inputs' style.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "style", rename_all = "lowercase")]
pub enum TruthInputs {
    Rig {
        description: String,
    },
    Hil {
        /// Road class (ISO 8608 A–H or motorway/major/minor).
        road: String,
        /// Road roughness Gd(n0) at n0 = 0.1 cycle/m (m³).
        road_gd_n0_m3: f64,
        /// Vehicle speed (m/s).
        speed_m_s: f64,
        description: String,
    },
}

/// An effect of `--effect`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthEffect {
    /// The catalog's key.
    pub key: String,
    /// Its switch parameter.
    pub switch: String,
    /// Switched on in the truth (`KEY=off` switches it off).
    pub on: bool,
    pub on_by_default: bool,
    /// The effect's parameters in the truth (SI); null: not a Real parameter.
    pub params: IndexMap<String, Option<f64>>,
    /// The size parameter was drawn from `random_range` (no value given).
    pub value_drawn_at_random: bool,
    /// [lo, hi] of the draw, in the size parameter's unit; null: not drawn.
    pub random_range: Option<[f64; 2]>,
}

/// The sensors of the CSV's columns: noise and resolution in the column's SI unit. Those whose
/// columns were not written are absent.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthSensors {
    #[serde(rename = "F_damper")]
    pub f_damper: LoadCell,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_damper: Option<TruthSensor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v_damper: Option<TruthSensor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_spool: Option<TruthSensor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub i_sol: Option<TruthSensor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_ext: Option<TruthSensor>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_comp: Option<TruthSensor>,
}

/// A sensor's white noise and resolution.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct TruthSensor {
    /// Standard deviation of the white noise.
    pub noise_std: f64,
    /// Resolution (the values are rounded to it).
    pub quantum: f64,
}

impl From<Sensor> for TruthSensor {
    fn from(s: Sensor) -> TruthSensor {
        TruthSensor { noise_std: s.noise, quantum: s.quantum }
    }
}

/// The load cell: noise (N), resolution (N) and its low-pass.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct LoadCell {
    pub noise_std: f64,
    pub quantum: f64,
    /// Low-pass cut-off (Hz); null: none.
    pub lowpass_hz: Option<f64>,
    pub lowpass: String,
}

/// The validation NRMSE of F_damper the best model could reach.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TruthNoiseFloor {
    /// Share of the samples in the train part (1).
    pub train_fraction: f64,
    /// From the force sensor's noise and resolution alone (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub expected_nrmse_validation: f64,
    pub expected_definition: String,
    /// The truth model itself, driven by the measured inputs (1).
    #[serde(deserialize_with = "nan_if_null")]
    pub oracle_nrmse_validation: f64,
    pub oracle_definition: String,
}

/// The truth parameters from the options; the records of each effect for the truth file.
fn truth_parameters(o: &GenerateOptions, rng: &mut Rng) -> Result<(Parameters, Vec<TruthEffect>), Error> {
    let mut p = Parameters {
        rtol: TRUTH_RTOL,
        control_mode: i32::from(o.spool_control),
        tare_load_cell: o.tare_load_cell.unwrap_or(o.input == InputStyle::Hil),
        ..Default::default()
    };
    if let Some(file) = &o.damper_file {
        crate::description::Description::read(file)?.apply(&mut p)?;
        p.rtol = TRUTH_RTOL;
        if p.control_mode == 2 && o.input == InputStyle::Hil {
            return Err(Error::PassiveForHil { path: file.clone() });
        }
    }
    if let Some(file) = &o.params_file {
        crate::ssv::apply(&mut p, file)?;
    }
    let mut records = Vec::new();
    for text in &o.effects {
        let (key, value) = match text.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (text.trim(), None),
        };
        let e = effect(key)?;
        let off = value.is_some_and(|v| v.eq_ignore_ascii_case("off") || v.eq_ignore_ascii_case("false"));
        set_effect(&mut p, e.key, !off)?;
        if !off {
            // what makes the effect show in the generator's records (an end stop within its stroke)
            for (name, x) in e.hide_with.set {
                set_real(&mut p, name, *x)?;
            }
        }
        let mut drawn = false;
        if !off {
            match value.filter(|v| !v.eq_ignore_ascii_case("on") && !v.eq_ignore_ascii_case("true")) {
                Some(v) => set_parameter(&mut p, e.size_parameter(), v)
                    .map_err(|err| err.context(format!("--effect {text}")))?,
                None => {
                    let (lo, hi) = e.hidden_range;
                    let x = if e.fitted[0].log { rng.log_range(lo, hi) } else { rng.range(lo, hi) };
                    set_real(&mut p, e.size_parameter(), x)?;
                    drawn = true;
                }
            }
        }
        records.push(TruthEffect {
            key: e.key.into(),
            switch: e.switch(),
            on: !off,
            on_by_default: e.default_on(),
            params: e.parameter_names().iter().map(|n| (n.to_string(), get_real(&p, n).ok())).collect(),
            value_drawn_at_random: drawn,
            random_range: drawn.then_some([e.hidden_range.0, e.hidden_range.1]),
        });
    }
    for (name, value) in &o.sets {
        set_parameter(&mut p, name, value).map_err(|e| e.context(format!("--set {name}={value}")))?;
    }
    p.validate().map_err(Error::TruthParameters)?;
    Ok((p, records))
}

/// The oil temperature over the record (K), None for a constant one: a linear rise from `T_ref`
/// by `o.heating`, or by the largest rise the hidden effects ask for (a heated run).
fn oil_temperature(o: &GenerateOptions, p: &Parameters, t: &[f64]) -> Result<Option<Vec<f64>>, Error> {
    let hidden_rise = o
        .effects
        .iter()
        .filter_map(|text| effect(text.split('=').next().unwrap_or(text)).ok())
        .map(|e| e.hide_with.temperature_rise)
        .fold(0.0, f64::max);
    let rise = o.heating.unwrap_or(hidden_rise);
    if !(rise.is_finite() && rise >= 0.0) {
        return Err(Error::BadOption {
            option: format!("--heating {rise}"),
            problem: "must be a temperature rise ≥ 0 K".into(),
        });
    }
    if rise == 0.0 {
        return Ok(None);
    }
    let duration = t[t.len() - 1] - t[0];
    Ok(Some(t.iter().map(|&tk| p.t_ref + rise * (tk - t[0]) / duration).collect()))
}

/// Linear ramp from 0 to 1 over `w` (s) at both ends of [0, len]. Linear, not smooth: the
/// velocity passes zero briskly instead of lingering near it, where the controller's direction
/// follows the sign of the velocity noise.
fn taper(tau: f64, len: f64, w: f64) -> f64 {
    let edge = |s: f64| (s / w).clamp(0.0, 1.0);
    edge(tau) * edge(len - tau)
}

/// Ramp time of the rig's velocity at the ends of a block, sweep or random stretch (s).
const RAMP: f64 = 0.015;
/// Constant-velocity blocks: speeds drawn in this range (m/s)…
const BLOCK_SPEED: (f64, f64) = (0.05, 0.25);
/// … each block moving about this far (m)…
const BLOCK_STROKE: f64 = 0.06;
/// … for at most this long (s).
const BLOCK_MAX_LEN: f64 = 0.35;
/// A block ending this close (s) before the sweep takes the rest of the first third: no
/// standstill before the sweep.
const BLOCK_MIN_REST: f64 = 0.05;
/// Beyond this stroke (m) the next block moves back towards the middle.
const BLOCK_STROKE_LIMIT: f64 = 0.01;
/// Spool-position demand levels (m), in the blocks, the sweep and the random part.
const SPOOL_LEVEL: (f64, f64) = (0.9e-3, 3.5e-3);
/// Force demand levels of the blocks (N).
const FORCE_LEVEL: (f64, f64) = (1e3, 20e3);
/// Time between the blocks' demand steps (s).
const BLOCK_STEP_EVERY: (f64, f64) = (0.08, 0.15);
/// The sweep's start frequency (Hz)…
const SWEEP_F0: f64 = 0.5;
/// … and its end frequency (Hz), at most [`SWEEP_MAX_CYCLES_PER_SAMPLE`] cycles per sample.
const SWEEP_F1: f64 = 12.0;
/// Most cycles of the sweep per sample (-): at least 20 samples per period.
const SWEEP_MAX_CYCLES_PER_SAMPLE: f64 = 0.05;
/// The sweep's displacement amplitude (m)…
const SWEEP_AMPLITUDE: f64 = 0.03;
/// … with its velocity amplitude capped at this (m/s).
const SWEEP_MAX_SPEED: f64 = 0.15;
/// Damping coefficient of the force demand C·v in the sweep (N·s/m).
const SWEEP_GAIN: (f64, f64) = (10e3, 60e3);
/// Time between the sweep's demand changes (s).
const SWEEP_CHANGE_EVERY: (f64, f64) = (0.4, 0.8);
/// Corner frequency of the two first-order low-passes that colour the random velocity (Hz).
const RANDOM_CORNER: f64 = 8.0;
/// RMS of the random velocity (m/s).
const RANDOM_RMS: f64 = 0.1;
/// Time constant of the position feedback that holds the random motion near mid-stroke (s).
const RANDOM_CENTRING: f64 = 0.5;
/// Damping coefficient of the random part's force demand C·v + F0·tanh(v/v0) (N·s/m)…
const RANDOM_GAIN: (f64, f64) = (5e3, 40e3);
/// … its friction-like part F0 (N)…
const RANDOM_COULOMB: (f64, f64) = (0.0, 3e3);
/// … rounded off over v0 (m/s).
const RANDOM_COULOMB_WIDTH: f64 = 0.01;
/// Time between the random part's demand changes (s).
const RANDOM_CHANGE_EVERY: (f64, f64) = (0.3, 0.6);

/// A demand as the rig's digital controller writes it: spool positions to 0.1 µm, forces to
/// 0.1 N.
fn round_demand(spool: bool, x: f64) -> f64 {
    if spool {
        (x * 1e7).round() / 1e7
    } else {
        (x * 10.0).round() / 10.0
    }
}

/// Rig-style inputs on the grid `t`: (true velocity, demand).
fn rig_inputs(t: &[f64], rng: &mut Rng, spool: bool, x_spool_rest: f64) -> (Vec<f64>, Vec<f64>) {
    let n = t.len();
    let duration = t[n - 1] - t[0];
    // The record starts at rest and moves at once: a standstill with a zero force demand would let
    // the force loop's integrator wind up in the direction of sign(v), which at rest is the sign
    // of the velocity noise, so the first motion would depend on noise the model cannot know.
    let rest = 0.0;
    let part = (duration - rest) / 3.0;
    let mut rig = RigRecord {
        t,
        dt: t[1] - t[0],
        spool,
        v: vec![0.0; n],
        demand: vec![if spool { x_spool_rest } else { 0.0 }; n],
    };
    let a_end = rest + part;
    rig.velocity_blocks(rng, rest, a_end);
    let b_end = a_end + part;
    rig.sine_sweep(rng, a_end, b_end, part);
    rig.random_velocity(rng, b_end);
    (rig.v, rig.demand)
}

/// The rig's inputs as they are made, part by part, on the grid `t` (interval `dt`, s).
struct RigRecord<'a> {
    t: &'a [f64],
    dt: f64,
    /// Spool-position control (else force control).
    spool: bool,
    /// True velocity (m/s).
    v: Vec<f64>,
    /// Demand (m or N).
    demand: Vec<f64>,
}

impl RigRecord<'_> {
    /// Part A, from `start` to `end` (s): constant-velocity blocks ([`RAMP`] ramps), the demand
    /// stepping inside each block.
    fn velocity_blocks(&mut self, rng: &mut Rng, start: f64, end: f64) {
        let (t, dt, n) = (self.t, self.dt, self.t.len());
        let mut ts = start;
        let mut x = 0.0f64;
        let mut dir = 1.0f64;
        while ts < end - 1e-9 {
            let speed = rng.range(BLOCK_SPEED.0, BLOCK_SPEED.1);
            let mut len = (BLOCK_STROKE / speed).min(BLOCK_MAX_LEN).min(end - ts);
            if end - (ts + len) < BLOCK_MIN_REST {
                len = end - ts; // no standstill before the sweep
            }
            if x.abs() > BLOCK_STROKE_LIMIT {
                dir = -x.signum();
            }
            let (i0, i1) = (((ts - t[0]) / dt).round() as usize, (((ts + len - t[0]) / dt).round() as usize).min(n));
            let mut next_change = f64::NEG_INFINITY;
            let mut level = 0.0;
            for (i, &ti) in t.iter().enumerate().take(i1).skip(i0) {
                let tau = ti - ts;
                self.v[i] = dir * speed * taper(tau, len, RAMP);
                if ti >= next_change {
                    level = if self.spool {
                        rng.range(SPOOL_LEVEL.0, SPOOL_LEVEL.1)
                    } else {
                        rng.range(FORCE_LEVEL.0, FORCE_LEVEL.1)
                    };
                    next_change = ti + rng.range(BLOCK_STEP_EVERY.0, BLOCK_STEP_EVERY.1);
                }
                self.demand[i] = round_demand(self.spool, if self.spool { level } else { dir * level });
            }
            x += dir * speed * (len - RAMP);
            dir = -dir;
            ts += len;
        }
    }

    /// Part B, from `start` to `end` (s), `len` long: a logarithmic sweep [`SWEEP_F0`] →
    /// [`SWEEP_F1`], displacement amplitude [`SWEEP_AMPLITUDE`] (velocity ≤ [`SWEEP_MAX_SPEED`]),
    /// the velocity a cosine so that the displacement has no offset.
    fn sine_sweep(&mut self, rng: &mut Rng, start: f64, end: f64, len: f64) {
        let t = self.t;
        let (f0, f1) = (SWEEP_F0, SWEEP_F1.min(SWEEP_MAX_CYCLES_PER_SAMPLE / self.dt));
        let k = libm::log(f1 / f0) / len;
        let mut next_change = f64::NEG_INFINITY;
        let mut gain = 0.0;
        let mut level = 0.0;
        for (i, &ti) in t.iter().enumerate() {
            if ti < start || ti >= end {
                continue;
            }
            let tau = ti - start;
            let growth = libm::exp(k * tau);
            let f = f0 * growth;
            let phase = 2.0 * PI * f0 * (growth - 1.0) / k;
            let amp = (2.0 * PI * f * SWEEP_AMPLITUDE).min(SWEEP_MAX_SPEED);
            self.v[i] = amp * libm::cos(phase) * taper(tau, len, RAMP);
            if ti >= next_change {
                gain = rng.range(SWEEP_GAIN.0, SWEEP_GAIN.1);
                level = rng.range(SPOOL_LEVEL.0, SPOOL_LEVEL.1);
                next_change = ti + rng.range(SWEEP_CHANGE_EVERY.0, SWEEP_CHANGE_EVERY.1);
            }
            self.demand[i] = round_demand(self.spool, if self.spool { level } else { gain * self.v[i] });
        }
    }

    /// Part C, from `start` (s) to the end: random velocity (white noise through two
    /// [`RANDOM_CORNER`] first-order low-passes, [`RANDOM_RMS`]), held near mid-stroke by a
    /// [`RANDOM_CENTRING`] position feedback.
    fn random_velocity(&mut self, rng: &mut Rng, start: f64) {
        let (t, dt, n) = (self.t, self.dt, self.t.len());
        let a = libm::exp(-2.0 * PI * RANDOM_CORNER * dt);
        let idx: Vec<usize> = (0..n).filter(|&i| t[i] >= start).collect();
        let (mut s1, mut s2) = (0.0, 0.0);
        let raw: Vec<f64> = idx
            .iter()
            .map(|_| {
                s1 = a * s1 + (1.0 - a) * rng.normal();
                s2 = a * s2 + (1.0 - a) * s1;
                s2
            })
            .collect();
        let scale = RANDOM_RMS / crate::dsp::rms(&raw).max(1e-12);
        let mut pos: f64 = (0..n).filter(|&i| t[i] < start).map(|i| self.v[i] * dt).sum();
        let (mut gain, mut f_coulomb, mut level) = (0.0, 0.0, 0.0);
        let mut next_change = f64::NEG_INFINITY;
        let len = t[n - 1] - start;
        for (j, &i) in idx.iter().enumerate() {
            let v = (scale * raw[j] - pos / RANDOM_CENTRING) * taper(t[i] - start, len, RAMP);
            self.v[i] = v;
            pos += v * dt;
            if t[i] >= next_change {
                gain = rng.range(RANDOM_GAIN.0, RANDOM_GAIN.1);
                f_coulomb = rng.range(RANDOM_COULOMB.0, RANDOM_COULOMB.1);
                level = rng.range(SPOOL_LEVEL.0, SPOOL_LEVEL.1);
                next_change = t[i] + rng.range(RANDOM_CHANGE_EVERY.0, RANDOM_CHANGE_EVERY.1);
            }
            self.demand[i] = round_demand(
                self.spool,
                if self.spool { level } else { gain * v + f_coulomb * libm::tanh(v / RANDOM_COULOMB_WIDTH) },
            );
        }
    }
}

/// ISO 8608 G_d(n0) (m³) of a road name or class.
fn road_gd0(road: &str) -> Result<f64, Error> {
    let r = road.trim().to_ascii_lowercase();
    Ok(match r.as_str() {
        "motorway" => 16e-6,
        "major" => 64e-6,
        "minor" => 128e-6,
        c if c.len() == 1 && ("a"..="h").contains(&c) => 16e-6 * f64::from(1u32 << (2 * (c.as_bytes()[0] - b'a'))),
        _ => {
            return Err(Error::BadOption {
                option: format!("--road {road}"),
                problem: "use motorway, major, minor or an ISO 8608 class A–H".into(),
            })
        }
    })
}

/// What [`hil_run`] returns: the measured velocity, the true velocity and the demand.
type HilRun = (Vec<f64>, Vec<f64>, Vec<f64>);

/// HiL-style run: the quarter truck (Table 1, clipped MSD) on a random ISO 8608 road, coupled to
/// the truth damper at every sample (Jacobi: each side sees the other's output of the same
/// sample).
fn hil_run(
    o: &GenerateOptions,
    p: &Parameters,
    t: &[f64],
    rng: &mut Rng,
    noise_rng: &mut Rng,
) -> Result<HilRun, Error> {
    use quarter_truck::tracking::DemandHistory;
    use quarter_truck::truck::{At, Inputs as TruckInputs, Params as TruckParams};
    let gd0 = road_gd0(&o.road)?;
    let n_waves = 300;
    let (n_lo, n_hi) = (0.01f64, 10.0f64);
    let dln = libm::log(n_hi / n_lo) / n_waves as f64;
    let waves: Vec<(f64, f64, f64)> = (0..n_waves)
        .map(|i| {
            let nn = n_lo * libm::exp((i as f64 + 0.5) * dln);
            let r = nn / 0.1;
            let gd = gd0 * (1.0 / (r * r));
            ((2.0 * gd * nn * dln).sqrt(), 2.0 * PI * nn * o.speed, rng.range(0.0, 2.0 * PI))
        })
        .collect();
    let fade = 1.0f64;
    let z_road = |tt: f64| -> f64 {
        let s = tt - t[0];
        let env = if s < fade { 0.5 - 0.5 * libm::cos(PI * s / fade) } else { 1.0 };
        env * waves.iter().map(|(amp, w, ph)| amp * libm::cos(w * s + ph)).sum::<f64>()
    };
    let truck = TruckParams::default();
    let mut y = truck.start_state();
    // the truck's own damper modes are not used here: its demand needs no past
    let mut past = DemandHistory::default();
    let n = t.len();
    let (mut v, mut v_true, mut demand) = (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
    let mut damper: Option<Damper> = None;
    let mut z_now = z_road(t[0]);
    for k in 0..n {
        let probe = truck.evaluate(&TruckInputs::default(), &y, At { step_start: t[k], since_step: 0.0, past: &past });
        let v_rel = y[1] - y[3];
        let v_measured = measure(&[v_rel], o.noise.v_damper, noise_rng)[0];
        let f_dem = (probe.f_demand * 10.0).round() / 10.0;
        let v_in = if o.errors_in_variables { v_rel } else { v_measured };
        let inputs =
            Inputs { v_damper: v_in, a_damper: 0.0, f_demand: f_dem, x_spool_demand: 0.0, ..Default::default() };
        let d = match damper.as_mut() {
            None => damper.insert(Damper::new(*p, inputs, t[0]).map_err(Error::TruthParameters)?),
            Some(d) => {
                d.do_step(t[k] - t[k - 1]).map_err(|cause| Error::TruthFailed { t: t[k], cause })?;
                d.inputs = inputs;
                d
            }
        };
        let load_cell = d.load_cell();
        v.push(v_measured);
        v_true.push(v_rel);
        demand.push(f_dem);
        if k + 1 < n {
            let h = t[k + 1] - t[k];
            let z_next = z_road(t[k + 1]);
            let u = TruckInputs { z_road: z_now, v_road: (z_next - z_now) / h, f_damper: load_cell };
            truck.advance(&u, &mut y, h, t[k], &mut past);
            z_now = z_next;
        }
    }
    Ok((v, v_true, demand))
}

fn measure(x: &[f64], s: Sensor, rng: &mut Rng) -> Vec<f64> {
    x.iter().map(|v| ((v + s.noise * rng.normal()) / s.quantum).round() * s.quantum).collect()
}

fn decimals(quantum: f64) -> usize {
    (-libm::log10(quantum)).ceil().max(0.0) as usize
}

/// Fewest samples of a generated record: the analysis's spectra and correlations need some
/// hundreds.
const MIN_SAMPLES: usize = 400;
/// The share of the record the noise floor's train part takes (-), compare's default split.
const TRAIN_FRACTION: f64 = 0.7;
/// Salts of the seed for the three random streams, so that the effects' sizes, the inputs and the
/// sensor noise are independent of one another: the effects' sizes…
const EFFECT_STREAM: u64 = 0x0E55_EC75;
/// … the inputs…
const INPUT_STREAM: u64 = 0x1A7B_0115;
/// … and the sensor noise.
const NOISE_STREAM: u64 = 0x5E45_0125;

/// Generates the data (no files written).
pub fn generate(o: &GenerateOptions) -> Result<Generated, Error> {
    let n = checked_samples(o)?;
    let mut effect_rng = Rng::new(o.seed ^ EFFECT_STREAM);
    let mut input_rng = Rng::new(o.seed ^ INPUT_STREAM);
    let mut noise_rng = Rng::new(o.seed ^ NOISE_STREAM);
    let (params, effect_records) = truth_parameters(o, &mut effect_rng)?;
    let t: Vec<f64> = (0..n).map(|k| k as f64 / o.rate).collect();
    let t_oil = oil_temperature(o, &params, &t)?;
    let run = match o.input {
        InputStyle::Rig => rig_run(o, &params, &t, &t_oil, &mut input_rng, &mut noise_rng)?,
        InputStyle::Hil => hil_truth_run(o, &params, &t, &t_oil, &mut input_rng, &mut noise_rng)?,
    };
    let TruthRun { velocity_column, v_drive, demand, clean } = run;

    // Measurement chain of the other sensors.
    let f_meas = measure(&clean.f_damper, o.noise.f_damper, &mut noise_rng);
    let held = params.control_mode == 2;
    let columns = measured_columns(o, held, &t, velocity_column, &demand, &f_meas, &clean, &t_oil, &mut noise_rng);

    let oracle_drive = Drive {
        time: t.clone(),
        v_damper: v_drive,
        demand: demand_of(o, &params, &demand),
        t_oil,
        x_damper_start: None,
    };
    let (expected_floor, oracle_nrmse) = noise_floor(o, &params, &f_meas, &oracle_drive, n)?;
    let truth = Truth {
        generator: format!("damper generate {}", env!("CARGO_PKG_VERSION")),
        note: "the truth: compare and diagnose never read this file".into(),
        measurement: o.out.display().to_string(),
        seed: o.seed,
        samples: n,
        rate_hz: o.rate,
        duration_s: o.duration,
        control_mode: params.control_mode.into(),
        tare_load_cell: params.tare_load_cell,
        velocity_driving_the_truth: if o.errors_in_variables {
            "the true velocity (errors in variables: the CSV has the sensor's version)"
        } else {
            "the measured velocity, as the rig controller sees it (the CSV's velocity, or its derivative)"
        }
        .into(),
        inputs: truth_inputs(o)?,
        effects: effect_records,
        set: o.sets.iter().map(|(name, _)| (name.clone(), get_parameter(&params, name).ok().map(Into::into))).collect(),
        changed_parameters: changed_parameters(&params).into_iter().map(|(n, v)| (n.to_string(), v.into())).collect(),
        sensors: truth_sensors(o),
        noise_floor: TruthNoiseFloor {
            train_fraction: TRAIN_FRACTION,
            expected_nrmse_validation: expected_floor,
            expected_definition: "sqrt(noise_std^2 + quantum^2/12) / std(measured F_damper, validation part)".into(),
            oracle_nrmse_validation: oracle_nrmse,
            oracle_definition:
                "validation NRMSE of the truth model with the load-cell filter, driven by the measured inputs".into(),
        },
    };
    Ok(Generated { params, time: t, columns, clean, truth, expected_floor, oracle_nrmse })
}

/// The number of samples the options ask for, or why they cannot be generated.
fn checked_samples(o: &GenerateOptions) -> Result<usize, Error> {
    if !(o.rate > 0.0 && o.rate.is_finite()) {
        return Err(Error::BadOption {
            option: format!("--rate {}", o.rate),
            problem: "must be a positive number of Hz".into(),
        });
    }
    if !(o.duration > 0.0 && o.duration.is_finite()) {
        return Err(Error::BadOption {
            option: format!("--duration {}", o.duration),
            problem: "must be a positive number of seconds".into(),
        });
    }
    let n = (o.duration * o.rate).round() as usize + 1;
    if n < MIN_SAMPLES {
        return Err(Error::TooFewGenerated { duration: o.duration, rate: o.rate, samples: n });
    }
    if o.displacement && o.input == InputStyle::Hil {
        return Err(Error::RigOnly { option: "--displacement", why: "" });
    }
    if o.spool_control && o.input == InputStyle::Hil {
        return Err(Error::RigOnly { option: "--control spool", why: " (the HiL truck demands a force)" });
    }
    if let Some(fc) = o.lowpass_hz {
        if fc.is_nan() || fc <= 0.0 {
            return Err(Error::BadOption {
                option: format!("--lowpass {fc}"),
                problem: "must be positive (or 'off')".into(),
            });
        }
    }
    Ok(n)
}

/// The demand the truth is driven with: none for a passive damper (the valve held), else the
/// spool position or the force.
fn demand_of(o: &GenerateOptions, params: &Parameters, d: &[f64]) -> Demand {
    let held = params.control_mode == 2;
    match (held, o.spool_control) {
        (true, _) => Demand::Held,
        (false, true) => Demand::SpoolPosition(d.to_vec()),
        (false, false) => Demand::Force(d.to_vec()),
    }
}

/// What driving the truth gave: the velocity (or displacement) column as measured, the velocity
/// the model is driven with, the demand, and the truth model's outputs.
struct TruthRun {
    velocity_column: (Column, Vec<f64>),
    v_drive: Vec<f64>,
    demand: Vec<f64>,
    clean: Prediction,
}

/// The truth model's outputs, driven by the demand `d` and the velocity as measured,
/// `v_measured` (as the rig's controller sees it), or with `errors_in_variables` the true one,
/// `v_true` (the module's documentation says why and what that does).
fn truth_prediction(
    o: &GenerateOptions,
    params: &Parameters,
    t: &[f64],
    t_oil: &Option<Vec<f64>>,
    (v_true, v_measured): (Vec<f64>, &[f64]),
    d: &[f64],
) -> Result<Prediction, Error> {
    let drive_truth = if o.errors_in_variables { v_true } else { v_measured.to_vec() };
    let drive = Drive {
        time: t.to_vec(),
        v_damper: drive_truth,
        demand: demand_of(o, params, d),
        t_oil: t_oil.clone(),
        x_damper_start: None,
    };
    Model { params: *params, load_cell_lowpass_hz: o.lowpass_hz }.run(&drive)
}

/// The rig run: the rig's inputs, the motion measured (velocity, or displacement and the velocity
/// compare makes of it), and the truth driven by it.
fn rig_run(
    o: &GenerateOptions,
    params: &Parameters,
    t: &[f64],
    t_oil: &Option<Vec<f64>>,
    input_rng: &mut Rng,
    noise_rng: &mut Rng,
) -> Result<TruthRun, Error> {
    let n = t.len();
    let nz = o.noise;
    let (v_true, d) = rig_inputs(t, input_rng, o.spool_control, params.x_spool_start);
    let (column, v_measured) = if o.displacement {
        let mut x_true = vec![params.x_damper_start; n];
        for k in 1..n {
            x_true[k] = x_true[k - 1] + v_true[k - 1] * (t[k] - t[k - 1]);
        }
        let x = measure(&x_true, nz.x_damper, noise_rng);
        // the velocity compare makes of the displacement (the rig controller's)
        let motion = crate::motion::motion(t, Some(crate::dsp::differentiate(t, &x)), Some(&x), true)?;
        let v = motion.v.unwrap_or_default();
        ((Column::XDamper, x), v)
    } else {
        let v = measure(&v_true, nz.v_damper, noise_rng);
        ((Column::VDamper, v.clone()), v)
    };
    let clean = truth_prediction(o, params, t, t_oil, (v_true, &v_measured), &d)?;
    Ok(TruthRun { velocity_column: column, v_drive: v_measured, demand: d, clean })
}

/// The HiL run: the closed loop makes the motion and the demand; the truth's force is then the
/// damper's under that motion as sampled, stepped as the rig inputs are (the velocity
/// interpolated between samples), as the motion of a real truck is continuous.
fn hil_truth_run(
    o: &GenerateOptions,
    params: &Parameters,
    t: &[f64],
    t_oil: &Option<Vec<f64>>,
    input_rng: &mut Rng,
    noise_rng: &mut Rng,
) -> Result<TruthRun, Error> {
    let (v_measured, v_true, d) = hil_run(o, params, t, input_rng, noise_rng)?;
    let clean = truth_prediction(o, params, t, t_oil, (v_true, &v_measured), &d)?;
    Ok(TruthRun { velocity_column: (Column::VDamper, v_measured.clone()), v_drive: v_measured, demand: d, clean })
}

/// The CSV's columns: time, the motion, the demand (unless passive), the force, the oil
/// temperature where it moves, and (unless minimal) the spool, the current and the pressures,
/// each through its sensor.
#[allow(clippy::too_many_arguments, reason = "the columns' sources, each used once")]
fn measured_columns(
    o: &GenerateOptions,
    held: bool,
    t: &[f64],
    velocity_column: (Column, Vec<f64>),
    demand: &[f64],
    f_meas: &[f64],
    clean: &Prediction,
    t_oil: &Option<Vec<f64>>,
    noise_rng: &mut Rng,
) -> Vec<(Column, Vec<f64>)> {
    let nz = o.noise;
    let mut columns: Vec<(Column, Vec<f64>)> = vec![(Column::Time, t.to_vec()), velocity_column];
    if !held {
        columns.push((if o.spool_control { Column::XSpoolDemand } else { Column::FDemand }, demand.to_vec()));
    }
    columns.push((Column::FDamper, f_meas.to_vec()));
    if let Some(temperature) = t_oil {
        columns.push((Column::TOil, measure(temperature, nz.t_oil, noise_rng)));
    }
    if !o.minimal {
        // a held valve's spool and coil are still: nothing to measure
        if !held {
            columns.push((Column::XSpool, measure(&clean.x_spool, nz.x_spool, noise_rng)));
            columns.push((Column::ISol, measure(&clean.i_sol, nz.i_sol, noise_rng)));
        }
        columns.push((Column::PExt, measure(&clean.p_ext, nz.pressure, noise_rng)));
        columns.push((Column::PComp, measure(&clean.p_comp, nz.pressure, noise_rng)));
    }
    columns
}

/// Noise floor: what the force sensor alone leaves (analytic), and what the truth model leaves
/// when driven by the measured inputs `oracle_drive` (the oracle; equal unless
/// errors-in-variables), both as validation NRMSEs of the measured force `f_meas` (`n` samples).
fn noise_floor(
    o: &GenerateOptions,
    params: &Parameters,
    f_meas: &[f64],
    oracle_drive: &Drive,
    n: usize,
) -> Result<(f64, f64), Error> {
    let split = (TRAIN_FRACTION * n as f64).round() as usize;
    let (noise, quantum) = (o.noise.f_damper.noise, o.noise.f_damper.quantum);
    let sigma_f = (noise * noise + quantum * quantum / 12.0).sqrt();
    let expected_floor = sigma_f / std(&f_meas[split..]);
    let oracle = Model { params: *params, load_cell_lowpass_hz: o.lowpass_hz }.force(oracle_drive, n)?;
    let oracle_nrmse = crate::dsp::metrics(&f_meas[split..], &oracle[split..]).nrmse;
    Ok((expected_floor, oracle_nrmse))
}

/// The truth file's sensors: the load cell and each sensor written.
fn truth_sensors(o: &GenerateOptions) -> TruthSensors {
    let nz = o.noise;
    let optional = |s: Sensor| (!o.minimal).then(|| s.into());
    TruthSensors {
        f_damper: LoadCell {
            noise_std: nz.f_damper.noise,
            quantum: nz.f_damper.quantum,
            lowpass_hz: o.lowpass_hz,
            lowpass: "first-order, on the force at the controller's rate before noise and quantisation (exact for a force linear between those points)"
                .into(),
        },
        x_damper: o.displacement.then(|| nz.x_damper.into()),
        v_damper: (!o.displacement).then(|| nz.v_damper.into()),
        x_spool: optional(nz.x_spool),
        i_sol: optional(nz.i_sol),
        p_ext: optional(nz.pressure),
        p_comp: optional(nz.pressure),
    }
}

/// The truth file's description of the inputs.
fn truth_inputs(o: &GenerateOptions) -> Result<TruthInputs, Error> {
    Ok(match o.input {
        InputStyle::Rig => TruthInputs::Rig {
            description: "thirds, starting at rest and moving at once: constant-velocity blocks 0.05-0.25 m/s with 15 ms ramps and demand steps \
                 (1-20 kN, or spool 0.9-3.5 mm) every 80-150 ms; a logarithmic sweep 0.5-12 Hz, 30 mm \
                 (<= 0.15 m/s), demand = C*v with C 10-60 kNs/m; random velocity (8 Hz band, 0.1 m/s RMS), \
                 demand = C*v + F0*tanh(v/0.01 m/s)"
                .into(),
        },
        InputStyle::Hil => TruthInputs::Hil {
            road: o.road.clone(),
            road_gd_n0_m3: road_gd0(&o.road)?,
            speed_m_s: o.speed,
            description: "quarter truck (Table 1, clipped Modified Skyhook) on an ISO 8608 road (300 sinusoids, \
                 0.01-10 cycle/m, 1 s fade-in), coupled to the truth damper at every sample"
                .into(),
        },
    })
}

/// The CSV text of generated columns.
pub fn csv_text(g: &Generated, o: &GenerateOptions) -> String {
    let nz = &o.noise;
    let digits = |c: Column| -> usize {
        match c {
            Column::Time => 7,
            Column::VDamper => decimals(nz.v_damper.quantum),
            Column::XDamper => decimals(nz.x_damper.quantum),
            Column::FDemand => 1,
            Column::XSpoolDemand => 7,
            Column::FDamper => decimals(nz.f_damper.quantum),
            Column::XSpool => decimals(nz.x_spool.quantum),
            Column::ISol => decimals(nz.i_sol.quantum),
            Column::PExt | Column::PComp => decimals(nz.pressure.quantum),
            Column::TOil => decimals(nz.t_oil.quantum),
        }
    };
    let mut s = String::new();
    s += &g.columns.iter().map(|(c, _)| c.name()).collect::<Vec<_>>().join(",");
    s.push('\n');
    let n = g.time.len();
    for k in 0..n {
        for (j, (c, x)) in g.columns.iter().enumerate() {
            if j > 0 {
                s.push(',');
            }
            let d = digits(*c);
            let mut cell = format!("{:.*}", d, x[k]);
            if cell.contains('.') {
                cell = cell.trim_end_matches('0').trim_end_matches('.').to_string();
            }
            if cell == "-0" {
                cell = "0".into();
            }
            let _ = write!(s, "{cell}");
        }
        s.push('\n');
    }
    s
}

/// Generates and writes the CSV to `o.out` and the truth to `o.truth`: the data set is the two
/// files, which `compare` reads back (the CSV) and tests score against (the truth).
pub fn write(o: &GenerateOptions) -> Result<Generated, Error> {
    if o.out == o.truth {
        return Err(Error::SameOutAndTruth);
    }
    let g = generate(o)?;
    for path in [&o.out, &o.truth] {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| Error::CreateDir { path: dir.to_path_buf(), source })?;
        }
    }
    std::fs::write(&o.out, csv_text(&g, o)).map_err(|source| Error::Io { path: o.out.clone(), source })?;
    std::fs::write(&o.truth, crate::summary::to_json(&g.truth))
        .map_err(|source| Error::Io { path: o.truth.clone(), source })?;
    Ok(g)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_truth_integrates_at_a_converged_tolerance_unless_rtol_is_set() {
        let mut o = GenerateOptions::new("unused.csv", "unused.json");
        let (p, _) = truth_parameters(&o, &mut Rng::new(1)).unwrap();
        assert_eq!(p.rtol, TRUTH_RTOL);
        assert!(TRUTH_RTOL < Parameters::default().rtol / 100.0);
        o.sets.push(("rtol".into(), "1e-3".into()));
        assert_eq!(truth_parameters(&o, &mut Rng::new(1)).unwrap().0.rtol, 1e-3);
    }
}
