//! The crate's error: one enum, [`Error`], its variants by concern (files, parameters and effects,
//! units, description and parameter-set files, the model and the FMU, fits, records, options).
//!
//! Each message is the text the command line prints, so a variant's `Display` is the message
//! (files, lines and fields named where the problem has them); foreign errors are kept as the
//! [`std::error::Error::source`] where there is one.

use semi_active_damper::model_description::Causality;
use semi_active_damper::physics::params::ParameterError;
use semi_active_damper::step_error::StepError;
use std::fmt;
use std::path::PathBuf;

/// Where in a file a problem is: the file, perhaps its line (1-based), perhaps the field there
/// (`kind`, `[cylinder] stroke`, `parameter r_port`); shown as `FILE, line N, FIELD`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Place {
    pub file: String,
    pub line: Option<usize>,
    pub field: Option<String>,
}

impl Place {
    /// `file`.
    pub fn file(file: impl Into<String>) -> Place {
        Place { file: file.into(), line: None, field: None }
    }

    /// `file, line N`.
    pub fn line(file: impl Into<String>, line: usize) -> Place {
        Place { file: file.into(), line: Some(line), field: None }
    }

    /// `file, line N, field`.
    pub fn field(file: impl Into<String>, line: usize, field: impl Into<String>) -> Place {
        Place { file: file.into(), line: Some(line), field: Some(field.into()) }
    }

    /// This place with `more` added to its field (`parameter r_port` → `parameter r_port, ssv:Real`).
    pub fn and(&self, more: impl fmt::Display) -> Place {
        let field = match &self.field {
            Some(f) => format!("{f}, {more}"),
            None => more.to_string(),
        };
        Place { field: Some(field), ..self.clone() }
    }
}

impl fmt::Display for Place {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        if let Some(line) = self.line {
            write!(f, ", line {line}")?;
        }
        if let Some(field) = &self.field {
            write!(f, ", {field}")?;
        }
        Ok(())
    }
}

/// Everything that can go wrong in the engine; the message is what the user reads. The largest
/// foreign errors are boxed, to keep a `Result` small.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    // ---- files ----
    /// A file that cannot be written (or read, where the message has no verb).
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    /// A file that cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    Read { path: PathBuf, source: std::io::Error },
    /// A directory that cannot be created.
    #[error("{}: cannot create: {source}", path.display())]
    CreateDir { path: PathBuf, source: std::io::Error },
    /// A file that would be overwritten.
    #[error("{}: exists; choose another name or remove it", path.display())]
    Exists { path: PathBuf },
    /// A JSON file that is not what it should be.
    #[error("{}: {source}", path.display())]
    Json { path: PathBuf, source: serde_json::Error },

    // ---- parameters and effects ----
    /// A name the model has but not as a parameter (an input or output).
    #[error("{}", format!("{name} is a model {causality:?}, not a parameter").to_lowercase())]
    NotAParameter { name: String, causality: Causality },
    /// A name the model does not have; `did_you_mean`: the closest names, if any are close.
    #[error("unknown parameter '{name}'{}", unknown_parameter_hint(did_you_mean, *parameters))]
    UnknownParameter { name: String, did_you_mean: Vec<&'static str>, parameters: usize },
    /// A parameter (or switch) not of the kind wanted (`kind`: "Real parameter", "Boolean"); `is`:
    /// its value, where known.
    #[error("{name} is not a {kind}{}", is.as_ref().map_or(String::new(), |v| format!(" (it is {v})")))]
    NotOfKind { name: String, kind: &'static str, is: Option<String> },
    /// A parameter's value in text that is not of its type.
    #[error("{name}={text}: {expected}")]
    BadValue { name: String, text: String, expected: &'static str },
    /// A value outside the range in `modelDescription.xml` (`of_model`: a Real's range).
    #[error("{name}={value} is out of {}range [{min}, {max}]", if *of_model { "the model's " } else { "" })]
    OutOfRange { name: String, value: String, min: String, max: String, of_model: bool },
    /// An option's `NAME=VALUE` without the name or the value.
    #[error("{option} {text}: expected NAME=VALUE")]
    BadAssignment { option: String, text: String },
    /// An effect key the catalog does not have.
    #[error("unknown effect '{key}'; the catalog has {}", catalog.join(", "))]
    UnknownEffect { key: String, catalog: Vec<&'static str> },
    /// An effect whose switch this build of the model does not have.
    #[error("{source} (this build of the model has no switch {switch} for the effect {effect})")]
    NoSwitch { switch: String, effect: &'static str, source: Box<Error> },
    /// Parameters that do not go together.
    #[error("{0}")]
    Invalid(#[from] ParameterError),
    /// The model's parameters do not go together.
    #[error("model parameters: {0}")]
    ModelParameters(#[source] ParameterError),
    /// A damper description whose parameters do not go together.
    #[error("{path}: the damper it describes is not valid: {source}")]
    InvalidDamper { path: String, source: ParameterError },

    // ---- units ----
    /// A unit symbol that is not known.
    #[error("unknown unit '{symbol}'")]
    UnknownUnit { symbol: String },
    /// A column's unit symbol that is not known (`known`: the units that are).
    #[error("unknown unit '{symbol}' (known: {known})")]
    UnknownUnitOf { symbol: String, known: String },
    /// A column's unit of another quantity than its variable's.
    #[error("unit '{unit}' is {quantity}, but {column} is {column_quantity}")]
    UnitOfOtherQuantity { unit: String, quantity: String, column: &'static str, column_quantity: String },
    /// A unit factor whose power is not an integer.
    #[error("bad power in '{term}'")]
    BadPower { term: String },
    /// A unit with more than one `/`.
    #[error("unit '{unit}': one '/' at most")]
    TwoSlashes { unit: String },
    /// A quantity that is not a finite number with a unit (`problem`: "does not start with a
    /// number", "is not a finite number").
    #[error("'{text}' {problem}")]
    NotAQuantity { text: String, problem: &'static str },

    // ---- files of a format: descriptions (TOML), parameter sets (SSV) ----
    /// A description that is not TOML.
    #[error("{file}, line {line}: not TOML: {}", source.message())]
    Toml { file: String, line: usize, source: Box<toml::de::Error> },
    /// A CSV file that cannot be read as CSV.
    #[error("{file}: {source}")]
    Csv { file: String, source: csv::Error },
    /// A parameter set that is not well-formed XML.
    #[error("{file}, line {line}: not well-formed XML: {source}")]
    Xml { file: String, line: usize, source: quick_xml::Error },
    /// An XML attribute that cannot be read.
    #[error("{at}: bad attribute: {source}")]
    BadAttribute { at: Place, source: quick_xml::events::attributes::AttrError },
    /// An XML attribute whose value cannot be unescaped.
    #[error("{at}, attribute {name}: {source}")]
    AttributeValue { at: Place, name: String, source: Box<quick_xml::Error> },
    /// A problem at a place in a file, in words.
    #[error("{at}: {problem}")]
    InFile { at: Place, problem: String },
    /// An error about what a place in a file gives.
    #[error("{at}: {source}")]
    AtPlace { at: Place, source: Box<Error> },
    /// An error about what an option or a source gives (`context`: `--with KEY=VALUE`, a
    /// description's setting, a record's path).
    #[error("{context}: {source}")]
    Context { context: String, source: Box<Error> },

    // ---- options ----
    /// A `--setting` naming a file that is not one of the records.
    #[error("--setting {label}: {} is not one of the records", path.display())]
    SettingStranger { label: String, path: PathBuf },
    /// A record given two settings.
    #[error("--setting: {} is given two settings, {first} and {second}", path.display())]
    SettingTwice { path: PathBuf, first: String, second: String },
    /// An option's value that is out of its range, or contradicts another (`problem` in words).
    #[error("{option}: {problem}")]
    BadOption { option: String, problem: String },

    // ---- the model and the FMU ----
    /// The model's step failed.
    #[error("the model failed between t = {from} s and {to} s: {cause}")]
    ModelFailed { from: f64, to: f64, cause: StepError },
    /// The worker threads cannot be started.
    #[error("cannot start {threads} threads: {source}")]
    Threads { threads: usize, source: rayon::ThreadPoolBuildError },
    /// The worker threads cannot be started, for one of several runs (`cause`: the pool's error,
    /// formatted, as one error is shared by every run).
    #[error("cannot start {threads} threads: {cause}")]
    ThreadsNotStarted { threads: usize, cause: String },
    /// A packaged FMU that cannot be used (`problem` in words).
    #[error("--fmu {}: {problem}", path.display())]
    FmuLoad { path: PathBuf, problem: String },
    /// A packaged FMU that cannot be imported.
    #[error("--fmu {}: not an FMI 2.0 FMU this program can import: {source}", path.display())]
    FmuImport { path: PathBuf, source: fmi::Error },
    /// A packaged FMU that cannot be instantiated on loading.
    #[error("--fmu {}: cannot instantiate the FMU: {source}", path.display())]
    FmuInstantiate { path: PathBuf, source: fmi::Error },
    /// An FMU call that failed outside the stepping (`call`: `fmi2Terminate`).
    #[error("the FMU {}: {call}: {source}", path.display())]
    FmuCall { path: PathBuf, call: &'static str, source: fmi::fmi2::Fmi2Error },
    /// An FMU run's instance that cannot be made.
    #[error("the FMU {}: fmi2Instantiate failed: {source}", path.display())]
    FmuInstance { path: PathBuf, source: fmi::Error },
    /// An FMU call that failed at a time.
    #[error("the FMU {} failed at t = {t} s: {call}: {source}", path.display())]
    FmuFailed { path: PathBuf, t: f64, call: &'static str, source: fmi::fmi2::Fmi2Error },
    /// The FMU's step that failed.
    #[error("the FMU {} failed between t = {from} s and {to} s: fmi2DoStep: {source}", path.display())]
    FmuStep { path: PathBuf, from: f64, to: f64, source: fmi::fmi2::Fmi2Error },
    /// A parameter value the FMU refused.
    #[error("the FMU {} refused {name} = {value}: {source}", path.display())]
    FmuRefusedParameter { path: PathBuf, name: &'static str, value: String, source: fmi::fmi2::Fmi2Error },
    /// Inputs the FMU refused (`inputs`: each with its value).
    #[error("the FMU {} refused the inputs at t = {t} s ({inputs}): {source}", path.display())]
    FmuRefusedInputs { path: PathBuf, t: f64, inputs: String, source: fmi::fmi2::Fmi2Error },
    /// A parameter whose type differs between the import and the run.
    #[error("parameter {name} changed its type")]
    TypeChanged { name: &'static str },

    // ---- generated records ----
    /// A passive damper's description for a HiL record (`--input hil`).
    #[error("{}: a passive damper: --input hil needs a semi-active one", path.display())]
    PassiveForHil { path: PathBuf },
    /// The generator's truth parameters do not go together.
    #[error("truth parameters: {0}")]
    TruthParameters(#[source] ParameterError),
    /// The generator's truth model failed.
    #[error("the truth model failed at t = {t} s: {cause}")]
    TruthFailed { t: f64, cause: StepError },
    /// A record too short to generate.
    #[error("--duration {duration} at --rate {rate} gives {samples} samples; at least 400 are needed")]
    TooFewGenerated { duration: f64, rate: f64, samples: usize },
    /// An option only for the rig's inputs (`why`: what follows the message, if anything).
    #[error("{option} works with --input rig only{why}")]
    RigOnly { option: &'static str, why: &'static str },
    /// The record and its truth given the same file.
    #[error("--out and --truth must be different files")]
    SameOutAndTruth,

    // ---- the comparison's model and split ----
    /// A passive damper's description for a measurement with a demand.
    #[error("{}: a passive damper, but the measurement has {demand}: a passive damper has no demand", path.display())]
    PassiveWithDemand { path: PathBuf, demand: &'static str },
    /// An effect both switched on and off.
    #[error("effect {effect} is both in --with and --without")]
    WithAndWithout { effect: &'static str },
    /// A `--set control_mode` other than the measurement's demand gives.
    #[error("--set control_mode={set} contradicts the measurement: it has {has} (control_mode {mode})")]
    ControlMode { set: i32, has: &'static str, mode: i32 },

    // ---- fits ----
    /// A fit given as many search boxes as parameters, or none.
    #[error("{parameters} parameters but {scales} scales")]
    ScaleCount { parameters: usize, scales: usize },
    /// A search box that is empty, or a logarithmic one not above zero.
    #[error("bad search box [{lo}, {hi}] (log {log})")]
    SearchBox { lo: f64, hi: f64, log: bool },
    /// Fewer residuals than parameters.
    #[error("{residuals} residuals for {parameters} parameters")]
    TooFewResiduals { residuals: usize, parameters: usize },
    /// An input noise draw of another length than the residuals.
    #[error("an input noise draw is not as long as the {residuals} residuals")]
    NoiseDrawLength { residuals: usize },
    /// A residual function whose length changed between calls.
    #[error("the residuals changed length ({before} → {after})")]
    ResidualsChangedLength { before: usize, after: usize },
    /// A steady point whose flow no pressure drop passes.
    #[error("no pressure drop passes the flow at v = {v} m/s")]
    NoPressureDrop { v: f64 },
    /// Too few quasi-steady samples for the steady fit.
    #[error("{samples} quasi-steady samples: too few to fit {parameters} parameters")]
    TooFewSamples { samples: usize, parameters: usize },
    /// A steady fit that failed from every start.
    #[error("the steady fit failed from every start")]
    SteadyFitFailed,
    /// A steady fit's parameter without a positive start.
    #[error("{name} = {start}: a steady fit needs a positive start value")]
    NoPositiveStart { name: String, start: f64 },
    /// A parameter's start value that leaves no room to search within its range.
    #[error("{name} = {start}: no room to search within the model's range [{min}, {max}]")]
    NoRoomToSearch { name: String, start: f64, min: f64, max: f64 },
    /// A calibration without a record.
    #[error("no calibration record given")]
    NoRecords,
    /// An effect named that is not among the candidates.
    #[error("{key} is not among the candidate effects")]
    NotACandidate { key: String },
    /// A calibration file without a covariance.
    #[error("{}: no covariance (the calibration held every parameter)", path.display())]
    NoCovariance { path: PathBuf },

    // ---- the diagnosis ----
    /// A record without a measured force.
    #[error("the measurement has no F_damper column")]
    NoForceColumn,
    /// `--skip` left nothing to try.
    #[error("--skip leaves no candidate effect")]
    NoCandidates,
    /// A validation error or floor that is not finite.
    #[error(
        "nothing to diagnose: the validation NRMSE is {nrmse} and the noise floor {floor} (is the measured force constant?)"
    )]
    NothingToDiagnose { nrmse: f64, floor: f64 },

    // ---- the motion ----
    /// A velocity whose integral departs from the displacement (`rms`: mm, `share`: % of the
    /// stroke's spread).
    #[error(
        "the integral of v_damper departs from x_damper by {rms:.3} mm RMS above {crossover_hz} Hz, {share:.0} % of \
         the stroke's spread: check the two columns' units and signs (velocity extension +, displacement \
         extension +)"
    )]
    VelocityDisplacement { rms: f64, crossover_hz: f64, share: f64 },
}

fn unknown_parameter_hint(did_you_mean: &[&str], parameters: usize) -> String {
    if did_you_mean.is_empty() {
        format!(" (the model has {parameters} parameters; see modelDescription.xml)")
    } else {
        format!("; did you mean {}?", did_you_mean.join(", "))
    }
}

impl Error {
    /// `context: self`.
    pub fn context(self, context: impl Into<String>) -> Error {
        Error::Context { context: context.into(), source: Box::new(self) }
    }

    /// `at: self`.
    pub fn at(self, at: Place) -> Error {
        Error::AtPlace { at, source: Box::new(self) }
    }
}
