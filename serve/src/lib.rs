//! `gapack serve`: the jobs layer as an HTTP service (axum on tokio).
//!
//! - `db`: the SQLite job store (a row per job, its events, transactional
//!   state changes; crash recovery re-queues what was running);
//! - `worker`: threads that run claimed jobs with `jobs::run`, each into
//!   `DATA/jobs/<id>/` with a `DirStore`, exactly as the CLI would;
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
mod db;
mod metrics;
mod web;
mod worker;

use std::collections::BTreeMap;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::Duration;

use anyhow::Context;
use gapack::jobs::Cancel;
use hyper_util::rt::{TokioIo, TokioTimer};
use hyper_util::service::TowerToHyperService;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{OwnedSemaphorePermit, Semaphore, broadcast, watch};

use db::Db;
use metrics::Metrics;

/// What the service is started with (`gapack serve`'s options).
#[derive(Debug, Clone)]
pub struct Options {
    /// Address to listen on (port 0: any free port). Any address but
    /// loopback needs a token.
    pub listen: SocketAddr,
    /// Folder of the job store (gapack.db) and of the jobs' files (jobs/<id>/).
    pub data: PathBuf,
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
    /// Jobs that may wait.
    pub max_queue: usize,
    /// optimise: checkpoint period (generations).
    pub checkpoint_every: usize,
}

/// What the handlers and the workers share.
pub struct Shared {
    db: Db,
    data: PathBuf,
    limits: Limits,
    token: Option<String>,
    /// Set once SIGINT or SIGTERM came: no new job is taken.
    stopping: AtomicBool,
    /// The running jobs' tokens.
    running: Mutex<BTreeMap<String, Cancel>>,
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
            max_queue: args.max_queue,
            checkpoint_every: args.checkpoint_every,
        }
    }
}

impl Shared {
    /// The state over `args.data` (created if absent; jobs a crash left
    /// running are re-queued, and counted in the second value), guarded by
    /// `token`. No worker runs yet.
    fn open(args: &Options, token: Option<String>) -> anyhow::Result<(Shared, usize)> {
        std::fs::create_dir_all(args.data.join("jobs"))
            .with_context(|| format!("cannot create {}", args.data.display()))?;
        let db = Db::open(&args.data.join("gapack.db")).context("cannot open the job store")?;
        let recovered = db.recover().context("cannot recover the job store")?;
        let (events, _) = broadcast::channel(1024);
        let (shutdown, _) = watch::channel(false);
        let shared = Shared {
            db,
            data: args.data.clone(),
            limits: Limits::of(args),
            token,
            stopping: AtomicBool::new(false),
            running: Mutex::new(BTreeMap::new()),
            wake: (Mutex::new(0), Condvar::new()),
            events,
            shutdown,
            metrics: Metrics::default(),
            request_timeout: args.request_timeout,
        };
        Ok((shared, recovered))
    }

    fn register(&self, id: &str, token: Cancel) {
        self.lock_running().insert(id.to_owned(), token);
    }

    fn unregister(&self, id: &str) {
        self.lock_running().remove(id);
    }

    /// Raise the token of running job `id`, if it runs here.
    fn cancel_running(&self, id: &str) {
        if let Some(token) = self.lock_running().get(id) {
            token.cancel();
        }
    }

    fn lock_running(&self) -> std::sync::MutexGuard<'_, BTreeMap<String, Cancel>> {
        self.running.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Wake one idle worker.
    fn wake_worker(&self) {
        let (lock, condvar) = &self.wake;
        *lock.lock().unwrap_or_else(PoisonError::into_inner) += 1;
        condvar.notify_one();
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
    let token = match &args.token_file {
        Some(path) => {
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
            Some(token)
        }
        None => None,
    };
    if token.is_none() && !args.listen.ip().is_loopback() {
        return Err(Failure::Input(anyhow::anyhow!(
            "listening on {} (not loopback) needs --token-file",
            args.listen
        )));
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let workers = args.workers.unwrap_or((cores / 2).max(1));
    let (shared, recovered) = Shared::open(args, token).map_err(Failure::Run)?;
    let shared = Arc::new(shared);
    // Already set (never, in the binary) is fine: logs go where it says.
    let _ = tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .with_max_level(tracing::Level::INFO)
        .try_init();
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
    tracing::info!(%addr, workers, recovered, data = %args.data.display(), "serving");
    let threads: Vec<_> = (0..workers)
        .map(|i| {
            let shared = Arc::clone(&shared);
            std::thread::spawn(move || worker::work(&shared, i))
        })
        .collect();
    let router = api::router(Arc::clone(&shared));
    let edges = Edges {
        max_connections: args.max_connections,
        header_timeout: args.header_timeout,
        drain: args.header_timeout.max(args.request_timeout),
    };
    runtime.block_on(serve(listener, router, &edges, &shared));
    for thread in threads {
        let _ = thread.join();
    }
    tracing::info!("stopped");
    Ok(())
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
    for token in shared.lock_running().values() {
        token.cancel();
    }
    shared.wake.1.notify_all();
    let _ = shared.shutdown.send(true);
}
