//! Reproducible random numbers for the unit tests that sweep states and matrices.

/// Uniform numbers in [0, 1) from Marsaglia's xorshift64 with the non-zero `seed`.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}
