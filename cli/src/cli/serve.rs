//! `gapack serve`, `gapack worker` and `gapack user`: the options on the
//! command line, handed to the service crate (`gapack_serve`). The server
//! and the workers run until SIGINT or SIGTERM.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, Subcommand};

use super::{Failure, print_line};

/// `gapack serve` options.
#[derive(Args)]
pub struct ServeArgs {
    /// Address to listen on (port 0: any free port; the first line on
    /// stdout says which). Any address but loopback needs --token-file.
    #[arg(long, default_value = "127.0.0.1:8080", value_name = "ADDR")]
    listen: SocketAddr,
    /// Folder of the jobs' files (jobs/<id>/), the same on every front and
    /// worker of one store; and of the SQLite store (gapack.db) by default.
    #[arg(long, default_value = "gapack-data", value_name = "DIR")]
    data: PathBuf,
    /// The job store: sqlite://FILE (one process) or
    /// postgres://USER[:PASSWORD]@HOST:PORT/DATABASE (shared by fronts and
    /// workers on many machines) [default: sqlite://DIR/gapack.db].
    #[arg(long, value_name = "URL", env = "GAPACK_STORE", hide_env_values = true)]
    store: Option<String>,
    /// Jobs run at once [default: one per two cores]; 0 only queues and
    /// serves (workers run them: gapack worker).
    #[arg(long, value_name = "N")]
    workers: Option<usize>,
    /// A worker's hold on a job without a heartbeat (s): the job of a lost
    /// worker goes back to the queue after it, to resume elsewhere.
    #[arg(long, default_value_t = 30, value_name = "S",
          value_parser = clap::value_parser!(u64).range(1..=3600))]
    lease_seconds: u64,
    /// Jobs one user may have waiting (a user's own --max-queued overrides it).
    #[arg(long, default_value_t = 250, value_name = "N")]
    max_queue_per_user: usize,
    /// File holding the bearer token every request must carry
    /// (`Authorization: Bearer TOKEN`).
    #[arg(long, value_name = "F")]
    token_file: Option<PathBuf>,
    /// Jobs that may wait in the queue; a submission beyond gets 503.
    #[arg(long, default_value_t = 1000, value_name = "N")]
    max_queue: usize,
    /// Most disks a submitted scene may hold (its upper bound); a config's
    /// [limits] cannot raise it.
    #[arg(long, default_value_t = 2_000_000, value_name = "N")]
    max_particles: u64,
    /// Most memory a submitted run may be estimated to need (MB).
    #[arg(long, default_value_t = 1024, value_name = "MB")]
    max_memory_mb: u64,
    /// Longest a job may run (s); it is then stopped, keeping what it finished.
    #[arg(long, default_value_t = 3600, value_name = "S")]
    max_seconds: u64,
    /// Let a submission ask for `force=true` (run over the config's and the
    /// server's limits).
    #[arg(long)]
    force: bool,
    /// optimise: save a checkpoint every N generations (a restart resumes from it).
    #[arg(long, default_value_t = 10, value_name = "N")]
    checkpoint_every: usize,
    /// Connections open at once; more wait to be accepted until one closes.
    #[arg(long, default_value_t = 512, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..))]
    max_connections: u32,
    /// Longest a client may take to send a request's headers (s), counted
    /// from the connection's start or the previous answer; the connection
    /// is then closed.
    #[arg(long, default_value_t = 10, value_name = "S",
          value_parser = clap::value_parser!(u64).range(1..))]
    header_timeout: u64,
    /// Longest the server takes to answer a request once its headers are in
    /// (s), reading its body included; it then answers 408. Event streams
    /// and file downloads are not cut.
    #[arg(long, default_value_t = 60, value_name = "S",
          value_parser = clap::value_parser!(u64).range(1..))]
    request_timeout: u64,
}

/// Run the service with `args`; its address is the first line on stdout.
pub fn run(args: &ServeArgs) -> Result<(), Failure> {
    let options = gapack_serve::Options {
        listen: args.listen,
        data: args.data.clone(),
        store: args.store.clone(),
        lease: Duration::from_secs(args.lease_seconds),
        max_queue_per_user: args.max_queue_per_user,
        workers: args.workers,
        token_file: args.token_file.clone(),
        max_queue: args.max_queue,
        max_particles: args.max_particles,
        max_memory_mb: args.max_memory_mb,
        max_seconds: args.max_seconds,
        force: args.force,
        checkpoint_every: args.checkpoint_every,
        max_connections: args.max_connections,
        header_timeout: Duration::from_secs(args.header_timeout),
        request_timeout: Duration::from_secs(args.request_timeout),
    };
    gapack_serve::run(&options, |addr| {
        print_line(format!("listening on http://{addr}"));
    })
    .map_err(failure)
}

/// `gapack worker` options.
#[derive(Args)]
pub struct WorkerArgs {
    /// The job store the fronts queue jobs in: postgres://USER[:PASSWORD]@HOST:PORT/DATABASE.
    #[arg(long, value_name = "URL", env = "GAPACK_STORE", hide_env_values = true)]
    store: String,
    /// Folder of the jobs' files (jobs/<id>/): the fronts' --data, shared.
    #[arg(long, default_value = "gapack-data", value_name = "DIR")]
    data: PathBuf,
    /// Jobs run at once [default: one per two cores].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    workers: Option<u64>,
    /// A hold on a job without a heartbeat (s): give the fronts' value.
    #[arg(long, default_value_t = 30, value_name = "S",
          value_parser = clap::value_parser!(u64).range(1..=3600))]
    lease_seconds: u64,
    /// Longest a job may run (s); it is then stopped, keeping what it finished.
    #[arg(long, default_value_t = 3600, value_name = "S")]
    max_seconds: u64,
    /// This worker's name in the store and the metrics [default: host:pid].
    #[arg(long, value_name = "NAME")]
    name: Option<String>,
}

/// Run workers with `args` until SIGINT or SIGTERM.
pub fn run_worker(args: &WorkerArgs) -> Result<(), Failure> {
    let options = gapack_serve::Options {
        data: args.data.clone(),
        store: Some(args.store.clone()),
        lease: Duration::from_secs(args.lease_seconds),
        workers: args
            .workers
            .map(|n| usize::try_from(n).unwrap_or(usize::MAX)),
        max_seconds: args.max_seconds,
        ..gapack_serve::Options::default()
    };
    gapack_serve::work(&options, args.name.as_deref()).map_err(failure)
}

/// `gapack user`: who may use the service.
#[derive(Subcommand)]
pub enum UserCommand {
    /// Add a user; prints their token once, alone on the last line.
    Add(UserAddArgs),
    /// Revoke every token of a user (refused from the next request on).
    Revoke(UserNameArgs),
    /// List the users: name, role, limits, live tokens.
    List(StoreArg),
}

/// The store a `gapack user` command works on.
#[derive(Args)]
pub struct StoreArg {
    /// The job store: sqlite://FILE or postgres://USER[:PASSWORD]@HOST:PORT/DATABASE.
    #[arg(long, value_name = "URL", env = "GAPACK_STORE", hide_env_values = true)]
    store: String,
}

/// `gapack user add` options.
#[derive(Args)]
pub struct UserAddArgs {
    /// Their name: letters, digits, '.', '_', '-' or '@'.
    name: String,
    #[command(flatten)]
    store: StoreArg,
    /// An admin sees and acts on every user's jobs.
    #[arg(long)]
    admin: bool,
    /// Most jobs they may have waiting [default: the server's --max-queue-per-user].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(i64).range(0..))]
    max_queued: Option<i64>,
    /// Most particles a scene of theirs may hold (never above the server's
    /// --max-particles) [default: the server's].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(i64).range(1..))]
    max_particles: Option<i64>,
}

/// `gapack user revoke` options.
#[derive(Args)]
pub struct UserNameArgs {
    /// The user's name.
    name: String,
    #[command(flatten)]
    store: StoreArg,
}

/// Run a `gapack user` command.
pub fn run_user(command: &UserCommand) -> Result<(), Failure> {
    use gapack_serve::users::{self, NewUser, UserError};
    let failed = |e: UserError| match e {
        UserError::Store(e) => Failure::Run(e.into()),
        other => Failure::Input(other.into()),
    };
    match command {
        UserCommand::Add(args) => {
            let role = if args.admin {
                gapack_serve::store::Role::Admin
            } else {
                gapack_serve::store::Role::User
            };
            let (user, token) = users::add(
                &args.store.store,
                &NewUser {
                    name: &args.name,
                    role,
                    max_queued: args.max_queued,
                    max_particles: args.max_particles,
                },
            )
            .map_err(failed)?;
            print_line(format!(
                "added user {} ({}); their token, shown this once (the store keeps only its hash):",
                user.name,
                user.role.name()
            ));
            print_line(token);
        }
        UserCommand::Revoke(args) => {
            users::revoke(&args.store.store, &args.name).map_err(failed)?;
            print_line(format!("revoked every token of user {}", args.name));
        }
        UserCommand::List(args) => {
            let all = users::list(&args.store).map_err(failed)?;
            print_line("name\trole\tmax_queued\tmax_particles\ttokens");
            let or_default = |n: Option<i64>| n.map_or_else(|| "-".to_owned(), |n| n.to_string());
            for u in all {
                print_line(format!(
                    "{}\t{}\t{}\t{}\t{}",
                    u.name,
                    u.role.name(),
                    or_default(u.max_queued),
                    or_default(u.max_particles),
                    u.tokens
                ));
            }
        }
    }
    Ok(())
}

/// The service's failure as the command line's.
fn failure(failure: gapack_serve::Failure) -> Failure {
    match failure {
        gapack_serve::Failure::Input(e) => Failure::Input(e),
        gapack_serve::Failure::Run(e) => Failure::Run(e),
    }
}
