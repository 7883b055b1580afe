//! The scenario families' runs across threads: each worker takes the next scenario, the
//! outcomes come back in the scenarios' order.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// `run` on every item on `threads` threads (at least one), `progress` called on each outcome
/// as it comes; the outcomes in the items' order.
pub fn in_parallel<T: Sync, O: Send>(
    items: &[T],
    threads: usize,
    run: &(dyn Fn(&T) -> O + Sync),
    progress: &(dyn Fn(&O) + Sync),
) -> Vec<O> {
    let next = AtomicUsize::new(0);
    let out: Mutex<Vec<(usize, O)>> = Mutex::new(Vec::new());
    std::thread::scope(|sc| {
        for _ in 0..threads.max(1) {
            sc.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    let Some(item) = items.get(i) else { break };
                    let o = run(item);
                    progress(&o);
                    if let Ok(mut v) = out.lock() {
                        v.push((i, o));
                    }
                }
            });
        }
    });
    let mut v = out.into_inner().unwrap_or_default();
    v.sort_by_key(|(i, _)| *i);
    v.into_iter().map(|(_, o)| o).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcomes_come_back_in_order_and_each_is_reported_once() {
        let items: Vec<u64> = (0..50).collect();
        let seen = AtomicUsize::new(0);
        let out = in_parallel(&items, 3, &|x| x * x, &|_| {
            seen.fetch_add(1, Ordering::SeqCst);
        });
        assert_eq!(out, items.iter().map(|x| x * x).collect::<Vec<_>>());
        assert_eq!(seen.load(Ordering::SeqCst), 50);
    }
}
