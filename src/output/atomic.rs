//! Atomic file writes: a temporary file in the same directory, then a rename.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use super::error::OutputError;

/// Write `contents` to `path` atomically: readers see the old file or the new
/// one, never a part; on error no temporary file is left.
///
/// # Errors
/// [`OutputError::Write`] or [`OutputError::Rename`] with the I/O cause.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    write_all_atomic(&[(path.to_path_buf(), contents.to_vec())])
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
    let mut temps = Vec::with_capacity(files.len());
    for (path, contents) in files {
        let written = temp_path(path, "tmp").and_then(|temp| {
            // Recorded before writing, so that a partial temporary file is removed too.
            temps.push(temp.clone());
            write_synced(&temp, contents)
        });
        if let Err(source) = written {
            remove_all(&temps);
            return Err(OutputError::Write {
                path: path.clone(),
                source,
            });
        }
    }
    // Per file renamed so far: the backup of the file it replaced, if any.
    let mut done: Vec<(&Path, Option<PathBuf>)> = Vec::with_capacity(files.len());
    for (i, ((path, _), temp)) in files.iter().zip(&temps).enumerate() {
        let renamed = back_up(path).and_then(|backup| match fs::rename(temp, path) {
            Ok(()) => Ok(backup),
            Err(e) => {
                // This file was not replaced: keep it, drop its backup.
                if let Some(backup) = backup {
                    let _ = fs::remove_file(backup);
                }
                Err(e)
            }
        });
        match renamed {
            Ok(backup) => done.push((path, backup)),
            Err(source) => {
                remove_all(&temps[i..]);
                undo(&done);
                return Err(OutputError::Rename {
                    path: path.clone(),
                    source,
                });
            }
        }
    }
    for (_, backup) in done {
        if let Some(backup) = backup {
            // A leftover backup is a hidden file; nothing more can be done here.
            let _ = fs::remove_file(backup);
        }
    }
    Ok(())
}

/// Keep the file at `path`, if there is one, as `.name.<pid>.old`: a hard
/// link, or a copy where links are not supported. A directory in the way is
/// an error (the rename would fail).
fn back_up(path: &Path) -> io::Result<Option<PathBuf>> {
    match fs::symlink_metadata(path) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(e),
        Ok(meta) if meta.is_dir() => Err(io::Error::new(
            io::ErrorKind::IsADirectory,
            "a directory is in the way",
        )),
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

/// Undo renames: put each backup back, or remove a file that was new.
fn undo(done: &[(&Path, Option<PathBuf>)]) {
    for (path, backup) in done.iter().rev() {
        // Best effort: the error being reported is the rename that failed.
        let _ = match backup {
            Some(backup) => fs::rename(backup, path),
            None => fs::remove_file(path),
        };
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
