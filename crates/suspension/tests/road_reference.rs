//! The Rust road source (src/road.rs) against numpy: the reference values in tests/data/ are
//! written by tests/data/make_road_reference.py (its docstring says what each file holds).
//!
//! The random numbers must agree bit for bit; the profiles within 1e-13 of their RMS (src/fft.rs
//! is not pocketfft: the FFTs round differently); the time series on numpy's own profile bit for
//! bit where no cosine of the fade enters, and within rounding of the cosine where one does.

use std::collections::BTreeMap;
use std::path::PathBuf;
use suspension::road::{Iso8608, Pcg64, Profile, Road, RoadParameters, SeedSequence, Travel};

/// The largest error of a profile or time series allowed, relative to its RMS.
const RELATIVE: f64 = 1e-13;

/// The rows of a reference CSV (after its comment line and header), as text fields, with the
/// header checked.
fn read(name: &str, header: &str) -> Vec<Vec<String>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().filter(|line| !line.starts_with('#'));
    assert_eq!(lines.next(), Some(header), "{name}: header");
    lines.map(|line| line.split(',').map(str::to_owned).collect()).collect()
}

fn f(field: &str) -> f64 {
    field.parse().unwrap_or_else(|e| panic!("{field:?}: {e}"))
}

fn u(field: &str) -> u64 {
    field.parse().unwrap_or_else(|e| panic!("{field:?}: {e}"))
}

fn rms(values: &[f64]) -> f64 {
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

/// max |a − b| over max(RMS of b, tiny).
fn relative_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let worst = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    worst / rms(b).max(f64::MIN_POSITIVE)
}

struct ProfileCase {
    length: f64,
    spectrum: Iso8608,
    seed: u64,
    dx: f64,
    n_samples: usize,
    stride: usize,
    rms: f64,
    /// numpy's z at i = 0, stride, 2·stride, …
    z: Vec<f64>,
}

fn profile_cases() -> Vec<ProfileCase> {
    let header = "case,length,gd0,seed,dx,w,n_min,n_max,n0,n_samples,stride,rms";
    let mut cases: Vec<ProfileCase> = read("road_profile_cases.csv", header)
        .iter()
        .enumerate()
        .map(|(i, r)| {
            assert_eq!(u(&r[0]), i as u64);
            let spectrum =
                Iso8608 { gd0: f(&r[2]), waviness: f(&r[5]), n_min: f(&r[6]), n_max: f(&r[7]), n0: f(&r[8]) };
            let (n_samples, stride) = (u(&r[9]) as usize, u(&r[10]) as usize);
            ProfileCase {
                length: f(&r[1]),
                spectrum,
                seed: u(&r[3]),
                dx: f(&r[4]),
                n_samples,
                stride,
                rms: f(&r[11]),
                z: vec![],
            }
        })
        .collect();
    for r in read("road_profiles.csv", "case,i,z") {
        let case = &mut cases[u(&r[0]) as usize];
        assert_eq!(u(&r[1]) as usize, case.z.len() * case.stride, "road_profiles.csv: rows in order");
        case.z.push(f(&r[2]));
    }
    cases
}

#[test]
fn seed_sequence_words_are_numpys() {
    let rows = read("road_seeds.csv", "seed,w0,w1,w2,w3,w4,w5,w6,w7");
    assert!(rows.len() >= 10);
    for r in rows {
        let numpy: Vec<u32> = r[1..].iter().map(|w| u(w) as u32).collect();
        assert_eq!(SeedSequence::new(u(&r[0])).generate_state::<8>().to_vec(), numpy, "seed {}", r[0]);
    }
}

#[test]
fn pcg64_draws_are_numpys_bit_for_bit() {
    let mut by_seed: BTreeMap<u64, Vec<Vec<String>>> = BTreeMap::new();
    for r in read("road_rng.csv", "seed,index,raw,uniform_0_2pi,uniform_m1p5_2p5") {
        by_seed.entry(u(&r[0])).or_default().push(r);
    }
    assert!(by_seed.len() >= 10);
    for (seed, rows) in by_seed {
        let (mut raw, mut phases, mut other) = (Pcg64::new(seed), Pcg64::new(seed), Pcg64::new(seed));
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(u(&r[1]), i as u64);
            assert_eq!(raw.next_u64(), u(&r[2]), "seed {seed}, draw {i}: random_raw");
            let phase = phases.uniform(0.0, 2.0 * std::f64::consts::PI).unwrap();
            assert_eq!(phase.to_bits(), f(&r[3]).to_bits(), "seed {seed}, draw {i}: uniform(0, 2π)");
            let value = other.uniform(-1.5, 2.5).unwrap();
            assert_eq!(value.to_bits(), f(&r[4]).to_bits(), "seed {seed}, draw {i}: uniform(-1.5, 2.5)");
        }
    }
}

#[test]
fn profiles_agree_with_numpys_to_rounding() {
    for (i, case) in profile_cases().iter().enumerate() {
        let profile = case.spectrum.profile(case.length, case.dx, case.seed).unwrap();
        assert_eq!(profile.heights().len(), case.n_samples, "case {i}: ceil(length/dx) + 1 samples");
        let ours: Vec<f64> = profile.heights().iter().step_by(case.stride).copied().collect();
        assert!((rms(&case.z) - case.rms).abs() <= 1e-12 * case.rms || case.stride > 1, "case {i}: stored RMS");
        let error = relative_error(&ours, &case.z);
        eprintln!("profile case {i}: {} samples, max |z − z_numpy| = {error:.2e} of the RMS", case.n_samples);
        assert!(error <= RELATIVE, "case {i}: max |z − z_numpy| = {error:.3e} of the RMS");
    }
}

struct SeriesCase {
    profile: usize,
    speed: f64,
    step: f64,
    n_steps: u64,
    fade_in: f64,
    offset: f64,
    stride: u64,
    /// numpy's (k, z_road, v_road)
    rows: Vec<(u64, f64, f64)>,
}

fn series_cases() -> Vec<SeriesCase> {
    let header = "case,profile,speed,step,n_steps,fade_in,offset,stride";
    let mut cases: Vec<SeriesCase> = read("road_series_cases.csv", header)
        .iter()
        .map(|r| SeriesCase {
            profile: u(&r[1]) as usize,
            speed: f(&r[2]),
            step: f(&r[3]),
            n_steps: u(&r[4]),
            fade_in: f(&r[5]),
            offset: f(&r[6]),
            stride: u(&r[7]),
            rows: vec![],
        })
        .collect();
    for r in read("road_series.csv", "case,k,z_road,v_road") {
        cases[u(&r[0]) as usize].rows.push((u(&r[1]), f(&r[2]), f(&r[3])));
    }
    cases
}

impl SeriesCase {
    fn travel(&self) -> Travel {
        Travel { speed: self.speed, offset: self.offset, fade_in: self.fade_in, fade_start: self.step }
    }

    /// Our (z_road, v_road) at the stored k; the last v_road repeats the one before, as numpy's.
    fn ours(&self, road: &Road) -> (Vec<f64>, Vec<f64>) {
        let (mut z, mut v) = (vec![], vec![]);
        for &(k, _, _) in &self.rows {
            z.push(road.z_at(k as f64 * self.step).unwrap());
            let k_rate = if k == self.n_steps { k - 1 } else { k };
            v.push(road.at_step(k_rate, self.step).unwrap().v_road);
        }
        assert_eq!(self.rows.len() as u64, self.n_steps / self.stride + 1);
        (z, v)
    }

    fn numpy(&self) -> (Vec<f64>, Vec<f64>) {
        (self.rows.iter().map(|r| r.1).collect(), self.rows.iter().map(|r| r.2).collect())
    }
}

#[test]
fn time_series_of_our_profiles_agree_with_numpys() {
    let profiles = profile_cases();
    for (i, case) in series_cases().iter().enumerate() {
        let p = &profiles[case.profile];
        let parameters = if case.offset == 0.0 && case.speed > 0.0 {
            // roads.road_case: the profile's length from the duration
            let duration = case.n_steps as f64 * case.step;
            let rc = RoadParameters::road_case(p.spectrum.gd0, case.speed, duration, p.seed, case.step, case.fade_in);
            rc.unwrap()
        } else {
            let s = p.spectrum;
            let t = case.travel();
            RoadParameters {
                gd0: s.gd0,
                seed: p.seed,
                speed: t.speed,
                length: p.length,
                dx: p.dx,
                waviness: s.waviness,
                n_min: s.n_min,
                n_max: s.n_max,
                n0: s.n0,
                fade_in: t.fade_in,
                fade_start: t.fade_start,
                offset: t.offset,
            }
        };
        assert_eq!(parameters.length, p.length, "series {i}: the length of the stored profile");
        assert_eq!(parameters.spectrum(), p.spectrum);
        let road = Road::new(&parameters).unwrap();
        let ((z, v), (z_np, v_np)) = (case.ours(&road), case.numpy());
        let (ez, ev) = (relative_error(&z, &z_np), relative_error(&v, &v_np));
        eprintln!("series {i}: max error of z_road {ez:.2e}, of v_road {ev:.2e} of their RMS");
        assert!(ez <= RELATIVE && ev <= RELATIVE, "series {i}: z_road {ez:.3e}, v_road {ev:.3e}");
    }
}

#[test]
fn time_series_on_numpys_profile_are_numpys_arithmetic() {
    let profiles = profile_cases();
    let mut compared = 0;
    for (i, case) in series_cases().iter().enumerate() {
        let p = &profiles[case.profile];
        if p.stride != 1 {
            continue; // numpy's profile is not stored whole
        }
        let road = Road::on_profile(Profile::new(p.dx, p.z.clone()).unwrap(), case.travel()).unwrap();
        let ((z, v), (z_np, v_np)) = (case.ours(&road), case.numpy());
        // whether the fade's cosine enters at t (s): 0 < ramp < 1
        let fading = |t: f64| case.fade_in > 0.0 && (t - case.step) > 0.0 && (t - case.step) < case.fade_in;
        let mut differ = 0;
        for (j, ((a, b), (c, d))) in z.iter().zip(&z_np).zip(v.iter().zip(&v_np)).enumerate() {
            if a.to_bits() == b.to_bits() && c.to_bits() == d.to_bits() {
                continue;
            }
            // only the cosine of the fade may round otherwise than numpy's cos (glibc's or its SIMD one)
            let k = case.rows[j].0 as f64;
            let near_fade = [k - 1.0, k, k + 1.0].iter().any(|&k| fading(k * case.step));
            assert!(near_fade, "series {i}, k {k}: z_road {a} ≠ {b} or v_road {c} ≠ {d} outside the fade");
            // a cosine one ulp (≤ ε/2) off moves z_road by ≤ ½·ε/2·|z| (z before the fade): allow two,
            // and the rounding of the products
            let unfaded = road.profile().interpolate(case.travel().distance(k * case.step)).abs();
            let bound = 0.5 * f64::EPSILON * unfaded + 2.0 * f64::EPSILON * b.abs();
            assert!((a - b).abs() <= bound, "series {i}, k {k}: z_road {a} ≠ {b} (bound {bound:e})");
            differ += 1;
        }
        let ev = relative_error(&v, &v_np);
        eprintln!(
            "series {i} on numpy's profile: {differ} of {} samples differ (v_road: {ev:.2e} of its RMS)",
            z.len()
        );
        assert!(ev <= RELATIVE, "series {i}: v_road {ev:.3e}");
        compared += 1;
    }
    assert!(compared >= 3);
}
