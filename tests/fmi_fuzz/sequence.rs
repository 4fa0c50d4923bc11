//! One run of random call sequences over the FMUs of one standard: live instances (kept across
//! sequences, up to [`MAX_LIVE`]), FMU states and serialized blobs (shared between instances and,
//! on purpose, between the FMUs), each call's status checked against the mirror of the state table.

use super::library::{fmus, Fmu, Instantiation, Standard, FMUS, H, S};
use super::mirror::{may_succeed, Call, Phase};
use super::report::{name, Report};
use super::rng::Rng;
use super::watchdog::Watchdog;

/// Most instances alive at once.
const MAX_LIVE: usize = 24;

pub(super) struct Instance {
    pub(super) fmu: usize,
    pub(super) c: H,
    pub(super) phase: Phase,
    pub(super) start: f64,
    pub(super) stop: Option<f64>,
    /// The FMU's time once initialised.
    pub(super) time: f64,
    /// FMI 3.0: the experiment (tolerance, start, stop) the next fmi3EnterInitializationMode
    /// passes, drawn where FMI 2.0 calls fmi2SetupExperiment.
    pub(super) experiment: (Option<f64>, f64, Option<f64>),
}

pub(super) struct State {
    pub(super) fmu: usize,
    pub(super) ptr: H,
    /// The time of an initialised state; `None` before initialisation; unknown (outer `None`)
    /// after a mutated blob was accepted.
    pub(super) time: Option<Option<f64>>,
}

pub(super) struct Blob {
    pub(super) fmu: usize,
    pub(super) bytes: Vec<u8>,
    /// As [`State::time`].
    pub(super) time: Option<Option<f64>>,
}

pub struct Fuzzer<'a> {
    pub(super) standard: Standard,
    pub(super) rng: Rng,
    pub(super) seed: u64,
    pub(super) sequence: u64,
    pub(super) dog: &'a Watchdog,
    pub report: Report,
    pub(super) live: Vec<Instance>,
    pub(super) states: Vec<State>,
    pub(super) blobs: Vec<Blob>,
}

impl<'a> Fuzzer<'a> {
    pub fn new(standard: Standard, seed: u64, dog: &'a Watchdog) -> Self {
        let rng = Rng::new(seed);
        let report = Report::default();
        Fuzzer { standard, rng, seed, sequence: 0, dog, report, live: vec![], states: vec![], blobs: vec![] }
    }

    /// FMU `fmu` of the run's standard.
    pub(super) fn api(&self, fmu: usize) -> &'static Fmu {
        &fmus(self.standard)[fmu]
    }

    /// Runs `n` sequences and frees everything.
    pub fn run(mut self, n: u64) -> Report {
        for k in 0..n {
            self.sequence = k;
            self.dog.at(self.seed, k);
            self.one_sequence();
            self.report.sequences += 1;
        }
        while !self.live.is_empty() {
            self.free_instance(0);
        }
        self.free_states();
        self.report
    }

    /// Records a call's status; `may_ok`: the standard allows OK here; `may_discard`: a step.
    pub(super) fn check(&mut self, what: &str, status: S, may_ok: bool, may_discard: bool) {
        self.report.calls += 1;
        self.report.statuses[(status as usize).min(5)] += 1;
        let bad = match status {
            OK | WARNING => !may_ok,
            DISCARD => !may_discard,
            ERROR => false,
            FATAL => {
                self.report.panics += 1;
                true
            }
            _ => true,
        };
        if bad {
            if status != FATAL {
                self.report.non_conforming += 1;
            }
            let (seed, seq) = (self.seed, self.sequence);
            self.report.fail(format!("seed {seed} sequence {seq}: {what} returned {}", name(status)));
        }
    }

    fn one_sequence(&mut self) {
        if self.live.is_empty() || self.rng.chance(0.3) {
            self.instantiate();
        }
        // half the sequences start from an instance taken legally to stepping, with random
        // parameters, so that steps, states and their corruption get their share of the calls
        if self.rng.chance(0.5) {
            let k = self.live.len() - 1;
            for _ in 0..self.rng.below(4) {
                self.set_legal_parameter(k);
            }
            self.setup_experiment_at(k, 0.0);
            self.enter_initialization(k);
            self.exit_initialization(k);
        }
        for _ in 0..20 + self.rng.below(40) {
            self.one_call();
        }
        // many instances stay alive; some go, and with them the states once in a while
        while self.live.len() > MAX_LIVE || (!self.live.is_empty() && self.rng.chance(0.2)) {
            let k = self.rng.below(self.live.len());
            self.free_instance(k);
        }
        if self.states.len() > 16 || self.rng.chance(0.1) {
            self.free_states();
        }
        if self.blobs.len() > 16 {
            self.blobs.drain(..8);
        }
    }

    fn one_call(&mut self) {
        if self.live.is_empty() {
            self.instantiate();
            return;
        }
        // mostly the sequence's newest instance, so that a lifecycle gets somewhere
        let newest = self.live.len() - 1;
        let k = if self.rng.chance(0.7) { newest } else { self.rng.below(self.live.len()) };
        match self.rng.below(100) {
            0..=3 => self.instantiate(),
            4 => self.bad_instantiate(),
            5 => self.free_instance(k),
            6..=9 => self.setup_experiment(k),
            10..=13 => self.enter_initialization(k),
            14..=18 => self.exit_initialization(k),
            19 => self.terminate(k),
            20..=21 => self.reset(k),
            22..=33 => self.set_real(k),
            34..=36 => self.set_integer_or_boolean(k),
            37 => self.strings(k),
            38..=43 => self.get_all(k),
            44..=65 => {
                // steps mostly go to an instance that can take them
                let ready: Vec<usize> =
                    (0..self.live.len()).filter(|&i| self.live[i].phase == Phase::StepComplete).collect();
                let k = if !ready.is_empty() && self.rng.chance(0.8) { *self.rng.pick(&ready) } else { k };
                self.do_step(k)
            }
            66..=70 => self.get_state(k),
            71..=75 => self.set_state(k),
            76..=77 => self.free_state(k),
            78..=82 => self.serialize(k),
            83..=90 => self.deserialize(k),
            91..=95 => self.status(k),
            _ => self.debug_logging(k),
        }
    }

    fn instantiate(&mut self) {
        let fmu = self.rng.below(FMUS);
        let logging = self.rng.chance(0.5);
        let f = self.api(fmu);
        let what = f.name("fmi2Instantiate", "fmi3InstantiateCoSimulation");
        // SAFETY: the instance is kept in `live` and freed once.
        let c = self.dog.call(what, || unsafe { f.instantiate(Instantiation::Valid, logging, "") });
        self.report.calls += 1;
        if c.is_null() {
            self.report.non_conforming += 1;
            self.report.fail(format!("seed {} sequence {}: valid {what} returned NULL", self.seed, self.sequence));
            return;
        }
        let experiment = (None, 0.0, None);
        self.live.push(Instance { fmu, c, phase: Phase::Instantiated, start: 0.0, stop: None, time: 0.0, experiment });
    }

    /// NULL or empty name, another FMU's or a NULL GUID, Model Exchange; for FMI 3.0 also Event
    /// Mode and intermediate variables: must give NULL.
    fn bad_instantiate(&mut self) {
        let fmu = self.rng.below(FMUS);
        let other = self.api((fmu + 1) % FMUS).info.guid.clone();
        let mut ways = vec![
            Instantiation::NullName,
            Instantiation::EmptyName,
            Instantiation::OtherGuid,
            Instantiation::NullGuid,
            Instantiation::ModelExchange,
        ];
        if self.standard == Standard::Fmi3 {
            ways.extend([Instantiation::EventMode, Instantiation::IntermediateVariables]);
        }
        let how = *self.rng.pick(&ways);
        let f = self.api(fmu);
        // SAFETY: an instance the FMU gives by mistake is freed below.
        let c = self.dog.call("instantiate (bad)", || unsafe { f.instantiate(how, false, &other) });
        self.report.calls += 1;
        if !c.is_null() {
            self.report.non_conforming += 1;
            self.report.fail(format!("seed {} sequence {}: {how:?} gave an instance", self.seed, self.sequence));
            // SAFETY: c is an instance of this library, freed once.
            unsafe { (f.common.free_instance)(c) };
        }
    }

    fn free_instance(&mut self, k: usize) {
        let i = self.live.swap_remove(k);
        let f = self.api(i.fmu);
        // SAFETY: i.c is a live instance of this library, not used afterwards.
        self.dog.call("free instance", || unsafe { (f.common.free_instance)(i.c) });
        self.report.calls += 1;
    }

    /// Frees every state through a fresh instance of its FMU.
    fn free_states(&mut self) {
        for s in std::mem::take(&mut self.states) {
            let f = self.api(s.fmu);
            let mut ptr = s.ptr;
            // SAFETY: a fresh instance; ptr is a live state of this FMU, freed once.
            let status = unsafe {
                let c = f.instantiate(Instantiation::Valid, false, "");
                let status = (f.common.free_fmu_state)(c, &mut ptr);
                (f.common.free_instance)(c);
                status
            };
            self.check("free FMU state (cleanup)", status, true, false);
            if status != OK {
                self.report.non_conforming += 1;
                self.report.fail(format!("seed {} sequence {}: a state could not be freed", self.seed, self.sequence));
            }
        }
    }

    pub(super) fn time_value(&mut self) -> f64 {
        *self.rng.pick(&[0.0, 0.0, 0.0, 0.25, -3.0, 1e3, 1e7, 1e100, -1e300, f64::NAN, f64::INFINITY, -0.0])
    }

    fn setup_experiment(&mut self, k: usize) {
        let start = self.time_value();
        self.setup_experiment_at(k, start);
    }

    /// The experiment: FMI 2.0's fmi2SetupExperiment; for FMI 3.0, drawn for the next
    /// fmi3EnterInitializationMode.
    fn setup_experiment_at(&mut self, k: usize, start: f64) {
        let stop = match self.rng.below(4) {
            0 => Some(start + self.rng.unit()),
            1 => Some(start - 1.0),
            2 => Some(self.time_value()),
            _ => None,
        };
        let tol = Some(*self.rng.pick(&[1e-4, 0.0, -1.0, f64::NAN]));
        let (c, fmu, phase) = (self.live[k].c, self.live[k].fmu, self.live[k].phase);
        let f = self.api(fmu);
        // SAFETY: c is a live instance of this FMU; the other arguments are plain values.
        let Some(status) = self.dog.call("fmi2SetupExperiment", || unsafe { f.setup_experiment(c, tol, start, stop) })
        else {
            self.live[k].experiment = (tol, start, stop);
            return;
        };
        let valid = start.is_finite() && stop.is_none_or(|s| s.is_finite() && s >= start);
        let may = may_succeed(self.standard, phase, Call::SetupExperiment) && valid;
        self.check("fmi2SetupExperiment", status, may, false);
        if status == OK {
            let i = &mut self.live[k];
            (i.start, i.stop) = (start, stop);
        }
    }
}

pub(super) const OK: S = 0;
pub(super) const WARNING: S = 1;
pub(super) const DISCARD: S = 2;
pub(super) const ERROR: S = 3;
pub(super) const FATAL: S = 4;
