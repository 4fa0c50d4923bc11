//! `--fmu`: the model run through the packaged FMU (rust-fmi's importer) gives the same comparison
//! and the same diagnosis as the in-process model, bit for bit; an FMU of another build is refused.
use crate::common;
#[path = "../../../tests/common/cdylib.rs"]
mod cdylib;
use cdylib::damper_library;

use damper_cli::json_summary::diagnosed as summary;
use damper_engine::comparison::CompareOptions;
use damper_engine::diagnose_measurement::{diagnose_measurement, Diagnosed};
use damper_engine::fmu_model::FmuModel;
use damper_engine::summary::to_json;
use std::io::Write;
use std::path::{Path, PathBuf};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// Packs `modelDescription.xml` (after `edit_xml`) and, with `binary`, the damper's cdylib of this
/// test's profile, as the root crate's tests/import_fmu.rs does.
fn pack_fmu(name: &str, binary: bool, edit_xml: impl Fn(String) -> String) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let fmu = profile_dir.join("fmu_backend_test").join(format!("{name}.fmu"));
    std::fs::create_dir_all(fmu.parent().unwrap()).unwrap();
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&fmu).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    let xml = std::fs::read_to_string(format!("{ROOT}/modelDescription.xml")).unwrap();
    zip.start_file("modelDescription.xml", options).unwrap();
    zip.write_all(edit_xml(xml).as_bytes()).unwrap();
    if binary {
        zip.start_file("binaries/linux64/SemiActiveDamper.so", options).unwrap();
        zip.write_all(&std::fs::read(damper_library(&profile_dir, ROOT)).unwrap()).unwrap();
    }
    zip.finish().unwrap();
    fmu
}

fn diagnose(csv: &Path, fmu: Option<PathBuf>) -> Diagnosed {
    let mut o = CompareOptions::new(csv);
    o.load_cell_lowpass_hz = Some(400.0);
    o.fmu = fmu;
    diagnose_measurement(&o, 2, &|_, _, _| {}).expect("diagnose")
}

fn same(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[test]
fn the_fmu_gives_the_in_process_diagnosis_bit_for_bit() {
    let dir = common::scratch("fmu_backend");
    let (csv, _) = common::generate(&dir, "m", |o| {
        o.duration = 3.0;
        o.effects = vec!["seal_friction".into()];
    });
    let fmu = pack_fmu("SemiActiveDamper", true, |x| x);
    let a = diagnose(&csv, None);
    let b = diagnose(&csv, Some(fmu.clone()));
    assert_eq!(a.comparison.setup.backend.name(), "in_process");
    assert_eq!(b.comparison.setup.backend.fmu_path(), Some(fmu.as_path()));

    let (pa, pb) = (&a.comparison.prediction, &b.comparison.prediction);
    for (name, x, y) in [
        ("F_damper", &pa.f_damper, &pb.f_damper),
        ("x_spool", &pa.x_spool, &pb.x_spool),
        ("x_spool_ref", &pa.x_spool_ref, &pb.x_spool_ref),
        ("i_sol", &pa.i_sol, &pb.i_sol),
        ("p_ext", &pa.p_ext, &pb.p_ext),
        ("p_comp", &pa.p_comp, &pb.p_comp),
        ("x_damper", &pa.x_damper, &pb.x_damper),
        ("F_demand_clipped", &pa.f_demand_clipped, &pb.f_demand_clipped),
    ] {
        let first = x.iter().zip(y.iter()).position(|(u, v)| u.to_bits() != v.to_bits());
        assert!(same(x, y), "compare: {name} differs, first at sample {first:?}");
    }

    let (da, db) = (&a.diagnosis, &b.diagnosis);
    assert_eq!(da.nrmse_baseline.to_bits(), db.nrmse_baseline.to_bits());
    assert_eq!(da.nrmse_noise_floor.to_bits(), db.nrmse_noise_floor.to_bits());
    assert_eq!((da.verdict, da.best_effect), (db.verdict, db.best_effect));
    assert_eq!(da.verdict, damper_engine::verdict::Verdict::Effect, "{}", da.explanation);
    assert_eq!(da.candidates.len(), db.candidates.len());
    for (ca, cb) in da.candidates.iter().zip(&db.candidates) {
        assert_eq!(ca.effect, cb.effect);
        let what = format!("candidate {}", ca.effect);
        assert_eq!(ca.nrmse_validation.to_bits(), cb.nrmse_validation.to_bits(), "{what}");
        assert_eq!(ca.nrmse_train.to_bits(), cb.nrmse_train.to_bits(), "{what}");
        assert_eq!(ca.evaluations, cb.evaluations, "{what}");
        assert_eq!(ca.params.len(), cb.params.len(), "{what}");
        for ((na, xa, ea), (nb, xb, eb)) in ca.params.iter().zip(&cb.params) {
            assert_eq!(na, nb, "{what}");
            assert_eq!(xa.to_bits(), xb.to_bits(), "{what}: {na} {xa:e} vs {xb:e}");
            assert_eq!(ea.map(f64::to_bits), eb.map(f64::to_bits), "{what}: {na} standard error");
        }
    }
    // everything else (the ladder, the fits of every signal, the regimes, ...): summary.json, whose
    // numbers are printed shortest-round-trip, so equal text is equal bits; only the backend and
    // the wall time may differ
    let (sa, mut sb) = (summary(&a), summary(&b));
    assert_eq!((sa.model.backend.as_str(), sb.model.backend.as_str()), ("in_process", "fmu"));
    (sb.model, sb.model_run_s) = (sa.model.clone(), sa.model_run_s);
    assert_eq!(to_json(&sa), to_json(&sb));
}

#[test]
fn an_fmu_of_another_build_is_refused() {
    // a parameter renamed: the FMU has one this program does not know, and lacks one it has
    let fmu = pack_fmu("Renamed", false, |x| x.replace("name=\"h_max\"", "name=\"h_max_old\""));
    let e = FmuModel::open(&fmu).map(drop).expect_err("refused").to_string();
    assert!(e.contains(&fmu.display().to_string()), "{e}");
    assert!(e.contains("does not know: h_max_old"), "{e}");
    assert!(e.contains("lacks this program's parameters: h_max"), "{e}");

    let other =
        pack_fmu("Other", false, |x| x.replace("modelIdentifier=\"SemiActiveDamper\"", "modelIdentifier=\"Other\""));
    let e = FmuModel::open(&other).map(drop).expect_err("refused").to_string();
    assert!(e.contains("not the damper FMU (its modelIdentifier is Other"), "{e}");

    let missing = std::env::temp_dir().join("no_such_dir").join("Damper.fmu");
    let e = FmuModel::open(&missing).map(drop).expect_err("refused").to_string();
    assert!(e.contains(&missing.display().to_string()) && e.contains("no such file"), "{e}");
}
