//! `gapack serve`: the options on the command line, handed to the service
//! crate (`gapack_serve`), which runs until SIGINT or SIGTERM.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use clap::Args;

use super::{Failure, print_line};

/// `gapack serve` options.
#[derive(Args)]
pub struct ServeArgs {
    /// Address to listen on (port 0: any free port; the first line on
    /// stdout says which). Any address but loopback needs --token-file.
    #[arg(long, default_value = "127.0.0.1:8080", value_name = "ADDR")]
    listen: SocketAddr,
    /// Folder of the job store (gapack.db) and of the jobs' files (jobs/<id>/).
    #[arg(long, default_value = "gapack-data", value_name = "DIR")]
    data: PathBuf,
    /// Jobs run at once [default: one per two cores]; 0 only queues.
    #[arg(long, value_name = "N")]
    workers: Option<usize>,
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
    .map_err(|failure| match failure {
        gapack_serve::Failure::Input(e) => Failure::Input(e),
        gapack_serve::Failure::Run(e) => Failure::Run(e),
    })
}
