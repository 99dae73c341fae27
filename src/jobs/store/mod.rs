//! Where a job's files go: a folder on disk ([`DirStore`], atomic sets) or
//! memory ([`MemoryStore`], for tests and the service). Names are relative
//! to the run's folder, `/`-separated (`well_a/packing.csv`).
//!
//! A run puts its files in place with one [`Store::commit`] at its end:
//! every file written and every stale file removed, or on failure nothing
//! changed, no folder of its own left and no temporary file. A large file
//! (a packing's table) may be streamed ahead with [`Store::stage`], never
//! held whole in memory, and put in place by that one commit
//! ([`Store::commit_staged`]).

mod atomic;

use std::collections::BTreeMap;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use crate::output::OutputError;
use atomic::TempFile;

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

    /// Make file `name` of the set the next [`Store::commit_staged`] puts
    /// in place, its bytes streamed by `write`, so that they need not be
    /// held whole in memory. Nothing is in place before that commit, and a
    /// [`Staged`] dropped uncommitted leaves nothing behind.
    ///
    /// The default holds the bytes in memory ([`DirStore`] writes them to
    /// a temporary file beside the file's place).
    ///
    /// # Errors
    /// [`StoreError`] naming the file and the cause (a bad name, or an
    /// error `write` returns).
    fn stage(
        &mut self,
        name: &str,
        write: &mut dyn FnMut(&mut dyn Write) -> io::Result<()>,
    ) -> Result<Staged, StoreError> {
        check_file_name(name)?;
        let mut bytes = Vec::new();
        write(&mut bytes).map_err(|source| OutputError::Write {
            path: PathBuf::from(name),
            source,
        })?;
        Ok(Staged::bytes(name.to_owned(), bytes))
    }

    /// [`Store::commit`] of a set of staged files ([`Store::stage`], or
    /// [`Staged::bytes`] for those made in memory): all of them put in
    /// place and the files named in `stale` removed, or on error nothing
    /// changed.
    ///
    /// The default takes the bytes of each ([`Staged::into_bytes`]) and
    /// calls [`Store::commit`].
    ///
    /// # Errors
    /// [`StoreError`] naming the file and the cause.
    fn commit_staged(&mut self, files: Vec<Staged>, stale: &[String]) -> Result<(), StoreError> {
        let files = files
            .into_iter()
            .map(|file| Ok((file.name().to_owned(), file.into_bytes()?)))
            .collect::<Result<Vec<_>, StoreError>>()?;
        self.commit(&files, stale)
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

/// The rule for the names of a job's files, which every store applies and
/// a front end serving them can apply too: relative to the run's folder,
/// `/`-separated (`well_a/packing.csv`); never empty nor absolute, with no
/// backslash and no part empty, `.` or `..`, so that none leaves the folder.
///
/// # Errors
/// [`StoreError::Name`] for a name that breaks the rule.
pub fn check_file_name(name: &str) -> Result<&str, StoreError> {
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

/// A file of a set to be committed ([`Store::commit_staged`]): its bytes in
/// memory, or written ahead to a temporary file ([`Store::stage`] of a
/// [`DirStore`]) that is removed, with the folders made for it, if this is
/// dropped uncommitted.
#[derive(Debug)]
pub struct Staged {
    name: String,
    held: Held,
}

#[derive(Debug)]
enum Held {
    Bytes(Vec<u8>),
    /// The temporary file and the folders made for it (outermost first).
    File(TempFile, Folders),
}

impl Staged {
    /// File `name` of a set, made in memory.
    pub fn bytes(name: String, bytes: Vec<u8>) -> Self {
        Staged {
            name,
            held: Held::Bytes(bytes),
        }
    }

    /// Its name, relative to the run's folder.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its bytes: those held, or those of its temporary file, read back
    /// (which is then removed).
    ///
    /// # Errors
    /// [`StoreError::Io`] when the temporary file cannot be read.
    pub fn into_bytes(self) -> Result<Vec<u8>, StoreError> {
        match self.held {
            Held::Bytes(bytes) => Ok(bytes),
            Held::File(file, _folders) => file.read().map_err(|source| StoreError::Io {
                action: "read",
                path: file.path().to_path_buf(),
                source,
            }),
        }
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
        for part in check_file_name(name)?.split('/') {
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
#[derive(Debug, Default)]
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

impl DirStore {
    /// Put `files` (names and bytes) and the files written ahead in place,
    /// and remove `stale`, as one step ([`atomic::commit`]): on failure
    /// every folder made for them (now and when they were staged) goes.
    fn put(
        &mut self,
        files: &[(&str, &[u8])],
        ahead: Vec<(TempFile, Folders)>,
        stale: &[String],
    ) -> Result<(), StoreError> {
        // Every name and link checked before anything is created.
        let mut writes = Vec::with_capacity(files.len());
        for &(name, bytes) in files {
            writes.push((self.unlinked(name, "write")?, bytes));
        }
        let removals = stale
            .iter()
            .map(|name| self.unlinked(name, "remove"))
            .collect::<Result<Vec<_>, _>>()?;
        // One record of every folder made, in the order made (those of the
        // files written ahead first), undone in reverse on failure.
        let mut made = Folders::default();
        let mut temps = Vec::with_capacity(ahead.len());
        for (temp, mut folders) in ahead {
            made.0.append(&mut folders.0);
            temps.push(temp);
        }
        for (path, _) in &writes {
            if let Some(parent) = path.parent() {
                Self::create(parent, &mut made)?;
            }
        }
        // On failure the temporary files go first (inside), then the
        // folders left empty (`made` dropped).
        atomic::commit(&writes, temps, &removals)?;
        made.keep();
        for path in &removals {
            // A well's folder left empty goes too; one still holding files stays.
            self.prune(path);
        }
        Ok(())
    }
}

impl Store for DirStore {
    fn write(&mut self, files: &[(String, Vec<u8>)]) -> Result<(), StoreError> {
        self.commit(files, &[])
    }

    fn commit(&mut self, files: &[(String, Vec<u8>)], stale: &[String]) -> Result<(), StoreError> {
        let files: Vec<(&str, &[u8])> = files
            .iter()
            .map(|(name, bytes)| (name.as_str(), bytes.as_slice()))
            .collect();
        self.put(&files, Vec::new(), stale)
    }

    /// Streams the bytes to a temporary file beside the file's place (its
    /// folders made now, and removed again if it is dropped uncommitted).
    fn stage(
        &mut self,
        name: &str,
        write: &mut dyn FnMut(&mut dyn Write) -> io::Result<()>,
    ) -> Result<Staged, StoreError> {
        let path = self.unlinked(name, "write")?;
        let mut made = Folders::default();
        if let Some(parent) = path.parent() {
            Self::create(parent, &mut made)?;
        }
        let file = TempFile::write(&path, write)?;
        Ok(Staged {
            name: name.to_owned(),
            held: Held::File(file, made),
        })
    }

    fn commit_staged(&mut self, files: Vec<Staged>, stale: &[String]) -> Result<(), StoreError> {
        let mut held = Vec::new();
        let mut ahead = Vec::new();
        for file in files {
            match file.held {
                Held::Bytes(bytes) => held.push((file.name, bytes)),
                Held::File(temp, made) => {
                    // Written ahead for this store's folder, under this name.
                    if temp.path() != self.unlinked(&file.name, "write")? {
                        let bytes = temp.read().map_err(|source| StoreError::Io {
                            action: "read",
                            path: temp.path().to_path_buf(),
                            source,
                        })?;
                        held.push((file.name, bytes));
                    } else {
                        ahead.push((temp, made));
                    }
                }
            }
        }
        let files: Vec<(&str, &[u8])> = held
            .iter()
            .map(|(name, bytes)| (name.as_str(), bytes.as_slice()))
            .collect();
        self.put(&files, ahead, stale)
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError> {
        let path = self.dir.join(check_file_name(name)?);
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
            check_file_name(name)?;
        }
        for (name, bytes) in files {
            self.files.insert(name.clone(), bytes.clone());
        }
        Ok(())
    }

    fn read(&self, name: &str) -> Result<Option<Vec<u8>>, StoreError> {
        Ok(self.files.get(check_file_name(name)?).cloned())
    }

    fn remove(&mut self, name: &str) -> Result<(), StoreError> {
        self.files.remove(check_file_name(name)?);
        Ok(())
    }

    fn commit(&mut self, files: &[(String, Vec<u8>)], stale: &[String]) -> Result<(), StoreError> {
        for name in files.iter().map(|(name, _)| name).chain(stale) {
            check_file_name(name)?;
        }
        for name in stale {
            self.files.remove(name);
        }
        for (name, bytes) in files {
            self.files.insert(name.clone(), bytes.clone());
        }
        Ok(())
    }

    fn commit_staged(&mut self, files: Vec<Staged>, stale: &[String]) -> Result<(), StoreError> {
        for name in files
            .iter()
            .map(Staged::name)
            .chain(stale.iter().map(String::as_str))
        {
            check_file_name(name)?;
        }
        // Every file's bytes first (one staged elsewhere is read back):
        // an error leaves the store as it was.
        let files = files
            .into_iter()
            .map(|file| Ok((file.name.clone(), file.into_bytes()?)))
            .collect::<Result<Vec<_>, StoreError>>()?;
        for name in stale {
            self.files.remove(name);
        }
        self.files.extend(files);
        Ok(())
    }

    fn location(&self) -> String {
        "memory".to_owned()
    }
}

#[cfg(test)]
pub(super) mod tests {
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
            assert!(
                matches!(check_file_name(bad), Err(StoreError::Name(_))),
                "{bad}"
            );
        }
        assert!(check_file_name("well_1/packing.csv").is_ok());
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

    /// A fresh, empty folder for one test (its tests' and `atomic`'s).
    pub(super) fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("gapack-store-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("scratch dir");
        dir
    }

    /// The names in `dir`, sorted.
    pub(in crate::jobs) fn listing(dir: &Path) -> Vec<String> {
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

    /// A stream writing `text` in pieces.
    fn streaming(text: &'static [u8]) -> impl FnMut(&mut dyn Write) -> io::Result<()> {
        move |out| {
            for piece in text.chunks(3) {
                out.write_all(piece)?;
            }
            Ok(())
        }
    }

    #[test]
    fn a_staged_file_is_in_place_only_after_its_commit() {
        let scratch = scratch("staged");
        let dir = scratch.join("out");
        let mut store = DirStore::new(&dir);
        let staged = store
            .stage("w/table.csv", &mut streaming(b"id,x\n0,1\n"))
            .expect("staged");
        assert_eq!(staged.name(), "w/table.csv");
        // Written ahead under a temporary name: nothing in place yet.
        assert_eq!(store.read("w/table.csv").expect("read"), None);
        let files = vec![staged, Staged::bytes("a.txt".to_owned(), b"a".to_vec())];
        store.commit_staged(files, &[]).expect("committed");
        assert_eq!(
            store.read("w/table.csv").expect("read"),
            Some(b"id,x\n0,1\n".to_vec())
        );
        assert_eq!(listing(&dir), ["a.txt", "w"]);
        assert_eq!(listing(&dir.join("w")), ["table.csv"]);
        let _ = fs::remove_dir_all(&scratch);
    }

    #[test]
    fn a_staged_file_dropped_or_failed_leaves_nothing() {
        let scratch = scratch("staged-failed");
        let dir = scratch.join("out");
        let mut store = DirStore::new(&dir);
        // Dropped uncommitted: its temporary file and its folders go.
        let staged = store
            .stage("w/t.csv", &mut streaming(b"t"))
            .expect("staged");
        assert_eq!(listing(&scratch), ["out"]);
        drop(staged);
        assert!(listing(&scratch).is_empty(), "{:?}", listing(&scratch));
        // A stream that fails: the error names the file, nothing is left.
        let err = store
            .stage("w/t.csv", &mut |out: &mut dyn Write| {
                out.write_all(b"part")?;
                Err(io::Error::other("disk full"))
            })
            .expect_err("the stream failed");
        assert!(
            matches!(&err, StoreError::Write(OutputError::Write { path, .. }) if path.ends_with("w/t.csv")),
            "{err:?}"
        );
        assert!(listing(&scratch).is_empty(), "{:?}", listing(&scratch));
        // A commit that fails at a rename: the set is undone, and the
        // staged file and the folders made for it go too.
        let staged = store
            .stage("w/t.csv", &mut streaming(b"t"))
            .expect("staged");
        let files = vec![
            staged,
            Staged::bytes("x/b.txt".to_owned(), b"b".to_vec()),
            Staged::bytes("x".to_owned(), b"x".to_vec()),
        ];
        store
            .commit_staged(files, &[])
            .expect_err("a directory is in the way of x");
        assert!(listing(&scratch).is_empty(), "{:?}", listing(&scratch));
        let _ = fs::remove_dir_all(&scratch);
    }

    #[test]
    fn a_memory_store_stages_in_memory() {
        let mut store = MemoryStore::default();
        store
            .write(&[("old.txt".to_owned(), b"old".to_vec())])
            .expect("written");
        let staged = store
            .stage("t.csv", &mut streaming(b"0,1\n2,3\n"))
            .expect("staged");
        assert!(!store.files.contains_key("t.csv"));
        store
            .commit_staged(vec![staged], &["old.txt".to_owned()])
            .expect("committed");
        assert_eq!(store.files.len(), 1);
        assert_eq!(store.files["t.csv"], b"0,1\n2,3\n");
        assert!(matches!(
            store.stage("../t.csv", &mut streaming(b"")),
            Err(StoreError::Name(_))
        ));
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
