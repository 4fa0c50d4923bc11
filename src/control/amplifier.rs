//! The power amplifier's pure delay (3 ms in the paper) as a FIFO of controller samples.

use crate::physics::params::MAX_DELAY_SAMPLES;

/// Fixed-capacity delay line: `push` returns the value pushed `len` samples earlier.
#[derive(Clone, Copy, Debug)]
pub struct DelayLine {
    buffer: [f64; MAX_DELAY_SAMPLES + 1],
    len: usize,
    head: usize,
}

impl DelayLine {
    /// A delay of `len` samples (clamped to the capacity) whose history is `value`.
    pub fn filled(len: usize, value: f64) -> Self {
        DelayLine { buffer: [value; MAX_DELAY_SAMPLES + 1], len: len.min(MAX_DELAY_SAMPLES), head: 0 }
    }

    /// Mutable access to every field, for FMU-state serialisation.
    pub fn fields_mut(&mut self) -> (&mut [f64; MAX_DELAY_SAMPLES + 1], &mut usize, &mut usize) {
        (&mut self.buffer, &mut self.len, &mut self.head)
    }

    /// True when this line has `len` samples and a valid read position (checks restored states).
    pub fn is_consistent(&self, len: usize) -> bool {
        self.len == len && (self.head < self.len || self.len == 0)
    }

    /// Makes this line equal to `from` for every use: its live entries, length and read
    /// position. The slots beyond `len` are never read or written, so they are left as they are:
    /// a plain copy would move all 201 slots (1.6 KB) at every step's save.
    pub fn assign(&mut self, from: &DelayLine) {
        self.buffer[..from.len].copy_from_slice(&from.buffer[..from.len]);
        self.len = from.len;
        self.head = from.head;
    }

    /// Pushes `value` and returns the value from `len` samples ago (`value` itself if `len` = 0).
    pub fn push(&mut self, value: f64) -> f64 {
        if self.len == 0 {
            return value;
        }
        let out = self.buffer[self.head];
        self.buffer[self.head] = value;
        self.head = (self.head + 1) % self.len;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delays_by_exactly_len_samples() {
        let mut d = DelayLine::filled(6, -1.0);
        let out: Vec<f64> = (0..10).map(|k| d.push(k as f64)).collect();
        assert_eq!(out, [-1.0, -1.0, -1.0, -1.0, -1.0, -1.0, 0.0, 1.0, 2.0, 3.0]);
        let mut none = DelayLine::filled(0, 0.0);
        assert_eq!(none.push(5.0), 5.0);
    }

    #[test]
    fn an_assigned_line_continues_as_its_source() {
        let mut source = DelayLine::filled(4, 0.0);
        for k in 0..6 {
            source.push(k as f64);
        }
        let mut copy = DelayLine::filled(9, -7.0);
        copy.assign(&source);
        assert!(copy.is_consistent(4));
        for k in 6..20 {
            assert_eq!(copy.push(k as f64), source.push(k as f64));
        }
    }
}
