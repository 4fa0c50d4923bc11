//! Real-time factor of the damper at a 1 ms communication step (one core), worst-case doStep time,
//! and the force error against a converged run (rtol 1e-9, steps ≤ 5 µs), for several tolerances
//! `rtol` and step limits `h_max`. Run: `cargo bench --bench realtime` (release build).
//!
//! Input: 10 s of random velocity (a sum of 12 sines, 0.5–15 Hz, random phases, ≈0.25 m/s rms,
//! stroke within ±60 mm) with a force demand stepping every 100 ms to a random level of 1–20 kN
//! in the direction that resists the motion.

use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::variables::default_parameters;
use std::time::Instant;

const H: f64 = 1e-3;
const T_END: f64 = 10.0;

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

struct Run {
    force: Vec<f64>,
    seconds: f64,
    worst_step: f64,
}

fn run(h_max: f64, rtol: f64, inputs: &[(f64, f64)]) -> Run {
    let mut p = default_parameters();
    p.h_max = h_max;
    p.rtol = rtol;
    let mut d = Damper::new(p, Inputs::default(), 0.0).unwrap();
    let mut force = Vec::with_capacity(inputs.len());
    let mut worst: f64 = 0.0;
    let start = Instant::now();
    for &(v, f) in inputs {
        d.inputs.v_damper = v;
        d.inputs.force_demand = f;
        let t0 = Instant::now();
        d.do_step(H).expect("step");
        worst = worst.max(t0.elapsed().as_secs_f64());
        force.push(d.outputs().plant.force);
    }
    Run { force, seconds: start.elapsed().as_secs_f64(), worst_step: worst }
}

fn rms(x: impl Iterator<Item = f64>) -> f64 {
    let (s, n) = x.fold((0.0, 0usize), |(s, n), v| (s + v * v, n + 1));
    (s / n as f64).sqrt()
}

fn main() {
    let inputs = scenario(7);
    let v_rms = rms(inputs.iter().map(|x| x.0));
    let converged = run(5e-6, 1e-9, &inputs);
    let f_rms = rms(converged.force.iter().copied());
    println!(
        "scenario: {T_END} s, v_rms {v_rms:.3} m/s, converged F_rms {:.2} kN (h_max 5 us, rtol 1e-9)",
        f_rms / 1e3
    );
    println!("| rtol | h_max [us] | real-time factor | mean doStep [us] | worst doStep [us] | RMS force error [N] | error / F_rms |");
    println!("|---|---|---|---|---|---|---|");
    for (rtol, h_max) in
        [(1e-2, 500e-6), (3e-3, 500e-6), (1e-3, 500e-6), (3e-4, 500e-6), (1e-4, 500e-6), (5e-5, 500e-6), (3e-5, 500e-6)]
    {
        let best = (0..3).map(|_| run(h_max, rtol, &inputs)).min_by(|a, b| a.seconds.total_cmp(&b.seconds)).unwrap();
        let err = rms(best.force.iter().zip(&converged.force).map(|(a, b)| a - b));
        println!(
            "| {:.0e} | {:.0} | {:.0}x | {:.2} | {:.1} | {:.1} | {:.2} % |",
            rtol,
            h_max * 1e6,
            T_END / best.seconds,
            best.seconds / inputs.len() as f64 * 1e6,
            best.worst_step * 1e6,
            err,
            100.0 * err / f_rms
        );
    }
}
