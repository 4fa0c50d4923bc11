//! The command line: `damper calibrate`, `damper diagnose`, `damper compare`, `damper generate`,
//! `damper effects`, `damper init`, `damper describe`
//! (clap's derive API; every value is checked while parsing, with the parse functions the
//! commands use).

use crate::{calibrate_cmd, compare, description_cmd, diagnose_cmd, effects_cmd};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};
use damper_engine::calibrate::{calibrate, CalibrateOptions, Round, DEFAULT_FIT};
use damper_engine::candidate::Candidate;
use damper_engine::comparison::CompareOptions;
use damper_engine::diagnose_measurement::diagnose_measurement;
use damper_engine::generate::{self, GenerateOptions, InputStyle, Noise};
use damper_engine::measurement::{Mapping, Measurement, DEFAULT_MAX_GAP};
use damper_engine::parameters::{effect, parse_assignment};
use damper_engine::units::{unit_list, Column};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

const EXAMPLES: &str = "\
Examples:
  damper calibrate step.csv sweep.csv --out out/cal --load-cell-lowpass 400
  damper diagnose road.csv --out out/road --params out/cal/parameters.ssv --load-cell-lowpass 400
  damper diagnose data/measurements/rig_valve_test.csv --out out/diagnose --load-cell-lowpass 400
  damper compare data/measurements/rig_valve_test.csv --out out/compare --with seal_friction=150
  damper generate --out g.csv --truth g.json --effect seal_friction --seed 7
  damper help diagnose

Exit status: 0 done, 1 bad data or model failure, 2 bad command line.";

// the measurement's columns, for the help of compare and of diagnose
macro_rules! columns {
    () => {
        "\
Columns (SI, named like the FMU's variables): time, v_damper (or x_damper), F_demand (or only
x_spool_demand: spool-position control), F_damper; optional x_spool, i_sol, p_ext, p_comp,
x_spool_demand. A header cell may carry its unit: 'F_damper [kN]'. Delimiter ',' ';' or tab
(RFC 4180 quoting), '#' comment lines, a decimal comma with ';' or tab; time in s, ms or us, or
ISO 8601 timestamps. Irregular sampling is resampled onto the median interval, and every
resampling and bridged gap is stated (see data/measurements/README.md in the repository)."
    };
}

const DIAGNOSE_HELP: &str = concat!(
    columns!(),
    "

Examples:
  damper diagnose data/measurements/rig_valve_test.csv --out out/diagnose --load-cell-lowpass 400
  damper diagnose rig.csv --out out/rig --map vel=v_damper:mm/s --skip amplifier_delay -v"
);

const COMPARE_HELP: &str = concat!(
    columns!(),
    "

Examples:
  damper compare data/measurements/rig_valve_test.csv --out out/compare --load-cell-lowpass 400
  damper compare rig.csv --out out/friction --with seal_friction=150 --set air_fraction=0.02"
);

const CALIBRATE_HELP: &str = concat!(
    "Fitted by default: r_port, x_lap, Cd_valve, V_hose, air_fraction, k1_mount, p_cv_crack, V_gas0,
p_reservoir0, K_sol, tau_coil (--fit NAME replaces the list; --fit-controller adds Kp_F, Ki_F,
Kp_x, Ki_x, Kd_x). A parameter the records cannot pin (relative standard uncertainty above
--max-relative-uncertainty, |correlation| above 0.95 with another, or a singular JᵀJ) is held at
its start value and the fit is redone without it; the table says which and why. The model runs at
rtol 3e-5 unless --set rtol=VALUE.

",
    columns!(),
    "

Examples:
  damper calibrate step.csv sweep.csv --out out/cal --load-cell-lowpass 400
  damper calibrate rig.csv --out out/cal2 --params out/cal/parameters.ssv --fit air_fraction --fit k1_mount
  damper diagnose road.csv --out out/road --params out/cal/parameters.ssv --load-cell-lowpass 400"
);

const GENERATE_HELP: &str = "\
Examples:
  damper generate --out g.csv --truth g.json --seed 7 --duration 3
  damper generate --out hil.csv --truth hil.json --input hil --road B --effect piston_leakage";

const EFFECTS_HELP: &str = "\
Examples:
  damper effects
  damper diagnose data/measurements/rig_valve_test.csv --out out/diagnose --skip amplifier_delay";

/// damper — the semi-active damper model against measurements
#[derive(Parser, Debug)]
#[command(name = "damper", version, after_help = EXAMPLES, subcommand_required = true, arg_required_else_help = true)]
struct Cli {
    #[command(flatten)]
    global: Global,
    #[command(subcommand)]
    command: Command,
}

// Options every command takes, before or after its name (a doc comment here would be the
// command's description).
#[derive(Args, Debug)]
struct Global {
    /// Threads that fit diagnose's candidates, or calibrate's finite differences, in parallel
    /// [default: the machine's parallelism]
    #[arg(long, global = true, value_name = "N", value_parser = threads_arg, allow_negative_numbers = true, help_heading = "Global options")]
    threads: Option<usize>,
    /// Print nothing but errors (the report and the summary are still written)
    #[arg(short, long, global = true, conflicts_with = "verbose", help_heading = "Global options")]
    quiet: bool,
    /// Also print what the reader decided (columns, units, notes), each candidate fit and the timing
    #[arg(short, long, global = true, help_heading = "Global options")]
    verbose: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Fit the nominal parameters on calibration records; write an SSP parameter set
    ///
    /// Fits the parameters a user cannot know (valve geometry, oil volumes and air, mount,
    /// reservoir gas, solenoid) on one or more records, their force residuals stacked (bounded
    /// Levenberg–Marquardt), reports which the data pin and how well, and writes DIR/parameters.ssv
    /// (SSP 1.0 parameter values, for --params and SSP importers) and DIR/calibration.json.
    #[command(after_help = CALIBRATE_HELP)]
    Calibrate(CalibrateArgs),
    /// Compare, then name the missing physical effect
    ///
    /// Compares (as `damper compare`), then names the missing effect: each catalog effect is
    /// switched on (or refitted), its parameters fitted on the train part and scored on the
    /// validation part; ranked, with a verdict (effect / partial / none / does_not_fit / unexplained) and a ladder of the
    /// error as the effects are added one at a time (two or more when one does not explain the
    /// residual). Writes DIR/report.html and DIR/summary.json, prints a summary.
    #[command(after_help = DIAGNOSE_HELP)]
    Diagnose(DiagnoseArgs),
    /// Drive the model with the measured inputs and show where it fails
    ///
    /// Writes DIR/report.html (self-contained) and DIR/summary.json, prints a summary.
    #[command(after_help = COMPARE_HELP)]
    Compare(CompareArgs),
    /// Write measurement-like data from the model with hidden effects
    ///
    /// The truth goes to a separate JSON file that compare and diagnose never read.
    #[command(after_help = GENERATE_HELP)]
    Generate(GenerateArgs),
    /// List the effect catalog (keys, switches, parameters)
    #[command(after_help = EFFECTS_HELP)]
    Effects(EffectsArgs),
    /// Write the documented template of a damper description (its datasheet)
    ///
    /// A TOML file whose keys name what a datasheet gives (bore, rod, stroke, gas pre-charge and
    /// volume, the valves' data), values in any unit ("36 mm", "10 bar"); edit it and give it to
    /// compare, diagnose, calibrate and generate with --damper FILE.toml.
    #[command(after_help = INIT_HELP)]
    Init(InitArgs),
    /// Show what a damper description sets, and write it as the FMU's parameter set
    ///
    /// Prints every parameter the description sets, with the line it comes from; with --ssv,
    /// writes them as an SSP 1.0 parameter set for an FMI master or an SSP.
    #[command(after_help = INIT_HELP)]
    Describe(DescribeArgs),
}

const INIT_HELP: &str = "\
Examples:
  damper init --out my_damper.toml
  damper describe my_damper.toml --ssv my_damper.ssv
  damper compare dyno.csv --out out/dyno --damper my_damper.toml";

#[derive(Args, Debug)]
struct EffectsArgs {
    /// Print the catalog as JSON (every field of each effect: its parameters with their search
    /// and plausible ranges, how a generator hides it, when a diagnosis tries it)
    #[arg(long)]
    json: bool,
}

#[derive(Args, Debug)]
struct InitArgs {
    /// The description to write (an existing file is not overwritten)
    #[arg(long, value_name = "FILE.toml")]
    out: PathBuf,
}

#[derive(Args, Debug)]
struct DescribeArgs {
    /// The damper description
    #[arg(value_name = "FILE.toml")]
    description: PathBuf,
    /// Write its parameters as an SSP 1.0 parameter set
    #[arg(long, value_name = "FILE.ssv")]
    ssv: Option<PathBuf>,
}

#[derive(Args, Debug)]
struct DiagnoseArgs {
    #[command(flatten)]
    compare: CompareArgs,
    /// Leave this effect out of the candidates; repeatable
    #[arg(long, value_name = "EFFECT", value_parser = effect_arg, help_heading = "Diagnosis")]
    skip: Vec<String>,
    /// The calibration.json of the --params set: the fitted sizes' uncertainties inherit its
    ///
    /// A named effect's parameters are fitted on top of calibrated values; their uncertainty moves
    /// the fit as the record's noise does, and the reported standard errors then include it.
    #[arg(long, value_name = "FILE.json", help_heading = "Diagnosis")]
    calibration: Option<PathBuf>,
    /// With --calibration of several settings: the setting of the --params set
    #[arg(long, value_name = "LABEL", requires = "calibration", help_heading = "Diagnosis")]
    calibration_setting: Option<String>,
}

// The options of compare, which diagnose shares.
/// The model's options shared by compare, diagnose and calibrate.
#[derive(Args, Debug)]
struct ModelArgs {
    /// The damper's description (damper init writes a template), applied to the defaults first
    #[arg(long, value_name = "FILE.toml", help_heading = "Model")]
    damper: Option<PathBuf>,
    /// Apply an SSP parameter set (e.g. damper calibrate's parameters.ssv) after the description,
    /// before --with, --without and --set
    #[arg(long, value_name = "FILE.ssv", help_heading = "Model")]
    params: Option<PathBuf>,
    /// Switch an effect on (VALUE sets its first parameter); repeatable
    #[arg(long, value_name = "EFFECT[=VALUE]", value_parser = effect_arg, help_heading = "Model")]
    with: Vec<String>,
    /// Switch an effect off; repeatable
    #[arg(long, value_name = "EFFECT", value_parser = effect_arg, help_heading = "Model")]
    without: Vec<String>,
    /// Set a model parameter by its FMU name; repeatable, applied last
    #[arg(long, value_name = "NAME=VALUE", value_parser = set_arg, help_heading = "Model")]
    set: Vec<(String, String)>,
}

/// How the measurement is read, shared by compare, diagnose and calibrate.
#[derive(Args, Debug)]
struct MeasurementArgs {
    /// CSV column SOURCE is the variable NAME, in UNIT; repeatable
    #[arg(long, value_name = "SOURCE=NAME[:UNIT]", value_parser = map_arg, long_help = map_long_help(), help_heading = "Measurement")]
    map: Vec<Mapping>,
    /// Bridge gaps of up to N missing samples by linear interpolation (each gap is listed in the
    /// summary); a longer gap stops the run, naming its lines
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_GAP, help_heading = "Measurement")]
    max_gap: usize,
    /// The measured force has its rest offset removed
    ///
    /// The rest offset is the reservoir gas force, about -1 kN. Default: raw load cell, as the
    /// FMU's default.
    #[arg(long, help_heading = "Measurement")]
    tare_load_cell: bool,
    /// First-order low-pass of the load cell, applied to the model's force [default: none]
    #[arg(long, value_parser = number_arg, value_name = "HZ", allow_negative_numbers = true, help_heading = "Measurement")]
    load_cell_lowpass: Option<f64>,
    /// Negate a column as it is read: F_damper, or v_damper/x_damper (the motion: both); repeatable
    ///
    /// For a file written in the other sign convention (compression positive). The check of the
    /// sign convention (a damper's force opposes its motion) names the flag to give.
    #[arg(long, value_name = "COLUMN", value_parser = flip_arg, help_heading = "Measurement")]
    flip: Vec<Column>,
    /// The time column wins where a comment line states another sample rate
    #[arg(long, help_heading = "Measurement")]
    trust_time_column: bool,
}

impl ModelArgs {
    fn apply(self, o: &mut CompareOptions) {
        o.damper_file = self.damper;
        o.params_file = self.params;
        o.with = self.with;
        o.without = self.without;
        o.sets = self.set;
    }
}

impl MeasurementArgs {
    fn apply(self, o: &mut CompareOptions) {
        o.maps = self.map;
        o.max_gap = self.max_gap;
        o.tare_load_cell = self.tare_load_cell;
        o.load_cell_lowpass_hz = self.load_cell_lowpass;
        o.flips = self.flip;
        o.trust_time_column = self.trust_time_column;
    }
}

#[derive(Args, Debug)]
struct CompareArgs {
    /// The measurement CSV (see the columns below)
    #[arg(value_name = "MEASUREMENT.csv")]
    measurement: PathBuf,
    /// Directory for report.html and summary.json
    #[arg(long, value_name = "DIR")]
    out: PathBuf,

    #[command(flatten)]
    model: ModelArgs,
    /// Run the model through this packaged FMU instead of in-process
    ///
    /// python3 scripts/package_fmu.py makes target/fmu/SemiActiveDamper.fmu. Same numbers; its
    /// parameters must match this program's.
    #[arg(long, value_name = "PATH.fmu", help_heading = "Model")]
    fmu: Option<PathBuf>,

    #[command(flatten)]
    measurement_args: MeasurementArgs,
    /// Train share, the rest validates
    #[arg(long, value_parser = number_arg, value_name = "FRACTION", default_value_t = 0.7, allow_negative_numbers = true, help_heading = "Measurement")]
    split: f64,
}

impl CompareArgs {
    /// The comparison's options, and the directory for its files.
    fn options(self) -> (CompareOptions, PathBuf) {
        let mut o = CompareOptions::new(self.measurement);
        self.model.apply(&mut o);
        self.measurement_args.apply(&mut o);
        o.split = self.split;
        o.fmu = self.fmu;
        (o, self.out)
    }
}

/// `--map`'s long help, with the units the reader knows (from units.rs, so it cannot drift).
fn map_long_help() -> String {
    format!(
        "CSV column SOURCE is the variable NAME, in UNIT; repeatable, e.g. --map vel=v_damper:mm/s\n\nUnits: {}.",
        unit_list()
    )
}

#[derive(Args, Debug)]
struct CalibrateArgs {
    /// The calibration records (step and sweep rig tests; see the columns below)
    #[arg(value_name = "RECORD.csv", required = true)]
    records: Vec<PathBuf>,
    /// Directory for parameters.ssv and calibration.json
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Fit this Real parameter (FMU name); repeatable, replaces the default list
    #[arg(long, value_name = "NAME", value_parser = fit_arg, help_heading = "Calibration")]
    fit: Vec<String>,
    /// Also fit the controller's gains Kp_F, Ki_F, Kp_x, Ki_x, Kd_x
    #[arg(long, help_heading = "Calibration")]
    fit_controller: bool,
    /// Fit this Real parameter once per setting of the damper (what an adjuster moves); repeatable
    ///
    /// The records of several settings are calibrated together: this parameter gets a value per
    /// setting, every other one value for all. Writes DIR/parameters_<setting>.ssv per setting.
    #[arg(long, value_name = "NAME", value_parser = per_setting_arg, help_heading = "Calibration")]
    per_setting: Vec<String>,
    /// The records taken at one setting, e.g. --setting "6 clicks=sweep6.csv,step6.csv"; repeatable
    ///
    /// A record named in no --setting is a setting of its own, labelled by its file name.
    #[arg(long, value_name = "LABEL=RECORD.csv,…", value_parser = setting_arg, help_heading = "Calibration")]
    setting: Vec<(String, Vec<PathBuf>)>,
    /// Largest relative standard uncertainty of a parameter called identified
    #[arg(long, value_name = "FRACTION", default_value_t = damper_engine::calibrate::MAX_RELATIVE_UNCERTAINTY, value_parser = positive_arg, allow_negative_numbers = true, help_heading = "Calibration")]
    max_relative_uncertainty: f64,

    #[command(flatten)]
    model: ModelArgs,
    #[command(flatten)]
    measurement_args: MeasurementArgs,
}

impl CalibrateArgs {
    fn options(self, threads: usize) -> (CalibrateOptions, PathBuf) {
        let mut o = CalibrateOptions::new(self.records);
        o.fit = self.fit;
        o.fit_controller = self.fit_controller;
        o.max_relative_uncertainty = self.max_relative_uncertainty;
        o.per_setting = self.per_setting;
        o.settings = self.setting;
        o.threads = threads;
        self.model.apply(&mut o.compare);
        self.measurement_args.apply(&mut o.compare);
        (o, self.out)
    }
}

#[derive(Args, Debug)]
struct GenerateArgs {
    /// The measurement-like CSV to write
    #[arg(long, value_name = "FILE.csv")]
    out: PathBuf,
    /// The JSON file for the truth (the effects and parameters used)
    #[arg(long, value_name = "TRUTH.json")]
    truth: PathBuf,

    /// Effect on at VALUE (its first parameter), at a random plausible value, or off; repeatable
    ///
    /// With no VALUE the effect's size is drawn at random from a plausible range (recorded in the
    /// truth file).
    #[arg(long, value_name = "KEY[=VALUE|off]", value_parser = effect_arg, help_heading = "Truth model")]
    effect: Vec<String>,
    /// Move any parameter, e.g. --set air_fraction=0.04; repeatable
    #[arg(long, value_name = "NAME=VALUE", value_parser = set_arg, help_heading = "Truth model")]
    set: Vec<(String, String)>,
    /// The truth damper's description (damper init), applied to the defaults first
    #[arg(long, value_name = "FILE.toml", help_heading = "Truth model")]
    damper: Option<PathBuf>,
    /// Apply an SSP parameter set to the truth's defaults, after the description, before --effect
    /// and --set
    #[arg(long, value_name = "FILE.ssv", help_heading = "Truth model")]
    params: Option<PathBuf>,
    /// Random seed
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = seed_arg, allow_negative_numbers = true, help_heading = "Truth model")]
    seed: u64,

    /// rig: velocity blocks with demand steps, sine sweep, random velocity; hil: quarter truck on
    /// a random road with the MSD demand
    #[arg(long, value_enum, default_value_t = Input::Rig, help_heading = "Inputs")]
    input: Input,
    /// Record length (s)
    #[arg(long, value_parser = number_arg, value_name = "S", default_value_t = 10.0, allow_negative_numbers = true, help_heading = "Inputs")]
    duration: f64,
    /// Sample rate (Hz)
    #[arg(long, value_parser = number_arg, value_name = "HZ", default_value_t = 1000.0, allow_negative_numbers = true, help_heading = "Inputs")]
    rate: f64,
    /// spool: x_spool_demand instead of F_demand (rig only)
    #[arg(long, value_enum, default_value_t = Control::Force, help_heading = "Inputs")]
    control: Control,
    /// HiL road: motorway, major, minor or ISO 8608 class A-H
    #[arg(long, value_name = "NAME", default_value = "minor", help_heading = "Inputs")]
    road: String,
    /// HiL vehicle speed (m/s)
    #[arg(long, value_parser = number_arg, value_name = "M/S", default_value_t = 14.0, allow_negative_numbers = true, help_heading = "Inputs")]
    speed: f64,
    /// Drive the truth with the true velocity, not the measured one
    ///
    /// Default: with the measured one, as the rig's controller sees it (then velocity noise stays
    /// out of the force residual).
    #[arg(long, help_heading = "Inputs")]
    errors_in_variables: bool,

    /// Write x_damper instead of v_damper
    #[arg(long, help_heading = "Columns and sensors")]
    displacement: bool,
    /// Only time, velocity, demand and F_damper
    #[arg(long, help_heading = "Columns and sensors")]
    minimal: bool,
    /// Load-cell low-pass (Hz), or off
    #[arg(long, value_name = "HZ|off", default_value = "400", value_parser = lowpass_arg, help_heading = "Columns and sensors")]
    lowpass: Lowpass,
    /// Multiply every sensor noise level by K (0: quantisation only)
    #[arg(long, value_name = "K", default_value_t = 1.0, value_parser = noise_arg, allow_negative_numbers = true, help_heading = "Columns and sensors")]
    noise: f64,
    /// One sensor's noise standard deviation and resolution, SI; repeatable
    ///
    /// Defaults: F_damper 20:1 N, v_damper 1e-4:1e-5 m/s, x_damper 2e-6:1e-6 m, x_spool
    /// 1e-6:1e-7 m, i_sol 5e-3:1e-3 A, p_ext/p_comp 1e4:1e3 Pa.
    #[arg(long, value_name = "NAME=NOISE[:Q]", value_parser = sensor_arg, help_heading = "Columns and sensors")]
    sensor: Vec<String>,
    /// The measured force has its rest offset removed [default: for hil]
    #[arg(long, conflicts_with = "raw_load_cell", help_heading = "Columns and sensors")]
    tare_load_cell: bool,
    /// The measured force keeps its rest offset [default: for rig]
    #[arg(long, help_heading = "Columns and sensors")]
    raw_load_cell: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Input {
    Rig,
    Hil,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Control {
    Force,
    Spool,
}

/// A load-cell low-pass in Hz, or none (`off`); a type of its own because clap reads a plain
/// `Option` as "may be left out".
#[derive(Clone, Copy, Debug)]
struct Lowpass(Option<f64>);

impl GenerateArgs {
    fn options(self) -> GenerateOptions {
        let mut o = GenerateOptions::new(self.out, self.truth);
        o.effects = self.effect;
        o.sets = self.set;
        o.damper_file = self.damper;
        o.params_file = self.params;
        o.seed = self.seed;
        o.input = match self.input {
            Input::Rig => InputStyle::Rig,
            Input::Hil => InputStyle::Hil,
        };
        o.duration = self.duration;
        o.rate = self.rate;
        o.spool_control = matches!(self.control, Control::Spool);
        o.lowpass_hz = self.lowpass.0;
        o.noise = Noise::default().scaled(self.noise);
        for text in &self.sensor {
            o.noise.set(text).expect("checked by sensor_arg");
        }
        o.tare_load_cell = match (self.tare_load_cell, self.raw_load_cell) {
            (true, _) => Some(true),
            (_, true) => Some(false),
            _ => None,
        };
        o.road = self.road;
        o.speed = self.speed;
        o.displacement = self.displacement;
        o.minimal = self.minimal;
        o.errors_in_variables = self.errors_in_variables;
        o
    }
}

/// clap names the option and the value already; the parse functions shared with the library do
/// too, so their prefix `OPTION VALUE: ` is dropped.
fn unprefixed(e: String, option: &str, text: &str) -> String {
    match e.strip_prefix(&format!("{option} {text}: ")) {
        Some(rest) => rest.to_string(),
        None => e,
    }
}

fn threads_arg(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("a number of threads, at least 1".into()),
    }
}

/// `KEY` or `KEY=VALUE`: the key is checked against the catalog here, the value where it is set.
fn effect_arg(text: &str) -> Result<String, String> {
    effect(text.split_once('=').map_or(text, |(key, _)| key)).map_err(|e| e.to_string())?;
    Ok(text.to_string())
}

/// A Real parameter of the model.
fn fit_arg(text: &str) -> Result<String, String> {
    let mut o = CalibrateOptions::new(Vec::new());
    o.fit = vec![text.to_string()];
    o.names().map_err(|e| unprefixed(e.to_string(), "--fit", text))?;
    Ok(text.to_string())
}

fn per_setting_arg(text: &str) -> Result<String, String> {
    let mut o = CalibrateOptions::new(Vec::new());
    o.per_setting = vec![text.to_string()];
    o.per_setting_names().map_err(|e| unprefixed(e.to_string(), "--per-setting", text))?;
    Ok(text.to_string())
}

fn setting_arg(text: &str) -> Result<(String, Vec<PathBuf>), String> {
    let (label, files) = text.split_once('=').ok_or("LABEL=RECORD.csv[,RECORD.csv…]")?;
    let files: Vec<PathBuf> = files.split(',').map(str::trim).filter(|f| !f.is_empty()).map(PathBuf::from).collect();
    if label.trim().is_empty() || files.is_empty() {
        return Err("LABEL=RECORD.csv[,RECORD.csv…]: a label and at least one record".into());
    }
    Ok((label.trim().to_string(), files))
}

fn positive_arg(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        Ok(_) => Err("must be a positive number".into()),
        Err(_) => Err("not a number".into()),
    }
}

fn set_arg(text: &str) -> Result<(String, String), String> {
    parse_assignment(text, "--set").map_err(|e| unprefixed(e.to_string(), "--set", text))
}

fn flip_arg(text: &str) -> Result<Column, String> {
    match Column::from_name(text) {
        Some(c @ (Column::FDamper | Column::VDamper | Column::XDamper)) => Ok(c),
        _ => Err("F_damper, v_damper or x_damper".into()),
    }
}

fn map_arg(text: &str) -> Result<Mapping, String> {
    Mapping::parse(text).map_err(|e| unprefixed(e.to_string(), "--map", text))
}

fn sensor_arg(text: &str) -> Result<String, String> {
    Noise::default().set(text).map_err(|e| unprefixed(e.to_string(), "--sensor", text))?;
    Ok(text.to_string())
}

fn number_arg(text: &str) -> Result<f64, String> {
    text.parse().map_err(|_| "not a number".into())
}

fn seed_arg(text: &str) -> Result<u64, String> {
    text.parse().map_err(|_| "not a non-negative integer".into())
}

fn lowpass_arg(text: &str) -> Result<Lowpass, String> {
    if text == "off" || text == "none" {
        return Ok(Lowpass(None));
    }
    text.parse().map(|hz| Lowpass(Some(hz))).map_err(|_| "a frequency in Hz, or off".into())
}

fn noise_arg(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(k) if k >= 0.0 => Ok(k),
        Ok(_) => Err("must be ≥ 0".into()),
        Err(_) => Err("not a number".into()),
    }
}

/// Runs the command line (`args` without the program name); returns the exit status.
pub fn main(args: impl IntoIterator<Item = std::ffi::OsString>) -> i32 {
    let cli = match Cli::try_parse_from(std::iter::once("damper".into()).chain(args)) {
        Ok(cli) => cli,
        Err(e) => return usage_error(e),
    };
    let g = &cli.global;
    let result = match cli.command {
        Command::Calibrate(a) => run_calibrate(a, g),
        Command::Diagnose(a) => run_diagnose(a, g),
        Command::Compare(a) => run_compare(a, g),
        Command::Generate(a) => run_generate(a, g),
        Command::Effects(a) => {
            if a.json {
                print!("{}", effects_cmd::json());
            } else if !g.quiet {
                print!("{}", effects_cmd::table());
            }
            Ok(())
        }
        Command::Init(a) => run_init(a, g),
        Command::Describe(a) => run_describe(a, g),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("damper: error: {e}");
            1
        }
    }
}

/// Prints clap's message (help and version too) and returns its exit status: 2 for a bad command
/// line, 0 for help and version. An unknown command gets the list of the commands, as clap names
/// only a similar one.
fn usage_error(mut e: clap::Error) -> i32 {
    if e.kind() == ErrorKind::InvalidSubcommand {
        let names: Vec<String> = Cli::command().get_subcommands().map(|c| c.get_name().to_string()).collect();
        let tip = format!("the commands are {}, help", names.join(", "));
        let mut tips = match e.get(ContextKind::Suggested) {
            Some(ContextValue::StyledStrs(tips)) => tips.clone(),
            _ => Vec::new(),
        };
        tips.push(tip.into());
        e.insert(ContextKind::Suggested, ContextValue::StyledStrs(tips));
    }
    let _ = e.print();
    e.exit_code()
}

fn run_init(a: InitArgs, g: &Global) -> Result<(), String> {
    damper_engine::description::write_template(&a.out).map_err(|e| e.to_string())?;
    if !g.quiet {
        println!("damper init: wrote {} (a passive damper's example: edit it to describe yours)", a.out.display());
    }
    Ok(())
}

fn run_describe(a: DescribeArgs, g: &Global) -> Result<(), String> {
    let (d, written) = description_cmd::described(&a.description).map_err(|e| e.to_string())?;
    if let Some(path) = &a.ssv {
        let note = format!("damper describe {}", a.description.display());
        let text = damper_engine::ssv::to_string(&d.name, &note, &written);
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    if !g.quiet {
        description_cmd::print(&d, &written, a.ssv.as_deref());
    }
    Ok(())
}

fn run_compare(a: CompareArgs, g: &Global) -> Result<(), String> {
    let t0 = Instant::now();
    let (o, out) = a.options();
    let c = compare::run(&o, &out, g.quiet)?;
    if g.verbose {
        print_reader(&c.measurement);
        eprintln!("time: {:.2} s in all, {:.2} s of it the model run", t0.elapsed().as_secs_f64(), c.run_seconds);
    }
    Ok(())
}

fn run_calibrate(a: CalibrateArgs, g: &Global) -> Result<(), String> {
    let threads = g.threads.unwrap_or_else(damper_engine::model::default_threads);
    let (o, out) = a.options(threads);
    let progress = |r: &Round| {
        if g.verbose {
            eprintln!(
                "  fit of {} parameters: {} iterations, {} model runs, RMS residual {:.1} N{}",
                r.fitted.len(),
                r.iterations,
                r.model_runs,
                r.rms_residual,
                r.held.as_ref().map_or(String::new(), |(n, why)| format!("; holding {n}: {why}"))
            );
        }
    };
    if g.verbose {
        let names = if o.fit.is_empty() { DEFAULT_FIT.join(", ") } else { o.fit.join(", ") };
        eprintln!("damper calibrate: fitting {names} on {threads} threads");
    }
    let c = calibrate(&o, &progress).map_err(|e| e.to_string())?;
    calibrate_cmd::write(&c, &o, &out, g.quiet)
}

fn run_diagnose(a: DiagnoseArgs, g: &Global) -> Result<(), String> {
    let t0 = Instant::now();
    let (mut o, out) = a.compare.options();
    o.skip = a.skip;
    o.calibration = a.calibration.map(|path| (path, a.calibration_setting));
    let threads = g.threads.unwrap_or_else(damper_engine::model::default_threads);
    let bar = fit_bar(g.quiet);
    let fits = AtomicUsize::new(0);
    let progress = |c: &Candidate, done: usize, total: usize| {
        fits.fetch_add(1, Ordering::Relaxed);
        // both at once: each round of the ladder has its own total, and a bar drawn between the
        // two would read e.g. 8/7
        bar.update(|s| {
            s.set_len(total as u64);
            s.set_pos(done as u64);
        });
        if g.verbose {
            bar.suspend(|| {
                eprintln!(
                    "  fitted {:<22} validation NRMSE {:.4} ({:+.0} %), {} model runs",
                    c.effect,
                    c.nrmse_validation,
                    -100.0 * c.reduction,
                    c.evaluations
                )
            });
        }
    };
    if g.verbose {
        eprintln!("damper diagnose: fitting the candidate effects on {threads} threads");
    }
    let r = diagnose_measurement(&o, threads, &progress);
    bar.finish_and_clear();
    let r = r.map_err(|e| e.to_string())?;
    diagnose_cmd::write(&r, &out, g.quiet)?;
    if g.verbose {
        print_reader(&r.comparison.measurement);
        eprintln!(
            "time: {:.2} s in all: {} candidate fits on {threads} threads, one model run {:.2} s",
            t0.elapsed().as_secs_f64(),
            fits.load(Ordering::Relaxed),
            r.comparison.run_seconds
        );
    }
    Ok(())
}

/// The candidate fits' progress on stderr, while the summary is for stdout: only when stdout is a
/// terminal that a person watches, and not with --quiet.
fn fit_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stdout().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("fitting candidate effects [{bar:30}] {pos}/{len} {elapsed}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    bar
}

/// What the reader made of the file: which column is which variable in which unit, and what it
/// left out (-v).
fn print_reader(m: &Measurement) {
    eprintln!("read {}: {} samples", m.path, m.len());
    for s in &m.sources {
        eprintln!("  {:<15} ← column {} ('{}') in {}", s.column.name(), s.index, s.header, s.unit);
    }
    if m.velocity_from_displacement {
        eprintln!("  v_damper        ← differentiated x_damper");
    }
    if !m.ignored.is_empty() {
        eprintln!("  not used: {}", m.ignored.join(", "));
    }
    for n in &m.notes {
        eprintln!("  note: {n}");
    }
}

fn run_generate(a: GenerateArgs, g: &Global) -> Result<(), String> {
    let t0 = Instant::now();
    let o = a.options();
    let d = generate::write(&o).map_err(|e| e.to_string())?;
    if !g.quiet {
        let names: Vec<&str> = d.columns.iter().map(|(c, _)| c.name()).collect();
        println!(
            "damper generate: {} samples at {} Hz ({} s, {} inputs, seed {}) → {} [{}]",
            d.time.len(),
            o.rate,
            o.duration,
            if o.input == InputStyle::Rig { "rig" } else { "HiL" },
            o.seed,
            o.out.display(),
            names.join(", ")
        );
        println!("truth (not read by compare/diagnose) → {}", o.truth.display());
    }
    if g.verbose {
        eprintln!("time: {:.2} s", t0.elapsed().as_secs_f64());
    }
    Ok(())
}
