//! What a run found: counts by kind and the first failures, each with its seed and sequence.

#[derive(Default, Debug)]
pub struct Report {
    pub sequences: u64,
    pub calls: u64,
    /// A step answered OK.
    pub steps: u64,
    /// Fatal: a panic the FFI guard caught.
    pub panics: u64,
    /// A Real getter answered OK with NaN or infinity.
    pub non_finite: u64,
    /// A status the standard does not allow for that call in that state (OK where it must fail,
    /// Discard outside a step, Pending, an unknown code, a refusal of the FMU's own state).
    pub non_conforming: u64,
    /// Statuses seen, by code 0..=5.
    pub statuses: [u64; 6],
    pub failures: Vec<String>,
}

impl Report {
    pub fn fail(&mut self, what: String) {
        if self.failures.len() < 20 {
            self.failures.push(what);
        }
    }

    pub fn is_clean(&self) -> bool {
        self.panics == 0 && self.non_finite == 0 && self.non_conforming == 0
    }

    pub fn add(&mut self, other: Report) {
        self.sequences += other.sequences;
        self.calls += other.calls;
        self.steps += other.steps;
        self.panics += other.panics;
        self.non_finite += other.non_finite;
        self.non_conforming += other.non_conforming;
        for (a, b) in self.statuses.iter_mut().zip(other.statuses) {
            *a += b;
        }
        for f in other.failures {
            self.fail(f);
        }
    }

    pub fn summary(&self) -> String {
        let s = &self.statuses;
        format!(
            "{} sequences, {} calls ({} steps OK): {} panics, {} non-finite values after OK, {} non-conforming statuses \
             (OK {}, Warning {}, Discard {}, Error {}, Fatal {}, Pending {})",
            self.sequences, self.calls, self.steps, self.panics, self.non_finite, self.non_conforming, s[0], s[1], s[2], s[3], s[4], s[5]
        )
    }
}

/// A status code's name.
pub fn name(status: u32) -> &'static str {
    ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"].get(status as usize).copied().unwrap_or("unknown")
}
