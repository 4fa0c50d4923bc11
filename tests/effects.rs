//! The effect catalog (`src/effects/`) and `modelDescription.xml` agree: every effect's switch
//! `effect_<key>` is a Boolean parameter that `is_on` reads, its parameters are Real parameters of
//! the XML, and its ranges nest (hidden values ⊂ plausible ⊂ search ⊂ the XML's min/max). An effect
//! added to the catalog but not to the XML (or the reverse) fails here with its name.

use semi_active_damper::effects::{PlantSignals, CATALOG};
use semi_active_damper::model_description::{BooleanVar, Causality, RealVar};
use semi_active_damper::variables::{boolean_parameter, default_parameters};

fn real_parameter(name: &str) -> RealVar {
    let v = RealVar::ALL.into_iter().find(|v| v.name() == name);
    let v = v.unwrap_or_else(|| panic!("{name} is not a variable of modelDescription.xml"));
    assert_eq!(v.causality(), Causality::Parameter, "{name}");
    v
}

#[test]
fn every_effect_has_its_switch_and_parameters_in_the_model_description() {
    let mut keys = Vec::new();
    for e in CATALOG {
        let info = e.info();
        assert!(!keys.contains(&info.key), "{} listed twice", info.key);
        keys.push(info.key);
        let switch = format!("effect_{}", info.key);
        let var = BooleanVar::ALL.into_iter().find(|v| v.name() == switch);
        let var = var.unwrap_or_else(|| panic!("{switch} is not in modelDescription.xml"));
        let mut p = default_parameters();
        for on in [true, false] {
            *boolean_parameter(&mut p, var).expect("a parameter") = on;
            assert_eq!(e.is_on(&p), on, "{}: is_on does not read {switch}", info.key);
        }
        assert!(!info.fitted.is_empty() && info.fitted.len() <= 2, "{}: one or two fitted parameters", info.key);
        for f in info.fitted {
            let v = real_parameter(f.name);
            let (lo, hi) = (v.min().unwrap_or(f64::NEG_INFINITY), v.max().unwrap_or(f64::INFINITY));
            assert!(lo <= f.search.0 && f.search.1 <= hi, "{}: search range outside the XML's", f.name);
            assert!(f.search.0 <= f.plausible.0 && f.plausible.1 <= f.search.1, "{}: plausible ⊄ search", f.name);
            assert!(!f.log || f.search.0 > 0.0, "{}: a log search needs a positive range", f.name);
        }
        let size = info.fitted[0];
        let (h0, h1) = info.hidden_range;
        assert!(size.plausible.0 <= h0 && h0 < h1 && h1 <= size.plausible.1, "{}: hidden ⊄ plausible", info.key);
        for name in info.other {
            real_parameter(name);
        }
    }
    // and the reverse: every effect switch of the XML has its file
    for v in BooleanVar::ALL {
        if let Some(key) = v.name().strip_prefix("effect_") {
            assert!(keys.contains(&key), "modelDescription.xml has {} but src/effects/ has no {key}", v.name());
        }
    }
}

#[test]
fn switched_off_effects_add_nothing() {
    let mut p = default_parameters();
    let s = PlantSignals { v_damper: 0.4, x_damper: 0.01, p_ext: 40e5, p_comp: 5e5, p_reservoir: 5e5, x_spool: 1e-3 };
    for e in CATALOG {
        let var = BooleanVar::ALL.into_iter().find(|v| v.name() == format!("effect_{}", e.info().key)).unwrap();
        *boolean_parameter(&mut p, var).unwrap() = false;
    }
    assert_eq!(semi_active_damper::effects::total_force(&p, &s), 0.0);
    assert_eq!(semi_active_damper::effects::total_bypass_flow(&p, &s), 0.0);
    // friction opposes the motion: in tension when extending
    p.effect_seal_friction = true;
    p.effect_viscous_friction = true;
    let f = semi_active_damper::effects::total_force(&p, &s);
    assert!((f - (p.f_coulomb * (0.4 / p.v_friction).tanh() + p.c_viscous * 0.4)).abs() < 1e-9, "{f}");
}

#[test]
fn the_worked_example_in_the_docs_is_the_file() {
    let docs = include_str!("../docs/effects.md");
    let file = include_str!("../src/effects/viscous_friction.rs");
    assert!(docs.contains(file), "docs/effects.md must show src/effects/viscous_friction.rs verbatim");
}
