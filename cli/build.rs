//! Names the commit the binary is built from, for `gapack --version`: sets
//! `GAPACK_BUILD_COMMIT` to the 12-hex abbreviation of `git rev-parse HEAD`
//! when this source tree is a git checkout (a worktree too), else to the
//! `GAPACK_COMMIT` environment variable when it is set (a build from a
//! source tarball that knows its commit), else to `unknown`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=GAPACK_COMMIT");
    let commit = from_git()
        .or_else(|| {
            std::env::var("GAPACK_COMMIT")
                .ok()
                .map(|c| c.trim().to_owned())
                .filter(|c| !c.is_empty())
        })
        .unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=GAPACK_BUILD_COMMIT={commit}");
}

/// `git` run in this crate's folder: its trimmed output when it succeeds.
fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?;
    Some(text.trim().to_owned())
}

/// The commit of HEAD, and the files that say when it moves watched; `None`
/// without git, or when the checkout around this folder is not the
/// workspace's own (an unpacked tarball inside some other repository).
fn from_git() -> Option<String> {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).parent()?;
    let top = PathBuf::from(git(&["rev-parse", "--show-toplevel"])?);
    if top.canonicalize().ok()? != workspace.canonicalize().ok()? {
        return None;
    }
    let commit = git(&["rev-parse", "--short=12", "HEAD"])?;
    // HEAD names the branch (in a worktree it lives in the worktree's own
    // git dir, which `--git-path` finds); a commit moves the branch's ref,
    // a loose file (written in its folder when it was packed) or a line of
    // packed-refs.
    for name in ["HEAD", "packed-refs"] {
        watch(git(&["rev-parse", "--git-path", name]), false);
    }
    if let Some(branch) = git(&["symbolic-ref", "-q", "HEAD"]) {
        watch(git(&["rev-parse", "--git-path", &branch]), true);
    }
    Some(commit)
}

/// Rebuild when the git file at `path` (relative to this folder) changes;
/// when it is not there, nothing (cargo would rerun every build for a
/// missing path), or with `or_folder` its folder, where it will be written.
fn watch(path: Option<String>, or_folder: bool) {
    let Some(path) = path else { return };
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    let watched = if path.exists() {
        Some(path.as_path())
    } else {
        path.parent().filter(|dir| or_folder && dir.exists())
    };
    if let Some(watched) = watched {
        println!("cargo:rerun-if-changed={}", watched.display());
    }
}
