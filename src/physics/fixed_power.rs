//! c·x^y for one exponent y fixed per parameter set, from tables: the polytropic laws of the air in
//! the oil and of the reservoir's gas raise a pressure or a volume to the power −1/n or −n at every
//! evaluation of the plant, three times in all, and `powf` (a logarithm, a product and an
//! exponential, to within an ulp) was a sixth of the damper's time. With y fixed, neither the
//! logarithm nor the exponential is needed:
//!
//! ```text
//! x = 2^e · m,  m ∈ [1, 2),  m in segment j of 128 with centre c_j = 1 + (j + ½)/128
//! c·x^y = [c·2^(e·y)] · [c_j^y] · (1 + s)^y,   s = m/c_j − 1,  |s| ≤ 1/257
//! (1 + s)^y = Σ_{k≤5} C(y, k) s^k   (binomial series; the first term left out, |C(y, 6)| s⁶, is ≤ 1.4e-14 for |y| ≤ 1.67)
//! ```
//!
//! The two bracketed factors come from tables built once with `powf`; a value costs two table reads,
//! a quotient by multiplication and a fifth-degree polynomial, a quarter of `powf`'s time and half
//! its latency. Relative error ≤ 2e-14 for |y| ≤ 1.67 (the range of the polytropic index), against
//! `powf`'s 1e-16: more than four orders of magnitude below any tolerance the integrator runs at
//! (the converged reference of the benchmark: rtol 1e-9). Outside the
//! tables' 64 binades, and for x that is not a positive normal number, it is `c·powf(x, y)`.

/// Mantissa bits that pick a segment.
const SEGMENT_BITS: u32 = 7;
const SEGMENTS: usize = 1 << SEGMENT_BITS;
/// Binades (factors of 2 in x) the tables cover.
const BINADES: usize = 64;

/// c·x^y with c and y fixed at construction.
#[derive(Clone, Copy, Debug)]
pub struct FixedPower {
    coefficient: f64,
    exponent: f64,
    /// The binade of `binade[0]`: x ∈ [2^lowest_binade, 2^(lowest_binade + 64)) uses the tables.
    lowest_binade: i64,
    /// c·2^(e·y) for e = lowest_binade + k.
    binade: [f64; BINADES],
    /// c_j^y.
    segment: [f64; SEGMENTS],
    /// 1/c_j.
    inverse_centre: [f64; SEGMENTS],
    /// The binomial coefficients C(y, k), k = 0..5.
    series: [f64; 6],
}

impl FixedPower {
    /// `coefficient`·x^`exponent` with tables for x in [2^`lowest_binade`, 2^(`lowest_binade` + 64)).
    /// `lowest_binade` lies in −1022..=959, so that every binade of the tables holds normal numbers
    /// and zero, subnormal, negative, infinite and NaN arguments all fall outside them.
    pub fn new(coefficient: f64, exponent: f64, lowest_binade: i64) -> Self {
        assert!((-1022..=959).contains(&lowest_binade), "lowest_binade {lowest_binade} outside −1022..=959");
        let centre = |j: usize| 1.0 + (j as f64 + 0.5) / SEGMENTS as f64;
        let mut series = [1.0; 6];
        for k in 1..6 {
            series[k] = series[k - 1] * (exponent - (k - 1) as f64) / k as f64;
        }
        FixedPower {
            coefficient,
            exponent,
            lowest_binade,
            binade: std::array::from_fn(|k| coefficient * libm::pow(2.0, (lowest_binade + k as i64) as f64 * exponent)),
            segment: std::array::from_fn(|j| libm::pow(centre(j), exponent)),
            inverse_centre: std::array::from_fn(|j| 1.0 / centre(j)),
            series,
        }
    }

    /// c·x^y.
    #[inline]
    pub fn of(&self, x: f64) -> f64 {
        let bits = x.to_bits();
        // x's binade within the tables; a negative x's sign bit, and the exponent field of zero,
        // subnormals, infinity and NaN, put it out of their range
        let binade = (bits >> 52) as i64 - 1023 - self.lowest_binade;
        if !(0..BINADES as i64).contains(&binade) {
            return self.coefficient * libm::pow(x, self.exponent);
        }
        let j = ((bits >> (52 - SEGMENT_BITS)) as usize) & (SEGMENTS - 1);
        let mantissa = f64::from_bits((bits & ((1 << 52) - 1)) | 1f64.to_bits());
        let s = mantissa * self.inverse_centre[j] - 1.0;
        let c = &self.series;
        // Estrin's scheme: three levels of dependent operations instead of Horner's five
        let s2 = s * s;
        let series = (c[0] + c[1] * s) + s2 * ((c[2] + c[3] * s) + s2 * (c[4] + c[5] * s));
        self.binade[binade as usize] * self.segment[j] * series
    }
}

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    /// Against `powf` over the tables' range and beyond it, for the exponents of the polytropic
    /// laws (n from 1 to 1.67: −1/n and −n) and a positive one.
    #[test]
    fn matches_powf_to_its_bound() {
        for exponent in [-1.0 / 1.4, -1.4, -1.0, -1.0 / 1.67, -1.67, 0.5, 1.67] {
            for lowest_binade in [-40, 10] {
                let power = FixedPower::new(3.7, exponent, lowest_binade);
                let mut worst: f64 = 0.0;
                // from 4 binades below the tables to 4 above, on a grid finer than the segments
                let (lo, hi) = ((lowest_binade - 4) as f64, (lowest_binade + BINADES as i64 + 4) as f64);
                for k in 0..=200_000 {
                    let x = 2f64.powf(lo + (hi - lo) * k as f64 / 200_000.0);
                    let exact = 3.7 * x.powf(exponent);
                    worst = worst.max((power.of(x) / exact - 1.0).abs());
                }
                assert!(worst <= 2e-14, "y {exponent}, binades from {lowest_binade}: relative error {worst:e}");
            }
        }
    }

    #[test]
    fn segment_and_binade_edges() {
        let power = FixedPower::new(1.0, -1.0 / 1.4, 10);
        for x in
            [1024.0, 2048.0, 1.5 * 1024.0, f64::from_bits(2048f64.to_bits() - 1), 2f64.powi(74), 2f64.powi(73) * 1.999]
        {
            assert!((power.of(x) / x.powf(-1.0 / 1.4) - 1.0).abs() <= 2e-14, "x {x}");
        }
        // not a positive normal number: powf's answer
        for x in [0.0, -1.0, f64::INFINITY, f64::MIN_POSITIVE / 4.0] {
            let (a, b) = (power.of(x), x.powf(-1.0 / 1.4));
            assert!(a == b || (a.is_nan() && b.is_nan()), "x {x}: {a} against {b}");
        }
        assert!(power.of(f64::NAN).is_nan());
    }
}
