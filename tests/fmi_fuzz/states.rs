//! The fuzzer's FMU-state calls: get, set and free states, serialize them, and deserialize blobs
//! as written, mutated, or made by the other FMU.

use super::mirror::Phase;
use super::sequence::{api, Blob, Fuzzer, State};
use fmi2_slave::api::fmi2::*;
use std::ptr::null_mut;

/// Special numbers written over one word of a mutated blob.
const SPECIALS: [f64; 8] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e-158, 1e300, 0.0, -1.0, 5e-324];

impl Fuzzer<'_> {
    /// A state of any FMU (the other one's on purpose), or none.
    fn pick_state(&mut self) -> Option<usize> {
        (!self.states.is_empty()).then(|| self.rng.below(self.states.len()))
    }

    pub(super) fn get_state(&mut self, k: usize) {
        let (c, fmu, phase, time) = (self.live[k].c, self.live[k].fmu, self.live[k].phase, self.live[k].time);
        // overwrite an existing state of this FMU now and then (FMI 2.0 §2.1.8)
        let reuse = self.pick_state().filter(|&s| self.states[s].fmu == fmu && self.rng.chance(0.3));
        let mut ptr = reuse.map_or(null_mut(), |s| self.states[s].ptr);
        // SAFETY: c is live; ptr is NULL or a live state of this FMU.
        let status = self.dog.call("fmi2GetFMUstate", || unsafe { (api(fmu).api.get_fmu_state)(c, &mut ptr) });
        self.check("fmi2GetFMUstate", status, true, false);
        if status != fmi2Status_fmi2OK {
            return;
        }
        let initialised = matches!(phase, Phase::StepComplete | Phase::StepFailed | Phase::Terminated);
        let state = State { fmu, ptr, time: Some(initialised.then_some(time)) };
        match reuse {
            Some(s) => self.states[s] = state,
            None => self.states.push(state),
        }
    }

    pub(super) fn set_state(&mut self, k: usize) {
        let Some(s) = self.pick_state() else { return };
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let (ptr, own, known) = (self.states[s].ptr, self.states[s].fmu == fmu, self.states[s].time);
        // SAFETY: c is live; ptr is a live state of one of the two FMUs (the other's must be refused).
        let status = self.dog.call("fmi2SetFMUstate", || unsafe { (api(fmu).api.set_fmu_state)(c, ptr) });
        self.check("fmi2SetFMUstate", status, own, false);
        if status != fmi2Status_fmi2OK {
            return;
        }
        let time = match known {
            Some(time) => time,
            // a mutated blob was accepted: ask the FMU whether the state is initialised
            None => {
                let mut t = f64::NAN;
                // SAFETY: c is live; t is a valid local.
                let probe = unsafe { (api(fmu).api.get_real_status)(c, fmi2StatusKind_fmi2LastSuccessfulTime, &mut t) };
                (probe == fmi2Status_fmi2OK).then_some(t)
            }
        };
        let i = &mut self.live[k];
        match time {
            Some(t) => (i.phase, i.time) = (Phase::StepComplete, t),
            None if !matches!(phase, Phase::Instantiated | Phase::InitializationMode) => i.phase = Phase::Instantiated,
            None => {}
        }
    }

    pub(super) fn free_state(&mut self, k: usize) {
        let Some(s) = self.pick_state() else { return };
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let own = self.states[s].fmu == fmu;
        let mut ptr = self.states[s].ptr;
        // SAFETY: c is live; ptr is a live state of one of the two FMUs (the other's must be refused).
        let status = self.dog.call("fmi2FreeFMUstate", || unsafe { (api(fmu).api.free_fmu_state)(c, &mut ptr) });
        self.check("fmi2FreeFMUstate", status, own, false);
        if status == fmi2Status_fmi2OK {
            self.states.swap_remove(s);
        }
    }

    pub(super) fn serialize(&mut self, k: usize) {
        let Some(s) = self.pick_state() else { return };
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let (ptr, own, time) = (self.states[s].ptr, self.states[s].fmu == fmu, self.states[s].time);
        let mut size = 0usize;
        // SAFETY: c is live; ptr a live state of one of the FMUs; size a valid local.
        let status = self
            .dog
            .call("fmi2SerializedFMUstateSize", || unsafe { (api(fmu).api.serialized_size)(c, ptr, &mut size) });
        self.check("fmi2SerializedFMUstateSize", status, own, false);
        if status != fmi2Status_fmi2OK {
            return;
        }
        let short = self.rng.chance(0.05);
        let mut bytes = vec![0 as fmi2Byte; if short { size / 2 } else { size }];
        // SAFETY: c is live; bytes holds bytes.len() writable bytes.
        let status = self.dog.call("fmi2SerializeFMUstate", || unsafe {
            (api(fmu).api.serialize)(c, ptr, bytes.as_mut_ptr(), bytes.len())
        });
        self.check("fmi2SerializeFMUstate", status, !short, false);
        if status == fmi2Status_fmi2OK {
            self.blobs.push(Blob { fmu, bytes, time });
        }
    }

    /// Changes a blob: one bit, one byte, one word to a special number, its length, or all of it.
    fn mutate(&mut self, bytes: &mut Vec<fmi2Byte>) {
        let n = bytes.len();
        match self.rng.below(6) {
            1 => bytes[self.rng.below(n)] = self.rng.next_u64() as fmi2Byte,
            // a payload word (after the 70-byte header of magic, version, GUID and length)
            2 if n >= 78 => {
                let at = 70 + 8 * self.rng.below((n - 70) / 8);
                let x = *self.rng.pick(&SPECIALS);
                for (b, v) in bytes[at..at + 8].iter_mut().zip(x.to_le_bytes()) {
                    *b = v as fmi2Byte;
                }
            }
            0 | 2 => bytes[self.rng.below(n)] ^= 1 << self.rng.below(8),
            3 => bytes.truncate(self.rng.below(n)),
            4 => bytes.extend_from_slice(&[0; 8]),
            _ => {
                for b in bytes.iter_mut().skip(70) {
                    *b = self.rng.next_u64() as fmi2Byte;
                }
            }
        }
    }

    pub(super) fn deserialize(&mut self, k: usize) {
        if self.blobs.is_empty() {
            return;
        }
        let b = self.rng.below(self.blobs.len());
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let mut bytes = self.blobs[b].bytes.clone();
        // a blob of a state whose time is unknown is only restored mutated
        let pristine = self.rng.chance(0.5) && self.blobs[b].time.is_some();
        if !pristine && !bytes.is_empty() {
            self.mutate(&mut bytes);
        }
        let own = self.blobs[b].fmu == fmu;
        let reuse = self.pick_state().filter(|&s| self.states[s].fmu == fmu && self.rng.chance(0.3));
        let mut ptr = reuse.map_or(null_mut(), |s| self.states[s].ptr);
        // SAFETY: c is live; bytes holds bytes.len() bytes; ptr is NULL or a live state of this FMU.
        let status = self.dog.call("fmi2DeSerializeFMUstate", || unsafe {
            (api(fmu).api.deserialize)(c, bytes.as_ptr(), bytes.len(), &mut ptr)
        });
        // what the FMU serialized, it must take back, in whatever state it was made
        let must = own && pristine;
        self.check("fmi2DeSerializeFMUstate", status, own, false);
        if must && status != fmi2Status_fmi2OK {
            self.report.non_conforming += 1;
            let (seed, seq) = (self.seed, self.sequence);
            self.report.fail(format!("seed {seed} sequence {seq}: the FMU refused a state it serialized"));
        }
        if status != fmi2Status_fmi2OK {
            return;
        }
        let time = if pristine { self.blobs[b].time } else { None };
        let state = State { fmu, ptr, time };
        match reuse {
            Some(s) => self.states[s] = state,
            None => self.states.push(state),
        }
    }
}
