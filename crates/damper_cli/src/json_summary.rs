//! `summary.json` (typed in `damper_engine::summary`) from a comparison or a diagnosis.

use damper_engine::analysis::{observations, Analysis, Lag, Whiteness};
use damper_engine::before_after::{regime_rows, After};
use damper_engine::candidate::Candidate;
use damper_engine::comparison::{Comparison, ModelSetup};
use damper_engine::diagnose_measurement::Diagnosed;
use damper_engine::dsp::{Metrics, NoiseEstimate};
use damper_engine::residual_signature;
use damper_engine::summary::{self, Summary};

fn metrics(m: &Metrics) -> summary::Metrics {
    summary::Metrics {
        fit_percent: m.fit_percent,
        nrmse: m.nrmse,
        rmse: m.rmse,
        bias: m.bias,
        std_measured: m.std_measured,
        samples: m.samples,
    }
}

/// The model settings of the summary.
pub fn model_settings(setup: &ModelSetup) -> summary::ModelSettings {
    let p = &setup.model.params;
    summary::ModelSettings {
        control_mode: p.control_mode.into(),
        tare_load_cell: p.tare_load_cell,
        load_cell_lowpass_hz: setup.model.load_cell_lowpass_hz,
        backend: setup.backend.name().into(),
        fmu: setup.backend.fmu_path().map(|p| p.display().to_string()),
        effects: setup.effects.iter().map(|(k, on)| (k.to_string(), *on)).collect(),
        changed_parameters: setup.changed.iter().map(|(n, v)| (n.to_string(), (*v).into())).collect(),
    }
}

/// `summary.json` of `damper compare`, with the diagnosis empty.
pub fn compared(c: &Comparison) -> Summary {
    let a = &c.analysis;
    let m = &c.measurement;
    Summary {
        tool: "damper compare".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        measurement: m.path.clone(),
        samples: m.len(),
        sample_interval_s: a.dt,
        duration_s: m.time[m.len() - 1] - m.time[0],
        control_mode: if c.drive.control_mode() == 0 { "force" } else { "spool_position" }.into(),
        velocity_from_displacement: m.velocity_from_displacement,
        model: model_settings(&c.setup),
        split: summary::Split {
            train_fraction: c.options.split,
            first_validation_sample: a.split,
            t_split: m.time[a.split],
        },
        residual_definition: "model - measured (as in docs/effects.md)".into(),
        nrmse_baseline: a.force().validation.nrmse,
        observations: observations(a),
        noise_floor_estimate: a.noise_floor_estimate,
        signals: signals(a),
        regimes: regimes(a),
        frequency_bands: frequency_bands(a),
        residual_signature: residual_signature(a),
        worst_windows: worst_windows(a),
        lag: lag(&a.force().lag),
        whiteness: whiteness(&a.whiteness),
        input_cross_correlation: input_cross_correlation(a),
        events: summary::Events {
            velocity_reversals: a.reversals.len(),
            demand_steps: a.demand_steps.len(),
            residual_jump_at_reversals: a.reversal_jump,
        },
        model_run_s: c.run_seconds,
        warnings: c.warnings.clone(),
        verdict: None,
        best_effect: None,
        candidates: None,
        diagnosis: None,
    }
}

/// Each compared signal's scores and lags, by its name (into the summary's map).
fn signals<M: FromIterator<(String, summary::Signal)>>(a: &Analysis) -> M {
    a.fits
        .iter()
        .map(|s| {
            let signal = summary::Signal {
                unit: s.column.si_unit().into(),
                train: metrics(&s.train),
                validation: metrics(&s.validation),
                lag_s: s.lag.seconds,
                lag_refined_s: s.lag.refined_seconds,
                lag_of_changes_s: s.lag.changes_seconds,
            };
            (s.column.name().to_string(), signal)
        })
        .collect()
}

/// Where the force error lives: each regime's share of it against its share of time.
fn regimes(a: &Analysis) -> Vec<summary::Regime> {
    a.regimes
        .iter()
        .map(|r| summary::Regime {
            group: r.group.into(),
            regime: r.name.clone(),
            samples: r.samples,
            time_share: r.time_share,
            rms_residual: r.rms,
            mean_residual: r.mean,
            error_share: r.error_share,
            concentration: r.concentration,
        })
        .collect()
}

/// The residual's share of variance per frequency band.
fn frequency_bands(a: &Analysis) -> Vec<summary::Band> {
    a.bands
        .iter()
        .map(|b| summary::Band {
            f_lo_hz: b.lo,
            f_hi_hz: b.hi,
            residual_share: b.residual_share,
            residual_rms: b.residual_rms,
            band_nrmse: b.band_nrmse,
        })
        .collect()
}

/// What the residual follows, its dominant band, and the sentence that says so.
fn residual_signature(a: &Analysis) -> summary::ResidualSignature {
    summary::ResidualSignature {
        follows: a
            .signature
            .iter()
            .map(|f| summary::Follows { quantity: f.quantity.key().into(), share: f.share })
            .collect(),
        dominant_band: a.dominant_band.map(|b| summary::DominantBand {
            f_lo_hz: b.lo_hz,
            f_hi_hz: b.hi_hz,
            share: b.share,
        }),
        text: residual_signature::sentence(&a.signature, a.dominant_band),
    }
}

/// The worst time windows of the force residual.
fn worst_windows(a: &Analysis) -> Vec<summary::Window> {
    a.worst
        .iter()
        .map(|w| summary::Window {
            t_start: w.t_start,
            t_end: w.t_end,
            rms_residual: w.rms,
            mean_residual: w.mean,
            mean_abs_velocity: w.mean_abs_velocity,
            tags: w.tags.clone(),
        })
        .collect()
}

/// The lag between measured and modelled force.
fn lag(l: &Lag) -> summary::Lag {
    summary::Lag {
        samples: l.samples as i64,
        seconds: l.seconds,
        refined_seconds: l.refined_seconds,
        peak_correlation: l.peak,
        search_range_s: l.max_seconds,
        of_changes_s: l.changes_seconds,
        found: l.found,
        definition: "argmax_k sum_t y(t+k) yhat(t): positive = the measured force comes later".into(),
    }
}

/// The residual's whiteness on the validation part.
fn whiteness(w: &Whiteness) -> summary::Whiteness {
    summary::Whiteness {
        part: "validation".into(),
        samples: w.samples,
        max_lag: w.max_lag,
        band: w.band,
        fraction_outside: w.fraction_outside,
        ljung_box_q: w.ljung_box_q,
        ljung_box_lags: w.ljung_box_lags,
        chi2_95: w.chi2_95,
        white: w.white,
    }
}

/// The residual's largest cross-correlation with each input, by the input's name (into the
/// summary's map).
fn input_cross_correlation<M: FromIterator<(String, summary::CrossCorrelation)>>(a: &Analysis) -> M {
    a.input_correlations
        .iter()
        .map(|x| {
            let xc = summary::CrossCorrelation {
                max_abs: x.max_abs,
                at_lag_s: x.at_lag_seconds,
                band: x.band,
                within_band: x.max_abs <= x.band,
            };
            (x.input.name().to_string(), xc)
        })
        .collect()
}

/// `summary.json` of `damper diagnose`: compare's with the diagnosis filled in.
pub fn diagnosed(r: &Diagnosed) -> Summary {
    let d = &r.diagnosis;
    Summary {
        nrmse_baseline: d.nrmse_baseline,
        verdict: Some(d.verdict),
        best_effect: d.best_effect.map(String::from),
        candidates: Some(d.candidates.iter().map(candidate).collect()),
        diagnosis: Some(summary::Diagnosis {
            effects: d.effects.iter().map(|e| e.to_string()).collect(),
            nrmse_after_ladder: d.ladder.nrmse_validation,
            after: r.after.as_ref().map(|a| after(&r.comparison, a)),
            nrmse_noise_floor: d.nrmse_noise_floor,
            floor: summary::Floor {
                nrmse_noise: d.floor.nrmse_noise,
                nrmse_numerics: d.floor.nrmse_numerics,
                noise_sigma: d.floor.noise.sigma,
                noise_sigma_window: d.floor.noise.sigma_window,
                noise_sigma_mad: d.floor.noise.sigma_mad,
                noise_sigma_all: d.floor.noise.sigma_all,
                noise_method: NoiseEstimate::METHOD.into(),
                rtol: d.floor.rtol,
                rtol_check: d.floor.rtol_check,
                delta_v: d.floor.delta_v,
                sensitive_threshold: d.floor.sensitive_threshold,
                left_out_validation: d.floor.left_out_validation,
                nrmse_inputs: d.floor.nrmse_inputs,
                nrmse_inputs_unseen: d.floor.nrmse_inputs_unseen,
            },
            explanation: d.explanation.clone(),
            ladder: d
                .ladder
                .rungs
                .iter()
                .map(|l| summary::Rung {
                    added: l.added.into(),
                    refit: l.refit,
                    params: summary::fitted(&l.params),
                    nrmse_validation: l.nrmse_validation,
                    explained: l.explained,
                    kept: l.kept,
                })
                .collect(),
            parts: d
                .parts
                .iter()
                .map(|p| summary::RecordPart {
                    part: p.name.clone(),
                    t_start: p.t_start,
                    t_end: p.t_end,
                    rms_residual: p.rms_residual,
                    rms_floor: p.rms_floor,
                    ratio: p.ratio(),
                })
                .collect(),
        }),
        ..compared(&r.comparison)
    }
}

fn candidate(c: &Candidate) -> summary::Candidate {
    summary::Candidate {
        effect: c.effect.into(),
        action: c.action.into(),
        nrmse_train: c.nrmse_train,
        nrmse_validation: c.nrmse_validation,
        reduction: c.reduction,
        explained: c.explained,
        params: summary::fitted_with(&c.params, &c.inherited),
        plausible: c.plausible,
        flags: c.flags.clone(),
        signature: c.signature.into(),
        model_runs: c.evaluations,
    }
}

/// The summary's `after` object.
fn after(c: &Comparison, after: &After) -> summary::After {
    let (b, a) = (&c.analysis, &after.analysis);
    let before_after = |before, after| summary::BeforeAfter { before, after };
    summary::After {
        effects: after.effects.iter().map(|e| e.to_string()).collect(),
        validation_nrmse: b
            .fits
            .iter()
            .zip(&a.fits)
            .map(|(fb, fa)| (fb.column.name().to_string(), before_after(fb.validation.nrmse, fa.validation.nrmse)))
            .collect(),
        white_after: a.whiteness.white,
        ljung_box_q: before_after(b.whiteness.ljung_box_q, a.whiteness.ljung_box_q),
        regimes: regime_rows(b, a)
            .into_iter()
            .map(|(g, n, share, rb, ra)| summary::RegimeChange {
                group: g.into(),
                regime: n.into(),
                time_share: share,
                rms_before: rb,
                rms_after: ra,
            })
            .collect(),
    }
}
