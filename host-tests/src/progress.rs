//! Where a long run is, and a way to stop it: the identify workflow and the diagnosis report
//! each stage as they start it (`choosing segments: 5 (2 of 3)`, `refining order 2 (1 of 3)`,
//! `diagnose: trying friction`) to the [`Reporter`] the front end installed on the calling
//! thread with [`reporting`]. Without one, nothing is reported and nothing is formatted.
//!
//! A reporter that says it was [`stopped`](Reporter::stopped) ends the run at the next stage
//! with [`Interrupted`]: Python's calls stop this way after a `KeyboardInterrupt`. The command
//! line prints the stages on standard error (a line each, or a spinner on a terminal) and
//! stops on a signal by exiting; the library itself never prints.

use std::cell::RefCell;
use std::rc::Rc;

/// Receives the stages of a run, in order.
pub trait Reporter {
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
    static REPORTER: RefCell<Option<Rc<dyn Reporter>>> = const { RefCell::new(None) };
}

/// Runs `f` with `reporter` receiving the stages reported on this thread, then restores the
/// reporter that was there before.
pub fn reporting<R>(reporter: Rc<dyn Reporter>, f: impl FnOnce() -> R) -> R {
    let before = REPORTER.with(|r| r.replace(Some(reporter)));
    // Restored on return and on unwinding alike.
    struct Restore(Option<Rc<dyn Reporter>>);
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    struct Collect(RefCell<Vec<String>>);
    impl Reporter for Collect {
        fn stage(&self, stage: &str) {
            self.0.borrow_mut().push(stage.to_string());
        }
    }

    #[test]
    fn stages_reach_the_reporter_of_their_thread_only_while_it_is_installed() {
        let outer = Rc::new(Collect(RefCell::new(Vec::new())));
        let inner = Rc::new(Collect(RefCell::new(Vec::new())));
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
        assert_eq!(*outer.0.borrow(), ["a", "c"]);
        assert_eq!(*inner.0.borrow(), ["b"]);
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
            reporting(Rc::new(Stop), || stage(|| "x".into())),
            Err(Interrupted)
        );
    }
}
