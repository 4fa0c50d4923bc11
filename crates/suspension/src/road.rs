//! A road source the truck FMUs can run themselves: the ISO 8608 random profile of
//! `python/damper_tools/roads.py` (`generate_profile`), driven over at a constant speed with its
//! raised-cosine fade-in (`time_series`, `road_case`), so that a master needs no Python to feed
//! the road sample by sample.
//!
//! ```text
//! G_d(n) = G_d(n0) (n/n0)^−w on n_min ≤ n ≤ n_max (cycle/m), 0 elsewhere
//! z = irfft(½ N √(2 G_d(n_k) Δn) e^{i φ_k}, N),  N = ⌈length/dx⌉ + 1,  n_k = k/(N dx),  Δn = 1/(N dx)
//! φ_k = numpy.random.default_rng(seed).uniform(0, 2π, N/2 + 1)   (every bin draws, in order)
//! z_road(t) = interp(offset + speed·t) · ½ (1 − cos(π·clip((t − fade_start)/fade_in, 0, 1)))
//! ```
//!
//! The parts, each with numpy's operations in numpy's order:
//!
//! - [`SeedSequence`] and [`Pcg64`]: numpy's `SeedSequence` (hashmix, pool of 4 words,
//!   `generate_state`) and its PCG64 (128-bit LCG, XSL-RR output) seeded as `PCG64.__init__` does;
//!   [`Pcg64::uniform`] is `Generator.uniform`, bit for bit;
//! - [`Iso8608`]: the spectrum and `generate_profile`; the inverse FFT is [`crate::fft`]'s (radix-2,
//!   Bluestein's for other lengths), not pocketfft's, so the profile agrees with numpy's to rounding
//!   (about 1e-15 of its RMS), not bit for bit;
//! - [`Profile::interpolate`]: `numpy.interp` on the profile's grid x_i = i·dx;
//! - [`Road`]: the road under the wheel at time t ([`Road::z_at`]), and its samples at the
//!   communication points ([`Road::segment`], [`Road::at_step`]) from which a truck extrapolates
//!   z_road + v_road·(t − t_k) over a step, as it does with a master's inputs.
//!
//! Allocation happens once, in [`Road::new`] (the profile, the FFT's buffers); [`Road::z_at`] and
//! the rest allocate nothing. A 25 m/s × 18 s road (451 m, 22 551 samples) keeps 180 kB; making it
//! takes about 5 ms and 3 MB at most, while the FFT runs (Bluestein's, through FFTs of 65 536).
//!
//! Determinism: the random numbers are integer arithmetic; the spectrum's cos, sin and pow and the
//! FFT's twiddles and chirp come from the `libm` crate, as the rest of the model's (clippy.toml),
//! not from the platform's C library, whose glibc and MinGW-w64 builds differ in the last bit; the
//! rest is IEEE arithmetic in an order fixed by the length alone, whatever the CPU. A road made here
//! has the same bits on Linux and on Windows (the test `profiles_are_the_same_bits_on_linux_and_windows`;
//! with rustfft's FFT, whose twiddles came from std's `cos` and `sin`, they differed by up to 2e-15
//! of the RMS).
//!
//! ```
//! use suspension::road::{Road, RoadParameters};
//! // roads.road_case("minor", 14, 2.0, seed=3): 28 m of ISO 8608 road at 14 m/s, a 1 s fade-in
//! let p = RoadParameters::road_case(128e-6, 14.0, 2.0, 3, 1e-3, 1.0).unwrap();
//! let road = Road::new(&p).unwrap();
//! assert_eq!(road.z_at(0.0).unwrap(), 0.0);
//! let s = road.segment(1.5, 1e-3).unwrap(); // z_road, v_road over [1.5, 1.501] s
//! assert!(s.z_road.abs() < 0.05 && s.v_road.is_finite());
//! assert!(road.z_at(2.1).is_err()); // off the 29 m profile: an error, not a wrap
//! ```

use crate::error::RoadError;
use crate::fft::{self, Complex};
use std::f64::consts::PI;

/// ISO 8608 reference spatial frequency n0 (cycle/m), roads.N0.
pub const N0: f64 = 0.1;
/// ISO 8608 exponent w (1), roads.WAVINESS.
pub const WAVINESS: f64 = 2.0;
/// roads.py's generation band (cycle/m): wavelengths of 100 m down to 0.1 m.
pub const N_MIN: f64 = 0.01;
pub const N_MAX: f64 = 10.0;
/// roads.py's spatial sample step (m).
pub const DX: f64 = 0.02;
/// Most samples a profile may have: 2²⁰ (21 km at dx = 0.02 m, 14 min at 25 m/s; the HiL runs need
/// 23 000). An FMU makes its road inside fmi2ExitInitializationMode, which a master expects back in
/// well under a second: just below this the FFT's buffers take about 100 MB and the profile about
/// 0.6 s (2²⁰ − 1 samples: Bluestein's through FFTs of 2²¹; 2²² − 1 took 2.6 s and 400 MB). An error
/// says so before anything is allocated.
pub const MAX_SAMPLES: usize = 1 << 20;
/// roads.time_series's tolerances (m) at the profile's start and end: a wheel within them is on it.
const START_TOLERANCE: f64 = 1e-12;
const END_TOLERANCE: f64 = 1e-9;

// --------------------------------------------------------------------------- numpy's random numbers

const POOL_SIZE: usize = 4;
const INIT_A: u32 = 0x43b0_d7e5;
const MULT_A: u32 = 0x931e_8875;
const INIT_B: u32 = 0x8b51_f9dd;
const MULT_B: u32 = 0x58f3_8ded;
const MIX_MULT_L: u32 = 0xca01_f9dd;
const MIX_MULT_R: u32 = 0x4973_f715;
const XSHIFT: u32 = 16;

/// numpy.random.SeedSequence of a non-negative integer entropy, with the default pool of four
/// 32-bit words and no spawn key (what `default_rng(seed)` builds): the entropy's words are hashed
/// into the pool and mixed (`mix_entropy`), and [`SeedSequence::generate_state`] hashes the pool
/// out again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SeedSequence {
    pool: [u32; POOL_SIZE],
}

impl SeedSequence {
    /// The sequence of the integer `entropy`: numpy splits it into 32-bit words, lowest first, one
    /// word for 0 .. 2³² − 1 (0 included), two above.
    pub fn new(entropy: u64) -> Self {
        let (low, high) = (entropy as u32, (entropy >> 32) as u32);
        if high == 0 {
            Self::from_words(&[low])
        } else {
            Self::from_words(&[low, high])
        }
    }

    /// The sequence of entropy given as numpy's assembled uint32 words (lowest first).
    pub fn from_words(entropy: &[u32]) -> Self {
        let mut hash_const = INIT_A;
        let mut pool = [0u32; POOL_SIZE];
        // the entropy up to the pool's size; a shorter entropy runs the hash on zeros
        for (i, word) in pool.iter_mut().enumerate() {
            *word = hashmix(entropy.get(i).copied().unwrap_or(0), &mut hash_const);
        }
        // every word into every other, so that late words reach early ones
        for src in 0..POOL_SIZE {
            for dst in (0..POOL_SIZE).filter(|&dst| dst != src) {
                pool[dst] = mix(pool[dst], hashmix(pool[src], &mut hash_const));
            }
        }
        // entropy beyond the pool's size, each word into every pool word
        for &extra in entropy.iter().skip(POOL_SIZE) {
            for word in pool.iter_mut() {
                *word = mix(*word, hashmix(extra, &mut hash_const));
            }
        }
        Self { pool }
    }

    /// The mixed pool (numpy's `SeedSequence.pool`).
    pub fn pool(&self) -> [u32; POOL_SIZE] {
        self.pool
    }

    /// `generate_state(N)`: N words (uint32) hashed from the pool, cycled.
    pub fn generate_state<const N: usize>(&self) -> [u32; N] {
        let mut out = [0u32; N];
        for (word, value) in out.iter_mut().zip(self.words()) {
            *word = value;
        }
        out
    }

    /// `generate_state(N, np.uint64)`: 2N words, read in pairs as little-endian 64-bit words.
    pub fn generate_state_u64<const N: usize>(&self) -> [u64; N] {
        let mut words = self.words();
        let mut out = [0u64; N];
        for word in out.iter_mut() {
            let (low, high) = (words.next().unwrap_or(0), words.next().unwrap_or(0));
            *word = u64::from(low) | (u64::from(high) << 32);
        }
        out
    }

    /// The endless stream generate_state takes its words from.
    fn words(&self) -> impl Iterator<Item = u32> + '_ {
        let mut hash_const = INIT_B;
        self.pool.iter().cycle().map(move |&word| {
            let mut value = word ^ hash_const;
            hash_const = hash_const.wrapping_mul(MULT_B);
            value = value.wrapping_mul(hash_const);
            value ^ (value >> XSHIFT)
        })
    }
}

/// SeedSequence's hash of one word; the multiplier moves on with every call.
fn hashmix(value: u32, hash_const: &mut u32) -> u32 {
    let mut value = value ^ *hash_const;
    *hash_const = hash_const.wrapping_mul(MULT_A);
    value = value.wrapping_mul(*hash_const);
    value ^ (value >> XSHIFT)
}

/// SeedSequence's mix of two words.
fn mix(x: u32, y: u32) -> u32 {
    let result = MIX_MULT_L.wrapping_mul(x).wrapping_sub(MIX_MULT_R.wrapping_mul(y));
    result ^ (result >> XSHIFT)
}

/// PCG's 128-bit multiplier (PCG_DEFAULT_MULTIPLIER_128).
const PCG_MULTIPLIER: u128 = (2_549_297_995_355_413_924 << 64) + 4_865_540_595_714_422_341;

/// numpy's PCG64 (`pcg_setseq_128_xsl_rr_64`): the state steps as an LCG modulo 2¹²⁸ with an odd
/// increment, and each output is the xor of its halves rotated by its top 6 bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pcg64 {
    state: u128,
    increment: u128,
}

impl Pcg64 {
    /// The generator of `numpy.random.default_rng(seed)` (and of `numpy.random.PCG64(seed)`).
    pub fn new(seed: u64) -> Self {
        Self::from_seed_sequence(&SeedSequence::new(seed))
    }

    /// Seeded as `PCG64.__init__` does: `generate_state(4, uint64)` gives the initial state (words
    /// 0, 1: high, low) and the stream (words 2, 3), set as `pcg_setseq_128_srandom_r` does.
    pub fn from_seed_sequence(seq: &SeedSequence) -> Self {
        let [state_high, state_low, stream_high, stream_low] = seq.generate_state_u64::<4>();
        let initial = (u128::from(state_high) << 64) | u128::from(state_low);
        let stream = (u128::from(stream_high) << 64) | u128::from(stream_low);
        let mut rng = Self { state: 0, increment: (stream << 1) | 1 };
        rng.step();
        rng.state = rng.state.wrapping_add(initial);
        rng.step();
        rng
    }

    fn step(&mut self) {
        self.state = self.state.wrapping_mul(PCG_MULTIPLIER).wrapping_add(self.increment);
    }

    /// The next 64 random bits (numpy's `next_uint64`, `PCG64.random_raw`): a step, then the
    /// output of the new state.
    pub fn next_u64(&mut self) -> u64 {
        self.step();
        let folded = ((self.state >> 64) as u64) ^ (self.state as u64);
        folded.rotate_right((self.state >> 122) as u32)
    }

    /// A double uniform on [0, 1) from the top 53 bits (numpy's `next_double`).
    pub fn next_double(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// `Generator.uniform(low, high)`: low + (high − low)·next_double. numpy's checks come first and
    /// draw nothing: high − low must be finite and not negative (−0.0 included).
    pub fn uniform(&mut self, low: f64, high: f64) -> Result<f64, RoadError> {
        let range = uniform_range(low, high)?;
        Ok(self.uniform_in(low, range))
    }

    /// `uniform` with its range checked already.
    fn uniform_in(&mut self, low: f64, range: f64) -> f64 {
        low + range * self.next_double()
    }
}

/// high − low for `Generator.uniform`, or why numpy refuses it.
fn uniform_range(low: f64, high: f64) -> Result<f64, RoadError> {
    let range = high - low;
    if range.is_finite() && !range.is_sign_negative() {
        Ok(range)
    } else {
        Err(RoadError::UniformRange { low, high })
    }
}

// --------------------------------------------------------------------------- ISO 8608 profiles

/// The ISO 8608 displacement spectrum of a road, one-sided, in a band of spatial frequencies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iso8608 {
    /// G_d(n0) (m³): 16e-6 for class A, ×4 per class; roads.py's "minor" road is 128e-6.
    pub gd0: f64,
    /// Exponent w (1).
    pub waviness: f64,
    /// Reference spatial frequency n0 (cycle/m).
    pub n0: f64,
    /// Band of the profile's content (cycle/m).
    pub n_min: f64,
    pub n_max: f64,
}

impl Iso8608 {
    /// G_d(n) (m³) at spatial frequency `n` (cycle/m), in or out of the band.
    pub fn psd(&self, n: f64) -> f64 {
        self.gd0 * libm::pow(n / self.n0, -self.waviness)
    }

    /// Whether a bin at frequency `n` (cycle/m) is in the band (generate_profile's mask; the mean,
    /// n = 0, never is).
    fn in_band(&self, n: f64) -> bool {
        n >= self.n_min && n <= self.n_max && n > 0.0
    }

    /// Finite numbers, G_d(n0) and n0 positive, 0 ≤ n_min ≤ n_max.
    pub fn check(&self) -> Result<(), RoadError> {
        positive("gd0", self.gd0)?;
        finite("waviness", self.waviness)?;
        positive("n0", self.n0)?;
        non_negative("n_min", self.n_min)?;
        positive("n_max", self.n_max)?;
        if self.n_min > self.n_max {
            return Err(RoadError::BandReversed { n_min: self.n_min, n_max: self.n_max });
        }
        Ok(())
    }

    /// `roads.generate_profile(length, gd0, seed, dx, w, n_min, n_max, n0)`: the profile z at x =
    /// 0, dx, … over at least `length` (m), from the phases of `default_rng(seed)`.
    pub fn profile(&self, length: f64, dx: f64, seed: u64) -> Result<Profile, RoadError> {
        let n = self.sample_count(length, dx)?;
        self.generate(n, dx, seed)
    }

    /// generate_profile's N = ⌈length/dx⌉ + 1, once the spectrum, the grid and the band are checked:
    /// n_max at most the Nyquist frequency 1/(2 dx), N within [`MAX_SAMPLES`], and at least one of
    /// the profile's frequencies in the band (else the road would be flat).
    pub fn sample_count(&self, length: f64, dx: f64) -> Result<usize, RoadError> {
        self.check()?;
        positive("length", length)?;
        positive("dx", dx)?;
        let nyquist = 0.5 / dx;
        if self.n_max > nyquist {
            return Err(RoadError::AboveNyquist { n_max: self.n_max, dx, nyquist });
        }
        let cells = (length / dx).ceil();
        if cells >= MAX_SAMPLES as f64 {
            return Err(RoadError::TooManySamples { length, dx, samples: cells + 1.0, max: MAX_SAMPLES });
        }
        let n = cells as usize + 1;
        if n < 2 {
            return Err(RoadError::TooFewSamples { samples: n });
        }
        let spacing = frequency_spacing(n, dx);
        if !(1..=n / 2).any(|k| self.in_band(k as f64 * spacing)) {
            return Err(RoadError::EmptyBand { n_min: self.n_min, n_max: self.n_max, spacing });
        }
        Ok(n)
    }

    /// The profile of `n` samples (a count [`Iso8608::sample_count`] accepted).
    fn generate(&self, n: usize, dx: f64, seed: u64) -> Result<Profile, RoadError> {
        let mut spectrum = self.spectrum(n, dx, seed);
        let z = inverse_real_fft(&mut spectrum);
        Profile::new(dx, z)
    }

    /// The full Hermitian spectrum of the profile (n bins) whose first n/2 + 1 are
    /// generate_profile's `0.5 * n * amplitude * exp(1j * phases)`.
    fn spectrum(&self, n: usize, dx: f64, seed: u64) -> Vec<Complex> {
        let spacing = frequency_spacing(n, dx); // rfftfreq's 1/(n d), and dn = n[1] − n[0]
        let scale = 0.5 * n as f64;
        let mut rng = Pcg64::new(seed);
        let mut full = vec![Complex::new(0.0, 0.0); n];
        for k in 0..=n / 2 {
            // every bin draws its phase, in the band or not, so the phases are numpy's
            let phase = rng.uniform_in(0.0, 2.0 * PI);
            let n_k = k as f64 * spacing;
            let psd = if self.in_band(n_k) { self.psd(n_k) } else { 0.0 };
            // a cosine of amplitude a has variance a²/2: a = √(2 G dn) gives each bin G dn
            let amplitude = (2.0 * psd * spacing).sqrt();
            let (sin, cos) = libm::sincos(phase);
            let c = scale * amplitude;
            put_hermitian(&mut full, k, Complex::new(c * cos, c * sin));
        }
        full
    }
}

/// The spacing (cycle/m) of the frequencies of `n` samples `dx` apart: rfftfreq's 1.0/(n·d).
fn frequency_spacing(n: usize, dx: f64) -> f64 {
    1.0 / (n as f64 * dx)
}

/// Puts bin `k` of a real signal's spectrum and its mirror n − k. irfft reads only the real part of
/// the mean (k = 0) and, for even n, of the Nyquist bin (k = n/2): their imaginary parts are dropped.
fn put_hermitian(full: &mut [Complex], k: usize, value: Complex) {
    let n = full.len();
    if k == 0 || 2 * k == n {
        full[k] = Complex::new(value.re, 0.0);
    } else {
        full[k] = value;
        full[n - k] = value.conj();
    }
}

/// numpy.fft.irfft of a full Hermitian spectrum: the unnormalised inverse DFT's real part times
/// 1/n (numpy's default "backward" norm multiplies by reciprocal(n)), by [`fft::inverse`].
fn inverse_real_fft(full: &mut [Complex]) -> Vec<f64> {
    let n = full.len();
    fft::inverse(full);
    let norm = 1.0 / n as f64;
    full.iter().map(|c| c.re * norm).collect()
}

/// A road profile: heights z_i (m) at x_i = i·dx (m), i = 0 … N − 1.
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    dx: f64,
    z: Vec<f64>,
}

impl Profile {
    /// A profile of the heights `z` (m, finite, at least two) every `dx` (m, positive).
    pub fn new(dx: f64, z: Vec<f64>) -> Result<Self, RoadError> {
        positive("dx", dx)?;
        if z.len() < 2 {
            return Err(RoadError::TooFewSamples { samples: z.len() });
        }
        if let Some((index, &value)) = z.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(RoadError::ProfileNotFinite { index, value });
        }
        Ok(Self { dx, z })
    }

    /// The sample step (m).
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// The heights z_i (m).
    pub fn heights(&self) -> &[f64] {
        &self.z
    }

    /// x_i = i·dx (m), as numpy's `np.arange(n, dtype=float) * dx`.
    pub fn distance(&self, i: usize) -> f64 {
        i as f64 * self.dx
    }

    /// The distance (m) of the last sample.
    pub fn end(&self) -> f64 {
        self.distance(self.z.len() - 1)
    }

    /// `numpy.interp(s, x, z)` at distance `s` (m), the same arithmetic: the end heights beyond the
    /// ends, the sample itself at a sample, else slope·(s − x_j) + z_j with slope =
    /// (z_{j+1} − z_j)/(x_{j+1} − x_j) and x_j ≤ s < x_{j+1}. NaN gives NaN.
    pub fn interpolate(&self, s: f64) -> f64 {
        let last = self.z.len() - 1;
        if s.is_nan() {
            return s;
        }
        if s < 0.0 {
            return self.z[0];
        }
        if s > self.end() {
            return self.z[last];
        }
        let j = self.index_below(s);
        let x_j = self.distance(j);
        if j == last || x_j == s {
            return self.z[j];
        }
        let slope = (self.z[j + 1] - self.z[j]) / (self.distance(j + 1) - x_j);
        slope * (s - x_j) + self.z[j]
    }

    /// The largest j with x_j ≤ s, for 0 ≤ s ≤ x_{N−1} (numpy's binary search gives the same j):
    /// s/dx guesses it, the rounding of x_j = j·dx decides it.
    fn index_below(&self, s: f64) -> usize {
        let last = self.z.len() - 1;
        let mut j = ((s / self.dx) as usize).min(last);
        while j > 0 && self.distance(j) > s {
            j -= 1;
        }
        while j < last && self.distance(j + 1) <= s {
            j += 1;
        }
        j
    }
}

// --------------------------------------------------------------------------- the road in time

/// How the wheel travels over a profile: the distance offset + speed·t, faded in from zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    /// Forward speed (m/s, ≥ 0).
    pub speed: f64,
    /// Distance along the profile at t = 0 (m).
    pub offset: f64,
    /// Length of the raised-cosine fade-in (s); 0: no fade.
    pub fade_in: f64,
    /// Start of the fade-in (s): the road is flat before it. roads.time_series starts it after the
    /// first step (`step`), where fmpy's inputs still hold their start values 0.
    pub fade_start: f64,
}

impl Travel {
    /// Finite numbers, speed and fade-in not negative, the offset on a profile ending at `end` (m).
    pub fn check(&self, end: f64) -> Result<(), RoadError> {
        non_negative("speed", self.speed)?;
        finite("offset", self.offset)?;
        non_negative("fade_in", self.fade_in)?;
        finite("fade_start", self.fade_start)?;
        if !on_profile(self.offset, end) {
            return Err(RoadError::OffsetOutside { offset: self.offset, end });
        }
        Ok(())
    }

    /// The wheel's distance (m) along the profile at time `t` (s).
    pub fn distance(&self, t: f64) -> f64 {
        self.offset + self.speed * t
    }

    /// The height `z` (m) faded in at time `t` (s), as roads.time_series: z·½(1 − cos(π ramp)) + 0.0
    /// with ramp = clip((t − fade_start)/fade_in, 0, 1); the + 0.0 turns −0.0 into 0.0.
    pub fn fade(&self, t: f64, z: f64) -> f64 {
        if self.fade_in > 0.0 {
            let ramp = ((t - self.fade_start) / self.fade_in).clamp(0.0, 1.0);
            z * 0.5 * (1.0 - fade_cosine(ramp)) + 0.0
        } else {
            z
        }
    }
}

/// cos(π·ramp) for a ramp in [0, 1]. At the ends it is exactly 1 and −1 (libm's cos(0) and cos(π)
/// round to them; a test checks it), so the fade's ends skip the call, which a truck would otherwise
/// make twice a step for the whole road after its fade-in.
fn fade_cosine(ramp: f64) -> f64 {
    if ramp >= 1.0 {
        -1.0
    } else if ramp <= 0.0 {
        1.0
    } else {
        libm::cos(PI * ramp)
    }
}

/// Whether the distance `s` (m) is on a profile from 0 to `end` (m), within roads.time_series's
/// tolerances.
fn on_profile(s: f64, end: f64) -> bool {
    s >= -START_TOLERANCE && s <= end + END_TOLERANCE
}

/// The road's height and rate over a communication step from t_k, as a master feeds them: the
/// truck takes z_road + v_road·(t − t_k).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RoadSegment {
    /// Road height at t_k (m).
    pub z_road: f64,
    /// (z_road(t_{k+1}) − z_road(t_k))/h (m/s).
    pub v_road: f64,
}

/// Everything that makes a road: its spectrum, seed, grid and how the wheel travels over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoadParameters {
    /// G_d(n0) (m³).
    pub gd0: f64,
    /// numpy's seed of the phases.
    pub seed: u64,
    /// Forward speed (m/s).
    pub speed: f64,
    /// Length the profile covers at least (m).
    pub length: f64,
    /// Sample step of the profile (m).
    pub dx: f64,
    /// ISO 8608 exponent w (1).
    pub waviness: f64,
    /// Band of the profile's content (cycle/m).
    pub n_min: f64,
    pub n_max: f64,
    /// ISO 8608 reference frequency (cycle/m).
    pub n0: f64,
    /// Raised-cosine fade-in (s) and its start (s).
    pub fade_in: f64,
    pub fade_start: f64,
    /// Distance along the profile at t = 0 (m).
    pub offset: f64,
}

impl RoadParameters {
    /// The road of `roads.road_case(gd0, speed, duration, seed, step, fade_in)` with roads.py's
    /// dx, band and n0: a profile of length speed·round(duration/step)·step + 1 m, the fade-in
    /// starting after the first step, no offset.
    pub fn road_case(
        gd0: f64,
        speed: f64,
        duration: f64,
        seed: u64,
        step: f64,
        fade_in: f64,
    ) -> Result<Self, RoadError> {
        positive("step", step)?;
        non_negative("duration", duration)?;
        non_negative("speed", speed)?;
        // Python's round(): half to even
        let n_steps = (duration / step).round_ties_even();
        Ok(Self {
            gd0,
            seed,
            speed,
            length: speed * n_steps * step + 1.0,
            dx: DX,
            waviness: WAVINESS,
            n_min: N_MIN,
            n_max: N_MAX,
            n0: N0,
            fade_in,
            fade_start: step,
            offset: 0.0,
        })
    }

    /// The spectrum part.
    pub fn spectrum(&self) -> Iso8608 {
        Iso8608 { gd0: self.gd0, waviness: self.waviness, n0: self.n0, n_min: self.n_min, n_max: self.n_max }
    }

    /// The travel part.
    pub fn travel(&self) -> Travel {
        Travel { speed: self.speed, offset: self.offset, fade_in: self.fade_in, fade_start: self.fade_start }
    }

    /// Every check [`Road::new`] makes, without generating the profile; the number of samples.
    pub fn check(&self) -> Result<usize, RoadError> {
        let n = self.spectrum().sample_count(self.length, self.dx)?;
        self.travel().check((n - 1) as f64 * self.dx)?;
        Ok(n)
    }
}

/// A road a truck drives over: a profile and how the wheel travels along it.
#[derive(Clone, Debug, PartialEq)]
pub struct Road {
    profile: Profile,
    travel: Travel,
}

impl Road {
    /// Checks the parameters, then generates the profile (the one allocation).
    pub fn new(p: &RoadParameters) -> Result<Self, RoadError> {
        let n = p.check()?;
        let profile = p.spectrum().generate(n, p.dx, p.seed)?;
        Ok(Self { profile, travel: p.travel() })
    }

    /// The road of a given profile (a measured track, say), travelled as `travel` says.
    pub fn on_profile(profile: Profile, travel: Travel) -> Result<Self, RoadError> {
        travel.check(profile.end())?;
        Ok(Self { profile, travel })
    }

    /// The profile.
    pub fn profile(&self) -> &Profile {
        &self.profile
    }

    /// How the wheel travels.
    pub fn travel(&self) -> Travel {
        self.travel
    }

    /// The road height (m) under the wheel at time `t` (s): the profile interpolated at
    /// offset + speed·t, faded in. An error where the wheel is off the profile.
    pub fn z_at(&self, t: f64) -> Result<f64, RoadError> {
        if !t.is_finite() {
            return Err(RoadError::TimeNotFinite { t });
        }
        let s = self.travel.distance(t);
        let end = self.profile.end();
        if !on_profile(s, end) {
            return Err(RoadError::OffProfile { t, s, end });
        }
        Ok(self.travel.fade(t, self.profile.interpolate(s)))
    }

    /// The road over the communication step from `t` (s) of `h` (s): z_road(t) and the rate
    /// (z_road(t + h) − z_road(t))/h. A truck extrapolating z_road + v_road·(τ − t) follows the
    /// chord through the road at the step's two ends.
    pub fn segment(&self, t: f64, h: f64) -> Result<RoadSegment, RoadError> {
        if !(h > 0.0 && h.is_finite()) {
            return Err(RoadError::Step { h });
        }
        let z_road = self.z_at(t)?;
        let v_road = (self.z_at(t + h)? - z_road) / h;
        Ok(RoadSegment { z_road, v_road })
    }

    /// Sample `k` of `roads.time_series(…, step, n_steps)` (k < n_steps), the same arithmetic:
    /// z_road at t_k = k·step and v_road = (z_road(t_{k+1}) − z_road(t_k))/step with t_{k+1} =
    /// (k + 1)·step. (The file's last v_road, at k = n_steps, repeats the one before; no step starts
    /// there.)
    pub fn at_step(&self, k: u64, step: f64) -> Result<RoadSegment, RoadError> {
        if !(step > 0.0 && step.is_finite()) {
            return Err(RoadError::Step { h: step });
        }
        let z_road = self.z_at(k as f64 * step)?;
        let v_road = (self.z_at((k + 1) as f64 * step)? - z_road) / step;
        Ok(RoadSegment { z_road, v_road })
    }

    /// Whether the wheel is on the profile at `t` (s), without interpolating: what [`Road::z_at`]
    /// checks before it does.
    pub fn covers(&self, t: f64) -> bool {
        t.is_finite() && on_profile(self.travel.distance(t), self.profile.end())
    }

    /// Whether the wheel stays on the profile from `t_start` to `t_end` (s): an initialisation that
    /// knows its stop time can refuse a road too short for it before the first step.
    pub fn check_until(&self, t_start: f64, t_end: f64) -> Result<(), RoadError> {
        // the distance grows with t (speed ≥ 0): the ends decide
        self.z_at(t_start)?;
        self.z_at(t_end)?;
        Ok(())
    }
}

// --------------------------------------------------------------------------- checks

fn finite(name: &'static str, value: f64) -> Result<(), RoadError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(RoadError::NotFinite { name, value })
    }
}

fn positive(name: &'static str, value: f64) -> Result<(), RoadError> {
    finite(name, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(RoadError::NotPositive { name, value })
    }
}

fn non_negative(name: &'static str, value: f64) -> Result<(), RoadError> {
    finite(name, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(RoadError::Negative { name, value })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A short road_case road: 14 m/s for 1 s (15 m), fade-in 0.5 s after the first 1 ms step.
    fn params() -> RoadParameters {
        RoadParameters::road_case(128e-6, 14.0, 1.0, 3, 1e-3, 0.5).unwrap()
    }

    #[test]
    fn the_fade_s_ends_are_libm_s_own_cosines() {
        // the ends skip libm's cos: the same bits only while cos(0) and cos(π) round to ±1
        assert_eq!(libm::cos(0.0).to_bits(), 1.0f64.to_bits());
        assert_eq!(libm::cos(PI).to_bits(), (-1.0f64).to_bits());
        let travel = Travel { speed: 14.0, offset: 0.0, fade_in: 0.5, fade_start: 1e-3 };
        for (t, z) in [(0.0, 0.013), (1e-3, -0.002), (0.5 + 1e-3, 0.007), (3.0, -0.011), (3.0, 5e-324)] {
            let ramp = ((t - travel.fade_start) / travel.fade_in).clamp(0.0, 1.0);
            let called = z * 0.5 * (1.0 - libm::cos(PI * ramp)) + 0.0;
            assert_eq!(travel.fade(t, z).to_bits(), called.to_bits(), "t = {t}, z = {z}");
        }
    }

    /// The error `Road::new` gives for the parameters `change` makes, and its message.
    fn refused(change: impl FnOnce(&mut RoadParameters)) -> (RoadError, String) {
        let mut p = params();
        change(&mut p);
        let e = Road::new(&p).unwrap_err();
        assert_eq!(p.check().unwrap_err().to_string(), e.to_string(), "check() and new() agree");
        (e, e.to_string())
    }

    #[test]
    fn bad_numbers_are_named_with_their_values() {
        let (e, text) = refused(|p| p.gd0 = 0.0);
        assert_eq!(e, RoadError::NotPositive { name: "gd0", value: 0.0 });
        assert_eq!(text, "road parameter gd0 = 0 must be positive");
        let (e, _) = refused(|p| p.gd0 = f64::NAN);
        assert!(matches!(e, RoadError::NotFinite { name: "gd0", .. }));
        assert_eq!(refused(|p| p.length = -1.0).0, RoadError::NotPositive { name: "length", value: -1.0 });
        assert_eq!(refused(|p| p.dx = 0.0).0, RoadError::NotPositive { name: "dx", value: 0.0 });
        assert_eq!(refused(|p| p.n0 = -0.1).0, RoadError::NotPositive { name: "n0", value: -0.1 });
        assert_eq!(refused(|p| p.n_min = -0.01).0, RoadError::Negative { name: "n_min", value: -0.01 });
        assert!(matches!(refused(|p| p.waviness = f64::INFINITY).0, RoadError::NotFinite { name: "waviness", .. }));
        let (e, text) = refused(|p| p.speed = -2.0);
        assert_eq!(e, RoadError::Negative { name: "speed", value: -2.0 });
        assert_eq!(text, "road parameter speed = -2 must not be negative");
        assert_eq!(refused(|p| p.fade_in = -1.0).0, RoadError::Negative { name: "fade_in", value: -1.0 });
        assert!(matches!(refused(|p| p.fade_start = f64::NAN).0, RoadError::NotFinite { name: "fade_start", .. }));
        assert!(matches!(refused(|p| p.offset = f64::NEG_INFINITY).0, RoadError::NotFinite { name: "offset", .. }));
    }

    #[test]
    fn the_band_and_the_grid_are_checked() {
        let (e, text) = refused(|p| p.n_max = 30.0);
        assert_eq!(e, RoadError::AboveNyquist { n_max: 30.0, dx: 0.02, nyquist: 25.0 });
        assert!(text.contains("n_max = 30 cycle/m") && text.contains("1/(2 dx) = 25 cycle/m"), "{text}");
        // at the Nyquist frequency itself, as generate_profile allows
        assert!(Road::new(&RoadParameters { n_max: 25.0, ..params() }).is_ok());
        assert_eq!(refused(|p| p.n_min = 11.0).0, RoadError::BandReversed { n_min: 11.0, n_max: 10.0 });
        // 0.06 m: 4 samples, frequencies 0, 12.5 cycle/m: none in 0.01 .. 10
        let (e, text) = refused(|p| p.length = 0.06);
        assert!(matches!(e, RoadError::EmptyBand { spacing, .. } if spacing == 12.5), "{e:?}");
        assert!(text.contains("multiples of 12.5 cycle/m"), "{text}");
        let (e, text) = refused(|p| p.length = 1e6);
        assert_eq!(e, RoadError::TooManySamples { length: 1e6, dx: 0.02, samples: 50_000_001.0, max: MAX_SAMPLES });
        assert!(text.contains("needs 50000001 samples, more than the 1048576 allowed"), "{text}");
        let (e, text) = refused(|p| p.offset = 20.0);
        assert_eq!(e, RoadError::OffsetOutside { offset: 20.0, end: 15.0 });
        assert_eq!(text, "road parameter offset = 20 m is off the road profile (0 .. 15 m)");
    }

    #[test]
    fn the_wheel_off_the_profile_is_an_error_not_a_wrap() {
        let road = Road::new(&params()).unwrap();
        let end = road.profile().end();
        assert_eq!(end, 15.0); // ceil(15 m / 0.02 m) + 1 = 751 samples
        let t_end = end / 14.0;
        assert!(road.z_at(t_end).is_ok());
        let e = road.z_at(1.1).unwrap_err();
        assert!(matches!(e, RoadError::OffProfile { t, end: 15.0, .. } if t == 1.1), "{e:?}");
        assert!(e.to_string().starts_with("at t = 1.1 s the wheel is at s = 15.4"), "{e}");
        assert!(road.z_at(-0.01).is_err());
        assert!(road.check_until(0.0, 1.0).is_ok() && road.check_until(0.0, 1.1).is_err());
        assert!(matches!(road.z_at(f64::NAN), Err(RoadError::TimeNotFinite { .. })));
        assert_eq!(road.segment(0.5, 0.0), Err(RoadError::Step { h: 0.0 }));
        assert_eq!(road.at_step(3, -1e-3), Err(RoadError::Step { h: -1e-3 }));
        // the step ending past the profile is refused as a whole
        assert!(road.segment(t_end, 1e-3).is_err());
    }

    #[test]
    fn the_ends_have_python_s_tolerances() {
        let profile = Profile::new(0.5, vec![1.0, 2.0, 4.0]).unwrap();
        let still = |offset| Travel { speed: 0.0, offset, fade_in: 0.0, fade_start: 0.0 };
        assert_eq!(Road::on_profile(profile.clone(), still(1.0 + 1e-9)).unwrap().z_at(7.0), Ok(4.0));
        assert!(Road::on_profile(profile.clone(), still(1.0 + 2e-9)).is_err());
        assert_eq!(Road::on_profile(profile.clone(), still(-1e-12)).unwrap().z_at(0.0), Ok(1.0));
        assert!(Road::on_profile(profile, still(-2e-12)).is_err());
    }

    #[test]
    fn interpolation_is_numpy_s() {
        let p = Profile::new(0.5, vec![1.0, 2.0, 4.0]).unwrap();
        assert_eq!([p.interpolate(0.0), p.interpolate(0.5), p.interpolate(1.0)], [1.0, 2.0, 4.0]);
        assert_eq!([p.interpolate(0.25), p.interpolate(0.75)], [1.5, 3.0]);
        assert_eq!([p.interpolate(-1.0), p.interpolate(9.0)], [1.0, 4.0]);
        assert!(p.interpolate(f64::NAN).is_nan());
        // x_j = j·dx rounds: 3·0.1 = 0.30000000000000004 > 0.3, so 0.3 lies below sample 3
        let q = Profile::new(0.1, vec![0.0, 1.0, 2.0, 3.0, 4.0]).unwrap();
        assert_eq!(q.index_below(0.3), 2);
        assert_eq!(q.index_below(q.distance(3)), 3);
    }

    #[test]
    fn the_fade_starts_flat_and_at_plus_zero() {
        let road = Road::new(&params()).unwrap();
        for t in [0.0, 1e-3] {
            assert_eq!(road.z_at(t).unwrap().to_bits(), 0, "+0.0 at t = {t}");
        }
        // after the fade, the profile itself
        let s = road.travel().distance(0.7);
        assert_eq!(road.z_at(0.7), Ok(road.profile().interpolate(s)));
        // standing still: the height under the wheel, faded in
        let still = Travel { speed: 0.0, offset: 3.0, fade_in: 0.0, fade_start: 0.0 };
        let parked = Road::on_profile(road.profile().clone(), still).unwrap();
        assert_eq!(parked.segment(0.0, 0.1).unwrap(), RoadSegment { z_road: parked.z_at(5.0).unwrap(), v_road: 0.0 });
    }

    #[test]
    fn a_segment_is_the_chord_between_the_communication_points() {
        let road = Road::new(&params()).unwrap();
        let (t, h) = (0.3, 2e-3);
        let s = road.segment(t, h).unwrap();
        assert_eq!(s.z_road, road.z_at(t).unwrap());
        let end = road.z_at(t + h).unwrap();
        assert!((s.z_road + s.v_road * h - end).abs() <= 1e-15 * end.abs().max(1e-3));
        // at_step is time_series's sample k: t_k = k·step, rate over (k + 1)·step
        let k = road.at_step(300, 1e-3).unwrap();
        let (z0, z1) = (road.z_at(300.0 * 1e-3).unwrap(), road.z_at(301.0 * 1e-3).unwrap());
        assert_eq!(k, RoadSegment { z_road: z0, v_road: (z1 - z0) / 1e-3 });
    }

    #[test]
    fn profiles_are_refused_with_the_bad_sample_named() {
        assert_eq!(
            Profile::new(0.1, vec![0.0, f64::NAN, 1.0]).unwrap_err().to_string(),
            "road profile height z[1] = NaN m is not a finite number"
        );
        assert_eq!(Profile::new(0.1, vec![0.0]), Err(RoadError::TooFewSamples { samples: 1 }));
        assert_eq!(Profile::new(-0.1, vec![0.0, 1.0]), Err(RoadError::NotPositive { name: "dx", value: -0.1 }));
    }

    #[test]
    fn uniform_refuses_what_numpy_refuses_and_draws_nothing() {
        let mut rng = Pcg64::new(5);
        assert_eq!(rng.uniform(1.0, 0.0), Err(RoadError::UniformRange { low: 1.0, high: 0.0 }));
        assert!(rng.uniform(0.0, f64::INFINITY).is_err() && rng.uniform(f64::NAN, 1.0).is_err());
        assert!(rng.uniform(0.0, -0.0).is_err()); // numpy: signbit of the range
        assert_eq!(rng.uniform(1.0, 1.0), Ok(1.0)); // np.random.default_rng(5).uniform(1, 1) = 1.0
        let mut fresh = Pcg64::new(5);
        fresh.next_u64();
        assert_eq!(rng, fresh, "only the accepted call drew");
    }

    #[test]
    fn seed_sequences_mix_entropy_beyond_the_pool() {
        // np.random.SeedSequence(0).pool
        assert_eq!(SeedSequence::new(0).pool(), [0xfe40_eb07, 0x4f36_3a36, 0x4eb2_009d, 0xc89a_7aa7]);
        // np.random.SeedSequence(2**160 - 1).generate_state(4): five words, one beyond the pool
        let words = SeedSequence::from_words(&[u32::MAX; 5]).generate_state::<4>();
        assert_eq!(words, [0x6981_bca9, 0x20de_dfba, 0x343d_d9d0, 0xe326_4fcb]);
    }

    /// FNV-1a (64-bit) over the little-endian bytes of the heights' bits.
    fn fnv1a(z: &[f64]) -> u64 {
        let mut hash = 0xcbf2_9ce4_8422_2325_u64;
        for byte in z.iter().flat_map(|v| v.to_bits().to_le_bytes()) {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0000_0100_0000_01b3);
        }
        hash
    }

    /// The profiles' bits, the same on Linux and on Windows: every cosine and sine of the spectrum
    /// and of the FFT is libm's, the rest IEEE arithmetic in a fixed order. The hashes are the bits
    /// of this implementation (a change of its arithmetic changes them), recorded with the Linux
    /// build and the same with the Windows one, under Wine:
    ///
    /// ```text
    /// CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER="$PWD/tests/win64/wine_runner.sh" \
    ///     cargo test --release -p suspension --target x86_64-pc-windows-gnu -- --nocapture profiles_are
    /// ```
    ///
    /// (rerun so after a change, and record new hashes only where both print them). With rustfft's
    /// FFT, whose twiddles came from the C library, the 1009- and 22 551-sample profiles differed.
    #[test]
    fn profiles_are_the_same_bits_on_linux_and_windows() {
        let minor = Iso8608 { gd0: 128e-6, waviness: WAVINESS, n0: N0, n_min: N_MIN, n_max: N_MAX };
        let other = Iso8608 { gd0: 256e-6, waviness: 2.5, n0: 0.2, n_min: 0.05, n_max: 2.0 };
        // (spectrum, length m, dx m, seed, FNV-1a of the heights): n = 1001 (odd), 1009 (prime),
        // 202 (even), 1024 (2¹⁰: the radix-2 FFT alone), 22 551 (road_case(minor, 25 m/s, 18 s))
        let cases = [
            (minor, 20.0, DX, 0, 0x4a8a_f3b8_dade_e1a0_u64),
            (minor, 20.15, DX, 2_147_483_647, 0xe64d_e2ee_7e35_0db5),
            (other, 10.05, 0.05, 7, 0xb2bd_9e7e_6191_2d7c),
            (other, 255.75, 0.25, 12_345_678_901_234_567_890, 0x487a_cc69_52e9_a2f5),
            (minor, 451.0, DX, 2024, 0x73d6_1b69_8d7b_dec4),
        ];
        let mut differ = vec![];
        for (spectrum, length, dx, seed, expected) in cases {
            let profile = spectrum.profile(length, dx, seed).unwrap();
            let (z, hash) = (profile.heights(), fnv1a(profile.heights()));
            eprintln!("profile of {} samples, seed {seed}: FNV-1a {hash:#018x}", z.len());
            if hash != expected {
                differ.push(format!("{} samples: {hash:#018x}, not {expected:#018x}", z.len()));
            }
        }
        assert!(differ.is_empty(), "other bits: {differ:?}");
    }

    #[test]
    fn road_case_has_python_s_length_and_rounding() {
        let p = RoadParameters::road_case(128e-6, 25.0, 18.0, 2024, 1e-3, 1.0).unwrap();
        assert_eq!(p.length, 451.0);
        assert_eq!(p.check(), Ok(22_551));
        // round(0.0025 / 1e-3) = round(2.5) = 2 (half to even): 2 steps of 1 ms, 1.02 m at 10 m/s
        let q = RoadParameters::road_case(128e-6, 10.0, 0.0025, 1, 1e-3, 0.0).unwrap();
        assert_eq!(q.length, 10.0 * 2.0 * 1e-3 + 1.0);
        assert_eq!(
            RoadParameters::road_case(128e-6, 10.0, 1.0, 1, 0.0, 0.0),
            Err(RoadError::NotPositive { name: "step", value: 0.0 })
        );
    }
}
