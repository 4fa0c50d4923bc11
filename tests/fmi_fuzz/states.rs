//! The fuzzer's FMU-state calls: get, set and free states, serialize them, and deserialize blobs
//! as written, mutated, or made by the other FMU.

use super::mirror::Phase;
use super::model_info::Type;
use super::sequence::{Blob, Fuzzer, State, OK};
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
        let f = self.api(fmu);
        let what = f.name("fmi2GetFMUstate", "fmi3GetFMUState");
        // SAFETY: c is live; ptr is NULL or a live state of this FMU.
        let status = self.dog.call(what, || unsafe { (f.common.get_fmu_state)(c, &mut ptr) });
        self.check(what, status, true, false);
        if status != OK {
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
        let f = self.api(fmu);
        let what = f.name("fmi2SetFMUstate", "fmi3SetFMUState");
        // SAFETY: c is live; ptr is a live state of one of the FMUs (the others' must be refused).
        let status = self.dog.call(what, || unsafe { (f.common.set_fmu_state)(c, ptr) });
        self.check(what, status, own, false);
        if status != OK {
            return;
        }
        let time = match known {
            Some(time) => time,
            // a mutated blob was accepted: ask the FMU whether the state is initialised
            None => self.probe_initialised(k),
        };
        let i = &mut self.live[k];
        match time {
            Some(t) => (i.phase, i.time) = (Phase::StepComplete, t),
            None if !matches!(phase, Phase::Instantiated | Phase::InitializationMode) => i.phase = Phase::Instantiated,
            None => {}
        }
    }

    /// Whether the state instance `k` was just set to is initialised, and its time: FMI 2.0 tells
    /// by fmi2GetRealStatus (refused before initialisation), FMI 3.0 by setting a parameter
    /// (refused after it) and its time by the independent variable.
    fn probe_initialised(&mut self, k: usize) -> Option<f64> {
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let f = self.api(fmu);
        let mut t = f64::NAN;
        match &f.api {
            super::library::Api::Fmi2(f2) => {
                // SAFETY: c is live; t is a valid local (2: fmi2LastSuccessfulTime).
                let probe = unsafe { (f2.get_real_status)(c, 2, &mut t) };
                (probe == OK).then_some(t)
            }
            super::library::Api::Fmi3(_) => {
                let p =
                    f.info.of(Type::Real).find(|v| v.causality == "parameter" && v.min.is_some()).expect("a parameter");
                let (lo, time_vr) = (p.min.unwrap(), f.info.independent().expect("FMI 3.0 time"));
                // SAFETY: c is live; one value reference and one value each.
                unsafe {
                    if f.set_real(c, &p.vr, 1, &lo, 1) == OK {
                        return None;
                    }
                    (f.get_real(c, &time_vr, 1, &mut t, 1) == OK).then_some(t)
                }
            }
        }
    }

    pub(super) fn free_state(&mut self, k: usize) {
        let Some(s) = self.pick_state() else { return };
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let own = self.states[s].fmu == fmu;
        let mut ptr = self.states[s].ptr;
        let f = self.api(fmu);
        let what = f.name("fmi2FreeFMUstate", "fmi3FreeFMUState");
        // SAFETY: c is live; ptr is a live state of one of the FMUs (the others' must be refused).
        let status = self.dog.call(what, || unsafe { (f.common.free_fmu_state)(c, &mut ptr) });
        self.check(what, status, own, false);
        if status == OK {
            self.states.swap_remove(s);
        }
    }

    pub(super) fn serialize(&mut self, k: usize) {
        let Some(s) = self.pick_state() else { return };
        let (c, fmu) = (self.live[k].c, self.live[k].fmu);
        let (ptr, own, time) = (self.states[s].ptr, self.states[s].fmu == fmu, self.states[s].time);
        let mut size = 0usize;
        let f = self.api(fmu);
        let what = f.name("fmi2SerializedFMUstateSize", "fmi3SerializedFMUStateSize");
        // SAFETY: c is live; ptr a live state of one of the FMUs; size a valid local.
        let status = self.dog.call(what, || unsafe { (f.common.serialized_size)(c, ptr, &mut size) });
        self.check(what, status, own, false);
        if status != OK {
            return;
        }
        let short = self.rng.chance(0.05);
        let mut bytes = vec![0u8; if short { size / 2 } else { size }];
        let what = f.name("fmi2SerializeFMUstate", "fmi3SerializeFMUState");
        // SAFETY: c is live; bytes holds bytes.len() writable bytes.
        let status = self.dog.call(what, || unsafe { (f.common.serialize)(c, ptr, bytes.as_mut_ptr(), bytes.len()) });
        self.check(what, status, !short, false);
        if status == OK {
            self.blobs.push(Blob { fmu, bytes, time });
        }
    }

    /// Changes a blob: one bit, one byte, one word to a special number, its length, or all of it.
    fn mutate(&mut self, bytes: &mut Vec<u8>) {
        let n = bytes.len();
        match self.rng.below(6) {
            1 => bytes[self.rng.below(n)] = self.rng.next_u64() as u8,
            // a payload word (after the 70-byte header of magic, version, GUID and length)
            2 if n >= 78 => {
                let at = 70 + 8 * self.rng.below((n - 70) / 8);
                let x = *self.rng.pick(&SPECIALS);
                bytes[at..at + 8].copy_from_slice(&x.to_le_bytes());
            }
            0 | 2 => bytes[self.rng.below(n)] ^= 1 << self.rng.below(8),
            3 => bytes.truncate(self.rng.below(n)),
            4 => bytes.extend_from_slice(&[0; 8]),
            _ => {
                for b in bytes.iter_mut().skip(70) {
                    *b = self.rng.next_u64() as u8;
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
        let f = self.api(fmu);
        let what = f.name("fmi2DeSerializeFMUstate", "fmi3DeserializeFMUState");
        // SAFETY: c is live; bytes holds bytes.len() bytes; ptr is NULL or a live state of this FMU.
        let status =
            self.dog.call(what, || unsafe { (f.common.deserialize)(c, bytes.as_ptr(), bytes.len(), &mut ptr) });
        // what the FMU serialized, it must take back, in whatever state it was made
        let must = own && pristine;
        self.check(what, status, own, false);
        if must && status != OK {
            self.report.non_conforming += 1;
            let (seed, seq) = (self.seed, self.sequence);
            self.report.fail(format!("seed {seed} sequence {seq}: the FMU refused a state it serialized"));
        }
        if status != OK {
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
