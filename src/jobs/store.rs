//! Where a job's files go: a folder on disk ([`DirStore`], atomic sets) or
//! memory ([`MemoryStore`], for tests and the service). Names are relative
//! to the run's folder, `/`-separated (`well_a/packing.csv`).

use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::output::{OutputError, write_all_atomic};

/// Why a store could not read or write.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StoreError {
    /// A file name that would leave the run's folder or is empty.
    #[error("invalid file name {0:?}")]
    Name(String),
    /// The folder could not be created.
    #[error("cannot create directory {}", .path.display())]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
    /// A set of files could not be written (none of them is new).
    #[error(transparent)]
    Write(#[from] OutputError),
    /// A file could not be read or removed.
    #[error("cannot {action} {}", .path.display())]
    Io {
        /// `read` or `remove`.
        action: &'static str,
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: io::Error,
    },
}

/// Where a job's outputs and checkpoint go.
pub trait Store {
    /// Write `files` as one set: all of them, or on error none.
    ///
    /// # Errors
    /// [`StoreError`] naming the file and the cause.
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), StoreError>;

    /// A file's bytes, `None` if there is no such file.
    ///
    /// # Errors
    /// [`StoreError`] when the file exists but cannot be read.
    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError>;

    /// Remove a file (and a folder it leaves empty); nothing if absent.
    ///
    /// # Errors
    /// [`StoreError`] when the file exists but cannot be removed.
    fn remove(&mut self, name: &str) -> Result<(), StoreError>;

    /// Where the files go, for messages (`out/square_100`, `memory`).
    fn location(&self) -> String;
}

/// Refuse names that are empty, absolute or climb out of the folder.
fn checked(name: &str) -> Result<&str, StoreError> {
    let bad = name.is_empty()
        || name.starts_with('/')
        || name.contains('\\')
        || name
            .split('/')
            .any(|part| part.is_empty() || part == "." || part == "..");
    if bad {
        Err(StoreError::Name(name.to_owned()))
    } else {
        Ok(name)
    }
}

/// A folder on disk: each set written atomically (temporary files, then
/// renames; a failure leaves every earlier file as it was).
#[derive(Debug, Clone)]
pub struct DirStore {
    dir: PathBuf,
}

impl DirStore {
    /// A store writing into `dir` (created when the first set is written).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        DirStore { dir: dir.into() }
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

impl Store for DirStore {
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), StoreError> {
        let mut paths = Vec::with_capacity(files.len());
        let mut created = Vec::new();
        for (name, bytes) in files {
            let path = self.dir.join(checked(name)?);
            if let Some(parent) = path.parent()
                && !parent.exists()
            {
                fs::create_dir_all(parent).map_err(|source| StoreError::CreateDir {
                    path: parent.to_path_buf(),
                    source,
                })?;
                created.push(parent.to_path_buf());
            }
            paths.push((path, bytes.clone()));
        }
        let written = write_all_atomic(&paths);
        if written.is_err() {
            for dir in created.iter().rev() {
                // Only succeeds if the folder is still empty, as it should be.
                let _ = fs::remove_dir(dir);
            }
        }
        Ok(written?)
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError> {
        let path = self.dir.join(checked(name)?);
        match fs::read(&path) {
            Ok(bytes) => Ok(Some(bytes)),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(None),
            Err(source) => Err(StoreError::Io {
                action: "read",
                path,
                source,
            }),
        }
    }

    fn remove(&mut self, name: &str) -> Result<(), StoreError> {
        let path = self.dir.join(checked(name)?);
        match fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
            Err(source) => {
                return Err(StoreError::Io {
                    action: "remove",
                    path,
                    source,
                });
            }
        }
        if let Some(parent) = path.parent()
            && parent != self.dir
        {
            // A well's folder left empty goes too; one still holding files stays.
            let _ = fs::remove_dir(parent);
        }
        Ok(())
    }

    fn location(&self) -> String {
        self.dir.display().to_string()
    }
}

/// Files kept in memory, by name.
#[derive(Debug, Clone, Default)]
pub struct MemoryStore {
    /// The files, by name.
    pub files: BTreeMap<String, Vec<u8>>,
}

impl Store for MemoryStore {
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), StoreError> {
        for (name, _) in files {
            checked(name)?;
        }
        for (name, bytes) in files {
            self.files.insert(name.clone(), bytes.clone());
        }
        Ok(())
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError> {
        Ok(self.files.get(checked(name)?).cloned())
    }

    fn remove(&mut self, name: &str) -> Result<(), StoreError> {
        self.files.remove(checked(name)?);
        Ok(())
    }

    fn location(&self) -> String {
        "memory".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_leave_the_folder_are_refused() {
        for bad in [
            "",
            "/etc/passwd",
            "../x",
            "a/../../x",
            "a//b",
            "a\\b",
            "./a",
        ] {
            assert!(matches!(checked(bad), Err(StoreError::Name(_))), "{bad}");
        }
        assert!(checked("well_1/packing.csv").is_ok());
    }

    #[test]
    fn a_dir_store_writes_reads_and_removes_with_subfolders() {
        let dir = std::env::temp_dir().join(format!("gapack-store-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        let mut store = DirStore::new(&dir);
        let files = vec![
            ("a.txt".to_owned(), b"a".to_vec()),
            ("w/b.txt".to_owned(), b"b".to_vec()),
        ];
        store.write(&files).expect("written");
        assert_eq!(store.read("w/b.txt").expect("read"), Some(b"b".to_vec()));
        assert_eq!(store.read("missing").expect("read"), None);
        store.remove("w/b.txt").expect("removed");
        assert!(!dir.join("w").exists(), "an emptied well folder goes");
        assert!(dir.join("a.txt").exists());
        let _ = fs::remove_dir_all(&dir);
    }
}
