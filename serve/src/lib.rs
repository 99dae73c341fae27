//! `gapack serve`: the jobs layer as an HTTP service (axum on tokio).
//!
//! - `store`: the job store (a row per job, its events, users and their
//!   tokens, leases), on SQLite (one process) or PostgreSQL (any number of
//!   fronts and workers on any number of machines);
//! - `worker`: threads that claim jobs under a lease and run them with
//!   `jobs::run`, each into `DATA/jobs/<id>/` with a `DirStore`, exactly
//!   as the CLI would; `lease`: the heartbeat that keeps their leases and
//!   the reaper that re-queues the jobs of lost workers;
//! - `users`: adding, revoking and listing users (`gapack user`);
//! - `api`: the routes, one module per group (jobs, events, files, the
//!   page and its data, health and metrics, the OpenAPI document) merged
//!   into one router, with the bearer token and one JSON error type;
//! - this file: the options, the shared state, startup, the accept loop
//!   and shutdown.
//!
//! The accept loop bounds the connections open at once (beyond the bound,
//! new ones wait in the kernel's backlog) and closes a connection whose
//! request headers are not all in within `header_timeout`, so slow or
//! stalled clients cannot hold every slot; the router bounds the time to
//! answer a request (`request_timeout`, its body read included).
//!
//! SIGINT or SIGTERM: the server stops taking jobs and connections, cancels
//! the running jobs (an optimise keeps its best packing and its checkpoint),
//! puts them back in the queue to resume at the next start, ends the event
//! streams, lets the open connections finish (for at most the longer of
//! the two timeouts), and exits.

mod api;
mod lease;
mod metrics;
pub mod store;
pub mod users;
mod web;
mod worker;

use std::collections::BTreeMap;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

use anyhow::Context;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, broadcast, watch};

use metrics::Metrics;
use store::{Caller, FIRST_USER, JobStore, QueueLimits, StoreUrl};

/// What the service is started with (`gapack serve`'s options).
#[derive(Debug, Clone)]
pub struct Options {
    /// Address to listen on (port 0: any free port). Any address but
    /// loopback needs a token.
    pub listen: SocketAddr,
    /// Folder of the jobs' files (`jobs/<id>/`), shared by every front and
    /// worker of one store; and of the SQLite store by default.
    pub data: PathBuf,
    /// The job store's URL (`None`: `sqlite://DATA/gapack.db`).
    pub store: Option<String>,
    /// How long a worker's hold on a job lasts without a heartbeat: a job
    /// whose worker is lost goes back to the queue after it.
    pub lease: Duration,
    /// Jobs one user may have waiting (a user's own limit overrides it).
    pub max_queue_per_user: usize,
    /// Jobs run at once (`None`: one per two cores); 0 only queues.
    pub workers: Option<usize>,
    /// File holding the bearer token every request must carry.
    pub token_file: Option<PathBuf>,
    /// Jobs that may wait in the queue; a submission beyond gets 503.
    pub max_queue: usize,
    /// Most disks a submitted scene may hold (its upper bound).
    pub max_particles: u64,
    /// Most memory a submitted run may be estimated to need (MB).
    pub max_memory_mb: u64,
    /// Longest a job may run (s; 0: no limit).
    pub max_seconds: u64,
    /// Whether a submission may ask for `force` (run over the limits).
    pub force: bool,
    /// optimise: save a checkpoint every N generations.
    pub checkpoint_every: usize,
    /// Connections open at once (at least 1); more wait to be accepted.
    pub max_connections: u32,
    /// Longest a client may take to send a request's headers (from the
    /// connection's start, or from the previous answer on a kept-alive
    /// connection); the connection is then closed.
    pub header_timeout: Duration,
    /// Longest the server takes to answer a request once its headers are
    /// in, reading its body included; it then answers `408`. An answer's
    /// body (an event stream, a file) is not bounded.
    pub request_timeout: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            listen: SocketAddr::from(([127, 0, 0, 1], 8080)),
            data: PathBuf::from("gapack-data"),
            store: None,
            lease: Duration::from_secs(30),
            max_queue_per_user: 250,
            workers: None,
            token_file: None,
            max_queue: 1000,
            max_particles: 2_000_000,
            max_memory_mb: 1024,
            max_seconds: 3600,
            force: false,
            checkpoint_every: 10,
            max_connections: 512,
            header_timeout: Duration::from_secs(10),
            request_timeout: Duration::from_secs(60),
        }
    }
}

/// Why the service did not start or stopped with an error.
#[derive(Debug)]
pub enum Failure {
    /// Bad options (a non-loopback address without a token, a bad token file).
    Input(anyhow::Error),
    /// The store, the runtime or the socket failed.
    Run(anyhow::Error),
}

/// The server's ceilings on what a submission may ask.
#[derive(Debug, Clone)]
pub struct Limits {
    /// Most disks a scene may hold.
    pub max_particles: u64,
    /// Most estimated memory (bytes).
    pub max_memory_bytes: f64,
    /// Longest run.
    pub max_seconds: Option<Duration>,
    /// Whether submissions may ask for `force`.
    pub force: bool,
    /// Jobs that may wait, in all and per user.
    pub queue: QueueLimits,
    /// optimise: checkpoint period (generations).
    pub checkpoint_every: usize,
}

/// What the handlers and the workers share.
pub struct Shared {
    store: Arc<dyn JobStore>,
    data: PathBuf,
    limits: Limits,
    /// The `--token-file` token (it signs in as [`Shared::admin`]).
    token: Option<String>,
    /// The store's first user: the token file's, and anyone's on a
    /// loopback server without tokens.
    admin: Caller,
    /// How long a lease lasts without a heartbeat.
    lease: Duration,
    /// This process's name among the store's workers (`host:pid`).
    name: String,
    /// Set once SIGINT or SIGTERM came: no new job is taken.
    stopping: AtomicBool,
    /// Set once this process's workers have ended: the keeper ends too.
    crew_done: AtomicBool,
    /// The jobs running in this process.
    running: Mutex<BTreeMap<String, lease::Running>>,
    /// Wakes idle workers when a job is queued.
    wake: (Mutex<u64>, Condvar),
    /// The id of each job with a new event (or state), for the streams.
    events: broadcast::Sender<String>,
    /// Turns true at shutdown: the streams end, the connections close.
    shutdown: watch::Sender<bool>,
    metrics: Metrics,
    /// Longest time to answer a request (the router's timeout).
    request_timeout: Duration,
}

impl Limits {
    /// The ceilings `args` set.
    fn of(args: &Options) -> Limits {
        Limits {
            max_particles: args.max_particles,
            max_memory_bytes: args.max_memory_mb as f64 * 1024.0 * 1024.0,
            max_seconds: (args.max_seconds > 0).then(|| Duration::from_secs(args.max_seconds)),
            force: args.force,
            queue: QueueLimits {
                total: args.max_queue,
                per_user: args.max_queue_per_user,
            },
            checkpoint_every: args.checkpoint_every,
        }
    }
}

impl Shared {
    /// The state over `args.store` (by default SQLite in `args.data`) and
    /// `args.data` (created if absent), guarded by `token`. With SQLite,
    /// jobs a crash left running are re-queued (counted in the second
    /// value); with PostgreSQL their leases see to them. No worker runs yet.
    fn open(args: &Options, token: Option<String>) -> anyhow::Result<(Shared, usize)> {
        std::fs::create_dir_all(args.data.join("jobs"))
            .with_context(|| format!("cannot create {}", args.data.display()))?;
        let url = match &args.store {
            Some(url) => StoreUrl::parse(url)?,
            None => StoreUrl::Sqlite(args.data.join("gapack.db")),
        };
        let store = store::open(&url)
            .with_context(|| format!("cannot open the job store {}", url.shown()))?;
        let recovered = store.recover().context("cannot recover the job store")?;
        let admin = store
            .user_named(FIRST_USER)?
            .context("the job store has no first user (admin)")?;
        let (events, _) = broadcast::channel(1024);
        let (shutdown, _) = watch::channel(false);
        let shared = Shared {
            store,
            data: args.data.clone(),
            limits: Limits::of(args),
            token,
            admin,
            lease: args.lease,
            name: format!("{}:{}", host_name(), std::process::id()),
            stopping: AtomicBool::new(false),
            crew_done: AtomicBool::new(false),
            running: Mutex::new(BTreeMap::new()),
            wake: (Mutex::new(0), Condvar::new()),
            events,
            shutdown,
            metrics: Metrics::default(),
            request_timeout: args.request_timeout,
        };
        Ok((shared, recovered))
    }

    fn register(&self, id: &str, running: lease::Running) {
        self.lock_running().insert(id.to_owned(), running);
    }

    fn unregister(&self, id: &str) -> Option<lease::Running> {
        self.lock_running().remove(id)
    }

    /// Raise the token of running job `id`, if it runs here.
    fn cancel_running(&self, id: &str) {
        if let Some(running) = self.lock_running().get(id) {
            running.cancel.cancel();
        }
    }

    fn lock_running(&self) -> std::sync::MutexGuard<'_, BTreeMap<String, lease::Running>> {
        self.running.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Wake one idle worker.
    fn wake_worker(&self) {
        let (lock, condvar) = &self.wake;
        *lock.lock().unwrap_or_else(PoisonError::into_inner) += 1;
        condvar.notify_one();
    }

    /// Wake every idle worker.
    fn wake_all(&self) {
        let (lock, condvar) = &self.wake;
        *lock.lock().unwrap_or_else(PoisonError::into_inner) += 1;
        condvar.notify_all();
    }

    /// Sleep until woken or `timeout`.
    fn wait_for_work(&self, timeout: Duration) {
        let (lock, condvar) = &self.wake;
        let guard = lock.lock().unwrap_or_else(PoisonError::into_inner);
        let seen = *guard;
        let _ = condvar
            .wait_timeout_while(guard, timeout, |n| {
                *n == seen && !self.stopping.load(Ordering::SeqCst)
            })
            .unwrap_or_else(PoisonError::into_inner);
    }

    /// Tell the streams that job `id` has news.
    fn notify(&self, id: &str) {
        // No receiver is fine: nobody follows the job.
        let _ = self.events.send(id.to_owned());
    }
}

/// Run the service until SIGINT or SIGTERM; `listening` is told the bound
/// address once the socket is open (the command line prints it first on
/// stdout, which tests and scripts read to find a port 0's port).
///
/// # Errors
/// [`Failure::Input`] for bad options (a non-loopback address without a
/// token, no connection allowed, a zero timeout), [`Failure::Run`] when the
/// store or the socket cannot be opened.
pub fn run(args: &Options, listening: impl FnOnce(SocketAddr)) -> Result<(), Failure> {
    if args.max_connections == 0 {
        return Err(Failure::Input(anyhow::anyhow!(
            "--max-connections must be at least 1"
        )));
    }
    if args.header_timeout.is_zero() || args.request_timeout.is_zero() {
        return Err(Failure::Input(anyhow::anyhow!(
            "--header-timeout and --request-timeout must be longer than zero"
        )));
    }
    let token = read_token(args)?;
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let workers = args.workers.unwrap_or((cores / 2).max(1));
    let (shared, recovered) = Shared::open(args, token).map_err(Failure::Run)?;
    let shared = Arc::new(shared);
    if shared.token.is_none() && !args.listen.ip().is_loopback() {
        let users = shared
            .store
            .has_tokens()
            .map_err(|e| Failure::Run(e.into()))?;
        if !users {
            return Err(Failure::Input(anyhow::anyhow!(
                "listening on {} (not loopback) needs --token-file or users with tokens (gapack user add)",
                args.listen
            )));
        }
    }
    init_log();
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("cannot start the async runtime")
        .map_err(Failure::Run)?;
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(args.listen))
        .with_context(|| format!("cannot listen on {}", args.listen))
        .map_err(Failure::Run)?;
    let addr = listener
        .local_addr()
        .context("cannot read the bound address")
        .map_err(Failure::Run)?;
    listening(addr);
    tracing::info!(%addr, workers, recovered, store = shared.store.engine(), data = %args.data.display(), "serving");
    let crew = Crew::start(&shared, workers);
    let router = api::router(Arc::clone(&shared));
    let edges = Edges {
        max_connections: args.max_connections,
        header_timeout: args.header_timeout,
        drain: args.header_timeout.max(args.request_timeout),
    };
    runtime.block_on(serve(listener, router, &edges, &shared));
    crew.join();
    tracing::info!("stopped");
    Ok(())
}

/// Run workers only (`gapack worker`): take jobs from the store at
/// `args.store` and run them until SIGINT or SIGTERM, which cancels the
/// running jobs and puts them back in the queue (to resume on any worker).
/// `name` names this process among the store's workers (default
/// `host:pid`).
///
/// # Errors
/// [`Failure::Input`] without a store URL or workers; [`Failure::Run`]
/// when the store cannot be opened.
pub fn work(args: &Options, name: Option<&str>) -> Result<(), Failure> {
    let shared_store = args
        .store
        .as_deref()
        .map(StoreUrl::parse)
        .transpose()
        .map_err(|e| Failure::Input(e.into()))?;
    if !matches!(shared_store, Some(StoreUrl::Postgres(_))) {
        return Err(Failure::Input(anyhow::anyhow!(
            "gapack worker needs --store postgres://… (the store the fronts queue jobs in): a SQLite store serves one process, its own workers"
        )));
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let workers = args.workers.unwrap_or((cores / 2).max(1));
    if workers == 0 {
        return Err(Failure::Input(anyhow::anyhow!(
            "--workers must be at least 1"
        )));
    }
    let (mut shared, _) = Shared::open(args, None).map_err(Failure::Run)?;
    if let Some(name) = name {
        shared.name = name.to_owned();
    }
    let shared = Arc::new(shared);
    init_log();
    tracing::info!(name = %shared.name, workers, store = shared.store.engine(), data = %args.data.display(), "working");
    let crew = Crew::start(&shared, workers);
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the async runtime")
        .map_err(Failure::Run)?;
    runtime.block_on(stop_signal(Arc::clone(&shared)));
    crew.join();
    tracing::info!("stopped");
    Ok(())
}

/// The `--token-file` token, if any: at least 16 characters.
fn read_token(args: &Options) -> Result<Option<String>, Failure> {
    let Some(path) = &args.token_file else {
        return Ok(None);
    };
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the token file {}", path.display()))
        .map_err(Failure::Input)?;
    let token = text.trim().to_owned();
    if token.len() < 16 {
        return Err(Failure::Input(anyhow::anyhow!(
            "the token in {} is too short: at least 16 characters",
            path.display()
        )));
    }
    Ok(Some(token))
}

/// Logs on stderr, at INFO (already set, as in tests, is fine).
fn init_log() {
    let _ = tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .with_max_level(tracing::Level::INFO)
        .try_init();
}

/// This machine's name, for the workers' names (`localhost` if unknown).
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|h| h.trim().to_owned())
        .filter(|h| !h.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "localhost".to_owned())
}

/// A process's threads besides the server's: its workers, the keeper of
/// their leases (and reaper of lost ones), and the listener to other
/// processes' news.
struct Crew {
    workers: Vec<std::thread::JoinHandle<()>>,
    keeper: std::thread::JoinHandle<()>,
    shared: Arc<Shared>,
}

impl Crew {
    /// Start `workers` worker threads and the lease keeper.
    fn start(shared: &Arc<Shared>, workers: usize) -> Crew {
        if let Some(news) = shared.store.subscribe() {
            let shared = Arc::clone(shared);
            // Ends with the store's listener (the process's end).
            std::thread::spawn(move || lease::listen(&shared, &news));
        }
        let names: Vec<String> = (0..workers)
            .map(|i| worker::worker_name(shared, i))
            .collect();
        let keeper = {
            let shared = Arc::clone(shared);
            std::thread::spawn(move || lease::keep(&shared, &names))
        };
        let workers = (0..workers)
            .map(|i| {
                let shared = Arc::clone(shared);
                std::thread::spawn(move || worker::work(&shared, i))
            })
            .collect();
        Crew {
            workers,
            keeper,
            shared: Arc::clone(shared),
        }
    }

    /// Wait for the workers to end their jobs (after the stop signal),
    /// then for the keeper, which beats until they have.
    fn join(self) {
        for thread in self.workers {
            let _ = thread.join();
        }
        self.shared.crew_done.store(true, Ordering::SeqCst);
        let _ = self.keeper.join();
    }
}

/// How the accept loop guards the service against slow or stalled clients.
struct Edges {
    /// Connections open at once.
    max_connections: u32,
    /// Longest wait for a request's headers.
    header_timeout: Duration,
    /// Longest wait, after the stop signal, for the open connections to end.
    drain: Duration,
}

/// Accept connections and serve `router` on each until SIGINT or SIGTERM,
/// then let the open connections finish (for at most `edges.drain`).
async fn serve(listener: TcpListener, router: axum::Router, edges: &Edges, shared: &Arc<Shared>) {
    let slots = Arc::new(Semaphore::new(edges.max_connections as usize));
    let stop = stop_signal(Arc::clone(shared));
    tokio::pin!(stop);
    // Runs until the stop signal: a server has no other end.
    loop {
        let slot = tokio::select! {
            slot = Arc::clone(&slots).acquire_owned() => match slot {
                Ok(slot) => slot,
                // Never closed; were it, no connection could be served.
                Err(_) => break,
            },
            () = &mut stop => break,
        };
        let tcp = tokio::select! {
            accepted = listener.accept() => match accepted {
                Ok((tcp, _)) => tcp,
                Err(e) => {
                    accept_failed(&e).await;
                    continue;
                }
            },
            () = &mut stop => break,
        };
        tokio::spawn(connection(
            tcp,
            router.clone(),
            edges.header_timeout,
            shared.shutdown.subscribe(),
            slot,
        ));
    }
    // New clients are refused from here on.
    drop(listener);
    // Every slot back: every connection has ended.
    let all = slots.acquire_many(edges.max_connections);
    if tokio::time::timeout(edges.drain, all).await.is_err() {
        tracing::warn!(
            open = edges.max_connections as usize - slots.available_permits(),
            "connections still open after {} s are dropped",
            edges.drain.as_secs()
        );
    }
}

/// Serve one connection (HTTP/1.1, kept alive) holding `slot` until it
/// ends: closed by the client, timed out reading headers, or, once
/// `shutdown` turns true, after its request in flight is answered.
async fn connection(
    tcp: TcpStream,
    router: axum::Router,
    header_timeout: Duration,
    mut shutdown: watch::Receiver<bool>,
    slot: OwnedSemaphorePermit,
) {
    // Small writes (an SSE event, a short answer) go out at once: with
    // Nagle's algorithm each waited for the client's delayed ACK (40 ms).
    if let Err(e) = tcp.set_nodelay(true) {
        tracing::warn!(error = %e, "cannot set TCP_NODELAY");
    }
    let served = hyper::server::conn::http1::Builder::new()
        .timer(TokioTimer::new())
        .header_read_timeout(header_timeout)
        .serve_connection(TokioIo::new(tcp), TowerToHyperService::new(router));
    tokio::pin!(served);
    let stopping = async {
        // The sender gone means the server is going too.
        let _ = shutdown.wait_for(|stopping| *stopping).await;
    };
    let ended = tokio::select! {
        ended = served.as_mut() => ended,
        () = stopping => {
            served.as_mut().graceful_shutdown();
            served.await
        }
    };
    // A client gone or too slow is its own affair: not worth a log line.
    if let Err(e) = ended {
        tracing::debug!(error = %e, "connection ended");
    }
    drop(slot);
}

/// After a failed accept: a connection reset before it was accepted is
/// skipped; anything else (out of file descriptors) is logged and the loop
/// pauses a second rather than spin.
async fn accept_failed(e: &std::io::Error) {
    use std::io::ErrorKind::{ConnectionAborted, ConnectionRefused, ConnectionReset};
    if matches!(
        e.kind(),
        ConnectionAborted | ConnectionRefused | ConnectionReset
    ) {
        return;
    }
    tracing::error!(error = %e, "cannot accept a connection");
    tokio::time::sleep(Duration::from_secs(1)).await;
}

/// Resolves at SIGINT or SIGTERM, after the server stopped taking jobs,
/// cancelled the running ones and ended the streams.
async fn stop_signal(shared: Arc<Shared>) {
    let interrupt = tokio::signal::ctrl_c();
    #[cfg(unix)]
    let terminate = async {
        match tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate()) {
            Ok(mut signal) => {
                signal.recv().await;
            }
            Err(_) => std::future::pending::<()>().await,
        }
    };
    #[cfg(not(unix))]
    let terminate = std::future::pending::<()>();
    tokio::select! {
        _ = interrupt => {}
        () = terminate => {}
    }
    tracing::info!("stopping: no new jobs; running jobs are cancelled and re-queued");
    shared.stopping.store(true, Ordering::SeqCst);
    for running in shared.lock_running().values() {
        running.cancel.cancel();
    }
    shared.wake.1.notify_all();
    let _ = shared.shutdown.send(true);
}
