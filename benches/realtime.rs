//! Speed and accuracy of the damper, side by side: for each tolerance `rtol`, the real-time factor
//! at a 1 ms communication step on one core, the time of each `do_step` (mean, 99th percentile,
//! worst as run, and the damper's own worst: its costliest steps replayed without the machine's
//! interruptions), the page faults in the loop, and the RMS force error against a converged run (rtol
//! 1e-9, steps ≤ 5 µs), in newtons, in % of the RMS force and in sigmas of the rig's load cell
//! (20 N); then the same input through the FMU's C API, in process, as a master calls it, against
//! the damper called directly; then six dampers (a full truck), each on its own input: run one by
//! one (the sum of their times), stepped in lockstep in one thread, and on two threads; last, the
//! RMS force error at the default and the diagnosis tolerance over twelve inputs of the same kind
//! (seeds 1–12), so that one input's luck does not stand for the tolerance.
//! Run: `cargo bench --bench realtime` (release build; `scripts/benchmark.sh` runs it with the
//! Python cross-check and a diagnosis, docs/performance.md has the results);
//! `cargo bench --bench realtime -- quick [rtol]` prints one line for one tolerance ([`quick`]);
//! `-- accuracy [rtol…]` the twelve inputs' errors alone ([`accuracy`]).
//!
//! Input: 10 s of random velocity (a sum of 12 sines, 0.5–15 Hz, random phases, ≈0.25 m/s rms,
//! stroke within ±60 mm) with a force demand stepping every 100 ms to a random level of 1–20 kN
//! in the direction that resists the motion.
#![allow(
    clippy::disallowed_methods,
    reason = "the benchmark's input signal; the model it drives takes its math from libm"
)]
// The C API's row calls the FMU's exported functions in process through the tests' importer
// (tests/common), whose raw pointers need unsafe code: the crate denies it (Cargo.toml).
#![allow(unsafe_code)]
#[path = "../tests/common/mod.rs"]
mod common;

use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::physics::params::Parameters;
use std::time::Instant;

const H: f64 = 1e-3;
const T_END: f64 = 10.0;
/// The rig load cell's noise (N), as `damper generate` models it.
const LOAD_CELL_SIGMA: f64 = 20.0;
/// The FMU's default tolerance and the diagnosis's (`ANALYSIS_RTOL`).
const DEFAULT_RTOL: f64 = 3e-4;
const DIAGNOSIS_RTOL: f64 = 3e-5;

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn scenario(seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Lcg(seed);
    let sines: Vec<(f64, f64, f64)> = (0..12)
        .map(|k| {
            let f = 0.5 * (30.0f64).powf(k as f64 / 11.0); // 0.5 … 15 Hz
            let w = 2.0 * std::f64::consts::PI * f;
            let amp_x = (0.010 / (1.0 + f / 3.0)).min(0.2 / w); // stroke amplitude [m]
            (w, amp_x, 2.0 * std::f64::consts::PI * rng.next())
        })
        .collect();
    let n = (T_END / H).round() as usize;
    let mut level = 5e3;
    (0..n)
        .map(|k| {
            let t = k as f64 * H;
            if k % 100 == 0 {
                level = 1e3 + 19e3 * rng.next();
            }
            let v: f64 = sines.iter().map(|(w, a, ph)| a * w * (w * t + ph).cos()).sum();
            (v, level * v.signum())
        })
        .collect()
}

fn damper(rtol: f64, h_max: f64) -> Damper {
    let p = Parameters { h_max, rtol, ..Default::default() };
    Damper::new(p, Inputs::default(), 0.0).unwrap()
}

fn step(d: &mut Damper, input: (f64, f64)) -> f64 {
    step_counted(d, input).0
}

/// [`step`], with the number of Rosenbrock steps the communication step took.
fn step_counted(d: &mut Damper, (v, f): (f64, f64)) -> (f64, u32) {
    d.inputs.v_damper = v;
    d.inputs.f_demand = f;
    let stats = d.do_step(H).expect("step");
    // what a master reading F_damper gets (the FMU's fmi2GetReal computes the load cell alone)
    (d.load_cell(), stats.substeps)
}

/// Minor and major page faults of this process so far (/proc/self/stat fields 10 and 12).
fn page_faults() -> u64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap_or("").split_whitespace().collect();
    [7, 9].iter().filter_map(|&i| fields.get(i)?.parse::<u64>().ok()).sum()
}

struct Run {
    force: Vec<f64>,
    seconds: f64,
    step_us: Vec<f64>,
    /// Rosenbrock steps per communication step.
    substeps: Vec<u32>,
    faults: u64,
}

fn run(rtol: f64, h_max: f64, inputs: &[(f64, f64)]) -> Run {
    let mut d = damper(rtol, h_max);
    // filled (not zero: calloc may leave fresh pages untouched) before the loop, so that the first
    // touch of their pages is not counted as the loop's
    let mut force = vec![f64::NAN; inputs.len()];
    let mut step_us = vec![f64::NAN; inputs.len()];
    let mut substeps = vec![u32::MAX; inputs.len()];
    let faults = page_faults();
    let start = Instant::now();
    for (k, &input) in inputs.iter().enumerate() {
        let t0 = Instant::now();
        (force[k], substeps[k]) = step_counted(&mut d, input);
        step_us[k] = t0.elapsed().as_secs_f64() * 1e6;
    }
    let seconds = start.elapsed().as_secs_f64();
    Run { force, seconds, step_us, substeps, faults: page_faults() - faults }
}

/// The damper's own worst step time (µs) in `measured`, without the machine's interruptions: the
/// 20 steps that took longest as run and the 20 with the most Rosenbrock steps, each replayed 50
/// times from a copy of the damper's state before it; the largest of their fastest replays. A
/// step's work is the same on every replay (the damper is deterministic), so the fastest replay
/// is its cost, and a step that was slow as run only because the host interrupted it shows that.
fn replayed_worst(rtol: f64, h_max: f64, inputs: &[(f64, f64)], measured: &Run) -> f64 {
    let mut by_time: Vec<usize> = (0..inputs.len()).collect();
    by_time.sort_by(|&a, &b| measured.step_us[b].total_cmp(&measured.step_us[a]));
    let mut by_work: Vec<usize> = (0..inputs.len()).collect();
    by_work.sort_by_key(|&k| std::cmp::Reverse(measured.substeps[k]));
    let mut candidates: Vec<usize> = by_time[..20].iter().chain(&by_work[..20]).copied().collect();
    candidates.sort_unstable();
    candidates.dedup();
    let mut d = damper(rtol, h_max);
    let mut worst = 0.0f64;
    let mut k = 0;
    for &candidate in &candidates {
        while k < candidate {
            step(&mut d, inputs[k]);
            k += 1;
        }
        let fastest = (0..50)
            .map(|_| {
                let mut replay = d.clone();
                let t0 = Instant::now();
                step(&mut replay, inputs[k]);
                t0.elapsed().as_secs_f64() * 1e6
            })
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(fastest);
    }
    worst
}

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = x.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (s / n as f64).sqrt()
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// Six dampers (one per wheel of a three-axle truck), each on its own input, stepped in lockstep;
/// `threads` threads share them. Returns the real-time factor of the whole truck.
fn six(rtol: f64, inputs: &[Vec<(f64, f64)>], threads: usize) -> f64 {
    let mut dampers: Vec<Damper> = (0..6).map(|_| damper(rtol, 500e-6)).collect();
    let start = Instant::now();
    std::thread::scope(|s| {
        for (chunk, ins) in dampers.chunks_mut(6 / threads).zip(inputs.chunks(6 / threads)) {
            s.spawn(move || {
                for k in 0..ins[0].len() {
                    for (d, input) in chunk.iter_mut().zip(ins) {
                        step(d, input[k]);
                    }
                }
            });
        }
    });
    T_END / start.elapsed().as_secs_f64()
}

/// The benchmark's input through the FMU's C API, in process, at the FMU's default tolerance, as an
/// importer calls it at each communication point: fmi2SetReal for the velocity and for the demand,
/// fmi2DoStep, fmi2GetReal for the force. Returns the seconds of the loop and the forces.
fn through_c_api(inputs: &[(f64, f64)]) -> (f64, Vec<f64>) {
    use semi_active_damper::model_description::RealVar;
    let fmu = common::Fmu::initialised("realtime", |_| {});
    let mut force = vec![f64::NAN; inputs.len()];
    let start = Instant::now();
    for (k, &(v, demand)) in inputs.iter().enumerate() {
        let statuses = [fmu.set(RealVar::VDamper, v), fmu.set(RealVar::FDemand, demand), fmu.step(k as f64 * H, H)];
        assert!(statuses.iter().all(|&s| s == common::OK), "step {k}: {statuses:?}");
        force[k] = fmu.get(RealVar::FDamper);
    }
    (start.elapsed().as_secs_f64(), force)
}

/// `quick [rtol]`: the benchmark's input at one tolerance (default: the FMU's), the fastest of 20 runs,
/// without the per-step timing, and a hash of every force: one line, for comparing two builds
/// (`scripts/compare_builds.py` alternates them, process by process).
fn quick(rtol: f64) {
    let inputs = scenario(7);
    let mut hash = 0u64;
    let fastest = (0..20)
        .map(|_| {
            let mut d = damper(rtol, 500e-6);
            hash = 0;
            let start = Instant::now();
            for &input in &inputs {
                hash = hash.rotate_left(5) ^ step(&mut d, input).to_bits();
            }
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min);
    println!("rtol {rtol:e}: {:.0}x real time, forces {hash:016x}", T_END / fastest);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(at) = args.iter().position(|a| a == "quick") {
        let rtol = args.get(at + 1).and_then(|r| r.parse().ok()).unwrap_or(DEFAULT_RTOL);
        return quick(rtol);
    }
    if let Some(at) = args.iter().position(|a| a == "accuracy") {
        let rtols: Vec<f64> = args[at + 1..].iter().filter_map(|r| r.parse().ok()).collect();
        return accuracy(if rtols.is_empty() { &[DEFAULT_RTOL, DIAGNOSIS_RTOL] } else { &rtols });
    }
    let inputs = scenario(7);
    let v_rms = rms(inputs.iter().map(|x| x.0));
    let converged = run(1e-9, 5e-6, &inputs);
    let f_rms = rms(converged.force.iter().copied());
    println!(
        "scenario: {T_END} s, v_rms {v_rms:.3} m/s, 1 ms steps; converged run (rtol 1e-9, h_max 5 us): F_rms {:.2} kN",
        f_rms / 1e3
    );
    println!();
    println!("| rtol | | real-time factor | mean doStep [us] | p99 [us] | worst as run [us] | worst replayed [us] | page faults | RMS force error [N] | % of F_rms | load-cell sigmas |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for rtol in [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 5e-5, 3e-5, 1e-5] {
        // the fastest of three: the machine's other work only ever adds time
        let best = (0..3).map(|_| run(rtol, 500e-6, &inputs)).min_by(|a, b| a.seconds.total_cmp(&b.seconds)).unwrap();
        let mut sorted = best.step_us.clone();
        sorted.sort_by(f64::total_cmp);
        let err = rms(best.force.iter().zip(&converged.force).map(|(a, b)| a - b));
        let role = match rtol {
            DEFAULT_RTOL => "FMU default",
            DIAGNOSIS_RTOL => "diagnosis",
            _ => "",
        };
        println!(
            "| {rtol:.0e} | {role} | {:.0}x | {:.2} | {:.1} | {:.1} | {:.1} | {} | {err:.1} | {:.3} % | {:.2} |",
            T_END / best.seconds,
            best.seconds / inputs.len() as f64 * 1e6,
            percentile(&sorted, 0.99),
            sorted[sorted.len() - 1],
            replayed_worst(rtol, 500e-6, &inputs, &best),
            best.faults,
            100.0 * err / f_rms,
            err / LOAD_CELL_SIGMA,
        );
    }
    println!();
    // the fastest of three, each against a direct run in the same minutes
    let (direct, api) = (0..3)
        .map(|_| (run(DEFAULT_RTOL, 500e-6, &inputs), through_c_api(&inputs)))
        .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
        .unwrap();
    println!(
        "Through the FMU's C API (in process; fmi2SetReal twice, fmi2DoStep, fmi2GetReal per step) at rtol {DEFAULT_RTOL:e}: \
         {:.0}x real time, {:.2} us per step against {:.2} us calling the damper directly; the same forces bit for bit: {}",
        T_END / api.0,
        api.0 / inputs.len() as f64 * 1e6,
        direct.seconds / inputs.len() as f64 * 1e6,
        if api.1.iter().zip(&direct.force).all(|(a, b)| a.to_bits() == b.to_bits()) { "yes" } else { "no" }
    );
    println!();
    let wheels: Vec<Vec<(f64, f64)>> = (0..6).map(|k| scenario(11 + k)).collect();
    println!("| rtol | one damper | the six run one by one | six dampers, one thread | six dampers, two threads |");
    println!("|---|---|---|---|---|");
    for rtol in [DEFAULT_RTOL, DIAGNOSIS_RTOL] {
        // the fastest of five: the machine's other work only ever adds time
        let alone: Vec<f64> =
            wheels.iter().map(|w| (0..5).map(|_| run(rtol, 500e-6, w).seconds).fold(f64::INFINITY, f64::min)).collect();
        let best = |threads| (0..5).map(|_| six(rtol, &wheels, threads)).fold(0.0, f64::max);
        println!(
            "| {rtol:.0e} | {:.0}x | {:.0}x | {:.0}x | {:.0}x |",
            T_END / alone[0],
            T_END / alone.iter().sum::<f64>(),
            best(1),
            best(2)
        );
    }
    println!();
    let references =
        (1..=12).map(|seed| if seed == 7 { converged.force.clone() } else { run(1e-9, 5e-6, &scenario(seed)).force });
    print_seed_spread(&[DEFAULT_RTOL, DIAGNOSIS_RTOL], &references.collect::<Vec<_>>());
}

/// The RMS force error over the twelve inputs of seeds 1–12, against their converged runs
/// (`references`), for each tolerance: least, median, largest.
fn print_seed_spread(rtols: &[f64], references: &[Vec<f64>]) {
    println!("| rtol | RMS force error over seeds 1-12 [N]: least | median | largest | largest in % of F_rms | largest in load-cell sigmas |");
    println!("|---|---|---|---|---|---|");
    for &rtol in rtols {
        // (error, RMS force) per seed
        let mut errors: Vec<(f64, f64)> = (1..=12)
            .zip(references)
            .map(|(seed, reference)| {
                let force = run(rtol, 500e-6, &scenario(seed)).force;
                (rms(force.iter().zip(reference).map(|(a, b)| a - b)), rms(reference.iter().copied()))
            })
            .collect();
        errors.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (largest, f_rms) = errors[errors.len() - 1];
        println!(
            "| {rtol:.0e} | {:.2} | {:.2} | {largest:.2} | {:.3} % | {:.2} |",
            errors[0].0,
            0.5 * (errors[(errors.len() - 1) / 2].0 + errors[errors.len() / 2].0),
            100.0 * largest / f_rms,
            largest / LOAD_CELL_SIGMA
        );
    }
}

/// `accuracy [rtol…]`: the twelve inputs' error table alone, for the tolerances given (default:
/// the FMU's and the diagnosis's), without the timing.
fn accuracy(rtols: &[f64]) {
    let references: Vec<Vec<f64>> = (1..=12).map(|seed| run(1e-9, 5e-6, &scenario(seed)).force).collect();
    print_seed_spread(rtols, &references);
}
