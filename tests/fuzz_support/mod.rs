//! What the mutation fuzzers share: a reproducible random generator, the time budget and the
//! loop that runs every seed, then mutations of the seeds (and of inputs worth keeping) until
//! the budget is spent, timing each input.
//!
//! `BALLAST_FUZZ_SECONDS` sets the budget (each fuzzer has its own default; `.ci/run` gives more)
//! and `BALLAST_FUZZ_SEED` the sequence (default 1), so a failure can be replayed.

use std::time::{Duration, Instant};

/// xorshift64*: reproducible from its seed, independent of the platform.
pub struct Rng(u64);

impl Rng {
    /// The generator of seed `BALLAST_FUZZ_SEED` (1 when not set).
    pub fn from_env() -> Rng {
        let seed: u64 = std::env::var("BALLAST_FUZZ_SEED")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(1);
        Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1)
    }

    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// The budget: `BALLAST_FUZZ_SECONDS` seconds, else `default_seconds`.
pub fn budget(default_seconds: f64) -> Duration {
    let seconds = std::env::var("BALLAST_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default_seconds);
    Duration::from_secs_f64(seconds)
}

/// What a fuzzing run did.
pub struct Campaign<T> {
    /// Inputs run, seeds included.
    pub runs: usize,
    /// Inputs kept to mutate from, beyond the seeds.
    pub kept: usize,
    /// How long the slowest input took, and that input.
    pub slowest: (Duration, Option<T>),
    /// How long the whole run took.
    pub elapsed: Duration,
}

/// At most this many inputs are mutated from (the seeds and the inputs kept).
const POOL: usize = 256;

/// Runs `test` on every seed, then on mutations (`mutate` of a random input of the pool, with
/// the seeds to splice from) until `budget` is spent. An input for which `test` returns `true`
/// joins the pool (up to [`POOL`]). Each call of `test` is timed.
pub fn campaign<T: Clone>(
    seeds: &[T],
    budget: Duration,
    rng: &mut Rng,
    mutate: impl Fn(&mut Rng, &T, &[T]) -> T,
    mut test: impl FnMut(&T) -> bool,
) -> Campaign<T> {
    let start = Instant::now();
    let mut pool: Vec<T> = seeds.to_vec();
    let mut done = Campaign {
        runs: 0,
        kept: 0,
        slowest: (Duration::ZERO, None),
        elapsed: Duration::ZERO,
    };
    while done.runs < seeds.len() || start.elapsed() < budget {
        let input = if done.runs < seeds.len() {
            seeds[done.runs].clone()
        } else {
            let base = &pool[rng.below(pool.len())];
            mutate(rng, base, seeds)
        };
        let took = Instant::now();
        let keep = test(&input);
        let took = took.elapsed();
        if took > done.slowest.0 {
            done.slowest = (took, Some(input.clone()));
        }
        if keep && done.runs >= seeds.len() && pool.len() < POOL {
            pool.push(input);
            done.kept += 1;
        }
        done.runs += 1;
    }
    done.elapsed = start.elapsed();
    done
}
