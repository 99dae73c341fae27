//! What the subcommands share: reading a config, the failure → exit code
//! mapping, the result line, and the progress bars drawn from job events.

pub mod colour;
pub mod docs;
pub mod hint;
pub mod inspect;
pub mod job;
#[cfg(feature = "mpi")]
pub mod ranks;
pub mod serve;

use std::fmt::Display;
use std::io::{ErrorKind, IsTerminal, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use gapack::config::{self, Config, DEFAULT_CONFIG, DEFAULT_ORIGIN};
use gapack::jobs::{Event, JobError, Observer, Stage};
use indicatif::{ProgressBar, ProgressStyle};

/// A failed command: the error and the exit code it maps to.
pub enum Failure {
    /// Bad input (unreadable or invalid config, bad arguments): exit code 2.
    Input(anyhow::Error),
    /// The run itself failed (packing, writing): exit code 1.
    Run(anyhow::Error),
    /// Stopped by Ctrl-C or SIGTERM before anything was finished: exit code 130.
    Stopped(anyhow::Error),
}

/// A job's error as a failure: input faults exit 2, the others 1; a
/// config error says how to force a run over the `[limits]`.
pub fn failure(e: JobError) -> Failure {
    match e {
        JobError::Config(c) => Failure::Input(hint::config_error(*c)),
        e if e.is_input() => Failure::Input(e.into()),
        e => Failure::Run(e.into()),
    }
}

/// The config's text and its origin (the path as given, or the embedded
/// default scene's label without a path).
pub fn load_text(path: Option<&Path>) -> Result<(String, String), Failure> {
    let Some(path) = path else {
        return Ok((DEFAULT_CONFIG.to_owned(), DEFAULT_ORIGIN.to_owned()));
    };
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read {origin}"))
        .map_err(Failure::Input)?;
    Ok((text, origin))
}

/// The config at `path` and its origin; `force` skips the `[limits]` refusals.
pub fn load_config(path: &Path, force: bool) -> Result<(Config, String), Failure> {
    let (text, origin) = load_text(Some(path))?;
    let options = config::ParseOptions { force };
    let config = config::parse_with(&text, &origin, options)
        .map_err(|e| Failure::Input(hint::config_error(e)))?;
    Ok((config, origin))
}

/// Set once stdout could not be written: nothing more is printed there.
static STDOUT_GONE: AtomicBool = AtomicBool::new(false);

/// Print `line` and a newline on stdout: the one way the binary prints
/// there (`println!` panics when stdout is closed, and must not be used).
///
/// A closed pipe (`gapack validate c.toml | head -1`: `BrokenPipe`) means
/// the reader has seen enough: this line and every later one are dropped
/// quietly, and the command goes on to its own exit code (a failed verify
/// still exits 1). Any other write error is said once on stderr, then
/// stdout is dropped the same way: a finished run is not failed for it.
pub fn print_line(line: impl Display) {
    print_bytes(format!("{line}\n").as_bytes());
}

/// Write `bytes` to stdout as they are (a script, a manual page), closed
/// pipes and write errors handled as [`print_line`] says.
pub fn print_bytes(bytes: &[u8]) {
    if STDOUT_GONE.load(Ordering::Relaxed) {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(bytes).and_then(|()| out.flush()) {
        STDOUT_GONE.store(true, Ordering::Relaxed);
        if e.kind() != ErrorKind::BrokenPipe {
            let _ = writeln!(
                std::io::stderr(),
                "{} cannot write to stdout: {e}",
                colour::warning()
            );
        }
    }
}

/// Print a result line on stdout with [`print_line`], unless `quiet`.
pub fn report(quiet: bool, line: impl FnOnce() -> String) {
    if !quiet {
        print_line(line());
    }
}

/// Packs expected to hold at least this many disks show a progress bar
/// (about a second at the generator's speed).
const LARGE_PACK: u64 = 200_000;

/// Draws a job's events as progress bars on stderr (hidden when quiet or
/// when stderr is not a terminal) and prints its warnings.
pub struct ProgressObserver {
    visible: bool,
    bar: ProgressBar,
    stage: Option<Stage>,
}

impl ProgressObserver {
    /// Bars unless `quiet` or stderr is not a terminal.
    pub fn new(quiet: bool) -> Self {
        ProgressObserver {
            visible: !quiet && std::io::stderr().is_terminal(),
            bar: ProgressBar::hidden(),
            stage: None,
        }
    }

    /// Clear the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// A new bar over `total` units for `stage`, unless it is an inner pack of a batch.
    fn start(&mut self, stage: Stage, total: Option<u64>) {
        let nested = stage == Stage::Pack && self.stage.is_some_and(|s| s != Stage::Pack);
        if nested {
            return;
        }
        self.bar.finish_and_clear();
        self.stage = Some(stage);
        let total = total.unwrap_or(0);
        let (unit, shown) = match stage {
            Stage::Pack => ("disk", total >= LARGE_PACK),
            Stage::Optimise | Stage::Layering => ("generation", true),
            Stage::Wells => ("well", true),
            _ => ("run", true),
        };
        if !self.visible || !shown {
            self.bar = ProgressBar::hidden();
            return;
        }
        self.bar = ProgressBar::new(total);
        let template = format!("{unit} {{pos:>4}}/{{len}} [{{bar:30}}] {{msg}} ({{elapsed}})");
        if let Ok(style) = ProgressStyle::with_template(&template) {
            self.bar.set_style(style.progress_chars("=> "));
        }
    }
}

impl Observer for ProgressObserver {
    fn event(&mut self, event: &Event) {
        match event {
            Event::Stage { stage, total } => self.start(*stage, *total),
            Event::Progress { stage, done } if self.stage == Some(*stage) => {
                let len = self.bar.length().unwrap_or(0);
                self.bar.set_position((*done).min(len));
            }
            Event::Generation {
                stage, index, best, ..
            } => {
                self.bar.set_position(*index as u64);
                let what = match stage {
                    Stage::Layering => "profile RMS",
                    _ => "best porosity",
                };
                self.bar.set_message(format!("{what} {best:.4}"));
            }
            Event::Well { name, .. } => {
                self.bar.set_message(name.clone());
                self.bar.inc(1);
            }
            Event::Run { label, .. } => {
                self.bar.set_message(label.clone());
                self.bar.inc(1);
            }
            Event::Warning(w) => self
                .bar
                .suspend(|| eprintln!("{} {}", colour::warning(), w.message)),
            _ => {}
        }
    }
}
