//! The stages of a long run on standard error ([`hsid_host::progress`]): nothing for a run
//! that ends within a second; after that the stage it is in, then each stage as it starts —
//! as a spinner on a terminal, as one line each (`hsid: [3.2 s] refining order 2 (1 of 3)`)
//! otherwise. `--quiet` silences them. Standard output, the files, the HTML report and the
//! JSON are the same either way.

use std::io::{IsTerminal, Write};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use hsid_host::progress::Reporter;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a run goes before its stages are shown.
const QUIET_FOR: Duration = Duration::from_secs(1);

struct Shown {
    /// The stage the run is in.
    stage: Option<String>,
    /// The run has lasted [`QUIET_FOR`]: stages are shown.
    live: bool,
    /// The run is over: nothing more is shown.
    done: bool,
    /// The spinner, on a terminal, once live.
    bar: Option<ProgressBar>,
}

/// Shows the stages on standard error; [`finish`](Self::finish) before the command prints its
/// result or its error.
#[derive(Clone)]
pub struct Stderr {
    shown: Arc<Mutex<Shown>>,
    start: Instant,
    terminal: bool,
}

impl Stderr {
    /// Starts the clock; the stages show from [`QUIET_FOR`] on.
    pub fn start() -> Self {
        let s = Self {
            shown: Arc::new(Mutex::new(Shown {
                stage: None,
                live: false,
                done: false,
                bar: None,
            })),
            start: Instant::now(),
            terminal: std::io::stderr().is_terminal(),
        };
        let timer = s.clone();
        // Without the thread, the first stage of a run that stays in it would never show.
        let _ = std::thread::Builder::new()
            .name("hsid-progress".into())
            .spawn(move || {
                std::thread::sleep(QUIET_FOR);
                timer.go_live();
            });
        s
    }

    fn lock(&self) -> MutexGuard<'_, Shown> {
        self.shown.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn go_live(&self) {
        let mut shown = self.lock();
        if shown.done || shown.live {
            return;
        }
        shown.live = true;
        if let Some(stage) = shown.stage.clone() {
            self.show(&mut shown, &stage);
        }
    }

    /// Shows `stage`: the spinner's message on a terminal (the spinner starts with the first
    /// stage, so a command without stages shows none), else a line.
    fn show(&self, shown: &mut Shown, stage: &str) {
        if !self.terminal {
            self.line(stage);
            return;
        }
        let bar = shown.bar.get_or_insert_with(|| {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template("{spinner} [{elapsed}] {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            bar.enable_steady_tick(Duration::from_millis(120));
            bar
        });
        bar.set_message(crate::failure::one_line(stage));
    }

    fn line(&self, stage: &str) {
        // Not `eprintln!`, which panics when standard error's reader went away (`2>&1 | head`):
        // a stage line that cannot be written is not worth stopping the run for.
        let _ = writeln!(
            std::io::stderr(),
            "hsid: [{:.1} s] {}",
            self.start.elapsed().as_secs_f64(),
            crate::failure::one_line(stage)
        );
    }

    /// Clears the spinner; nothing is shown after this.
    pub fn finish(&self) {
        let mut shown = self.lock();
        shown.done = true;
        if let Some(bar) = shown.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Reporter for Stderr {
    fn stage(&self, stage: &str) {
        let mut shown = self.lock();
        if shown.done {
            return;
        }
        shown.stage = Some(stage.to_string());
        if shown.live {
            self.show(&mut shown, stage);
        }
    }
}

/// The reporter for a command: the stages on standard error, or none with `--quiet`.
pub fn reporter(quiet: bool) -> Option<Stderr> {
    (!quiet).then(Stderr::start)
}

/// Runs `f` with `reporter` receiving its stages (none: nothing shown), then clears it.
pub fn run<R>(reporter: Option<&Stderr>, f: impl FnOnce() -> R) -> R {
    match reporter {
        Some(r) => {
            let out = hsid_host::progress::reporting(Arc::new(r.clone()), f);
            r.finish();
            out
        }
        None => f(),
    }
}
