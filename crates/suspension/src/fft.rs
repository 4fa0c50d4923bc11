//! The discrete Fourier transform of any length, for the road profiles of [`crate::road`]: the
//! same bits on every platform, since every cosine and sine comes from the `libm` crate (not from
//! the platform's C library, whose glibc and MinGW-w64 builds differ in the last bit) and the rest
//! is IEEE arithmetic in a fixed order, without fused multiply-adds.
//!
//! ```text
//! forward:  X_k = Σ_j x_j e^{−2πi jk/n}      inverse:  x_j = Σ_k X_k e^{+2πi jk/n}   (unnormalised)
//! ```
//!
//! - a power of two: the iterative radix-2 FFT (bit reversal, then decimation in time, its stages
//!   taken in pairs as radix-4 butterflies), with its twiddle factors e^{−2πi k/n} from a table of
//!   n/2 computed from their exact angles, not by repeated multiplication;
//! - any other n: Bluestein's chirp z-transform. With jk = (j² + k² − (k − j)²)/2 and the chirp
//!   c_j = e^{−πi j²/n}, X_k = c_k Σ_j (x_j c_j) conj(c_{k−j}): a convolution, computed cyclically
//!   by the FFTs of the power of two m ≥ 2n − 1 (the kernel's, the chirped signal's, the inverse of
//!   their product). The chirp's angle is π (j² mod 2n)/n with j² mod 2n in integers, so that it
//!   stays in [0, 2π) however large j² is;
//! - the inverse is the forward transform of the conjugate, conjugated (exact).
//!
//! Every angle 2π p/q is reduced to the first octant by integer arithmetic on p and q before its
//! cosine and sine are taken ([`root_of_unity`]), so that no twiddle carries the rounding of a
//! large angle. Accuracy: a few ε of the output's RMS, at most (log₂ m + 4)ε (this module's tests,
//! against a compensated O(n²) DFT). Cost: O(n log n) for every n; the only allocations are the
//! twiddle table (m/2 values) and, for Bluestein, the kernel's transform and a work buffer (m
//! values each); the input's buffer keeps the chirp meanwhile. Bluestein's three FFTs of m ≥ 2n − 1
//! make a length that is not a power of two several times as costly as a power of two near it
//! (22 551: about 4 ms, 32 768: 0.7 ms).

use std::ops::{Add, Mul, Sub};

/// A complex number of two f64s; the products are written out, so they round the same everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Complex {
    pub re: f64,
    pub im: f64,
}

impl Complex {
    /// 0 + 0i.
    pub const ZERO: Self = Self { re: 0.0, im: 0.0 };

    /// re + im·i.
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }

    /// The complex conjugate.
    pub fn conj(self) -> Self {
        Self { re: self.re, im: -self.im }
    }

    /// |z|².
    pub fn norm_sqr(self) -> f64 {
        self.re * self.re + self.im * self.im
    }

    /// The product with a real number.
    pub fn scale(self, factor: f64) -> Self {
        Self { re: self.re * factor, im: self.im * factor }
    }
}

impl Add for Complex {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self { re: self.re + other.re, im: self.im + other.im }
    }
}

impl Sub for Complex {
    type Output = Self;
    fn sub(self, other: Self) -> Self {
        Self { re: self.re - other.re, im: self.im - other.im }
    }
}

impl Mul for Complex {
    type Output = Self;
    fn mul(self, other: Self) -> Self {
        Self { re: self.re * other.re - self.im * other.im, im: self.re * other.im + self.im * other.re }
    }
}

/// e^{−2πi p/q} for 0 ≤ p < q (and q < 2⁶⁰): the angle is reduced to [0, π/4] in integers (in
/// units of 2π/(8q)), its cosine and sine taken by libm, and the symmetries of the circle put back.
pub fn root_of_unity(p: u64, q: u64) -> Complex {
    debug_assert!(p < q && q < 1 << 60);
    // θ = 2π a/(8q) ∈ [0, 2π): π is 4q, π/2 is 2q, π/4 is q
    let mut a = 8 * p;
    let mut negate_sin = false;
    let mut negate_cos = false;
    let mut swap = false;
    if a > 4 * q {
        a = 8 * q - a; // θ → 2π − θ
        negate_sin = true;
    }
    if a > 2 * q {
        a = 4 * q - a; // θ → π − θ
        negate_cos = true;
    }
    if a > q {
        a = 2 * q - a; // θ → π/2 − θ
        swap = true;
    }
    // a ≤ q: φ = (π/4)·a/q, with a and 4q exact in f64
    let phi = std::f64::consts::PI * a as f64 / (4 * q) as f64;
    let (mut sin, mut cos) = libm::sincos(phi);
    if swap {
        std::mem::swap(&mut sin, &mut cos);
    }
    if negate_cos {
        cos = -cos;
    }
    if negate_sin {
        sin = -sin;
    }
    // e^{−iθ} = cos θ − i sin θ
    Complex::new(cos, -sin)
}

/// The forward DFT of `data` in place (unnormalised).
pub fn forward(data: &mut [Complex]) {
    let n = data.len();
    if n <= 1 {
        return;
    }
    if n.is_power_of_two() {
        let twiddles = twiddles(n);
        bit_reverse(data);
        butterflies_in_time(data, &twiddles);
    } else {
        bluestein(data);
    }
}

/// The inverse DFT of `data` in place, unnormalised (the forward transform's inverse times n):
/// conj(forward(conj(x))).
pub fn inverse(data: &mut [Complex]) {
    for value in data.iter_mut() {
        *value = value.conj();
    }
    forward(data);
    for value in data.iter_mut() {
        *value = value.conj();
    }
}

/// The twiddle factors e^{−2πi k/m}, k = 0 … m/2 − 1, of the radix-2 FFT of size m (a power of
/// two): [`root_of_unity`]'s values, bit for bit, the first octant computed and the other three
/// mirrored from it (its cosines and sines swapped and negated, as `root_of_unity` reduces them).
fn twiddles(m: usize) -> Vec<Complex> {
    let half = m / 2;
    let at = |k: usize| root_of_unity(k as u64, m as u64);
    if m < 16 {
        return (0..half).map(at).collect();
    }
    let (quarter, eighth) = (m / 4, m / 8);
    let mut table = vec![Complex::ZERO; half];
    for (k, w) in table.iter_mut().enumerate().take(eighth + 1) {
        *w = at(k);
    }
    for k in 1..eighth {
        // w = cos θ − i sin θ with 0 < θ < π/4
        let w = table[k];
        table[quarter - k] = Complex::new(-w.im, -w.re); // π/2 − θ
        table[quarter + k] = Complex::new(w.im, -w.re); // π/2 + θ
        table[half - k] = Complex::new(-w.re, w.im); // π − θ
    }
    table[quarter] = at(quarter);
    table[quarter + eighth] = at(quarter + eighth);
    table
}

/// Puts `data` (a power-of-two length) in bit-reversed order of its indices.
fn bit_reverse(data: &mut [Complex]) {
    let m = data.len();
    debug_assert!(m.is_power_of_two() && m >= 2);
    let shift = usize::BITS - m.trailing_zeros();
    for i in 0..m {
        let j = i.reverse_bits() >> shift;
        if j > i {
            data.swap(i, j);
        }
    }
}

/// The FFT by decimation in time (Cooley–Tukey) of `data` (a power-of-two length m) given in
/// bit-reversed order, in place, the transform in natural order. Its radix-2 stages of length 2,
/// 4, …, m go in pairs, as radix-4 stages of length 4, 16, … (after one radix-2 stage of length 2
/// where log₂ m is odd); the stage of length `len` takes every (m/len)-th twiddle.
fn butterflies_in_time(data: &mut [Complex], twiddles: &[Complex]) {
    let m = data.len();
    debug_assert!(m.is_power_of_two() && m >= 2 && twiddles.len() == m / 2);
    let mut len = if m.trailing_zeros() % 2 == 1 {
        for pair in data.chunks_exact_mut(2) {
            let (u, v) = (pair[0], pair[1]);
            pair[0] = u + v;
            pair[1] = u - v;
        }
        8
    } else {
        4
    };
    while len <= m {
        let (quarter, stride) = (len / 4, m / len);
        for block in data.chunks_exact_mut(len) {
            let (q0, rest) = block.split_at_mut(quarter);
            let (q1, rest) = rest.split_at_mut(quarter);
            let (q2, q3) = rest.split_at_mut(quarter);
            for (i, (((x0, x1), x2), x3)) in
                q0.iter_mut().zip(q1.iter_mut()).zip(q2.iter_mut()).zip(q3.iter_mut()).enumerate()
            {
                let (p0, p1, p2, p3) = if i == 0 {
                    (*x0, *x1, *x2, *x3) // the twiddles are 1
                } else {
                    let [w1, w2, w3] = powers(twiddles, i * stride);
                    (*x0, *x1 * w2, *x2 * w1, *x3 * w3)
                };
                let (y0, y1, s, d) = (p0 + p1, p0 - p1, p2 + p3, times_minus_i(p2 - p3));
                *x0 = y0 + s;
                *x1 = y1 + d;
                *x2 = y0 - s;
                *x3 = y1 - d;
            }
        }
        len *= 4;
    }
}

/// The FFT by decimation in frequency (Gentleman–Sande) of `data` in natural order, in place, the
/// transform in bit-reversed order: the stages of [`butterflies_in_time`] undone in reverse,
/// radix-4 stages of length m, m/4, … (and one radix-2 stage of length 2 at the end where log₂ m
/// is odd).
fn butterflies_in_frequency(data: &mut [Complex], twiddles: &[Complex]) {
    let m = data.len();
    debug_assert!(m.is_power_of_two() && m >= 2 && twiddles.len() == m / 2);
    let mut len = m;
    while len >= 4 {
        let (quarter, stride) = (len / 4, m / len);
        for block in data.chunks_exact_mut(len) {
            let (q0, rest) = block.split_at_mut(quarter);
            let (q1, rest) = rest.split_at_mut(quarter);
            let (q2, q3) = rest.split_at_mut(quarter);
            for (i, (((x0, x1), x2), x3)) in
                q0.iter_mut().zip(q1.iter_mut()).zip(q2.iter_mut()).zip(q3.iter_mut()).enumerate()
            {
                let (a, b) = (*x0 + *x2, *x1 + *x3);
                let (c, e) = (*x0 - *x2, times_minus_i(*x1 - *x3));
                let (z0, z1, z2, z3) = (a + b, a - b, c + e, c - e);
                *x0 = z0;
                if i == 0 {
                    (*x1, *x2, *x3) = (z1, z2, z3); // the twiddles are 1
                } else {
                    let [w1, w2, w3] = powers(twiddles, i * stride);
                    (*x1, *x2, *x3) = (z1 * w2, z2 * w1, z3 * w3);
                }
            }
        }
        len /= 4;
    }
    if len == 2 {
        for pair in data.chunks_exact_mut(2) {
            let (u, v) = (pair[0], pair[1]);
            pair[0] = u + v;
            pair[1] = u - v;
        }
    }
}

/// The twiddles w^k, w^{2k}, w^{3k} of `twiddles(m)` (w = e^{−2πi/m}, 0 < k < m/4): w^{3k} past the
/// table's half circle is −w^{3k − m/2}.
fn powers(twiddles: &[Complex], k: usize) -> [Complex; 3] {
    let half = twiddles.len();
    let k3 = 3 * k;
    let w3 = if k3 < half { twiddles[k3] } else { twiddles[k3 - half].scale(-1.0) };
    [twiddles[k], twiddles[2 * k], w3]
}

/// z·(−i) = im − i·re, exact: the twiddle e^{−iπ/2}.
fn times_minus_i(z: Complex) -> Complex {
    Complex::new(z.im, -z.re)
}

/// The DFT of `data` (any length n ≥ 2) in place by Bluestein's algorithm (the module's doc). The
/// convolution's transforms need no bit reversal: the forward ones by decimation in frequency
/// leave the spectra in bit-reversed order, their product is taken in that order, and the inverse
/// by decimation in time takes it so.
fn bluestein(data: &mut [Complex]) {
    let n = data.len();
    let m = (2 * n - 1).next_power_of_two();
    let twiddles = twiddles(m);
    // the kernel b_j = conj(c_j) at j and m − j (a cyclic even sequence), zero between
    let mut kernel = vec![Complex::ZERO; m];
    let two_n = 2 * n as u64;
    for j in 0..n {
        let j2 = (j as u64 * j as u64) % two_n;
        let b = root_of_unity(j2, two_n).conj(); // c_j = e^{−2πi (j² mod 2n)/(2n)}
        kernel[j] = b;
        if j > 0 {
            kernel[m - j] = b;
        }
    }
    // a_j = x_j c_j, zero padded; `data` keeps c_j for the last multiplication
    let mut work = vec![Complex::ZERO; m];
    for ((x, a), b) in data.iter_mut().zip(work.iter_mut()).zip(&kernel) {
        let c = b.conj();
        *a = *x * c;
        *x = c;
    }
    // the cyclic convolution a ⊛ b = inverse(A·B)/m (m a power of two: 1/m is exact), the
    // inverse as the conjugate of the forward transform of the conjugate
    butterflies_in_frequency(&mut kernel, &twiddles);
    butterflies_in_frequency(&mut work, &twiddles);
    let norm = 1.0 / m as f64;
    for (a, b) in work.iter_mut().zip(&kernel) {
        *a = (*a * *b).conj().scale(norm);
    }
    butterflies_in_time(&mut work, &twiddles);
    for (x, a) in data.iter_mut().zip(&work) {
        *x = *x * a.conj();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::road::Pcg64;

    /// n complex values with parts uniform in [−1, 1), from a seed.
    fn signal(n: usize, seed: u64) -> Vec<Complex> {
        let mut rng = Pcg64::new(seed);
        (0..n).map(|_| Complex::new(2.0 * rng.next_double() - 1.0, 2.0 * rng.next_double() - 1.0)).collect()
    }

    /// Σ|z|², compensated.
    fn energy(values: &[Complex]) -> f64 {
        let mut sum = Sum::default();
        for v in values {
            sum.add(v.re * v.re);
            sum.add(v.im * v.im);
        }
        sum.value()
    }

    fn rms(values: &[Complex]) -> f64 {
        (energy(values) / values.len() as f64).sqrt()
    }

    /// The sum s + t exactly: the rounded sum and its error (Knuth's TwoSum).
    fn two_sum(s: f64, t: f64) -> (f64, f64) {
        let sum = s + t;
        let t_virtual = sum - s;
        let s_virtual = sum - t_virtual;
        (sum, (s - s_virtual) + (t - t_virtual))
    }

    /// A sum of many terms with the error of every addition kept aside (compensated summation).
    #[derive(Default)]
    struct Sum {
        sum: f64,
        error: f64,
    }

    impl Sum {
        fn add(&mut self, term: f64) {
            let (sum, error) = two_sum(self.sum, term);
            self.sum = sum;
            self.error += error;
        }
        fn value(&self) -> f64 {
            self.sum + self.error
        }
    }

    /// Bin k of the DFT of x by its definition, with `circle` = e^{−2πi r/n} by [`root_of_unity`]
    /// (libm) at r = jk mod n, the sums compensated, so that its error is the products' rounding
    /// only (about ε of the RMS).
    fn naive_bin(x: &[Complex], circle: &[Complex], k: usize) -> Complex {
        let n = x.len() as u64;
        let (mut re, mut im) = (Sum::default(), Sum::default());
        for (j, &value) in x.iter().enumerate() {
            let w = circle[((j as u64 * k as u64) % n) as usize];
            re.add(value.re * w.re);
            re.add(-(value.im * w.im));
            im.add(value.re * w.im);
            im.add(value.im * w.re);
        }
        Complex::new(re.value(), im.value())
    }

    /// The bins to check: all of them up to 4096, else 1000 spread over the spectrum and its ends.
    fn bins(n: usize) -> Vec<usize> {
        if n <= 4096 {
            (0..n).collect()
        } else {
            let mut k: Vec<usize> = (0..32).chain(n - 32..n).chain((0..936).map(|i| i * n / 936)).collect();
            k.sort_unstable();
            k.dedup();
            k
        }
    }

    /// The largest error allowed, relative to the output's RMS: ε per radix-2 stage of the FFT
    /// that computes it (log₂ n stages, or log₂ m for Bluestein's FFTs of size m ≥ 2n − 1), plus
    /// 4ε for the twiddles, the chirp and the reference. Measured: at most 0.44 of it (6.1ε at
    /// n = 4093, 5.2ε at 22 551, 3.7ε at 65 536, 3.1ε at 97).
    fn bound(n: usize) -> f64 {
        let m = if n.is_power_of_two() { n } else { (2 * n - 1).next_power_of_two() };
        (f64::from(m.trailing_zeros()) + 4.0) * f64::EPSILON
    }

    const SIZES: [usize; 14] = [65, 96, 97, 101, 127, 128, 255, 256, 1000, 1024, 4093, 4096, 22_551, 65_536];

    fn sizes() -> impl Iterator<Item = usize> {
        (1..=64).chain(SIZES)
    }

    #[test]
    fn the_fft_is_the_dft() {
        let mut worst = 0.0_f64;
        for n in sizes() {
            let x = signal(n, n as u64);
            let mut y = x.clone();
            forward(&mut y);
            let scale = rms(&y);
            let circle: Vec<Complex> = (0..n as u64).map(|r| root_of_unity(r, n as u64)).collect();
            for k in bins(n) {
                let error = (y[k] - naive_bin(&x, &circle, k)).norm_sqr().sqrt() / scale;
                assert!(error <= bound(n), "n = {n}, bin {k}: {error:.3e} of the RMS, bound {:.3e}", bound(n));
                worst = worst.max(error / bound(n));
            }
        }
        eprintln!("forward FFT against the compensated DFT: at most {worst:.2} of the bound");
    }

    #[test]
    fn the_inverse_undoes_the_forward_transform() {
        let mut worst = 0.0_f64;
        for n in sizes() {
            let x = signal(n, 1000 + n as u64);
            let mut y = x.clone();
            forward(&mut y);
            inverse(&mut y);
            let scale = rms(&x);
            let norm = 1.0 / n as f64;
            for (j, (a, b)) in y.iter().zip(&x).enumerate() {
                let error = (a.scale(norm) - *b).norm_sqr().sqrt() / scale;
                assert!(error <= 2.0 * bound(n), "n = {n}, sample {j}: {error:.3e} of the RMS");
                worst = worst.max(error / (2.0 * bound(n)));
            }
        }
        eprintln!("inverse(forward(x))/n against x: at most {worst:.2} of twice the bound");
    }

    #[test]
    fn parseval_holds() {
        let mut worst = 0.0_f64;
        for n in sizes() {
            let x = signal(n, 2000 + n as u64);
            let mut y = x.clone();
            forward(&mut y);
            // Σ|X_k|² = n Σ|x_j|²
            let (energy_x, energy_y) = (energy(&x), energy(&y) / n as f64);
            let error = (energy_y - energy_x).abs() / energy_x;
            worst = worst.max(error / bound(n));
            assert!(error <= bound(n), "n = {n}: Σ|X|²/(n Σ|x|²) − 1 = {error:.3e}");
        }
        eprintln!("Parseval: Σ|X|²/(n Σ|x|²) − 1 at most {worst:.2} of the bound");
    }

    #[test]
    fn the_inverse_is_e_to_the_plus_i() {
        // a single bin k of the spectrum is the wave e^{+2πi jk/n}
        for n in [7usize, 8, 12, 31] {
            for k in 0..n {
                let mut y = vec![Complex::ZERO; n];
                y[k] = Complex::new(1.0, 0.0);
                inverse(&mut y);
                for (j, v) in y.iter().enumerate() {
                    let wave = root_of_unity((j * k % n) as u64, n as u64).conj();
                    assert!((*v - wave).norm_sqr().sqrt() <= 8.0 * f64::EPSILON, "n {n}, k {k}, j {j}: {v:?}");
                }
            }
        }
        let mut empty: [Complex; 0] = [];
        forward(&mut empty);
        let mut one = [Complex::new(2.5, -1.0)];
        inverse(&mut one);
        assert_eq!(one, [Complex::new(2.5, -1.0)]);
    }

    #[test]
    fn the_mirrored_twiddles_are_the_direct_ones_bit_for_bit() {
        for log2 in 1..=16 {
            let m = 1usize << log2;
            let table = twiddles(m);
            assert_eq!(table.len(), m / 2);
            for (k, w) in table.iter().enumerate() {
                let exact = root_of_unity(k as u64, m as u64);
                let bits = |z: Complex| (z.re.to_bits(), z.im.to_bits());
                assert_eq!(bits(*w), bits(exact), "m = {m}, k = {k}");
            }
        }
    }

    #[test]
    fn decimation_in_frequency_is_the_transform_bit_reversed() {
        for m in [2usize, 4, 8, 64, 1024] {
            let x = signal(m, 3000 + m as u64);
            let (mut natural, mut reversed) = (x.clone(), x);
            forward(&mut natural);
            butterflies_in_frequency(&mut reversed, &twiddles(m));
            bit_reverse(&mut reversed);
            let error = natural.iter().zip(&reversed).map(|(a, b)| (*a - *b).norm_sqr().sqrt()).fold(0.0, f64::max);
            assert!(error <= bound(m) * rms(&natural), "m = {m}: {error:.3e}");
        }
    }

    #[test]
    fn the_unit_circle_is_reduced_exactly() {
        // the quarter turns are exact, the octants mirror each other's bits
        assert_eq!(root_of_unity(0, 4), Complex::new(1.0, -0.0));
        assert_eq!(root_of_unity(1, 4), Complex::new(0.0, -1.0));
        assert_eq!(root_of_unity(2, 4), Complex::new(-1.0, -0.0));
        assert_eq!(root_of_unity(3, 4), Complex::new(0.0, 1.0));
        let q = 1 << 20;
        for p in [1u64, 12_345, 100_000, q / 8 - 1] {
            let w = root_of_unity(p, q);
            assert_eq!(root_of_unity(q / 4 - p, q), Complex::new(-w.im, -w.re), "π/2 − θ, p = {p}");
            assert_eq!(root_of_unity(q / 2 - p, q), Complex::new(-w.re, w.im), "π − θ, p = {p}");
            assert_eq!(root_of_unity(q - p, q), w.conj(), "2π − θ, p = {p}");
        }
        // against the angle taken whole: within an ulp or two of the reduced angle's
        for (p, q) in [(1u64, 3u64), (2, 3), (5, 22_551), (22_550, 22_551), (7_000_001, 8_388_608)] {
            let theta = 2.0 * std::f64::consts::PI * p as f64 / q as f64;
            let w = root_of_unity(p, q);
            assert!((w.re - libm::cos(theta)).abs() <= 4.0 * f64::EPSILON, "{p}/{q}");
            assert!((w.im + libm::sin(theta)).abs() <= 4.0 * f64::EPSILON, "{p}/{q}");
        }
    }
}
