//! Coupled runs of FMI 2.0 Co-Simulation FMUs at the FMUs' own speed: a fixed-step Jacobi loop over
//! rust-fmi's importer (the `fmi` crate, Rust's counterpart of the FMI Library), with no Python in
//! the step loop. damper_tools.runner calls it through its C ABI ([`c_api`]) for the sweeps and
//! campaigns; Rust callers use [`run`].
//!
//! Why a loop of our own and not libcosim's or ecos's execution (docs/sweeps.md has the
//! figures): on the quarter truck and its damper both cost more per step than the two FMUs together,
//! libcosim's observers and ecos's parallel stepping with per-variable property maps; ecos's result
//! writer keeps six decimals, and ecos reads the coupled outputs after setting the next inputs. This
//! loop makes the calls damper_tools.cosim makes, in its order, so its results equal the fmpy
//! reference's bit for bit; libcosim and ecos stay as the cross-checks that run the same SSP.
//!
//! - [`job`]: the run as JSON (models, parameters, connections, fed inputs, record, step);
//! - [`system`]: import (cached per file), initialisation, the stepping loop;
//! - [`capture`]: the FMUs' log messages, for the errors;
//! - [`error`]: why a run stopped ([`RunError`]);
//! - [`tracking_fit`]: the grid of the sweeps' tracking fit (damper_tools.tracking_quality).
//!
//! ```no_run
//! // the quarter truck on its own ISO 8608 road, coupled to the damper, 2 s at 1 ms
//! let job = cosim_runner::Job::from_json(r#"{
//!     "step": 0.001, "n_steps": 2000,
//!     "models": [
//!         {"name": "truck", "fmu": "target/fmu/QuarterTruck.fmu", "parameters": {"road_source": 1, "road_length": 30.0}},
//!         {"name": "damper", "fmu": "target/fmu/SemiActiveDamper.fmu", "parameters": {"tare_load_cell": true}}],
//!     "connections": [["truck", "v_damper", "damper", "v_damper"], ["truck", "F_demand", "damper", "F_demand"],
//!                     ["damper", "F_damper", "truck", "F_damper"]],
//!     "record": [["truck", "a_body"], ["damper", "F_damper"]]}"#).unwrap();
//! let mut record = vec![0.0; (job.n_steps + 1) * job.record.len()];
//! cosim_runner::run(&job, &[], &mut record).unwrap();
//! let f_damper_at_1s = record[1000 * 2 + 1];
//! assert!(f_damper_at_1s.is_finite());
//! ```

pub mod c_api;
pub mod capture;
pub mod error;
pub mod job;
pub mod system;
pub mod tracking_fit;

pub use error::RunError;
pub use job::Job;
pub use system::run;
