//! The FMU as an importer sees it: packed into an .fmu (modelDescription.xml + the cdylib this
//! `cargo test` built), loaded by rust-fmi's `fmi` crate (dlopen), and driven through its FMI 2.0
//! API. The results must equal the in-process model bit for bit.
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::model_description::RealVar;
use semi_active_damper::physics::params::Parameters;

use crate::common::cdylib::damper_library;

use std::io::Write;
use std::path::PathBuf;
use std::sync::OnceLock;

/// Packs the damper's cdylib of this test's profile ([`damper_library`]) into an .fmu in
/// target/<profile>/import_test/, once per test program: the tests run in parallel threads, and one
/// rewriting the file while another reads it broke the zip.
fn pack_fmu() -> PathBuf {
    static FMU: OnceLock<PathBuf> = OnceLock::new();
    FMU.get_or_init(pack).clone()
}

fn pack() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let library = damper_library(&profile_dir, env!("CARGO_MANIFEST_DIR"));
    let fmu = profile_dir.join("import_test").join("SemiActiveDamper.fmu");
    std::fs::create_dir_all(fmu.parent().unwrap()).unwrap();
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&fmu).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    let xml = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription.xml")).unwrap();
    zip.start_file("modelDescription.xml", options).unwrap();
    zip.write_all(&xml).unwrap();
    zip.start_file("binaries/linux64/SemiActiveDamper.so", options).unwrap();
    zip.write_all(&std::fs::read(&library).unwrap()).unwrap();
    zip.finish().unwrap();
    fmu
}

#[test]
fn rust_fmi_importer_runs_the_fmu_like_the_model() {
    let import: Fmi2Import = fmi::import::from_path(pack_fmu()).expect("import the FMU");
    let mut fmu = import.instantiate_cs("rust-fmi", false, false).expect("instantiate");
    fmu.setup_experiment(None, 0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();

    let mut model = Damper::new(Parameters::default(), Inputs::START, 0.0).unwrap();
    let (v_in, f_in, f_out) = (RealVar::VDamper.vr(), RealVar::FDemand.vr(), RealVar::FDamper.vr());
    let h = 1e-3;
    for k in 0..500 {
        let t = k as f64 * h;
        let inputs = Inputs { v_damper: 0.3 * (12.0 * t).sin(), f_demand: 9e3 * (5.0 * t).cos(), ..model.inputs };
        fmu.set_real(&[v_in, f_in], &[inputs.v_damper, inputs.f_demand]).unwrap();
        fmu.do_step(t, h, true).unwrap();
        model.inputs = inputs;
        model.do_step(h).unwrap();
        let mut force = [0.0];
        fmu.get_real(&[f_out], &mut force).unwrap();
        assert_eq!(force[0].to_bits(), model.outputs().plant.force.to_bits(), "t = {t}");
    }
    // the importer sees our errors as errors
    assert!(fmu.set_real(&[v_in], &[f64::NAN]).is_err());
    assert!(fmu.do_step(0.0, h, true).is_err(), "wrong communication point");
}

#[test]
fn the_force_feeds_through_from_the_velocity_with_friction_on() {
    // ModelStructure: F_damper depends on v_damper (seal and viscous friction add F(v)); a new
    // velocity shows in the force before the next step, as in the in-process model
    let import: Fmi2Import = fmi::import::from_path(pack_fmu()).expect("import the FMU");
    let mut fmu = import.instantiate_cs("rust-fmi", false, false).expect("instantiate");
    let params = Parameters { effect_seal_friction: true, ..Default::default() };
    fmu.set_boolean(&[semi_active_damper::model_description::BooleanVar::EffectSealFriction.vr()], &[1]).unwrap();
    fmu.setup_experiment(None, 0.0, None).unwrap();
    fmu.enter_initialization_mode().unwrap();
    fmu.exit_initialization_mode().unwrap();
    let mut model = Damper::new(params, Inputs::START, 0.0).unwrap();
    let (v_in, f_out) = (RealVar::VDamper.vr(), RealVar::FDamper.vr());
    let h = 1e-3;
    for k in 0..200 {
        let v = 0.2 * (20.0 * k as f64 * h).sin();
        fmu.set_real(&[v_in], &[v]).unwrap();
        model.inputs.v_damper = v;
        let mut force = [0.0];
        fmu.get_real(&[f_out], &mut force).unwrap();
        assert_eq!(force[0].to_bits(), model.outputs().plant.force.to_bits(), "step {k}");
        fmu.do_step(k as f64 * h, h, true).unwrap();
        model.do_step(h).unwrap();
    }
}
