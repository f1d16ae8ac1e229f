//! A map over indices on every available core, whose result does not depend on the thread
//! count: the distance grid's nodes, the print raster's layers, the optimizer's independent
//! solves.

use std::thread;

/// Nodes per block handed to one thread at a time.
const BLOCK: usize = 1024;

/// `(0..count).map(f).collect()`, with blocks of `BLOCK` indices dealt round-robin to up to
/// `available_parallelism` threads. Each element depends only on its index, so the result does
/// not depend on the thread count.
pub(crate) fn map_nodes<T: Send>(count: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    map_blocks_on(cores(), BLOCK, count, f)
}

/// As [`map_nodes`], one index at a time: for few, costly elements (a print layer).
pub(crate) fn map_each<T: Send>(count: usize, f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    map_blocks_on(cores(), 1, count, f)
}

/// The cores available: how many threads [`map_each`] runs at most.
pub(crate) fn cores() -> usize {
    thread::available_parallelism().map_or(1, |n| n.get())
}

/// [`map_nodes`] on `threads` threads (at least one), in blocks of `block` indices.
fn map_blocks_on<T: Send>(
    threads: usize,
    block: usize,
    count: usize,
    f: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let threads = threads.max(1);
    let block = block.max(1);
    let blocks = count.div_ceil(block);
    let f = &f;
    let per_thread: Vec<Vec<Vec<T>>> = thread::scope(|scope| {
        let handles: Vec<_> = (0..threads.min(blocks))
            .map(|t| {
                scope.spawn(move || {
                    (t..blocks)
                        .step_by(threads)
                        .map(|b| (b * block..((b + 1) * block).min(count)).map(f).collect())
                        .collect()
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    let mut iters: Vec<_> = per_thread.into_iter().map(Vec::into_iter).collect();
    let mut out = Vec::with_capacity(count);
    for b in 0..blocks {
        out.extend(iters[b % threads].next().into_iter().flatten());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{map_blocks_on, BLOCK};

    #[test]
    fn the_result_does_not_depend_on_the_thread_count() {
        let f = |i: usize| (i as f64).sqrt().sin();
        for count in [0, 1, 1023, 1024, 1025, 5000] {
            let sequential: Vec<f64> = (0..count).map(f).collect();
            for threads in [0, 1, 2, 3, 7] {
                for block in [1, BLOCK] {
                    assert_eq!(
                        map_blocks_on(threads, block, count, f),
                        sequential,
                        "{threads} threads, blocks of {block}, {count} nodes"
                    );
                }
            }
        }
    }
}
