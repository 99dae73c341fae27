//! A private PostgreSQL cluster for the tests that need the PostgreSQL job
//! store: `initdb` on a fresh folder under the system's temporary folder,
//! the server on a free loopback port with trust authentication (user
//! `gapack`), stopped and removed when dropped.
//!
//! The binaries are Debian's (`/usr/lib/postgresql/<version>/bin`, the
//! newest). Without them a test skips, saying how to run it, unless
//! `GAPACK_POSTGRES_TESTS=required` (as CI sets it): then it fails. Run as
//! root (initdb refuses root), the cluster runs as user `nobody`. Beside
//! it, [`Worker`]: a `gapack worker` process on such a store.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};

/// The environment variable that makes a missing PostgreSQL a failure.
pub const REQUIRED: &str = "GAPACK_POSTGRES_TESTS";

/// A running PostgreSQL cluster, stopped and removed when dropped.
pub struct Cluster {
    /// The folder of `initdb`, `pg_ctl`, `psql`.
    bin: PathBuf,
    /// The cluster's own folder: `data/`, the log, the socket.
    root: PathBuf,
    /// Its loopback port.
    port: u16,
    /// Whether the server runs as `nobody` (this process is root).
    as_nobody: bool,
    /// Whether the server is up (for `Drop`).
    running: bool,
}

/// The newest `/usr/lib/postgresql/*/bin` holding `initdb`.
fn newest_bin() -> Option<PathBuf> {
    let mut found: Vec<(Vec<u64>, PathBuf)> = std::fs::read_dir("/usr/lib/postgresql")
        .ok()?
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let version: Vec<u64> = name
                .split('.')
                .map(|p| p.parse().ok())
                .collect::<Option<_>>()?;
            let bin = e.path().join("bin");
            bin.join("initdb").is_file().then_some((version, bin))
        })
        .collect();
    found.sort();
    found.pop().map(|(_, bin)| bin)
}

/// A free loopback port (bound then released: free a moment later, as
/// good as a test needs).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free loopback port")
        .port()
}

impl Cluster {
    /// A fresh cluster, started; `None` (after one line on stderr saying
    /// how to run the test) when PostgreSQL is not installed and not
    /// required.
    ///
    /// # Panics
    /// When PostgreSQL is required (`GAPACK_POSTGRES_TESTS=required`) but
    /// not installed, or when the cluster cannot be made or started.
    pub fn start() -> Option<Cluster> {
        let Some(bin) = newest_bin() else {
            let required = std::env::var(REQUIRED).is_ok_and(|v| v == "required");
            assert!(
                !required,
                "{REQUIRED}=required but no PostgreSQL in /usr/lib/postgresql/*/bin: install Debian's postgresql"
            );
            // Straight to stderr, past the test harness's capture: a
            // skipped test says so even when it passes.
            let _ = writeln!(
                std::io::stderr(),
                "skipped: no PostgreSQL in /usr/lib/postgresql/*/bin; install Debian's postgresql (apt-get install postgresql) to run this test, or set {REQUIRED}=required to make its absence a failure"
            );
            return None;
        };
        static COUNT: AtomicU32 = AtomicU32::new(0);
        let root = std::env::temp_dir().join(format!(
            "gapack-pg-{}-{}",
            std::process::id(),
            COUNT.fetch_add(1, Ordering::SeqCst)
        ));
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).expect("the cluster's folder");
        // SAFETY: geteuid only reads this process's effective user id.
        let as_nobody = unsafe { libc::geteuid() } == 0;
        if as_nobody {
            let chown = Command::new("chown")
                .arg("nobody:nogroup")
                .arg(&root)
                .status()
                .expect("run chown");
            assert!(chown.success(), "chown nobody {}", root.display());
        }
        let mut cluster = Cluster {
            bin,
            root,
            port: free_port(),
            as_nobody,
            running: false,
        };
        let data = cluster.data();
        cluster.pg(
            "initdb",
            &[
                "-D",
                &data,
                "--auth=trust",
                "-U",
                "gapack",
                "-E",
                "UTF8",
                "--locale=C.UTF-8",
            ],
        );
        cluster.start_again();
        Some(cluster)
    }

    /// The data folder.
    fn data(&self) -> String {
        self.root.join("data").display().to_string()
    }

    /// Run the cluster's `tool` with `args`; panics unless it succeeds.
    fn pg(&self, tool: &str, args: &[&str]) -> Output {
        let out = self
            .command(tool)
            .args(args)
            .stdin(Stdio::null())
            .output()
            .unwrap_or_else(|e| panic!("run {tool}: {e}"));
        assert!(
            out.status.success(),
            "{tool} {args:?} failed: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        out
    }

    /// The cluster's `tool`, to run as `nobody` when this process is root,
    /// from the temporary folder (`nobody` may not enter the current one).
    fn command(&self, tool: &str) -> Command {
        let program = self.bin.join(tool);
        let mut command = if self.as_nobody {
            let mut c = Command::new("runuser");
            c.args(["-u", "nobody", "--"]).arg(&program);
            c
        } else {
            Command::new(&program)
        };
        command.current_dir(std::env::temp_dir());
        command
    }

    /// The URL of database `db` (user `gapack`, no password).
    pub fn url(&self, db: &str) -> String {
        format!("postgres://gapack@127.0.0.1:{}/{db}", self.port)
    }

    /// Create database `name`; its URL.
    pub fn create_database(&self, name: &str) -> String {
        self.psql("postgres", &format!("CREATE DATABASE {name}"));
        self.url(name)
    }

    /// Run one SQL statement on database `db` with the cluster's `psql`
    /// (unaligned, tuples only: one line per row, `|` between columns);
    /// panics unless it succeeds.
    pub fn psql(&self, db: &str, sql: &str) -> String {
        let out = Command::new(self.bin.join("psql"))
            .args(["-X", "-q", "-A", "-t", "-v", "ON_ERROR_STOP=1", "-c", sql])
            .arg(self.url(db))
            .stdin(Stdio::null())
            .output()
            .expect("run psql");
        assert!(
            out.status.success(),
            "psql {sql:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).trim_end().to_owned()
    }

    /// Stop the server (`-m fast`: sessions are ended, then a clean
    /// shutdown); the data stay for [`Cluster::start_again`].
    pub fn stop(&mut self) {
        self.pg("pg_ctl", &["-D", &self.data(), "-m", "fast", "-w", "stop"]);
        self.running = false;
    }

    /// Start the server (again) on the same port and data.
    pub fn start_again(&mut self) {
        let options = format!(
            "-p {} -k {} -c listen_addresses=127.0.0.1 -c fsync=off -c max_connections=200",
            self.port,
            self.root.display()
        );
        let log = self.root.join("log").display().to_string();
        let data = self.data();
        self.pg(
            "pg_ctl",
            &["-D", &data, "-l", &log, "-o", &options, "-w", "start"],
        );
        self.running = true;
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        if self.running {
            let data = self.data();
            let _ = self
                .command("pg_ctl")
                .args(["-D", &data, "-m", "immediate", "-w", "stop"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status();
        }
        let _ = std::fs::remove_dir_all(&self.root);
    }
}

/// A `gapack worker` process, killed when dropped.
pub struct Worker {
    child: Child,
    /// Its name (`--name`): its threads are `NAME:0`, `NAME:1`, ….
    pub name: String,
}

impl Worker {
    /// Start worker `name` with `threads` threads on store `url` and
    /// folder `data`, leases of `lease_seconds`, its log beside `data`
    /// (`DATA.NAME.log`, as the front's is `DATA.log`).
    pub fn start(data: &Path, url: &str, name: &str, threads: usize, lease_seconds: u64) -> Worker {
        let log = fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(data.with_extension(format!("{name}.log")))
            .expect("worker log");
        let child = Command::new(env!("CARGO_BIN_EXE_gapack"))
            .args(["worker", "--store", url, "--data"])
            .arg(data)
            .arg("--workers")
            .arg(threads.to_string())
            .args(["--name", name, "--lease-seconds"])
            .arg(lease_seconds.to_string())
            .stdout(Stdio::null())
            .stderr(log)
            .spawn()
            .expect("start gapack worker");
        Worker {
            child,
            name: name.to_owned(),
        }
    }

    /// Whether the process still runs.
    pub fn alive(&mut self) -> bool {
        self.child.try_wait().expect("wait").is_none()
    }

    /// `kill -9`, and reap it.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.kill();
    }
}
