//! Atomic sets of files: each written to a temporary file beside its place
//! (a [`tempfile`] named `.name.XXXXXX.tmp`), then all of them renamed
//! into place, the files they replace or remove kept as backups until the
//! whole set is in place.
//!
//! Every temporary file and backup is a [`TempPath`] from the moment it
//! exists, and the renames made are undone by a guard ([`Undo`]): an error,
//! an early return or a panic unwinding through a commit removes them and
//! puts every file back, so no exit path that runs destructors leaves a
//! hidden file behind.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use tempfile::{Builder, NamedTempFile, TempPath};

use crate::output::OutputError;

/// Write a set of files and remove others, as one step: every temporary
/// file first (those of `files`, beside the ones written `ahead`), then
/// every rename, then every removal (itself a move to a backup), and only
/// when all of them succeeded are the backups deleted.
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
pub(super) fn commit(
    files: &[(PathBuf, &[u8])],
    ahead: Vec<TempFile>,
    remove: &[PathBuf],
) -> Result<(), OutputError> {
    // Written and synced side by side: each waits for its own disk flush,
    // and those flushes overlap instead of queueing one after another. The
    // error reported is the first file's in order, whichever failed first;
    // the temporary files written go when the others are dropped.
    let written: Vec<io::Result<TempPath>> = files
        .par_iter()
        .map(|(path, contents)| temp_beside(path, &mut |out| out.write_all(contents)))
        .collect();
    let mut renames = Vec::with_capacity(files.len() + ahead.len());
    for ((path, _), temp) in files.iter().zip(written) {
        let temp = temp.map_err(|source| OutputError::Write {
            path: path.clone(),
            source,
        })?;
        renames.push((path.clone(), temp));
    }
    renames.extend(ahead.into_iter().map(|file| (file.path, file.temp)));
    let mut undo = Undo::default();
    // The temporary files not renamed yet go when `renames` is dropped.
    for (path, temp) in renames {
        let failed = |source| OutputError::Rename {
            path: path.clone(),
            source,
        };
        let backup = back_up(&path).map_err(failed)?;
        // On failure the temporary file is dropped with the error (removed),
        // and so is the backup (the file it copies is still in place).
        temp.persist(&path).map_err(|e| failed(e.error))?;
        undo.done.push((path, backup));
    }
    for path in remove {
        let removed = set_aside(path).map_err(|source| OutputError::Remove {
            path: path.clone(),
            source,
        })?;
        if let Some(backup) = removed {
            undo.done.push((path.clone(), Some(backup)));
        }
    }
    // Every step succeeded: nothing is undone, and the backups go.
    undo.done.clear();
    Ok(())
}

/// A file written ahead of the set it belongs to, under a temporary name
/// beside its destination (`.name.XXXXXX.tmp`), synced to disk: put in
/// place by [`commit`] with the rest of its set, and removed if it is
/// dropped first (an error, a cancel, a panic unwinding).
#[derive(Debug)]
pub(super) struct TempFile {
    /// Where it goes.
    path: PathBuf,
    /// Where it is, removed on drop.
    temp: TempPath,
}

impl TempFile {
    /// Write the bytes `write` streams to a temporary file beside `path`
    /// (through a buffer), and sync it. The folder must exist.
    ///
    /// # Errors
    /// [`OutputError::Write`] naming `path`, with the I/O cause (the
    /// temporary file removed).
    pub(super) fn write(
        path: &Path,
        write: &mut dyn FnMut(&mut dyn Write) -> io::Result<()>,
    ) -> Result<Self, OutputError> {
        let temp = temp_beside(path, write).map_err(|source| OutputError::Write {
            path: path.to_path_buf(),
            source,
        })?;
        Ok(TempFile {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// Where the file goes.
    pub(super) fn path(&self) -> &Path {
        &self.path
    }

    /// The bytes written, read back.
    ///
    /// # Errors
    /// The I/O error reading the temporary file.
    pub(super) fn read(&self) -> io::Result<Vec<u8>> {
        fs::read(&self.temp)
    }
}

/// The renames of a commit under way, undone (latest first) when it is
/// dropped before they are cleared: per file replaced, written or removed,
/// the backup of what was there before, if anything was (put back), or
/// nothing (the new file removed).
#[derive(Default)]
struct Undo {
    done: Vec<(PathBuf, Option<TempPath>)>,
}

impl Drop for Undo {
    fn drop(&mut self) {
        // Best effort throughout: the error being reported is the step that
        // failed. A backup not put back is removed when it is dropped.
        for (path, backup) in self.done.drain(..).rev() {
            let _ = match backup {
                Some(backup) => backup.persist(&path).map_err(|e| e.error),
                None => fs::remove_file(&path),
            };
        }
    }
}

/// The builder of hidden files `<prefix>XXXXXX<suffix>`.
fn hidden<'a>(prefix: &'a str, suffix: &'a str) -> Builder<'a, 'a> {
    let mut builder = Builder::new();
    builder.prefix(prefix).suffix(suffix);
    // Readable as a file created in place would be (0o666 less the umask),
    // not only by its owner as a temporary file is by default.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder
}

/// The folder `path` is in, and the prefix `.name.` of its hidden files.
fn place(path: &Path) -> io::Result<(&Path, String)> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    Ok((dir, format!(".{}.", name.to_string_lossy())))
}

/// A temporary file beside `path` (`.name.XXXXXX.tmp`) holding the bytes `write` streams
/// (through a 64 KiB buffer), synced to disk; removed on error.
fn temp_beside(
    path: &Path,
    write: &mut dyn FnMut(&mut dyn Write) -> io::Result<()>,
) -> io::Result<TempPath> {
    let (dir, prefix) = place(path)?;
    let file: NamedTempFile = hidden(&prefix, ".tmp").tempfile_in(dir)?;
    let mut out = BufWriter::with_capacity(1 << 16, file);
    write(&mut out)?;
    let file = out.into_inner().map_err(io::IntoInnerError::into_error)?;
    file.as_file().sync_all()?;
    Ok(file.into_temp_path())
}

/// Keep the file at `path`, if there is one, as `.name.XXXXXX.old`: a hard
/// link, or a copy where links are not supported. A directory in the way is
/// an error (the rename would fail), and so is a symbolic link (a copy
/// would follow it).
fn back_up(path: &Path) -> io::Result<Option<TempPath>> {
    match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
        Ok(meta) if meta.is_dir() => Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "a directory is in the way",
        )),
        Ok(meta) if meta.file_type().is_symlink() => Err(symlink_refused()),
        Ok(_) => {
            let (dir, prefix) = place(path)?;
            let backup = hidden(&prefix, ".old").make_in(dir, |at| {
                match fs::hard_link(path, at) {
                    // A name taken: the builder draws another.
                    Err(e) if e.kind() == io::ErrorKind::AlreadyExists => Err(e),
                    Err(_) => fs::copy(path, at).map(drop),
                    Ok(()) => Ok(()),
                }
            })?;
            Ok(Some(backup.into_temp_path()))
        }
    }
}

/// Move the file at `path` to a backup (`.name.XXXXXX.old`), the removal
/// undone by renaming it back; `None` if there is no file. A directory or
/// a symbolic link is refused.
fn set_aside(path: &Path) -> io::Result<Option<TempPath>> {
    if fs::symlink_metadata(path).is_ok_and(|meta| meta.is_dir()) {
        return Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "it is a directory",
        ));
    }
    let Some(backup) = back_up(path)? else {
        return Ok(None);
    };
    // The backup dropped on error: the file stays where it is.
    fs::remove_file(path)?;
    Ok(Some(backup))
}

fn symlink_refused() -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        "it is a symbolic link, which is never followed",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::jobs::store::tests::{listing, scratch};

    /// Commit `files`, nothing written ahead and nothing removed.
    fn write_all(files: &[(PathBuf, &[u8])]) -> Result<(), OutputError> {
        commit(files, Vec::new(), &[])
    }

    #[test]
    fn writes_and_replaces() {
        let dir = scratch("atomic-replace");
        let path = dir.join("a.txt");
        write_all(&[(path.clone(), b"one")]).expect("first write");
        write_all(&[(path.clone(), b"two")]).expect("second write");
        assert_eq!(fs::read(&path).expect("read back"), b"two");
        assert_eq!(listing(&dir), ["a.txt"]);
        let _ = fs::remove_dir_all(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn files_are_as_readable_as_files_created_in_place() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("atomic-mode");
        let (path, there) = (dir.join("a.txt"), dir.join("b.txt"));
        write_all(&[(path.clone(), b"a")]).expect("written");
        fs::write(&there, b"b").expect("created in place");
        let mode = |p: &Path| fs::metadata(p).expect("metadata").permissions().mode();
        assert_eq!(mode(&path), mode(&there));
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_set_leaves_nothing() {
        let dir = scratch("atomic-failure");
        fs::write(dir.join("a.txt"), b"old").expect("seed old file");
        let files = [
            (dir.join("a.txt"), &b"new"[..]),
            (dir.join("missing").join("b.txt"), &b"b"[..]),
        ];
        let err = write_all(&files).expect_err("the second file cannot be written");
        assert!(matches!(err, OutputError::Write { .. }), "{err}");
        assert_eq!(listing(&dir), ["a.txt"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"old");
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_rename_restores_the_files_replaced_before_it() {
        let dir = scratch("atomic-rename");
        fs::write(dir.join("a.txt"), b"old a").expect("seed a");
        fs::create_dir_all(dir.join("c.txt")).expect("a directory in the way");
        let files = [
            (dir.join("a.txt"), &b"new a"[..]),
            (dir.join("b.txt"), &b"new b"[..]),
            (dir.join("c.txt"), &b"new c"[..]),
        ];
        let err = write_all(&files).expect_err("c.txt is a directory");
        assert!(matches!(err, OutputError::Rename { .. }), "{err}");
        assert_eq!(listing(&dir), ["a.txt", "c.txt"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"old a");
        assert!(dir.join("c.txt").is_dir());
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_removal_puts_back_what_was_removed_and_replaced() {
        let dir = scratch("atomic-remove");
        fs::write(dir.join("a.txt"), b"old a").expect("seed a");
        fs::write(dir.join("s.txt"), b"stale").expect("seed s");
        fs::create_dir_all(dir.join("d")).expect("a directory to remove");
        let remove = [dir.join("s.txt"), dir.join("gone.txt"), dir.join("d")];
        let err = commit(&[(dir.join("a.txt"), &b"new a"[..])], Vec::new(), &remove)
            .expect_err("d is a directory");
        assert!(matches!(err, OutputError::Remove { .. }), "{err}");
        assert_eq!(listing(&dir), ["a.txt", "d", "s.txt"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"old a");
        assert_eq!(fs::read(dir.join("s.txt")).expect("read back"), b"stale");
        commit(
            &[(dir.join("a.txt"), &b"new a"[..])],
            Vec::new(),
            &remove[..2],
        )
        .expect("committed");
        assert_eq!(listing(&dir), ["a.txt", "d"]);
        assert_eq!(fs::read(dir.join("a.txt")).expect("read back"), b"new a");
        let _ = fs::remove_dir_all(&dir);
    }
}
