//! The FMUs of a job imported (once per process and file), instantiated, initialised and stepped:
//! fixed-step Jacobi, as damper_tools.cosim (fmpy), fmpy.ssp, libcosim and ecos couple them. At each
//! step from t_k = start + k·h every connected input takes its output's value at t_k and every fed
//! input its sample k; then every instance steps from t_k by h; then the outputs are read at
//! t_{k+1}. The calls and their order within an instance are damper_tools.cosim's, so a run here
//! gives its numbers bit for bit.

use crate::capture;
use crate::error::RunError;
use crate::job::{Job, Port};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::fmi2::schema::{Causality, ScalarVariableElement};
use fmi::fmi2::Fmi2Error;
use fmi::traits::FmiImport;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// A variable's type, for its start value.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Real,
    Integer,
    Boolean,
    Other,
}

/// An FMU unzipped and its variables indexed by name.
#[derive(Debug)]
struct Imported {
    import: Fmi2Import,
    variables: HashMap<String, (u32, Kind, Causality)>,
}

/// Imports the FMU at `path`, or takes the import already made of the same file (path, size and
/// modification time): unzipping and reading the XML cost milliseconds a run should not pay.
fn import(path: &Path) -> Result<Arc<Imported>, RunError> {
    type Key = (PathBuf, u64, Option<SystemTime>);
    static CACHE: Mutex<Vec<(Key, Arc<Imported>)>> = Mutex::new(Vec::new());
    let refused = |problem: String| RunError::Import { path: path.to_path_buf(), problem };
    let meta = std::fs::metadata(path).map_err(|e| refused(e.to_string()))?;
    let key = (std::path::absolute(path).map_err(|e| refused(e.to_string()))?, meta.len(), meta.modified().ok());
    let mut cache = CACHE.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, imported)) = cache.iter().find(|(k, _)| *k == key) {
        return Ok(imported.clone());
    }
    let import: Fmi2Import = fmi::import::from_path(path).map_err(|e| refused(e.to_string()))?;
    let md = import.model_description();
    if md.co_simulation.is_none() {
        return Err(refused("the FMU has no Co-Simulation interface".into()));
    }
    let kind = |e: &ScalarVariableElement| match e {
        ScalarVariableElement::Real(_) => Kind::Real,
        ScalarVariableElement::Integer(_) => Kind::Integer,
        ScalarVariableElement::Boolean(_) => Kind::Boolean,
        _ => Kind::Other,
    };
    let variables = md
        .get_model_variables()
        .map(|v| (v.name.clone(), (v.value_reference, kind(&v.elem), v.causality.clone())))
        .collect();
    let imported = Arc::new(Imported { import, variables });
    // the FMUs of one process are few; a rebuilt file replaces its old import
    cache.retain(|(k, _)| k.0 != key.0);
    cache.push((key, imported.clone()));
    Ok(imported)
}

/// One instance while it runs: what it reads and sets each step, and the buffers for them.
struct Running {
    name: String,
    fmu: InstanceCS,
    /// Value references read after each step (recorded variables and connected outputs).
    get_vrs: Vec<u32>,
    got: Vec<f64>,
    /// Value references set before each step, and where each value comes from.
    set_vrs: Vec<u32>,
    set_from: Vec<Source>,
    to_set: Vec<f64>,
}

/// Where a set value comes from: an output read at t_k (instance, index in its `got`), or sample k
/// of an input series.
#[derive(Clone, Copy)]
enum Source {
    Output(usize, usize),
    Series(usize),
}

fn refused(instance: &str, call: &'static str, time: f64, e: &Fmi2Error) -> RunError {
    let message = capture::last(instance).unwrap_or_else(|| format!("{e} (the FMU logged no message)"));
    RunError::Refused { instance: instance.to_owned(), call, time, message }
}

/// The job's models, checked and indexed: each one's import and the value reference of a port.
struct Resolved {
    imports: Vec<Arc<Imported>>,
}

impl Resolved {
    fn new(job: &Job) -> Result<Resolved, RunError> {
        let imports = job.models.iter().map(|m| import(&m.fmu)).collect::<Result<_, _>>()?;
        Ok(Resolved { imports })
    }

    /// The model index and value reference of a Real port, checked to have one of `causalities`.
    fn real(&self, job: &Job, p: &Port, causalities: &[Causality], role: &str) -> Result<(usize, u32), RunError> {
        let i = job.models.iter().position(|m| m.name == p.0).expect("Job::check found every instance");
        let problem = |why: String| RunError::Variable { instance: p.0.clone(), variable: p.1.clone(), problem: why };
        let (vr, kind, causality) = self.imports[i]
            .variables
            .get(&p.1)
            .ok_or_else(|| problem(format!("not a variable of {}", job.models[i].fmu.display())))?;
        let (vr, kind) = (*vr, *kind);
        if kind != Kind::Real {
            return Err(problem(format!("{kind:?}, not Real: only Real variables can be {role}")));
        }
        if !causalities.is_empty() && !causalities.contains(causality) {
            return Err(problem(format!("causality {causality:?}: cannot be {role}")));
        }
        Ok((i, vr))
    }
}

/// Sets one start value, typed as the model description types the variable.
fn set_start(r: &mut Running, kinds: &Imported, name: &str, value: &serde_json::Value) -> Result<(), RunError> {
    let problem =
        |why: String| RunError::Variable { instance: r.name.clone(), variable: name.to_owned(), problem: why };
    let (vr, kind) = kinds
        .variables
        .get(name)
        .map(|(vr, kind, _)| (*vr, *kind))
        .ok_or_else(|| problem("no such variable in the FMU".into()))?;
    let status = match (kind, value) {
        (Kind::Real, serde_json::Value::Number(x)) => r.fmu.set_real(&[vr], &[x.as_f64().unwrap_or(f64::NAN)]),
        (Kind::Integer, serde_json::Value::Number(x)) => {
            let Some(n) = x.as_i64().and_then(|n| i32::try_from(n).ok()) else {
                return Err(problem(format!("{x} is not a 32-bit integer")));
            };
            r.fmu.set_integer(&[vr], &[n])
        }
        (Kind::Boolean, serde_json::Value::Bool(b)) => r.fmu.set_boolean(&[vr], &[i32::from(*b)]),
        (kind, v) => return Err(problem(format!("{v} cannot set a {kind:?} variable"))),
    };
    status.map(drop).map_err(|e| refused(&r.name, "fmi2Set (a start value)", f64::NAN, &e))
}

/// Instantiates and initialises every model: setupExperiment, start values, enter and exit
/// initialisation mode (damper_tools.fmu.Slave.initialize's order).
fn start(job: &Job, resolved: &Resolved) -> Result<Vec<Running>, RunError> {
    let mut running = Vec::with_capacity(job.models.len());
    for (m, imported) in job.models.iter().zip(&resolved.imports) {
        let fmu = imported
            .import
            .instantiate_cs(&m.name, false, false)
            .map_err(|e| RunError::Import { path: m.fmu.clone(), problem: format!("fmi2Instantiate: {e}") })?;
        let mut r = Running {
            name: m.name.clone(),
            fmu,
            get_vrs: Vec::new(),
            got: Vec::new(),
            set_vrs: Vec::new(),
            set_from: Vec::new(),
            to_set: Vec::new(),
        };
        let t0 = job.start_time;
        let at = |call| move |e: Fmi2Error| refused(&m.name, call, t0, &e);
        r.fmu.setup_experiment(None, t0, Some(job.stop_time())).map_err(at("fmi2SetupExperiment"))?;
        for (name, value) in &m.parameters {
            set_start(&mut r, imported, name, value)?;
        }
        r.fmu.enter_initialization_mode().map_err(at("fmi2EnterInitializationMode"))?;
        r.fmu.exit_initialization_mode().map_err(at("fmi2ExitInitializationMode"))?;
        running.push(r);
    }
    Ok(running)
}

/// Where each recorded variable is in its instance's `got`.
fn wire(job: &Job, resolved: &Resolved, running: &mut [Running]) -> Result<Vec<(usize, usize)>, RunError> {
    let read = |(i, vr): (usize, u32), running: &mut [Running]| {
        let r = &mut running[i];
        let j = r.get_vrs.iter().position(|&v| v == vr).unwrap_or_else(|| {
            r.get_vrs.push(vr);
            r.get_vrs.len() - 1
        });
        (i, j)
    };
    let recorded = job
        .record
        .iter()
        .map(|p| resolved.real(job, p, &[], "recorded").map(|at| read(at, running)))
        .collect::<Result<Vec<_>, _>>()?;
    for c in &job.connections {
        let out = resolved.real(job, &c.source(), &[Causality::Output], "a connection's source")?;
        let (i, vr) = resolved.real(job, &c.sink(), &[Causality::Input], "a connection's sink")?;
        let (oi, oj) = read(out, running);
        running[i].set_vrs.push(vr);
        running[i].set_from.push(Source::Output(oi, oj));
    }
    for (s, p) in job.inputs.iter().enumerate() {
        let (i, vr) = resolved.real(job, p, &[Causality::Input], "fed")?;
        running[i].set_vrs.push(vr);
        running[i].set_from.push(Source::Series(s));
    }
    for r in running.iter_mut() {
        r.got = vec![0.0; r.get_vrs.len()];
        r.to_set = vec![0.0; r.set_vrs.len()];
    }
    Ok(recorded)
}

/// Reads every instance's outputs at time `t` and writes the recorded ones to `row`.
fn read(running: &mut [Running], recorded: &[(usize, usize)], row: &mut [f64], t: f64) -> Result<(), RunError> {
    for r in running.iter_mut() {
        if !r.get_vrs.is_empty() {
            r.fmu.get_real(&r.get_vrs, &mut r.got).map_err(|e| refused(&r.name, "fmi2GetReal", t, &e))?;
        }
    }
    for (x, &(i, j)) in row.iter_mut().zip(recorded) {
        *x = running[i].got[j];
    }
    Ok(())
}

/// Runs the job: `inputs` holds one series of at least n_steps samples per `job.inputs`, in order;
/// `record` receives (n_steps + 1) rows of the recorded variables, row k at t_k (row 0 after
/// initialisation). Returns at the first refused call with the FMU's message.
pub fn run(job: &Job, inputs: &[&[f64]], record: &mut [f64]) -> Result<(), RunError> {
    capture::install();
    capture::clear();
    if inputs.len() != job.inputs.len() {
        return Err(RunError::Inputs(format!("{} series for {} inputs", inputs.len(), job.inputs.len())));
    }
    if let Some((p, s)) = job.inputs.iter().zip(inputs).find(|(_, s)| s.len() < job.n_steps) {
        return Err(RunError::Inputs(format!("{}.{}: {} samples, {} needed", p.0, p.1, s.len(), job.n_steps)));
    }
    let width = job.record.len();
    let needed = (job.n_steps + 1) * width;
    if record.len() != needed {
        return Err(RunError::RecordSize { given: record.len(), needed });
    }
    let resolved = Resolved::new(job)?;
    let mut running = start(job, &resolved)?;
    let recorded = wire(job, &resolved, &mut running)?;
    let row = |k: usize| k * width..(k + 1) * width;
    read(&mut running, &recorded, &mut record[row(0)], job.time(0))?;
    for k in 0..job.n_steps {
        let t = job.time(k);
        set_inputs(&mut running, inputs, k);
        for r in running.iter_mut() {
            if !r.set_vrs.is_empty() {
                r.fmu.set_real(&r.set_vrs, &r.to_set).map_err(|e| refused(&r.name, "fmi2SetReal", t, &e))?;
            }
            r.fmu.do_step(t, job.step, true).map_err(|e| refused(&r.name, "fmi2DoStep", t, &e))?;
        }
        read(&mut running, &recorded, &mut record[row(k + 1)], job.time(k + 1))?;
    }
    for r in running.iter_mut() {
        r.fmu.terminate().map_err(|e| refused(&r.name, "fmi2Terminate", job.stop_time(), &e))?;
    }
    Ok(())
}

/// Every instance's values to set before step k: connected outputs as read at t_k, series samples k.
fn set_inputs(running: &mut [Running], inputs: &[&[f64]], k: usize) {
    for i in 0..running.len() {
        for j in 0..running[i].set_from.len() {
            running[i].to_set[j] = match running[i].set_from[j] {
                Source::Output(oi, oj) => running[oi].got[oj],
                Source::Series(s) => inputs[s][k],
            };
        }
    }
}
