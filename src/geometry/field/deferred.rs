//! The distances of a grid's nodes far outside the surface, left out of the grid's build: a
//! thread of low priority computes them on a core the build leaves idle, and a read that comes
//! first computes its block itself. Either way the values are the same bits.

use std::sync::{Arc, OnceLock, Weak};

use super::blocks::Blocks;
use crate::geometry::tree::TriangleTree;

/// The blocks of a grid left out of its build, and what computes them.
#[derive(Debug, Clone)]
pub(super) struct Deferred {
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    blocks: Blocks,
    tree: TriangleTree,
    /// Each block's distances once computed, in the block's node order (empty for the blocks
    /// computed with the grid, which are never asked for).
    computed: Vec<OnceLock<Vec<f64>>>,
}

impl Deferred {
    /// The blocks `pending` of `blocks`, their distances from `tree`, and a thread that computes
    /// them one by one while the grid lives (when one can be started).
    pub(super) fn new(blocks: Blocks, tree: TriangleTree, pending: Vec<usize>) -> Deferred {
        let shared = Arc::new(Shared {
            blocks,
            tree,
            computed: (0..blocks.count()).map(|_| OnceLock::new()).collect(),
        });
        let weak = Arc::downgrade(&shared);
        // Without the thread every block is still computed when first read.
        let _ = std::thread::Builder::new()
            .name("ballast-grid".to_string())
            .spawn(move || fill(&weak, &pending));
        Deferred { shared }
    }

    /// The unsigned distance of the node of flat index `node`, which must lie in a pending block.
    pub(super) fn distance(&self, node: usize) -> f64 {
        let shared = &self.shared;
        let b = shared.blocks.of_node(node);
        shared.block(b)[shared.blocks.position_in_block(b, node)]
    }
}

impl Shared {
    /// Block `b`'s distances, computed now unless they were. A thread never waits for another:
    /// when two compute the same block, the one that finishes second keeps the first's (equal)
    /// values.
    fn block(&self, b: usize) -> &[f64] {
        let slot = &self.computed[b];
        if let Some(values) = slot.get() {
            return values;
        }
        let values = self
            .blocks
            .distances(&self.tree, b, self.blocks.bound(&self.tree, b));
        slot.get_or_init(|| values)
    }
}

/// Computes the blocks `pending` in turn, at the lowest priority, until they are done or the grid
/// is gone.
fn fill(shared: &Weak<Shared>, pending: &[usize]) {
    lower_priority();
    for &b in pending {
        let Some(shared) = shared.upgrade() else {
            return;
        };
        shared.block(b);
    }
}

/// Gives the calling thread the lowest scheduling priority, so it runs on cores nothing else
/// wants (Linux: a thread's nice value is its own).
fn lower_priority() {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: plain system calls on the calling thread, with no memory passed.
        unsafe {
            let thread = libc::syscall(libc::SYS_gettid) as libc::id_t;
            libc::setpriority(libc::PRIO_PROCESS, thread, 19);
        }
    }
}
