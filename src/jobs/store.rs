//! Where a job's files go: a folder on disk ([`DirStore`], atomic sets) or
//! memory ([`MemoryStore`], for tests and the service). Names are relative
//! to the run's folder, `/`-separated (`well_a/packing.csv`).
//!
//! A run puts its files in place with one [`Store::commit`] at its end:
//! every file written and every stale file removed, or on failure nothing
//! changed, no folder of its own left and no temporary file.

use std::collections::BTreeMap;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::output::{OutputError, commit_atomic};

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
    /// A symbolic link inside the store's folder, where a file was to be
    /// written or removed: links are never followed out of the folder.
    #[error("will not {action} through {}: it is a symbolic link", .path.display())]
    Symlink {
        /// `write` or `remove`.
        action: &'static str,
        /// The link (a folder or a file inside the store's folder).
        path: PathBuf,
    },
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

    /// Write `files` and remove the files named in `stale`, as one step:
    /// all of it, or on error nothing changed. Names in `stale` that do not
    /// exist are skipped.
    ///
    /// The default writes, then removes: a store that can undo neither
    /// should override it ([`DirStore`] and [`MemoryStore`] do, atomically).
    ///
    /// # Errors
    /// [`StoreError`] naming the file and the cause.
    fn commit(&mut self, files: &[(String, Vec<u8>)], stale: &[String]) -> Result<(), StoreError> {
        self.write(files)?;
        for name in stale {
            self.remove(name)?;
        }
        Ok(())
    }

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
/// renames; a failure leaves every earlier file as it was, and removes the
/// folders it created).
///
/// # Behavior
/// Folders are created when a set is committed, never before; a symbolic
/// link inside the folder (a well's folder, a file) is refused with
/// [`StoreError::Symlink`] rather than written or removed through. The
/// folder itself may be a link: it is the place the user chose.
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

    /// The path of `name`, after checking that no part of it inside the
    /// folder is a symbolic link (parts that do not exist yet are not).
    fn unlinked(&self, name: &str, action: &'static str) -> Result<PathBuf, StoreError> {
        let mut path = self.dir.clone();
        let mut exists = true;
        for part in checked(name)?.split('/') {
            path.push(part);
            if exists {
                match fs::symlink_metadata(&path) {
                    Ok(meta) if meta.file_type().is_symlink() => {
                        return Err(StoreError::Symlink { action, path });
                    }
                    Ok(_) => {}
                    // Missing (or unreadable): nothing below it can be a link
                    // we would follow; the write itself reports any other fault.
                    Err(_) => exists = false,
                }
            }
        }
        Ok(path)
    }

    /// Create `dir` and its missing ancestors one by one, recording each
    /// one created in `made` (outermost first).
    fn create(dir: &Path, made: &mut Folders) -> Result<(), StoreError> {
        let missing: Vec<&Path> = dir
            .ancestors()
            .take_while(|d| !d.as_os_str().is_empty() && fs::symlink_metadata(d).is_err())
            .collect();
        let existing = dir.ancestors().nth(missing.len());
        if let Some(d) = existing.filter(|d| !d.as_os_str().is_empty() && !d.is_dir()) {
            return Err(StoreError::CreateDir {
                path: d.to_path_buf(),
                source: io::Error::new(io::ErrorKind::NotADirectory, "a file is in the way"),
            });
        }
        for d in missing.into_iter().rev() {
            match fs::create_dir(d) {
                Ok(()) => made.0.push(d.to_path_buf()),
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && d.is_dir() => {}
                Err(source) => {
                    return Err(StoreError::CreateDir {
                        path: d.to_path_buf(),
                        source,
                    });
                }
            }
        }
        Ok(())
    }

    /// Remove the folders of `path` inside the store's folder that are
    /// left empty, innermost first (best effort).
    fn prune(&self, path: &Path) {
        for dir in path.ancestors().skip(1) {
            if dir == self.dir || !dir.starts_with(&self.dir) {
                break;
            }
            // Only succeeds if the folder is empty; a link is never a folder here.
            if fs::remove_dir(dir).is_err() {
                break;
            }
        }
    }
}

/// Folders a commit created, removed again (innermost first) when it is
/// dropped on failure; [`Folders::keep`] once the commit succeeded.
#[derive(Default)]
struct Folders(Vec<PathBuf>);

impl Folders {
    fn keep(mut self) {
        self.0.clear();
    }
}

impl Drop for Folders {
    fn drop(&mut self) {
        for dir in self.0.iter().rev() {
            // Only succeeds if the folder is still empty, as it should be.
            let _ = fs::remove_dir(dir);
        }
    }
}

impl Store for DirStore {
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), StoreError> {
        self.commit(files, &[])
    }

    fn commit(&mut self, files: &[(String, Vec<u8>)], stale: &[String]) -> Result<(), StoreError> {
        // Every name and link checked before anything is created.
        let mut writes = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            writes.push((self.unlinked(name, "write")?, bytes.as_slice()));
        }
        let removals = stale
            .iter()
            .map(|name| self.unlinked(name, "remove"))
            .collect::<Result<Vec<_>, _>>()?;
        let mut made = Folders::default();
        for (path, _) in &writes {
            if let Some(parent) = path.parent() {
                Self::create(parent, &mut made)?;
            }
        }
        commit_atomic(&writes, &removals)?;
        made.keep();
        for path in &removals {
            // A well's folder left empty goes too; one still holding files stays.
            self.prune(path);
        }
        Ok(())
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError> {
        let path = self.dir.join(checked(name)?);
        match fs::read(&path) {
            Ok(bytes) => Ok(Some(bytes)),
            // Nothing there: no file, or a file where a folder on the way
            // should be (the write then says so).
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::NotFound | io::ErrorKind::NotADirectory
                ) =>
            {
                Ok(None)
            }
            Err(source) => Err(StoreError::Io {
                action: "read",
                path,
                source,
            }),
        }
    }

    fn remove(&mut self, name: &str) -> Result<(), StoreError> {
        let path = self.unlinked(name, "remove")?;
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
        self.prune(&path);
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

    fn commit(&mut self, files: &[(String, Vec<u8>)], stale: &[String]) -> Result<(), StoreError> {
        for name in files.iter().map(|(name, _)| name).chain(stale) {
            checked(name)?;
        }
        for name in stale {
            self.files.remove(name);
        }
        for (name, bytes) in files {
            self.files.insert(name.clone(), bytes.clone());
        }
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

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("gapack-store-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("scratch dir");
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .expect("listed")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_failed_commit_removes_every_folder_it_created() {
        let scratch = scratch("made");
        let root = scratch.join("new/deeper/out");
        let mut store = DirStore::new(&root);
        // `a/b.txt` makes the folder `a`, in the way of the file `a`: the
        // commit fails at its last rename, after every folder was made.
        let files = vec![
            ("a/b.txt".to_owned(), b"b".to_vec()),
            ("a".to_owned(), b"a".to_vec()),
        ];
        let err = store.write(&files).expect_err("a directory is in the way");
        assert!(matches!(err, StoreError::Write(_)), "{err:?}");
        assert!(
            listing(&scratch).is_empty(),
            "left behind: {:?}",
            listing(&scratch)
        );
        let _ = fs::remove_dir_all(&scratch);
    }

    #[test]
    fn a_commit_removes_stale_files_or_on_failure_keeps_them() {
        let dir = scratch("stale");
        let mut store = DirStore::new(&dir);
        let old = vec![
            ("a.txt".to_owned(), b"a".to_vec()),
            ("w/s.txt".to_owned(), b"s".to_vec()),
        ];
        store.write(&old).expect("written");
        let stale = ["a.txt".to_owned(), "w/s.txt".to_owned()];
        // A failure: nothing removed, nothing new.
        fs::create_dir(dir.join("c.txt")).expect("a directory in the way");
        let new = vec![
            ("b.txt".to_owned(), b"b".to_vec()),
            ("c.txt".to_owned(), b"c".to_vec()),
        ];
        store
            .commit(&new, &stale)
            .expect_err("c.txt is a directory");
        assert_eq!(listing(&dir), ["a.txt", "c.txt", "w"]);
        assert_eq!(store.read("w/s.txt").expect("read"), Some(b"s".to_vec()));
        fs::remove_dir(dir.join("c.txt")).expect("cleared");
        store.commit(&new, &stale).expect("committed");
        assert_eq!(listing(&dir), ["b.txt", "c.txt"], "w/ emptied goes too");
        let _ = fs::remove_dir_all(&dir);
    }

    #[test]
    fn links_inside_the_folder_are_refused_never_followed() {
        let dir = scratch("links");
        let root = dir.join("out");
        let outside = dir.join("outside");
        fs::create_dir_all(&root).expect("root");
        fs::create_dir_all(&outside).expect("outside");
        fs::write(outside.join("x.txt"), b"theirs").expect("their file");
        std::os::unix::fs::symlink(&outside, root.join("w")).expect("folder link");
        std::os::unix::fs::symlink(outside.join("x.txt"), root.join("f.txt")).expect("file link");
        let mut store = DirStore::new(&root);
        for name in ["w/x.txt", "w/new.txt", "f.txt"] {
            let err = store
                .write(&[(name.to_owned(), b"ours".to_vec())])
                .expect_err("a link");
            let link = root.join(name.split('/').next().expect("a part"));
            assert_eq!(
                err.to_string(),
                format!(
                    "will not write through {}: it is a symbolic link",
                    link.display()
                )
            );
            let err = store.remove(name).expect_err("a link");
            assert!(
                matches!(
                    err,
                    StoreError::Symlink {
                        action: "remove",
                        ..
                    }
                ),
                "{err:?}"
            );
            let err = store.commit(&[], &[name.to_owned()]).expect_err("a link");
            assert!(matches!(err, StoreError::Symlink { .. }), "{err:?}");
        }
        assert_eq!(listing(&outside), ["x.txt"]);
        assert_eq!(fs::read(outside.join("x.txt")).expect("read"), b"theirs");
        // The folder itself may be a link: the place the user chose.
        let mut through = DirStore::new(root.join("w"));
        through
            .write(&[("y.txt".to_owned(), b"y".to_vec())])
            .expect("the store's own folder may be a link");
        assert_eq!(listing(&outside), ["x.txt", "y.txt"]);
        let _ = fs::remove_dir_all(&dir);
    }
}
