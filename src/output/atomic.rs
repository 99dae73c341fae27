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
/// A failure while writing leaves none of the files changed and no temporary
/// file behind. Renames within a directory do not fail in practice; if one
/// does, the files renamed before it stay replaced and the other temporary
/// files are removed.
///
/// # Errors
/// [`OutputError::Write`] or [`OutputError::Rename`] with the I/O cause.
pub fn write_all_atomic(files: &[(PathBuf, Vec<u8>)]) -> Result<(), OutputError> {
    let mut temps = Vec::with_capacity(files.len());
    for (path, contents) in files {
        let written = temp_path(path).and_then(|temp| {
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
    for (i, ((path, _), temp)) in files.iter().zip(&temps).enumerate() {
        if let Err(source) = fs::rename(temp, path) {
            remove_all(&temps[i..]);
            return Err(OutputError::Rename {
                path: path.clone(),
                source,
            });
        }
    }
    Ok(())
}

/// `dir/.name.<pid>.tmp` for `dir/name`.
fn temp_path(path: &Path) -> io::Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path has no file name"))?;
    Ok(path.with_file_name(format!(
        ".{}.{}.tmp",
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
}
