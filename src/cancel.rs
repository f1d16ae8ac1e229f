//! A request, from another thread, that long work stop early.
//!
//! Watch mode hands one [`Cancel`] to every build; a newer save sets it, and the stages that can
//! take long (distance grids, skeletons, optimizer solves) look at it often and give up. Work that
//! was given up is never kept: a grid left half sampled is not cached, and a build that was
//! cancelled writes nothing.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A shared flag: clones see the same flag. The default is never set.
#[derive(Debug, Clone, Default)]
pub struct Cancel {
    flag: Arc<AtomicBool>,
}

impl Cancel {
    /// A flag not set yet.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the work holding a clone of this flag to stop.
    pub fn cancel(&self) {
        self.flag.store(true, Ordering::SeqCst);
    }

    /// Clears the flag, for the next piece of work.
    pub fn reset(&self) {
        self.flag.store(false, Ordering::SeqCst);
    }

    /// Whether stopping was asked for.
    pub fn is_cancelled(&self) -> bool {
        self.flag.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::Cancel;

    #[test]
    fn clones_share_the_flag_and_reset_clears_it() {
        let cancel = Cancel::new();
        let seen_elsewhere = cancel.clone();
        assert!(!seen_elsewhere.is_cancelled());
        std::thread::spawn(move || cancel.cancel()).join().unwrap();
        assert!(seen_elsewhere.is_cancelled());
        seen_elsewhere.reset();
        assert!(!seen_elsewhere.is_cancelled());
    }
}
