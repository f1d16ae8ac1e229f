//! A request, from another thread, that long work stop early, and why.
//!
//! Watch mode hands one [`Cancel`] to every build; a newer save cancels it, and the stages that
//! can take long (distance grids, skeletons, optimizer solves) look at it often and give up. Work
//! that was given up is never kept: a grid left half sampled is not cached, and a build that was
//! cancelled writes nothing.
//!
//! `build` interrupts it instead (Ctrl-C, SIGTERM, its time limit): the search stops as when
//! cancelled, but the optimizer keeps the best design of the rounds it finished, and the build
//! writes it, marked as interrupted.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

use serde::Serialize;

/// Why `build` was stopped before its search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Interruption {
    /// Ctrl-C.
    #[serde(rename = "SIGINT")]
    Interrupt,
    /// A polite kill (SIGTERM).
    #[serde(rename = "SIGTERM")]
    Terminate,
    /// `build --time-limit` ran out.
    #[serde(rename = "time-limit")]
    TimeLimit,
}

impl Interruption {
    /// What stopped the build, for files a user reads: "Ctrl-C (SIGINT)", "SIGTERM" or
    /// "the time limit (`--time-limit`)".
    pub fn cause(self) -> &'static str {
        match self {
            Interruption::Interrupt => "Ctrl-C (SIGINT)",
            Interruption::Terminate => "SIGTERM",
            Interruption::TimeLimit => "the time limit (`--time-limit`)",
        }
    }
}

/// Not stopped.
const RUNNING: u8 = 0;
/// Cancelled: whatever was found is thrown away.
const CANCELLED: u8 = 1;

/// The flag's value for `interruption`.
fn code(interruption: Interruption) -> u8 {
    match interruption {
        Interruption::Interrupt => 2,
        Interruption::Terminate => 3,
        Interruption::TimeLimit => 4,
    }
}

/// A shared flag: clones see the same flag. The default is never set. The first request to stop
/// wins: a later one does not change why the work stopped.
#[derive(Debug, Clone, Default)]
pub struct Cancel {
    flag: Arc<AtomicU8>,
}

impl Cancel {
    /// A flag not set yet.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the work holding a clone of this flag to stop and keep nothing.
    pub fn cancel(&self) {
        self.stop(CANCELLED);
    }

    /// Asks the work holding a clone of this flag to stop and keep the best it found so far.
    pub fn interrupt(&self, why: Interruption) {
        self.stop(code(why));
    }

    fn stop(&self, value: u8) {
        let _ = self
            .flag
            .compare_exchange(RUNNING, value, Ordering::SeqCst, Ordering::SeqCst);
    }

    /// Clears the flag, for the next piece of work.
    pub fn reset(&self) {
        self.flag.store(RUNNING, Ordering::SeqCst);
    }

    /// Whether stopping was asked for, cancelled or interrupted.
    pub fn is_cancelled(&self) -> bool {
        self.flag.load(Ordering::Relaxed) != RUNNING
    }

    /// Why the work was interrupted, when it was interrupted rather than cancelled.
    pub fn interruption(&self) -> Option<Interruption> {
        let value = self.flag.load(Ordering::SeqCst);
        [
            Interruption::Interrupt,
            Interruption::Terminate,
            Interruption::TimeLimit,
        ]
        .into_iter()
        .find(|&why| code(why) == value)
    }
}

#[cfg(test)]
mod tests {
    use super::{Cancel, Interruption};

    #[test]
    fn clones_share_the_flag_and_reset_clears_it() {
        let cancel = Cancel::new();
        let seen_elsewhere = cancel.clone();
        assert!(!seen_elsewhere.is_cancelled());
        std::thread::spawn(move || cancel.cancel()).join().unwrap();
        assert!(seen_elsewhere.is_cancelled());
        assert_eq!(seen_elsewhere.interruption(), None);
        seen_elsewhere.reset();
        assert!(!seen_elsewhere.is_cancelled());
    }

    #[test]
    fn the_first_reason_to_stop_wins() {
        let cancel = Cancel::new();
        cancel.interrupt(Interruption::TimeLimit);
        cancel.interrupt(Interruption::Interrupt);
        cancel.cancel();
        assert!(cancel.is_cancelled());
        assert_eq!(cancel.interruption(), Some(Interruption::TimeLimit));
        cancel.reset();
        cancel.cancel();
        cancel.interrupt(Interruption::Terminate);
        assert_eq!(cancel.interruption(), None);
    }
}
