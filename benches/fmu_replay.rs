//! The damper FMU's own time on a recorded input: the packaged `.fmu` loaded by rust-fmi's importer
//! (dlopen, as a master loads it), its inputs replayed from a CSV at each communication point
//! (fmi2SetReal of the columns, fmi2DoStep, fmi2GetReal of F_damper), nothing else in the loop.
//! What a master adds to a coupled run is measured against this (`damper_tools.coupled_benchmark`).
//!
//! ```text
//! cargo bench --bench fmu_replay -- target/fmu/SemiActiveDamper.fmu inputs.csv [--step 1e-3]
//!     [--repeat 10] [--set tare_load_cell=true]…
//! ```
//!
//! The CSV has a header of the damper's Real input names (v_damper, F_demand, a_damper), one row per
//! communication point. Each repetition is timed whole, as a master runs a record: instantiation,
//! initialisation, the steps and fmi2Terminate (a coupled run's time is timed the same way). Prints
//! one JSON line: the fastest of the repetitions (s), their median, the steps, and a hash of the
//! forces (the same bits from run to run).

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use semi_active_damper::model_description::{BooleanVar, RealVar};
use std::path::PathBuf;
use std::time::Instant;

struct Options {
    fmu: PathBuf,
    inputs: PathBuf,
    step: f64,
    repeat: usize,
    booleans: Vec<(BooleanVar, bool)>,
    reals: Vec<(RealVar, f64)>,
}

fn usage(why: &str) -> ! {
    eprintln!("fmu_replay: {why}\nusage: fmu_replay FMU INPUTS.csv [--step S] [--repeat N] [--set name=value]…");
    std::process::exit(2)
}

fn parse_set(arg: &str, o: &mut Options) {
    let (name, value) = arg.split_once('=').unwrap_or_else(|| usage(&format!("--set {arg}: no '='")));
    if let Some(v) = BooleanVar::ALL.iter().find(|v| v.name() == name) {
        let b = value.parse().unwrap_or_else(|_| usage(&format!("--set {arg}: not true or false")));
        o.booleans.push((*v, b));
    } else if let Some(v) = RealVar::ALL.iter().find(|v| v.name() == name) {
        let x = value.parse().unwrap_or_else(|_| usage(&format!("--set {arg}: not a number")));
        o.reals.push((*v, x));
    } else {
        usage(&format!("--set {arg}: the damper has no Boolean or Real {name}"))
    }
}

fn options() -> Options {
    // cargo bench passes --bench; the rest is ours
    let args: Vec<String> = std::env::args().skip(1).filter(|a| a != "--bench").collect();
    let mut it = args.iter();
    let mut positional = Vec::new();
    let mut o = Options {
        fmu: PathBuf::new(),
        inputs: PathBuf::new(),
        step: 1e-3,
        repeat: 10,
        booleans: Vec::new(),
        reals: Vec::new(),
    };
    while let Some(a) = it.next() {
        let mut value = |flag: &str| it.next().cloned().unwrap_or_else(|| usage(&format!("{flag} needs a value")));
        match a.as_str() {
            "--step" => o.step = value("--step").parse().unwrap_or_else(|_| usage("--step: not a number")),
            "--repeat" => o.repeat = value("--repeat").parse().unwrap_or_else(|_| usage("--repeat: not a count")),
            "--set" => parse_set(&value("--set"), &mut o),
            _ => positional.push(PathBuf::from(a)),
        }
    }
    match <[PathBuf; 2]>::try_from(positional) {
        Ok([fmu, inputs]) => (o.fmu, o.inputs) = (fmu, inputs),
        Err(_) => usage("need the FMU and the inputs' CSV"),
    }
    o
}

/// The inputs' value references and their rows, from the CSV (an error names the line).
fn read_inputs(path: &PathBuf) -> (Vec<u32>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| usage(&format!("{}: {e}", path.display())));
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_else(|| usage(&format!("{}: empty", path.display())));
    let vrs = header
        .split(',')
        .map(|name| {
            let name = name.trim();
            RealVar::ALL
                .iter()
                .find(|v| v.name() == name)
                .map(|v| v.vr())
                .unwrap_or_else(|| usage(&format!("{}:1: the damper has no Real input {name}", path.display())))
        })
        .collect::<Vec<_>>();
    let rows = lines
        .enumerate()
        .map(|(i, line)| {
            let row: Vec<f64> = line
                .split(',')
                .map(|x| x.trim().parse().unwrap_or_else(|_| usage(&format!("{}:{}: {x:?}", path.display(), i + 2))))
                .collect();
            if row.len() != vrs.len() {
                usage(&format!("{}:{}: {} values, {} columns", path.display(), i + 2, row.len(), vrs.len()));
            }
            row
        })
        .collect();
    (vrs, rows)
}

/// One run from a fresh instance to its termination: its seconds and the forces' hash.
fn run(import: &Fmi2Import, o: &Options, vrs: &[u32], rows: &[Vec<f64>]) -> (f64, u64) {
    let start = Instant::now();
    let mut fmu = import.instantiate_cs("fmu_replay", false, false).expect("instantiate");
    fmu.setup_experiment(None, 0.0, None).expect("setup");
    fmu.enter_initialization_mode().expect("enter initialisation");
    for &(v, b) in &o.booleans {
        fmu.set_boolean(&[v.vr()], &[i32::from(b)]).expect("set a Boolean");
    }
    for &(v, x) in &o.reals {
        fmu.set_real(&[v.vr()], &[x]).expect("set a Real");
    }
    fmu.exit_initialization_mode().expect("exit initialisation");
    let f_out = [RealVar::FDamper.vr()];
    let (mut force, mut hash) = ([0.0], 0u64);
    for (k, row) in rows.iter().enumerate() {
        fmu.set_real(vrs, row).expect("set the inputs");
        fmu.do_step(k as f64 * o.step, o.step, true).expect("step");
        fmu.get_real(&f_out, &mut force).expect("get F_damper");
        hash = hash.rotate_left(5) ^ force[0].to_bits();
    }
    fmu.terminate().expect("terminate");
    (start.elapsed().as_secs_f64(), hash)
}

fn main() {
    let o = options();
    let (vrs, rows) = read_inputs(&o.inputs);
    let import: Fmi2Import =
        fmi::import::from_path(&o.fmu).unwrap_or_else(|e| usage(&format!("{}: {e}", o.fmu.display())));
    let mut times = Vec::new();
    let mut hashes = Vec::new();
    for _ in 0..o.repeat.max(1) {
        let (t, h) = run(&import, &o, &vrs, &rows);
        times.push(t);
        hashes.push(h);
    }
    times.sort_by(f64::total_cmp);
    assert!(hashes.windows(2).all(|w| w[0] == w[1]), "the forces differ from run to run");
    println!(
        "{{\"fastest_s\": {:.6}, \"median_s\": {:.6}, \"steps\": {}, \"forces_hash\": \"{:016x}\"}}",
        times[0],
        times[times.len() / 2],
        rows.len(),
        hashes[0]
    );
}
