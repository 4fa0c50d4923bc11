//! The damper model run through a packaged FMU (`--fmu PATH.fmu`) with rust-fmi's FMI 2.0
//! importer, stepped exactly as [`Model::run_first`] steps the in-process model, so that the two
//! backends give the same numbers.
//!
//! The FMU's parameters are matched by name with this program's (from its own
//! `modelDescription.xml`): a parameter only one side has, or of another type, means the FMU is a
//! different build, and it is refused rather than run with a default the user never sees.
//!
//! Every run instantiates its own FMU instance from the shared import (the shared library is
//! loaded once per process; its instances share nothing), so fits on several threads run the FMU
//! concurrently.

use crate::dsp::Lowpass;
use crate::error::Error;
use crate::model::{substeps, Backend, Drive, Model, Prediction};
use crate::parameters::{get_parameter, parameter_names, Value};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::fmi2::schema::{Causality, ScalarVariableElement};
use fmi::fmi2::Fmi2Error;
use fmi::traits::FmiImport;
use semi_active_damper::damper::Inputs;
use semi_active_damper::model_description::MODEL_IDENTIFIER;
use semi_active_damper::physics::params::Parameters;
use std::path::{Path, PathBuf};

/// The FMU's inputs, in the order [`FmuModel::set_inputs`] sets them.
const INPUTS: [&str; 5] = ["v_damper", "a_damper", "F_demand", "x_spool_demand", "T_oil"];
/// The outputs read, in the order of [`Prediction`]'s fields.
const OUTPUTS: [&str; 8] =
    ["F_damper", "x_spool", "x_spool_ref", "i_sol", "p_ext", "p_comp", "x_damper", "F_demand_clipped"];

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Real,
    Integer,
    Boolean,
}

#[derive(Clone, Debug)]
struct FmuParameter {
    name: &'static str,
    vr: u32,
    kind: Kind,
}

/// A packaged damper FMU, imported (unzipped, its XML parsed) and checked against this program.
#[derive(Debug)]
pub struct FmuModel {
    path: PathBuf,
    import: Fmi2Import,
    parameters: Vec<FmuParameter>,
    inputs: [u32; INPUTS.len()],
    outputs: [u32; 8],
}

/// The first few names of a list, for an error message.
fn some<S: AsRef<str>>(names: &[S]) -> String {
    let shown: Vec<&str> = names.iter().take(8).map(AsRef::as_ref).collect();
    match names.len() - shown.len() {
        0 => shown.join(", "),
        more => format!("{} and {more} more", shown.join(", ")),
    }
}

fn kind_of(e: &ScalarVariableElement) -> Option<Kind> {
    match e {
        ScalarVariableElement::Real(_) => Some(Kind::Real),
        ScalarVariableElement::Integer(_) => Some(Kind::Integer),
        ScalarVariableElement::Boolean(_) => Some(Kind::Boolean),
        _ => None,
    }
}

fn kind_of_value(v: Value) -> Kind {
    match v {
        Value::Real(_) => Kind::Real,
        Value::Integer(_) => Kind::Integer,
        Value::Boolean(_) => Kind::Boolean,
    }
}

impl FmuModel {
    /// Imports the FMU at `path` and checks it against this program's parameters, inputs and
    /// outputs; the errors name the path and what does not match.
    pub fn open(path: &Path) -> Result<FmuModel, Error> {
        let refused = |problem: String| Error::FmuLoad { path: path.to_path_buf(), problem };
        if !path.is_file() {
            return Err(refused("no such file (package the FMU with python3 scripts/package_fmu.py)".into()));
        }
        let import: Fmi2Import =
            fmi::import::from_path(path).map_err(|source| Error::FmuImport { path: path.to_path_buf(), source })?;
        let md = import.model_description();
        let Some(cs) = &md.co_simulation else {
            return Err(refused("the FMU has no Co-Simulation interface".into()));
        };
        if cs.model_identifier != MODEL_IDENTIFIER {
            return Err(refused(format!(
                "not the damper FMU (its modelIdentifier is {}, the damper's {MODEL_IDENTIFIER})",
                cs.model_identifier
            )));
        }
        let known = parameter_names();
        let defaults = Parameters::default();
        let (mut parameters, mut unknown, mut mistyped) = (Vec::new(), Vec::new(), Vec::new());
        for v in md.get_model_variables().filter(|v| v.causality == Causality::Parameter) {
            let Some(&name) = known.iter().find(|n| **n == v.name) else {
                unknown.push(v.name.clone());
                continue;
            };
            let ours = kind_of_value(get_parameter(&defaults, name)?);
            if kind_of(&v.elem) != Some(ours) {
                let theirs = kind_of(&v.elem).map_or_else(|| "String or Enumeration".into(), |k| format!("{k:?}"));
                mistyped.push(format!("{name} ({theirs} in the FMU, {ours:?} here)"));
                continue;
            }
            parameters.push(FmuParameter { name, vr: v.value_reference, kind: ours });
        }
        let is_parameter =
            |n: &str| md.get_model_variables().any(|v| v.name == n && v.causality == Causality::Parameter);
        let missing: Vec<&str> = known.iter().copied().filter(|n| !is_parameter(n)).collect();
        let mut problems = Vec::new();
        if !unknown.is_empty() {
            problems.push(format!("the FMU has parameters this program does not know: {}", some(&unknown)));
        }
        if !missing.is_empty() {
            problems.push(format!("the FMU lacks this program's parameters: {}", some(&missing)));
        }
        if !mistyped.is_empty() {
            problems.push(format!("parameters of another type: {}", some(&mistyped)));
        }
        if !problems.is_empty() {
            return Err(refused(format!(
                "a different build of the damper model ({}); repackage it from this source \
                 (python3 scripts/package_fmu.py)",
                problems.join("; ")
            )));
        }
        let vr = |name: &str, causality: Causality| -> Result<u32, Error> {
            md.get_model_variables()
                .find(|v| v.name == name && v.causality == causality && kind_of(&v.elem) == Some(Kind::Real))
                .map(|v| v.value_reference)
                .ok_or_else(|| refused(format!("the FMU has no Real {causality} {name} (is it the damper FMU?)")))
        };
        let mut inputs = [0; INPUTS.len()];
        for (slot, name) in inputs.iter_mut().zip(INPUTS) {
            *slot = vr(name, Causality::Input)?;
        }
        let mut outputs = [0; 8];
        for (slot, name) in outputs.iter_mut().zip(OUTPUTS) {
            *slot = vr(name, Causality::Output)?;
        }
        // a missing or foreign binary shows here once, not in every run of every thread
        import
            .instantiate_cs("damper", false, false)
            .map_err(|source| Error::FmuInstantiate { path: path.to_path_buf(), source })?;
        Ok(FmuModel { path: path.to_path_buf(), import, parameters, inputs, outputs })
    }
}

impl Backend for FmuModel {
    /// As [`Model::run_first`], through the FMU: the first `n` samples; `all` records every
    /// signal, otherwise only the force. Each call has its own FMU instance.
    fn run_first(&self, model: &Model, drive: &Drive, n: usize, all: bool) -> Result<Prediction, Error> {
        let n = n.min(drive.len());
        let t = &drive.time;
        let mut out = Prediction::default();
        if n == 0 {
            return Ok(out);
        }
        let fail =
            |call: &'static str, source: Fmi2Error| Error::FmuFailed { path: self.path.clone(), t: t[0], call, source };
        let mut fmu = self
            .import
            .instantiate_cs("damper", false, false)
            .map_err(|source| Error::FmuInstance { path: self.path.clone(), source })?;
        fmu.setup_experiment(None, t[0], None).map_err(|e| fail("fmi2SetupExperiment", e))?;
        self.set_parameters(&mut fmu, &model.params)?;
        // the in-process model starts at rest with the inputs of the first sample
        // (Damper::new(params, inputs(0), t[0])); the FMU builds its damper on leaving
        // initialisation mode, from the inputs set by then
        fmu.enter_initialization_mode().map_err(|e| fail("fmi2EnterInitializationMode", e))?;
        self.set_inputs(&mut fmu, drive, 0)?;
        fmu.exit_initialization_mode().map_err(|e| fail("fmi2ExitInitializationMode", e))?;
        self.read_outputs(&mut fmu, t[0], all, &mut out)?;
        // The communication point is the FMU's own clock, the previous point plus the step, not
        // t[k - 1]: the FMU aligns its clock to the point it is given, and the in-process model's
        // clock is that sum, which can differ from t[k - 1] in the last bit (and the controller's
        // sample grid is placed relative to the clock).
        let mut now = t[0];
        let mut filter = model.load_cell_lowpass_hz.map(|fc| Lowpass::new(fc, out.f_damper[0]));
        for k in 1..n {
            let m = substeps(t[k] - t[k - 1], model.params.t_sample);
            let h = (t[k] - t[k - 1]) / m as f64;
            for j in 0..m {
                self.set(&mut fmu, drive, drive.substep_inputs(k - 1, j, m), k - 1)?;
                fmu.do_step(now, h, true).map_err(|source| Error::FmuStep {
                    path: self.path.clone(),
                    from: t[k - 1],
                    to: t[k],
                    source,
                })?;
                now += h;
                if j + 1 < m {
                    if let Some(f) = filter.as_mut() {
                        f.step(h, self.load_cell(&mut fmu, now)?);
                    }
                }
            }
            self.set_inputs(&mut fmu, drive, k)?;
            self.read_outputs(&mut fmu, t[k], all, &mut out)?;
            if let (Some(f), Some(last)) = (filter.as_mut(), out.f_damper.last_mut()) {
                *last = f.step(h, *last);
            }
        }
        fmu.terminate().map_err(|source| Error::FmuCall { path: self.path.clone(), call: "fmi2Terminate", source })?;
        // dropping the instance frees it (fmi2FreeInstance)
        drop(fmu);
        Ok(out)
    }

    fn name(&self) -> &'static str {
        "fmu"
    }

    fn describe(&self) -> String {
        format!("run through the FMU {}", self.path.display())
    }

    fn fmu_path(&self) -> Option<&Path> {
        Some(&self.path)
    }
}

impl FmuModel {
    /// Sets every parameter of the FMU by name, from `params`.
    fn set_parameters(&self, fmu: &mut InstanceCS, params: &Parameters) -> Result<(), Error> {
        for p in &self.parameters {
            let value = get_parameter(params, p.name)?;
            let result = match (p.kind, value) {
                (Kind::Real, Value::Real(x)) => fmu.set_real(&[p.vr], &[x]),
                (Kind::Integer, Value::Integer(i)) => fmu.set_integer(&[p.vr], &[i]),
                (Kind::Boolean, Value::Boolean(b)) => fmu.set_boolean(&[p.vr], &[i32::from(b)]),
                _ => return Err(Error::TypeChanged { name: p.name }),
            };
            result.map_err(|source| Error::FmuRefusedParameter {
                path: self.path.clone(),
                name: p.name,
                value: value.to_string(),
                source,
            })?;
        }
        Ok(())
    }

    fn set_inputs(&self, fmu: &mut InstanceCS, drive: &Drive, k: usize) -> Result<(), Error> {
        self.set(fmu, drive, drive.inputs(k), k)
    }

    /// Sets `i`, the inputs at sample `k` (which the error names).
    fn set(&self, fmu: &mut InstanceCS, drive: &Drive, i: Inputs, k: usize) -> Result<(), Error> {
        let values = [i.v_damper, i.a_damper, i.f_demand, i.x_spool_demand, i.t_oil];
        fmu.set_real(&self.inputs, &values).map(|_| ()).map_err(|source| {
            let named: Vec<String> = INPUTS.iter().zip(values).map(|(name, x)| format!("{name} {x}")).collect();
            Error::FmuRefusedInputs { path: self.path.clone(), t: drive.time[k], inputs: named.join(", "), source }
        })
    }

    /// The first `y.len()` outputs (of [`OUTPUTS`]) at time `t` (s).
    fn read(&self, fmu: &mut InstanceCS, t: f64, y: &mut [f64]) -> Result<(), Error> {
        fmu.get_real(&self.outputs[..y.len()], y).map(|_| ()).map_err(|source| Error::FmuFailed {
            path: self.path.clone(),
            t,
            call: "fmi2GetReal",
            source,
        })
    }

    /// The load-cell force at time `t` (s) between two samples.
    fn load_cell(&self, fmu: &mut InstanceCS, t: f64) -> Result<f64, Error> {
        let mut y = [0.0];
        self.read(fmu, t, &mut y)?;
        Ok(y[0])
    }

    fn read_outputs(&self, fmu: &mut InstanceCS, t: f64, all: bool, out: &mut Prediction) -> Result<(), Error> {
        let mut y = [0.0; 8];
        let count = if all { 8 } else { 1 };
        self.read(fmu, t, &mut y[..count])?;
        out.f_damper.push(y[0]);
        if all {
            let fields = [
                &mut out.x_spool,
                &mut out.x_spool_ref,
                &mut out.i_sol,
                &mut out.p_ext,
                &mut out.p_comp,
                &mut out.x_damper,
                &mut out.f_demand_clipped,
            ];
            for (field, value) in fields.into_iter().zip(&y[1..]) {
                field.push(*value);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fits share one import between threads.
    #[test]
    fn the_import_can_be_shared_between_threads() {
        fn shared<T: Send + Sync>() {}
        shared::<FmuModel>();
    }
}
