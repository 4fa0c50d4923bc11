//! Calibration on generated records of a damper whose nominal parameters differ from the model's:
//! the moved parameters are recovered within 3 reported standard uncertainties; with the
//! calibrated parameter set a hidden effect that the nominal model misattributes is named; the
//! .ssv written round-trips and a bad one is an error with its line and field.
use crate::common;

use damper_engine::calibrate::{calibrate, CalibrateOptions, Calibration, Status};
use damper_engine::calibration_file::parameter_set;
use damper_engine::comparison::{build_model, CompareOptions};
use damper_engine::diagnose_measurement::diagnose_measurement;
use damper_engine::generate::GenerateOptions;
use damper_engine::parameters::get_real;
use damper_engine::ssv;
use semi_active_damper::physics::params::Parameters;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The damper "as built": seven nominal parameters moved by 15–30 %.
const MOVED: [(&str, f64); 7] = [
    ("air_fraction", 0.032),
    ("k1_mount", 4.0e7),
    ("p_reservoir0", 6.0e5),
    ("K_sol", 51.0),
    ("V_hose", 1.3e-5),
    ("p_cv_crack", 3.9e4),
    ("tau_coil", 3.6e-4),
];
/// The floor: moved parameters recovered within 3 reported standard uncertainties. (Measured: all
/// seven within 2.2. With tau_coil left at its default, p_reservoir0 landed 6.7 uncertainties
/// (0.06 %) from its truth and V_gas0 3.1, the same at rtol 1e-6: a reported uncertainty can be
/// optimistic; docs/calibrate.md.)
const WITHIN_UNCERTAINTY: usize = 6;
/// Every moved parameter within this relative error, and its relative uncertainty below it.
const RELATIVE: f64 = 0.01;

/// The real damper: the moved parameters, and converged numerics (rtol 1e-6) so that the data
/// carry no solver error of their own.
fn as_built(o: &mut GenerateOptions) {
    o.sets = MOVED.iter().map(|(n, v)| (n.to_string(), v.to_string())).collect();
    o.sets.push(("rtol".into(), "1e-6".into()));
}

/// A rig record in force control and one in spool-position control, 8 s each.
fn calibration_records(dir: &Path) -> Vec<PathBuf> {
    let (force, _) = common::generate(dir, "cal_force", |o| {
        as_built(o);
        o.duration = 8.0;
        o.seed = 11;
    });
    let (spool, _) = common::generate(dir, "cal_spool", |o| {
        as_built(o);
        o.duration = 8.0;
        o.seed = 12;
        o.spool_control = true;
    });
    vec![force, spool]
}

/// The calibration of the records of [`calibration_records`], once for all tests, with its
/// parameter set written to `parameters.ssv` in the returned directory.
fn calibrated() -> &'static (PathBuf, Calibration) {
    static CAL: OnceLock<(PathBuf, Calibration)> = OnceLock::new();
    CAL.get_or_init(|| {
        let dir = common::scratch("calibrate");
        let mut o = CalibrateOptions::new(calibration_records(&dir));
        o.compare.load_cell_lowpass_hz = Some(400.0);
        o.threads = 2;
        let c = calibrate(&o, &|_| {}).expect("calibrate");
        std::fs::write(dir.join("parameters.ssv"), ssv::to_string("test", "calibrated", &parameter_set(&c, None)))
            .unwrap();
        (dir, c)
    })
}

#[test]
fn moved_parameters_are_recovered_within_their_uncertainty() {
    let (_, c) = calibrated();
    for p in &c.parameters {
        eprintln!(
            "{:<14} start {:.4e} fitted {:.4e} ± {:?} corr {:?} {:?}",
            p.name, p.start, p.value, p.std_error, p.correlation, p.status
        );
    }
    for r in &c.records {
        eprintln!("{}: NRMSE {:.4} → {:.4} (floor {:.4})", r.path, r.nrmse_before, r.nrmse_after, r.noise_floor);
    }
    eprintln!("{} model runs, {:.1} s", c.model_runs, c.seconds);
    let mut within = 0;
    for (name, truth) in MOVED {
        let p = c.parameters.iter().find(|p| p.name == name).expect("fitted by default");
        assert_eq!(p.status, Status::Fitted, "{name}");
        let se = p.std_error.expect("identified");
        let what = format!("{name}: fitted {} ± {se}, truth {truth}", p.value);
        eprintln!("{what}: {:.1} uncertainties off", (p.value - truth).abs() / se);
        within += usize::from((p.value - truth).abs() <= 3.0 * se);
        assert!((p.value / truth - 1.0).abs() < RELATIVE, "{what}");
        assert!(p.relative().unwrap() < RELATIVE, "{name}: relative uncertainty {:?}", p.relative());
    }
    assert!(within >= WITHIN_UNCERTAINTY, "{within} of {} within 3 uncertainties", MOVED.len());
    for r in &c.records {
        assert!(r.nrmse_after < 1.2 * r.noise_floor && r.nrmse_after < 0.2 * r.nrmse_before, "{r:?}");
    }
    // a parameter held is reported with its reason and kept at its start value
    for p in c.parameters.iter().filter(|p| p.status != Status::Fitted) {
        assert!(p.value == p.start && p.std_error.is_none(), "{p:?}");
    }
}

#[test]
fn a_hidden_effect_is_named_with_the_calibrated_parameters() {
    let (dir, _) = calibrated();
    let (record, g) = common::generate(dir, "friction", |o| {
        as_built(o);
        o.effects = vec!["seal_friction=80".into()];
        o.duration = 8.0;
        o.seed = 31;
    });
    let truth = g.params.f_coulomb;
    let diagnose = |params: Option<PathBuf>| {
        let mut o = CompareOptions::new(&record);
        o.load_cell_lowpass_hz = Some(400.0);
        o.params_file = params;
        // both diagnoses choose among the effects that could stand in for friction (the mount, the
        // oil's and the gas's stiffness, the check valve, viscous friction): the nominal verdict is
        // `unexplained`, which fits every pair of candidates (80 s with all eleven, 15 s with these)
        o.skip =
            ["end_stops", "gas_release", "piston_leakage", "flow_forces", "amplifier_delay"].map(String::from).to_vec();
        diagnose_measurement(&o, 2, &|_, _, _| {}).expect("diagnose").diagnosis
    };
    let nominal = diagnose(None);
    eprintln!("nominal: {} {:?}", nominal.verdict, nominal.effects);
    assert_ne!(nominal.effects, ["seal_friction"], "the nominal model already names it: {}", nominal.explanation);
    let d = diagnose(Some(dir.join("parameters.ssv")));
    eprintln!("calibrated: {} {:?}", d.verdict, d.effects);
    assert_eq!(d.effects, ["seal_friction"], "{}", d.explanation);
    let best = &d.candidates[0];
    let fitted = best.params.iter().find(|p| p.0 == "F_coulomb").expect("F_coulomb").1;
    assert!((fitted - truth).abs() < 0.2 * truth, "F_coulomb {fitted} vs {truth}");
}

#[test]
fn the_parameter_set_round_trips_and_a_bad_one_names_line_and_field() {
    let (dir, c) = calibrated();
    let path = dir.join("parameters.ssv");
    let mut p = Parameters::default();
    ssv::apply(&mut p, &path).expect("apply");
    for q in &c.parameters {
        assert_eq!(get_real(&p, q.name).unwrap(), q.value, "{}", q.name);
    }
    let text = std::fs::read_to_string(&path).unwrap();
    let bad = |name: &str, from: &str, to: &str| {
        let f = dir.join(name);
        std::fs::write(&f, text.replacen(from, to, 1)).unwrap();
        let line = text[..text.find(from).unwrap()].matches('\n').count() + 1;
        (ssv::apply(&mut Parameters::default(), &f).unwrap_err().to_string(), f.display().to_string(), line)
    };
    // an unknown name: the line of its ssv:Parameter
    let (e, f, line) = bad("unknown.ssv", "name=\"V_hose\"", "name=\"V_hoses\"");
    assert!(e.starts_with(&format!("{f}, line {line}, parameter V_hoses: unknown parameter")), "{e}");
    // r_port's value element as written (held at its start, or fitted)
    let after = &text[text.find("name=\"r_port\"").unwrap()..];
    let element = &after[after.find("<ssv:Real value=\"").unwrap()..];
    let element = &element[..element.find("/>").unwrap() + 2];
    let value = element.split('"').nth(1).unwrap();
    // a wrong type
    let (e, f, _) = bad("type.ssv", element, "<ssv:Boolean value=\"true\"/>");
    assert!(e.starts_with(&format!("{f}, line")) && e.contains("parameter r_port: the file gives a Boolean"), "{e}");
    // a value out of the model's range, and one that is not a number: the line of the value
    let (e, _, _) = bad("range.ssv", element, "<ssv:Real value=\"3\" unit=\"m\"/>");
    assert!(e.contains("parameter r_port: r_port=3 is out of the model's range"), "{e}");
    let (e, f, line) = bad("number.ssv", element, &element.replace(value, &format!("{value}x")));
    assert!(
        e.starts_with(&format!("{f}, line {line}, parameter r_port, ssv:Real value=\"{value}x\": not a number")),
        "{e}"
    );
    // --params before --set: the file's value is overridden
    let mut o = CompareOptions::new(&c.records[0].path);
    o.params_file = Some(path.clone());
    o.sets = vec![("K_sol".into(), "70".into())];
    let m = damper_engine::measurement::Measurement::read(&o.measurement, &[], 10).unwrap();
    let setup = build_model(&o, &damper_engine::model::Drive::from_measurement(&m)).unwrap();
    assert_eq!(setup.model.params.k_sol, 70.0);
    assert_eq!(get_real(&setup.model.params, "air_fraction").unwrap(), get_real(&p, "air_fraction").unwrap());
}

/// Two velocity chains in one calibration, each truth driven by the true velocity: a transducer
/// with 1 mm/s of noise, smoothed (coloured: its noise paths' input error enters the covariance),
/// beside a quiet one (white: none). The two moved parameters land within 3 uncertainties.
#[test]
fn records_of_a_noisy_and_a_quiet_velocity_calibrate_together() {
    let dir = common::scratch("calibrate_chains");
    let moved = [("air_fraction", 0.032), ("p_reservoir0", 6.0e5)];
    let record = |name: &str, seed: u64, velocity_noise: Option<f64>| {
        common::generate(&dir, name, |o| {
            o.sets = moved.iter().map(|(n, v)| (n.to_string(), v.to_string())).collect();
            o.sets.push(("rtol".into(), "1e-6".into()));
            o.duration = 4.0;
            o.seed = seed;
            o.errors_in_variables = true;
            if let Some(sigma) = velocity_noise {
                o.noise.v_damper.noise = sigma;
            }
        })
        .0
    };
    let mut o = CalibrateOptions::new(vec![record("noisy", 21, Some(1e-3)), record("quiet", 22, None)]);
    o.fit = moved.iter().map(|(n, _)| n.to_string()).collect();
    o.compare.load_cell_lowpass_hz = Some(400.0);
    o.threads = 2;
    let c = calibrate(&o, &|_| {}).expect("calibrate");
    for (name, truth) in moved {
        let p = c.parameters.iter().find(|p| p.name == name).unwrap();
        let se = p.std_error.unwrap_or_else(|| panic!("{name} not identified: {:?}", p.status));
        eprintln!("{name}: {} ± {se}, truth {truth}", p.value);
        assert!((p.value - truth).abs() <= 3.0 * se, "{name}: {} ± {se}, truth {truth}", p.value);
    }
}
