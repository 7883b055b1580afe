//! Where a long run is, and a way to stop it: the identify workflow and the diagnosis report
//! each stage as they start it (`choosing segments: 5 (2 of 3)`, `refining order 2 (1 of 3)`,
//! `diagnose: trying friction`) to the [`Reporter`] the front end installed on the calling
//! thread with [`reporting`]. Without one, nothing is reported and nothing is formatted.
//!
//! A reporter that says it was [`stopped`](Reporter::stopped) ends the run at the next stage
//! with [`Interrupted`]: Python's calls stop this way after a `KeyboardInterrupt`. The command
//! line prints the stages on standard error (a line each, or a spinner on a terminal) and
//! stops on a signal by exiting; the library itself never prints.
//!
//! Independent candidates run across the cores (`map`): each worker reports to the reporter
//! of the thread that started them, so a reporter is shared between threads and receives the
//! stages of parallel candidates in the order they start.

use std::cell::RefCell;
use std::sync::Arc;

use rayon::prelude::*;

/// Receives the stages of a run, in the order they start (candidates that run in parallel
/// report from their own threads).
pub trait Reporter: Send + Sync {
    /// A stage starts; `stage` is one line of text.
    fn stage(&self, stage: &str);

    /// Whether the run is to stop at its next stage.
    fn stopped(&self) -> bool {
        false
    }
}

/// The run was stopped by its caller ([`Reporter::stopped`]) before it ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("stopped by the caller (interrupted) before the run ended")]
pub struct Interrupted;

thread_local! {
    static REPORTER: RefCell<Option<Arc<dyn Reporter>>> = const { RefCell::new(None) };
}

/// Runs `f` with `reporter` receiving the stages reported on this thread, then restores the
/// reporter that was there before.
pub fn reporting<R>(reporter: Arc<dyn Reporter>, f: impl FnOnce() -> R) -> R {
    let before = REPORTER.with(|r| r.replace(Some(reporter)));
    // Restored on return and on unwinding alike.
    struct Restore(Option<Arc<dyn Reporter>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let before = self.0.take();
            REPORTER.with(|r| *r.borrow_mut() = before);
        }
    }
    let _restore = Restore(before);
    f()
}

/// Reports the stage `text` gives to this thread's reporter, if there is one (`text` is
/// called only then); [`Interrupted`] when the reporter says the run is to stop.
pub(crate) fn stage(text: impl FnOnce() -> String) -> Result<(), Interrupted> {
    let reporter = REPORTER.with(|r| r.borrow().clone());
    match reporter {
        Some(r) if r.stopped() => Err(Interrupted),
        Some(r) => {
            r.stage(&text());
            Ok(())
        }
        None => Ok(()),
    }
}

/// `f(i, item)` of each of `items`, across the cores (rayon's pool), in the items' order;
/// the stages the calls report reach this thread's reporter, and its
/// [`stopped`](Reporter::stopped) stops each of them. The calls are independent: the results
/// are those of calling them one after the other.
pub(crate) fn map<T: Sync, R: Send>(items: &[T], f: impl Fn(usize, &T) -> R + Sync) -> Vec<R> {
    let reporter = REPORTER.with(|r| r.borrow().clone());
    items
        .par_iter()
        .enumerate()
        .map(|(i, item)| match &reporter {
            Some(r) => reporting(r.clone(), || f(i, item)),
            None => f(i, item),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    use std::sync::Mutex;

    struct Collect(Mutex<Vec<String>>);
    impl Collect {
        fn new() -> Arc<Self> {
            Arc::new(Self(Mutex::new(Vec::new())))
        }
        fn stages(&self) -> Vec<String> {
            self.0.lock().unwrap().clone()
        }
    }
    impl Reporter for Collect {
        fn stage(&self, stage: &str) {
            self.0.lock().unwrap().push(stage.to_string());
        }
    }

    #[test]
    fn stages_reach_the_reporter_of_their_thread_only_while_it_is_installed() {
        let outer = Collect::new();
        let inner = Collect::new();
        stage(|| unreachable!("no reporter: nothing is formatted")).unwrap();
        reporting(outer.clone(), || {
            stage(|| "a".into()).unwrap();
            reporting(inner.clone(), || stage(|| "b".into())).unwrap();
            stage(|| "c".into()).unwrap();
            std::thread::scope(|s| {
                s.spawn(|| stage(|| "another thread".into()));
            });
        });
        stage(|| unreachable!("removed again")).unwrap();
        assert_eq!(outer.stages(), ["a", "c"]);
        assert_eq!(inner.stages(), ["b"]);
    }

    #[test]
    fn parallel_calls_report_to_the_caller_and_keep_the_order_of_their_items() {
        let reporter = Collect::new();
        let items: Vec<u64> = (0..64).collect();
        let out = reporting(reporter.clone(), || {
            map(&items, |i, &x| {
                stage(|| format!("item {i}")).unwrap();
                (0..20_000u64).fold(x, |a, k| a.wrapping_mul(31).wrapping_add(k))
            })
        });
        let serial: Vec<u64> = items
            .iter()
            .map(|&x| (0..20_000u64).fold(x, |a, k| a.wrapping_mul(31).wrapping_add(k)))
            .collect();
        assert_eq!(out, serial);
        let mut stages = reporter.stages();
        stages.sort();
        let mut want: Vec<String> = (0..64).map(|i| format!("item {i}")).collect();
        want.sort();
        assert_eq!(stages, want);
        // Without a reporter nothing is reported, on any thread.
        map(&items, |_, _| {
            stage(|| unreachable!("no reporter")).unwrap()
        });
    }

    #[test]
    fn a_stop_reaches_every_parallel_call() {
        let items: Vec<usize> = (0..16).collect();
        let out = reporting(Arc::new(Stop), || map(&items, |_, _| stage(|| "x".into())));
        assert!(out.iter().all(|r| *r == Err(Interrupted)));
    }

    struct Stop;
    impl Reporter for Stop {
        fn stage(&self, _: &str) {
            unreachable!("a stopped run reports nothing more");
        }
        fn stopped(&self) -> bool {
            true
        }
    }

    #[test]
    fn a_stopped_reporter_ends_the_run_at_its_next_stage() {
        assert_eq!(
            reporting(Arc::new(Stop), || stage(|| "x".into())),
            Err(Interrupted)
        );
    }
}
