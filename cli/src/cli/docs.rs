//! `gapack completions` and `gapack man`: the shell completion scripts and
//! the roff manual pages, made from the command line's own definition so
//! that they never fall behind it.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Args, Command};
use clap_complete::Shell;
use clap_mangen::Man;
use gapack::jobs::{DirStore, Store};

use super::{Failure, print_bytes};

/// `gapack completions` arguments.
#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell to complete in.
    #[arg(value_enum)]
    shell: Shell,
}

/// `gapack man` arguments.
#[derive(Args)]
pub struct ManArgs {
    /// Write a page per command (gapack.1, gapack-pack.1, …) to DIR, all of
    /// them or none, instead of printing gapack.1 on stdout.
    #[arg(long, value_name = "DIR")]
    dir: Option<PathBuf>,
}

/// Print the completion script of `shell` for `cmd` on stdout.
pub fn run_completions(args: &CompletionsArgs, mut cmd: Command) -> Result<(), Failure> {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "gapack", &mut script);
    print_bytes(&script);
    Ok(())
}

/// Print `cmd`'s manual page on stdout, or write one per command to `--dir`.
pub fn run_man(args: &ManArgs, cmd: Command) -> Result<(), Failure> {
    let mut cmd = cmd.disable_help_subcommand(true);
    // Gives each subcommand its display name (`gapack-pack`): its page's name.
    cmd.build();
    let Some(dir) = &args.dir else {
        print_bytes(&page(&cmd).map_err(Failure::Run)?);
        return Ok(());
    };
    let mut pages = Vec::new();
    add_pages(&cmd, &mut pages).map_err(Failure::Run)?;
    DirStore::new(dir)
        .write(&pages)
        .with_context(|| format!("cannot write the manual pages in {}", dir.display()))
        .map_err(Failure::Run)?;
    for (name, _) in &pages {
        super::print_line(dir.join(name).display());
    }
    Ok(())
}

/// The roff page of `cmd`.
fn page(cmd: &Command) -> anyhow::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    Man::new(cmd.clone())
        .render(&mut bytes)
        .context("cannot render the manual page")?;
    Ok(bytes)
}

/// The pages of `cmd` and of each of its visible subcommands, named as
/// `man` looks them up (`gapack-user-add.1`).
fn add_pages(cmd: &Command, pages: &mut Vec<(String, Vec<u8>)>) -> anyhow::Result<()> {
    pages.push((Man::new(cmd.clone()).get_filename(), page(cmd)?));
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        add_pages(sub, pages)?;
    }
    Ok(())
}
