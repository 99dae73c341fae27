//! What the CLI adds to the library's words: how to force a run over the
//! `[limits]`, and how to go on after a job was stopped.

use std::path::Path;

use gapack::config::ConfigError;
use gapack::jobs::{self, Outcome, Report};

/// What the command line adds to a `[limits]` refusal that `--force` skips
/// (the library's message ends with the config keys that raise the limit).
pub const FORCE: &str = ", or run with --force to go ahead";

/// A config error as the command line says it: a refusal that `--force`
/// skips ([`ConfigError::forceable`]) ends with [`FORCE`].
pub fn config_error(e: ConfigError) -> anyhow::Error {
    if e.forceable() {
        anyhow::anyhow!("{e}{FORCE}")
    } else {
        e.into()
    }
}

/// After a stop: how to go on (a search) or what was kept (the others).
pub fn after_stop(outcome: &Outcome, config: Option<&Path>, seed: Option<u64>, force: bool) {
    if !outcome.interrupted {
        return;
    }
    if let Report::Optimise {
        resumable: true,
        summary,
        ..
    } = &outcome.report
    {
        let mut command = String::from("gapack optimise");
        if let Some(config) = config {
            command += &format!(" {}", config.display());
        }
        command += &format!(" --out {}", outcome.location);
        if let Some(seed) = seed {
            command += &format!(" --seed {seed}");
        }
        if force {
            command += " --force";
        }
        eprintln!(
            "note: stopped after generation {}; `{command} --resume` goes on from {}/{}",
            summary.generations,
            outcome.location,
            jobs::CHECKPOINT_JSON
        );
    } else if let Report::Sweep { rows, .. } = &outcome.report {
        let config = config.map_or_else(String::new, |c| format!(" {}", c.display()));
        let mut flags = seed.map_or_else(String::new, |s| format!(" --seed {s}"));
        if force {
            flags += " --force";
        }
        eprintln!(
            "note: stopped; the runs finished are written to {}/sweep.csv, and `gapack sweep{config} --out {}{flags} --resume` runs the other {}",
            outcome.location,
            outcome.location,
            rows.iter()
                .filter(|r| r.status == gapack::study::Status::NotRun)
                .count()
        );
    } else {
        eprintln!(
            "note: stopped; what was finished is written to {}",
            outcome.location
        );
    }
}
