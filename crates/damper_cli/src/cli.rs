//! The command line: `damper diagnose`, `damper compare`, `damper generate`, `damper effects`.

use crate::compare::{self, CompareOptions};
use crate::generate::{self, GenerateOptions, InputStyle, Noise};
use crate::measurement::Mapping;
use crate::parameters::{effects, parse_assignment, EffectExt};

const USAGE: &str = "\
damper — the semi-active damper model against measurements

USAGE:
  damper diagnose MEASUREMENT.csv --out DIR [options]
  damper compare MEASUREMENT.csv --out DIR [options]
  damper generate --out FILE.csv --truth TRUTH.json [options]
  damper effects
  damper help [COMMAND]

diagnose: compare, then name the missing effect: each catalog effect is switched on (or refitted),
  its parameters fitted on the train part and scored on the validation part; ranked, with a verdict
  (effect / none / unexplained) and a ladder of the error as the effects are added one at a time
  (two or more when one does not explain the residual). Options of compare, and:
  --skip EFFECT             leave this effect out of the candidates; repeatable

compare: drives the model with the measured inputs and shows where it fails.
  Writes DIR/report.html (self-contained) and DIR/summary.json, prints a summary.
  --with EFFECT[=VALUE]     switch an effect on (VALUE sets its first parameter); repeatable
  --without EFFECT          switch an effect off; repeatable
  --set NAME=VALUE          set a model parameter by its FMU name; repeatable, applied last
  --map SOURCE=NAME[:UNIT]  CSV column SOURCE is the variable NAME, in UNIT; repeatable
                            units: s ms m cm mm m/s cm/s mm/s N kN Pa kPa MPa bar A mA
  --split FRACTION          train share, the rest validates (default 0.7)
  --tare-load-cell          the measured force has its rest offset (the reservoir gas force,
                            about -1 kN) removed; default: raw load cell, as the FMU's default
  --load-cell-lowpass HZ    first-order low-pass of the load cell, applied to the model's force
                            (default: none)
  --fmu PATH.fmu            run the model through this packaged FMU (python3 scripts/package_fmu.py
                            makes target/fmu/SemiActiveDamper.fmu) instead of in-process; same
                            numbers, its parameters must match this program's
  --quiet                   print nothing
  Columns (SI, named like the FMU's variables): time, v_damper (or x_damper), F_demand (or only
  x_spool_demand: spool-position control), F_damper; optional x_spool, i_sol, p_ext, p_comp,
  x_spool_demand. A header cell may carry its unit: 'F_damper [kN]'.

generate: measurement-like CSV from the model with hidden effects; the truth goes to a separate
  JSON file that compare never reads.
  --effect KEY[=VALUE|off]  effect on at VALUE (its first parameter), at a random plausible value
                            when none is given, or off; repeatable
  --set NAME=VALUE          move any parameter, e.g. --set air_fraction=0.04; repeatable
  --seed N                  random seed (default 1)
  --input rig|hil           rig: velocity blocks with demand steps, sine sweep, random velocity;
                            hil: quarter truck on a random road with the MSD demand (default rig)
  --duration S --rate HZ    record length and sample rate (default 10 s, 1000 Hz)
  --control force|spool     spool: x_spool_demand instead of F_demand (rig only; default force)
  --displacement            write x_damper instead of v_damper
  --minimal                 only time, velocity, demand and F_damper
  --errors-in-variables     drive the truth with the true velocity; default: with the measured one,
                            as the rig's controller sees it (then velocity noise stays out of the
                            force residual)
  --lowpass HZ|off          load-cell low-pass (default 400 Hz)
  --noise K                 multiply every sensor noise level by K (default 1; 0: quantisation only)
  --sensor NAME=NOISE[:Q]   one sensor's noise standard deviation and resolution, SI; repeatable
                            (defaults: F_damper 20:1 N, v_damper 1e-4:1e-5 m/s, x_damper 2e-6:1e-6 m,
                            x_spool 1e-6:1e-7 m, i_sol 5e-3:1e-3 A, p_ext/p_comp 1e4:1e3 Pa)
  --tare-load-cell / --raw-load-cell   default: raw for rig, tared for hil
  --road NAME --speed M/S   hil road (motorway, major, minor or class A-H; default minor, 14)

effects: lists the effect catalog (keys, switches, parameters).

Exit status: 0 done, 1 bad data or model failure, 2 bad command line.
";

/// Parsed options: repeated `--name value` pairs, flags and positional arguments.
struct Args {
    pairs: Vec<(String, String)>,
    flags: Vec<String>,
    positional: Vec<String>,
}

fn parse(args: &[String], with_value: &[&str], flags: &[&str]) -> Result<Args, String> {
    let mut out = Args { pairs: Vec::new(), flags: Vec::new(), positional: Vec::new() };
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        if let Some(name) = a.strip_prefix("--") {
            let (name, inline) = match name.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (name, None),
            };
            if with_value.contains(&name) {
                let value = match inline {
                    Some(v) => v,
                    None => {
                        i += 1;
                        args.get(i).cloned().ok_or_else(|| format!("--{name} needs a value"))?
                    }
                };
                out.pairs.push((name.to_string(), value));
            } else if flags.contains(&name) {
                if inline.is_some() {
                    return Err(format!("--{name} takes no value"));
                }
                out.flags.push(name.to_string());
            } else {
                return Err(format!("unknown option --{name} (see damper help)"));
            }
        } else {
            out.positional.push(a.clone());
        }
        i += 1;
    }
    Ok(out)
}

impl Args {
    fn all(&self, name: &str) -> Vec<String> {
        self.pairs.iter().filter(|(n, _)| n == name).map(|(_, v)| v.clone()).collect()
    }
    fn one(&self, name: &str) -> Result<Option<String>, String> {
        let v = self.all(name);
        if v.len() > 1 {
            return Err(format!("--{name} given {} times", v.len()));
        }
        Ok(v.into_iter().next())
    }
    fn number(&self, name: &str) -> Result<Option<f64>, String> {
        self.one(name)?.map(|v| v.parse::<f64>().map_err(|_| format!("--{name} {v}: not a number"))).transpose()
    }
    fn flag(&self, name: &str) -> bool {
        self.flags.iter().any(|f| f == name)
    }
}

enum Failure {
    Usage(String),
    Data(String),
}

/// Runs the command line; returns the exit status.
pub fn main(args: &[String]) -> i32 {
    let result = match args.first().map(String::as_str) {
        None | Some("help" | "--help" | "-h") => {
            print!("{USAGE}");
            Ok(())
        }
        Some("--version" | "-V") => {
            println!("damper {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        Some("compare") => run_compare(&args[1..]),
        Some("generate") => run_generate(&args[1..]),
        Some("effects") => {
            print_effects();
            Ok(())
        }
        Some("diagnose") => run_diagnose(&args[1..]),
        Some(other) => {
            Err(Failure::Usage(format!("unknown command '{other}' (commands: compare, generate, effects, help)")))
        }
    };
    match result {
        Ok(()) => 0,
        Err(Failure::Usage(e)) => {
            eprintln!("damper: error: {e}");
            2
        }
        Err(Failure::Data(e)) => {
            eprintln!("damper: error: {e}");
            1
        }
    }
}

fn print_effects() {
    println!("{:<22}{:<30}{:<9}{:<28}meaning", "effect", "switch", "default", "parameters");
    for e in effects() {
        println!(
            "{:<22}{:<30}{:<9}{:<28}{}",
            e.key,
            e.switch(),
            if e.default_on() { "on" } else { "off" },
            e.parameter_names().join(", "),
            e.meaning
        );
    }
}

fn run_compare(args: &[String]) -> Result<(), Failure> {
    let o = compare_options(args, "compare")?;
    compare::run(&o).map(|_| ()).map_err(Failure::Data)
}

fn run_diagnose(args: &[String]) -> Result<(), Failure> {
    let o = compare_options(args, "diagnose")?;
    crate::diagnose_cmd::run(&o, crate::model::default_threads()).map(|_| ()).map_err(Failure::Data)
}

/// The options shared by compare and diagnose.
fn compare_options(args: &[String], command: &str) -> Result<CompareOptions, Failure> {
    let mut with_value = vec!["out", "with", "without", "map", "set", "split", "load-cell-lowpass", "fmu"];
    if command == "diagnose" {
        with_value.push("skip");
    }
    let a = parse(args, &with_value, &["tare-load-cell", "quiet"]).map_err(Failure::Usage)?;
    let [measurement] = a.positional.as_slice() else {
        return Err(Failure::Usage(format!(
            "{command} needs exactly one MEASUREMENT.csv, got {}: damper {command} MEASUREMENT.csv --out DIR",
            a.positional.len()
        )));
    };
    let out =
        a.one("out").map_err(Failure::Usage)?.ok_or_else(|| Failure::Usage(format!("{command} needs --out DIR")))?;
    let mut o = CompareOptions::new(measurement, out);
    o.with = a.all("with");
    o.without = a.all("without");
    o.maps = a.all("map").iter().map(|m| Mapping::parse(m)).collect::<Result<_, _>>().map_err(Failure::Usage)?;
    o.sets =
        a.all("set").iter().map(|s| parse_assignment(s, "--set")).collect::<Result<_, _>>().map_err(Failure::Usage)?;
    if let Some(s) = a.number("split").map_err(Failure::Usage)? {
        o.split = s;
    }
    o.tare_load_cell = a.flag("tare-load-cell");
    o.load_cell_lowpass_hz = a.number("load-cell-lowpass").map_err(Failure::Usage)?;
    o.fmu = a.one("fmu").map_err(Failure::Usage)?.map(std::path::PathBuf::from);
    o.quiet = a.flag("quiet");
    o.skip = a.all("skip");
    for key in o.with.iter().chain(&o.without).chain(&o.skip) {
        crate::parameters::effect(key.split('=').next().unwrap_or(key)).map_err(Failure::Usage)?;
    }
    Ok(o)
}

fn run_generate(args: &[String]) -> Result<(), Failure> {
    let a = parse(
        args,
        &[
            "out", "truth", "effect", "set", "seed", "input", "duration", "rate", "control", "lowpass", "noise",
            "sensor", "road", "speed",
        ],
        &["displacement", "minimal", "errors-in-variables", "tare-load-cell", "raw-load-cell", "quiet"],
    )
    .map_err(Failure::Usage)?;
    if let Some(p) = a.positional.first() {
        return Err(Failure::Usage(format!("generate takes no positional argument ('{p}'); use --out FILE.csv")));
    }
    let out =
        a.one("out").map_err(Failure::Usage)?.ok_or_else(|| Failure::Usage("generate needs --out FILE.csv".into()))?;
    let truth = a
        .one("truth")
        .map_err(Failure::Usage)?
        .ok_or_else(|| Failure::Usage("generate needs --truth TRUTH.json (the truth goes to its own file)".into()))?;
    let mut o = GenerateOptions::new(out, truth);
    o.effects = a.all("effect");
    for e in &o.effects {
        crate::parameters::effect(e.split('=').next().unwrap_or(e)).map_err(Failure::Usage)?;
    }
    o.sets =
        a.all("set").iter().map(|s| parse_assignment(s, "--set")).collect::<Result<_, _>>().map_err(Failure::Usage)?;
    if let Some(s) = a.one("seed").map_err(Failure::Usage)? {
        o.seed = s.parse().map_err(|_| Failure::Usage(format!("--seed {s}: not a non-negative integer")))?;
    }
    if let Some(s) = a.one("input").map_err(Failure::Usage)? {
        o.input = match s.as_str() {
            "rig" => InputStyle::Rig,
            "hil" => InputStyle::Hil,
            _ => return Err(Failure::Usage(format!("--input {s}: use rig or hil"))),
        };
    }
    if let Some(d) = a.number("duration").map_err(Failure::Usage)? {
        o.duration = d;
    }
    if let Some(r) = a.number("rate").map_err(Failure::Usage)? {
        o.rate = r;
    }
    if let Some(c) = a.one("control").map_err(Failure::Usage)? {
        o.spool_control = match c.as_str() {
            "force" => false,
            "spool" => true,
            _ => return Err(Failure::Usage(format!("--control {c}: use force or spool"))),
        };
    }
    if let Some(l) = a.one("lowpass").map_err(Failure::Usage)? {
        o.lowpass_hz = if l == "off" || l == "none" {
            None
        } else {
            Some(l.parse().map_err(|_| Failure::Usage(format!("--lowpass {l}: a frequency in Hz, or off")))?)
        };
    }
    if let Some(k) = a.number("noise").map_err(Failure::Usage)? {
        if k.is_nan() || k < 0.0 {
            return Err(Failure::Usage(format!("--noise {k}: must be ≥ 0")));
        }
        o.noise = Noise::default().scaled(k);
    }
    for text in a.all("sensor") {
        o.noise.set(&text).map_err(Failure::Usage)?;
    }
    match (a.flag("tare-load-cell"), a.flag("raw-load-cell")) {
        (true, true) => return Err(Failure::Usage("--tare-load-cell and --raw-load-cell contradict".into())),
        (true, false) => o.tare_load_cell = Some(true),
        (false, true) => o.tare_load_cell = Some(false),
        _ => {}
    }
    if let Some(r) = a.one("road").map_err(Failure::Usage)? {
        o.road = r;
    }
    if let Some(s) = a.number("speed").map_err(Failure::Usage)? {
        o.speed = s;
    }
    o.displacement = a.flag("displacement");
    o.minimal = a.flag("minimal");
    o.errors_in_variables = a.flag("errors-in-variables");
    o.quiet = a.flag("quiet");
    generate::run(&o).map(|_| ()).map_err(Failure::Data)
}
