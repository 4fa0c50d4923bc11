//! The diagnosis on data with a hidden effect: over seeds, each effect hidden at a random plausible
//! value (by `damper generate`, absent from the model) ranks first, brings the residual to the noise
//! floor, cuts the validation NRMSE by at least half wherever the baseline leaves room for that
//! (baseline ≥ 2× the floor: a weak effect near the noise cannot halve it), and is fitted within
//! 20 % of the truth;
//! data with nothing hidden get "none"; an effect outside the catalog (a slow drift of the load
//! cell, as from temperature) gets "unexplained".
mod common;

use damper_cli::compare::CompareOptions;
use damper_cli::diagnose_cmd::{diagnose_measurement, Diagnosed};
use damper_cli::parameters::get_real;

/// The floors.
const MIN_CUT: f64 = 0.5;
const PARAM_TOLERANCE: f64 = 0.2;
/// "At the noise floor": within this factor of the floor estimated from the residual.
const FLOOR_FACTOR: f64 = 1.3;
const SEEDS: [u64; 2] = [1, 2];

fn run(csv: &std::path::Path, dir: &std::path::Path) -> Diagnosed {
    let mut o = CompareOptions::new(csv, dir.join("out"));
    o.load_cell_lowpass_hz = Some(400.0);
    o.quiet = true;
    diagnose_measurement(&o, 2, false).expect("diagnose")
}

#[test]
fn each_hidden_catalog_effect_is_named_and_fitted() {
    // (effect, the parameter fitted and compared with the truth)
    let cases = [
        ("seal_friction", "F_coulomb"),
        ("piston_leakage", "G_leak"),
        ("amplifier_delay", "tau_amp"),
        ("compressibility", "air_fraction"),
        ("mount_compliance", "k1_mount"),
        ("check_valve_cracking", "p_cv_crack"),
        ("flow_forces", "Cv_valve"),
    ];
    for (effect, param) in cases {
        for seed in SEEDS {
            let dir = common::scratch(&format!("diag_{effect}_{seed}"));
            let (csv, g) = common::generate(&dir, "m", |o| {
                o.effects = vec![effect.to_string()];
                o.seed = seed;
            });
            let r = run(&csv, &dir);
            let d = &r.diagnosis;
            let best = &d.candidates[0];
            let truth = get_real(&g.params, param).unwrap();
            let fitted = best.params.iter().find(|p| p.0 == param).map(|p| p.1).unwrap();
            let what = format!(
                "{effect} (seed {seed}): verdict {} {:?}, best {} cut {:.2}, NRMSE {:.4} (floor {:.4}), {param} {fitted:.4e} vs truth {truth:.4e}",
                d.verdict, d.best_effect, best.effect, best.reduction, best.nrmse_validation, d.nrmse_noise_floor
            );
            eprintln!("{what}");
            assert_eq!(d.verdict, "effect", "{what}");
            assert_eq!(d.best_effect, Some(effect), "{what}");
            if d.nrmse_baseline >= 2.0 * d.nrmse_noise_floor {
                assert!(best.reduction >= MIN_CUT, "{what}");
            }
            assert!(best.nrmse_validation <= FLOOR_FACTOR * d.nrmse_noise_floor, "{what}");
            assert!((fitted - truth).abs() <= PARAM_TOLERANCE * truth, "{what}");
        }
    }
}

#[test]
fn nothing_hidden_gives_none() {
    for seed in SEEDS {
        let dir = common::scratch(&format!("diag_none_{seed}"));
        let (csv, _) = common::generate(&dir, "m", |o| o.seed = seed);
        let d = run(&csv, &dir).diagnosis;
        assert_eq!(d.verdict, "none", "seed {seed}: {}", d.explanation);
        assert_eq!(d.best_effect, None);
    }
}

#[test]
fn an_effect_outside_the_catalog_is_unexplained() {
    let dir = common::scratch("diag_drift");
    let (csv, _) = common::generate(&dir, "m", |o| o.seed = 3);
    // a load-cell drift of +600 N over the record (as from warming): no catalog effect makes it
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let col = header.split(',').position(|c| c == "F_damper").unwrap();
    let rows: Vec<&str> = lines.collect();
    let n = rows.len();
    let mut out = format!("{header}\n");
    for (k, row) in rows.iter().enumerate() {
        let mut cells: Vec<String> = row.split(',').map(String::from).collect();
        let f: f64 = cells[col].parse().unwrap();
        cells[col] = format!("{}", f + 600.0 * k as f64 / n as f64);
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    let drifted = dir.join("drifted.csv");
    std::fs::write(&drifted, out).unwrap();
    let d = run(&drifted, &dir).diagnosis;
    assert_eq!(d.verdict, "unexplained", "{}", d.explanation);
    assert_eq!(d.best_effect, None);
}
