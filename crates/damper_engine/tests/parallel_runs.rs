//! Models run in parallel, and the force simulator a fit uses, give the sequential run's numbers.
use crate::common;

use common::{generate, scratch};
use damper_engine::measurement::{Measurement, DEFAULT_MAX_GAP};
use damper_engine::model::{force_simulator, run_parallel, Drive, InProcess, Model};
use damper_engine::parameters::{set_effect, set_real};

#[test]
fn models_run_in_parallel_give_the_sequential_results() {
    let dir = scratch("parallel");
    let (csv, _) = generate(&dir, "p", |o| o.duration = 1.0);
    let m = Measurement::read(&csv, &[], DEFAULT_MAX_GAP).unwrap();
    let drive = Drive::from_measurement(&m);
    let models: Vec<Model> = [0.0f64, 150.0, 300.0]
        .iter()
        .map(|&fc| {
            let mut p = semi_active_damper::physics::params::Parameters::default();
            set_effect(&mut p, "seal_friction", fc > 0.0).unwrap();
            set_real(&mut p, "F_coulomb", fc.max(1.0)).unwrap();
            Model::new(p)
        })
        .collect();
    let parallel = run_parallel(&models, &drive, 2);
    let simulate = force_simulator(&InProcess, &drive, None);
    for (model, result) in models.iter().zip(parallel) {
        let sequential = model.run(&drive).unwrap();
        assert_eq!(result.unwrap().f_damper, sequential.f_damper);
        assert_eq!(simulate(&model.params, 500).unwrap(), sequential.f_damper[..500].to_vec());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
