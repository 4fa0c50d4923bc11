//! A run as the caller describes it (JSON): the FMU instances with their parameters, the
//! connections output → input, the inputs the caller feeds sample by sample, what to record, and
//! the fixed step.
//!
//! ```json
//! {"step": 0.001, "n_steps": 15000,
//!  "models": [{"name": "truck", "fmu": "target/fmu/QuarterTruck.fmu", "parameters": {"road_source": 1}},
//!             {"name": "damper", "fmu": "target/fmu/SemiActiveDamper.fmu", "parameters": {"tare_load_cell": true}}],
//!  "connections": [["truck", "v_damper", "damper", "v_damper"], ["damper", "F_damper", "truck", "F_damper"]],
//!  "inputs": [["damper", "a_damper"]],
//!  "record": [["truck", "a_body"], ["damper", "F_damper"]]}
//! ```

use crate::error::RunError;
use serde::Deserialize;
use std::path::PathBuf;

/// One FMU instance of the system.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// The instance name, unique in the job (the FMU's instanceName).
    pub name: String,
    /// The `.fmu` file.
    pub fmu: PathBuf,
    /// Start values by variable name, set in initialisation mode (Real, Integer or Boolean, as the
    /// model description types the variable).
    #[serde(default)]
    pub parameters: serde_json::Map<String, serde_json::Value>,
}

/// A variable of an instance: (instance, variable name).
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
pub struct Port(pub String, pub String);

/// A connection: (source instance, output, sink instance, input).
#[derive(Clone, Debug, Deserialize, PartialEq, Eq)]
pub struct Connection(pub String, pub String, pub String, pub String);

impl Connection {
    /// The output it reads.
    pub fn source(&self) -> Port {
        Port(self.0.clone(), self.1.clone())
    }

    /// The input it sets.
    pub fn sink(&self) -> Port {
        Port(self.2.clone(), self.3.clone())
    }
}

/// A run: `n_steps` Jacobi steps of `step` seconds from `start_time`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Job {
    /// Communication step (s).
    pub step: f64,
    /// Number of steps.
    pub n_steps: usize,
    /// Start time (s); the stop time passed to the FMUs is start_time + n_steps·step.
    #[serde(default)]
    pub start_time: f64,
    pub models: Vec<Model>,
    /// Real connections, each output read at t_k and set on its input before the step from t_k.
    #[serde(default)]
    pub connections: Vec<Connection>,
    /// Real inputs the caller feeds: series of n_steps samples, sample k set before step k.
    #[serde(default)]
    pub inputs: Vec<Port>,
    /// Real variables recorded at the n_steps + 1 communication points (row 0 after initialisation).
    pub record: Vec<Port>,
}

impl Job {
    /// Parses and checks the job; the error names the field.
    pub fn from_json(text: &str) -> Result<Job, RunError> {
        let job: Job = serde_json::from_str(text).map_err(|e| RunError::Job(e.to_string()))?;
        job.check()?;
        Ok(job)
    }

    fn check(&self) -> Result<(), RunError> {
        let bad = |why: String| Err(RunError::Job(why));
        if !(self.step > 0.0 && self.step.is_finite()) {
            return bad(format!("step = {} s: must be positive and finite", self.step));
        }
        if self.n_steps == 0 {
            return bad("n_steps = 0: a run needs at least one step".into());
        }
        if !self.start_time.is_finite() {
            return bad(format!("start_time = {}: not a finite number", self.start_time));
        }
        if self.models.is_empty() {
            return bad("models: none given".into());
        }
        for (i, m) in self.models.iter().enumerate() {
            if self.models[..i].iter().any(|o| o.name == m.name) {
                return bad(format!("models: the instance name {:?} is used twice", m.name));
            }
        }
        let known = |p: &Port| self.models.iter().any(|m| m.name == p.0);
        let ports = self.connections.iter().flat_map(|c| [c.source(), c.sink()]);
        for p in ports.chain(self.inputs.iter().cloned()).chain(self.record.iter().cloned()) {
            if !known(&p) {
                return bad(format!("{}.{}: no model is named {:?}", p.0, p.1, p.0));
            }
        }
        let sinks: Vec<Port> =
            self.connections.iter().map(Connection::sink).chain(self.inputs.iter().cloned()).collect();
        for (i, p) in sinks.iter().enumerate() {
            if sinks[..i].contains(p) {
                return bad(format!("{}.{}: set by two connections or inputs", p.0, p.1));
            }
        }
        Ok(())
    }

    /// Stop time (s) passed to fmi2SetupExperiment.
    pub fn stop_time(&self) -> f64 {
        self.start_time + self.n_steps as f64 * self.step
    }

    /// Communication point t_k (s), as numpy's start + step·arange(n + 1) gives it.
    pub fn time(&self, k: usize) -> f64 {
        self.start_time + self.step * k as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(extra: &str) -> Result<Job, RunError> {
        Job::from_json(&format!(
            r#"{{"step": 0.001, "n_steps": 10, "models": [{{"name": "a", "fmu": "a.fmu"}}, {{"name": "b", "fmu": "b.fmu"}}],
                "record": [["a", "y"]] {extra}}}"#
        ))
    }

    #[test]
    fn a_good_job_parses() {
        let j = job(r#", "connections": [["a", "y", "b", "u"]], "inputs": [["a", "u"]]"#).unwrap();
        assert_eq!(j.connections[0].sink(), Port("b".into(), "u".into()));
        assert_eq!(j.stop_time(), 0.01);
    }

    #[test]
    fn bad_jobs_name_what_is_wrong() {
        let err = |extra: &str| job(extra).unwrap_err().to_string();
        assert!(err(r#", "connections": [["c", "y", "b", "u"]]"#).contains("no model is named \"c\""));
        assert!(err(r#", "connections": [["a", "y", "b", "u"]], "inputs": [["b", "u"]]"#).contains("set by two"));
        assert!(err(r#", "stepsize": 1"#).contains("unknown field `stepsize`"));
        assert!(Job::from_json(r#"{"step": 0, "n_steps": 1, "models": [], "record": []}"#)
            .unwrap_err()
            .to_string()
            .contains("step = 0 s"));
    }
}
