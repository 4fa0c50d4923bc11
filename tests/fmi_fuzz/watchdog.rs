//! Hang detection: the fuzzer runs on a worker thread and marks the start and end of every call;
//! the test's thread fails the test as soon as one call has run for longer than [`LIMIT`].

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The criterion: any call over 1 s is a hang. `CALL_SEQUENCES_HANG_SECONDS` raises it for
/// runs under valgrind, which is some 50 times slower.
pub fn limit() -> Duration {
    let seconds = std::env::var("CALL_SEQUENCES_HANG_SECONDS").ok().and_then(|s| s.parse().ok());
    Duration::from_secs_f64(seconds.unwrap_or(1.0))
}

pub struct Watchdog {
    base: Instant,
    /// Nanoseconds since `base` at which the running call started, 0 when none runs.
    started: AtomicU64,
    /// The running call, for the failure message.
    what: Mutex<&'static str>,
    /// Longest call so far (ns).
    pub longest: AtomicU64,
    /// Seed and sequence being run, for the failure message.
    seed: AtomicU64,
    sequence: AtomicU64,
}

impl Watchdog {
    fn now(&self) -> u64 {
        self.base.elapsed().as_nanos() as u64 + 1
    }

    /// Records which sequence runs.
    pub fn at(&self, seed: u64, sequence: u64) {
        self.seed.store(seed, Ordering::Relaxed);
        self.sequence.store(sequence, Ordering::Relaxed);
    }

    /// Times one call.
    pub fn call<T>(&self, what: &'static str, f: impl FnOnce() -> T) -> T {
        *self.what.lock().unwrap() = what;
        let start = self.now();
        self.started.store(start, Ordering::SeqCst);
        let out = f();
        self.started.store(0, Ordering::SeqCst);
        self.longest.fetch_max(self.now() - start, Ordering::Relaxed);
        out
    }
}

/// Runs `work` on a worker thread under a watchdog; panics (failing the test) if one call takes
/// longer than [`limit`], naming the call, the seed and the sequence.
pub fn run<T: Send + 'static>(work: impl FnOnce(Arc<Watchdog>) -> T + Send + 'static) -> T {
    let dog = Arc::new(Watchdog {
        base: Instant::now(),
        started: AtomicU64::new(0),
        what: Mutex::new(""),
        longest: AtomicU64::new(0),
        seed: AtomicU64::new(0),
        sequence: AtomicU64::new(0),
    });
    let limit = limit();
    let worker = {
        let dog = dog.clone();
        std::thread::spawn(move || work(dog))
    };
    while !worker.is_finished() {
        std::thread::sleep(Duration::from_millis(20));
        let started = dog.started.load(Ordering::SeqCst);
        if started != 0 && dog.now().saturating_sub(started) > limit.as_nanos() as u64 {
            let what = *dog.what.lock().unwrap();
            let (seed, sequence) = (dog.seed.load(Ordering::Relaxed), dog.sequence.load(Ordering::Relaxed));
            panic!("hang: {what} has run for more than {limit:?} (seed {seed}, sequence {sequence})");
        }
    }
    worker.join().unwrap_or_else(|e| std::panic::resume_unwind(e))
}
