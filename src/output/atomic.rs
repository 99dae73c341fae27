//! Atomic file writes: a temporary file in the same directory, then a rename.
//!
//! Every temporary file and backup is owned by a guard ([`Commit`]) from
//! the moment its name is chosen: an error, an early return or a panic
//! unwinding through the write removes them and undoes the renames made,
//! so no exit path that runs destructors leaves a `.name.<pid>.tmp`.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::error::OutputError;

/// Write `contents` to `path` atomically: readers see the old file or the new
/// one, never a part; on error no temporary file is left.
///
/// # Errors
/// [`OutputError::Write`] or [`OutputError::Rename`] with the I/O cause.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    commit_atomic(&[(path.to_path_buf(), contents)], &[])
}

/// Write a set of files: every temporary file first, then every rename.
///
/// A failure leaves none of the files changed and no temporary file behind:
/// a failure while writing removes the temporary files; a failed rename
/// (a directory in the way, a vanished directory) undoes the renames before
/// it, restoring the files they replaced from hard links (or copies) taken
/// just before.
///
/// # Errors
/// [`OutputError::Write`] or [`OutputError::Rename`] with the I/O cause.
pub fn write_all_atomic(files: &[(PathBuf, Vec<u8>)]) -> Result<(), OutputError> {
    let files: Vec<(PathBuf, &[u8])> = files
        .iter()
        .map(|(path, contents)| (path.clone(), contents.as_slice()))
        .collect();
    commit_atomic(&files, &[])
}

/// Write a set of files and remove others, as one step: every temporary
/// file first, then every rename, then every removal (itself a rename to a
/// backup name), and only when all of them succeeded are the backups
/// deleted.
///
/// # Behavior
/// A failure anywhere leaves every file as it was — those replaced and
/// those removed are put back from their backups, the new ones removed —
/// and no temporary file or backup behind. A symbolic link where a file is
/// to be replaced or removed is refused, never followed. Paths to remove
/// that do not exist are skipped.
///
/// # Errors
/// [`OutputError::Write`], [`OutputError::Rename`] or
/// [`OutputError::Remove`] with the I/O cause.
pub fn commit_atomic(files: &[(PathBuf, &[u8])], remove: &[PathBuf]) -> Result<(), OutputError> {
    commit_with_temps(files, Vec::new(), remove)
}

/// [`commit_atomic`], with files written ahead under temporary names
/// ([`TempFile`]) put in place among them: renamed after `files`' own
/// temporary files, and removed with them on failure.
///
/// # Errors
/// As [`commit_atomic`].
pub fn commit_with_temps(
    files: &[(PathBuf, &[u8])],
    written: Vec<TempFile>,
    remove: &[PathBuf],
) -> Result<(), OutputError> {
    let mut commit = Commit::default();
    // Every rename to make: each destination and its temporary file, the
    // temporary file owned by the guard from the moment it is listed (for
    // `files`, before it exists: a partial one goes too).
    let mut renames = Vec::with_capacity(files.len() + written.len());
    for (path, _) in files {
        let temp = temp_path(path, "tmp").map_err(|source| OutputError::Write {
            path: path.clone(),
            source,
        })?;
        commit.temps.push(temp.clone());
        renames.push((path.clone(), temp));
    }
    for file in written {
        let (path, temp) = file.into_parts();
        commit.temps.push(temp.clone());
        renames.push((path, temp));
    }
    // Written and synced side by side: each waits for its own disk flush,
    // and those flushes overlap instead of queueing one after another. The
    // error reported is the first file's in order, whichever failed first.
    let results: Vec<io::Result<()>> = files
        .par_iter()
        .zip(&renames)
        .map(|((_, contents), (_, temp))| write_synced(temp, contents))
        .collect();
    for ((path, _), result) in files.iter().zip(results) {
        result.map_err(|source| OutputError::Write {
            path: path.clone(),
            source,
        })?;
    }
    for (path, temp) in renames {
        let backup = back_up(&path).map_err(|source| OutputError::Rename {
            path: path.clone(),
            source,
        })?;
        if let Some(backup) = &backup {
            commit.backups.push(backup.clone());
        }
        fs::rename(&temp, &path).map_err(|source| OutputError::Rename {
            path: path.clone(),
            source,
        })?;
        commit.done.push((path, backup));
    }
    for path in remove {
        let removed = set_aside(path).map_err(|source| OutputError::Remove {
            path: path.clone(),
            source,
        })?;
        if let Some(backup) = removed {
            commit.backups.push(backup.clone());
            commit.done.push((path.clone(), Some(backup)));
        }
    }
    commit.keep();
    Ok(())
}

/// A file written ahead of the set it belongs to, under a temporary name
/// beside its destination (`.name.<pid>.<n>.tmp`), synced to disk: put in
/// place by [`commit_with_temps`] with the rest of its set, and removed if
/// it is dropped first (an error, a cancel, a panic unwinding).
#[derive(Debug)]
pub struct TempFile {
    /// Where it goes.
    path: PathBuf,
    /// Where it is; `None` once handed to a commit.
    temp: Option<PathBuf>,
}

/// Numbers the temporary files written ahead, so that two of the same
/// name in one process never share one.
static AHEAD: AtomicU64 = AtomicU64::new(0);

impl TempFile {
    /// Write the bytes `write` streams to a temporary file beside `path`
    /// (through a buffer), and sync it. The folder must exist.
    ///
    /// # Errors
    /// [`OutputError::Write`] naming `path`, with the I/O cause (the
    /// temporary file removed).
    pub fn write(
        path: &Path,
        write: &mut dyn FnMut(&mut dyn Write) -> io::Result<()>,
    ) -> Result<Self, OutputError> {
        let failed = |source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        };
        let n = AHEAD.fetch_add(1, Ordering::Relaxed);
        // Owned before the file exists: a partial one goes too.
        let file = TempFile {
            path: path.to_path_buf(),
            temp: Some(temp_path(path, &format!("{n}.tmp")).map_err(failed)?),
        };
        let temp = file.temp.as_deref().unwrap_or(path);
        let mut out = BufWriter::with_capacity(1 << 16, fs::File::create(temp).map_err(failed)?);
        write(&mut out).map_err(failed)?;
        out.into_inner()
            .map_err(|e| failed(e.into_error()))?
            .sync_all()
            .map_err(failed)?;
        Ok(file)
    }

    /// Where the file goes.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The bytes written, read back.
    ///
    /// # Errors
    /// The I/O error reading the temporary file.
    pub fn read(&self) -> io::Result<Vec<u8>> {
        fs::read(self.temp.as_deref().unwrap_or(&self.path))
    }

    /// Its destination and its temporary name, no longer removed on drop.
    fn into_parts(mut self) -> (PathBuf, PathBuf) {
        let temp = self.temp.take().unwrap_or_default();
        (std::mem::take(&mut self.path), temp)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            // Best effort: the error being reported is the one that dropped it.
            let _ = fs::remove_file(temp);
        }
    }
}

/// The debris of a commit under way, cleaned up when it is dropped unless
/// [`Commit::keep`] was called: temporary files removed, renames undone
/// (latest first), backups put back or removed.
#[derive(Default)]
struct Commit {
    /// Temporary files, whether written, partial or renamed already.
    temps: Vec<PathBuf>,
    /// Backups taken, whether used yet or not.
    backups: Vec<PathBuf>,
    /// Per file replaced, written or removed so far: the backup of what
    /// was there before, if anything was.
    done: Vec<(PathBuf, Option<PathBuf>)>,
}

impl Commit {
    /// Every step succeeded: the backups go and nothing is undone.
    fn keep(mut self) {
        self.temps.clear();
        self.done.clear();
        // A leftover backup would be a hidden file; nothing more can be done here.
        remove_all(&std::mem::take(&mut self.backups));
    }
}

impl Drop for Commit {
    fn drop(&mut self) {
        // Best effort throughout: the error being reported is the step that failed.
        remove_all(&self.temps);
        for (path, backup) in self.done.iter().rev() {
            let _ = match backup {
                Some(backup) => fs::rename(backup, path),
                None => fs::remove_file(path),
            };
        }
        // Backups not put back (taken for a rename that then failed).
        remove_all(&self.backups);
    }
}

/// Move the file at `path` to its backup name (`.name.<pid>.old`), the
/// removal undone by renaming it back; `None` if there is no file. A
/// directory or a symbolic link is refused.
fn set_aside(path: &Path) -> io::Result<Option<PathBuf>> {
    match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
        Ok(meta) if meta.is_dir() => Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "it is a directory",
        )),
        Ok(meta) if meta.file_type().is_symlink() => Err(symlink_refused()),
        Ok(_) => {
            let backup = temp_path(path, "old")?;
            fs::rename(path, &backup)?;
            Ok(Some(backup))
        }
    }
}

fn symlink_refused() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "it is a symbolic link, which is never followed",
    )
}

/// Keep the file at `path`, if there is one, as `.name.<pid>.old`: a hard
/// link, or a copy where links are not supported. A directory in the way is
/// an error (the rename would fail), and so is a symbolic link (a copy
/// would follow it).
fn back_up(path: &Path) -> io::Result<Option<PathBuf>> {
    match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
        Ok(meta) if meta.is_dir() => Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "a directory is in the way",
        )),
        Ok(meta) if meta.file_type().is_symlink() => Err(symlink_refused()),
        Ok(_) => {
            let backup = temp_path(path, "old")?;
            let _ = fs::remove_file(&backup);
            if fs::hard_link(path, &backup).is_err() {
                fs::copy(path, &backup)?;
            }
            Ok(Some(backup))
        }
    }
}

/// `dir/.name.<pid>.<suffix>` for `dir/name`.
fn temp_path(path: &Path, suffix: &str) -> io::Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"))?;
    Ok(path.with_file_name(format!(
        ".{}.{}.{suffix}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

fn write_synced(path: &Path, contents: &[u8]) -> io::Result<()> {
    let mut file = fs::File::create(path)?;
    file.write_all(contents)?;
    file.sync_all()
}

fn remove_all(paths: &[PathBuf]) {
    for path in paths {
        // The file may never have been created; nothing more can be done here.
        let _ = fs::remove_file(path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("gapack-atomic-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("create scratch dir");
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .expect("read scratch dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_and_replaces() {
        let dir = scratch("replace");
        let path = dir.join("a.txt");
        write_atomic(&path, b"one").expect("first write");
        write_atomic(&path, b"two").expect("second write");
        assert_eq!(fs::read(&path).expect("read back"), b"two");
        assert_eq!(listing(&dir), ["a.txt"]);
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_set_leaves_nothing() {
        let dir = scratch("failure");
        fs::write(dir.join("a.txt"), b"old").expect("seed old file");
        let files = [
            (dir.join("a.txt"), b"new".to_vec()),
            (dir.join("missing").join("b.txt"), b"b".to_vec()),
        ];
        let err = write_all_atomic(&files).expect_err("the second file cannot be written");
        assert!(matches!(err, OutputError::Write { .. }), "{err}");
        assert_eq!(listing(&dir), ["a.txt"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"old");
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_rename_restores_the_files_replaced_before_it() {
        let dir = scratch("rename");
        fs::write(dir.join("a.txt"), b"old a").expect("seed a");
        fs::create_dir_all(dir.join("c.txt")).expect("a directory in the way");
        let files = [
            (dir.join("a.txt"), b"new a".to_vec()),
            (dir.join("b.txt"), b"new b".to_vec()),
            (dir.join("c.txt"), b"new c".to_vec()),
        ];
        let err = write_all_atomic(&files).expect_err("c.txt is a directory");
        assert!(matches!(err, OutputError::Rename { .. }), "{err}");
        assert_eq!(listing(&dir), ["a.txt", "c.txt"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"old a");
        assert!(dir.join("c.txt").is_dir());
        let _ = fs::remove_dir_all(&dir);
    }
}
