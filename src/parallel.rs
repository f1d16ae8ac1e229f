//! A map over indices on every available core, whose result does not depend on the thread
//! count: the distance grid's nodes, the print raster's layers, the optimizer's independent
//! solves.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread;

/// Nodes per block handed to one thread at a time.
const BLOCK: usize = 1024;

/// `(0..count).map(f).collect()`, with blocks of `BLOCK` indices handed out to up to
/// `available_parallelism` threads, each taking the next block as it finishes one. Each element
/// depends only on its index, so the result does not depend on the thread count or on which
/// thread computed what.
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

/// [`map_nodes`] on `threads` threads (at least one), in blocks of `block` indices. A thread
/// takes the next block not yet taken whenever it is free, so a costly element (a solve that
/// runs long) holds up one thread, not every block dealt to it after.
fn map_blocks_on<T: Send>(
    threads: usize,
    block: usize,
    count: usize,
    f: impl Fn(usize) -> T + Sync,
) -> Vec<T> {
    let threads = threads.max(1);
    let block = block.max(1);
    let blocks = count.div_ceil(block);
    let next = AtomicUsize::new(0);
    let (f, next) = (&f, &next);
    let done: Vec<Vec<(usize, Vec<T>)>> = thread::scope(|scope| {
        let handles: Vec<_> = (0..threads.min(blocks))
            .map(|_| {
                scope.spawn(move || {
                    let mut done = Vec::new();
                    loop {
                        let b = next.fetch_add(1, Ordering::Relaxed);
                        if b >= blocks {
                            return done;
                        }
                        done.push((
                            b,
                            (b * block..((b + 1) * block).min(count)).map(f).collect(),
                        ));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    let mut in_order: Vec<Option<Vec<T>>> = (0..blocks).map(|_| None).collect();
    for (b, values) in done.into_iter().flatten() {
        in_order[b] = Some(values);
    }
    let mut out = Vec::with_capacity(count);
    out.extend(in_order.into_iter().flatten().flatten());
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
