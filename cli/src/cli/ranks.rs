//! The ranks of an MPI launch (`mpirun -np N gapack …`, `srun gapack …`) as
//! a [`Farm`]: every rank runs the job, rank 0 leads (writes, reports) and
//! deals out the pieces of each [`Farm::spread`] on demand.
//!
//! # Behavior
//! Rank 0's threads take pieces one at a time from a shared counter; every
//! other rank asks rank 0 for as many pieces as it has threads, sends their
//! results with its next request, and gets fewer pieces as the work runs
//! out (guided self-scheduling), so a slow packing holds up one thread, not
//! a rank's whole share. When every piece is done, rank 0 sends all the
//! results to every rank. Only the thread that started MPI calls it
//! (`MPI_THREAD_FUNNELED`), and it polls with short sleeps rather than
//! blocking, so a waiting rank leaves its cores to the work.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use gapack::farm::{Farm, Task};
use mpi::Threading;
use mpi::collective::{CommunicatorCollectives, SystemOperation};
use mpi::environment::Universe;
use mpi::point_to_point::{Destination, MatchedReceiveVec, Source};
use mpi::topology::{Communicator, SimpleCommunicator};
use rayon::prelude::*;

/// A worker's results and its request for more.
const REQUEST: i32 = 1;
/// Rank 0's answer to a request: the next pieces (none: this spread is done).
const WORK: i32 = 2;
/// Every result of a spread, from rank 0.
const RESULTS: i32 = 3;
/// Rank 0's bytes of a broadcast.
const SHARE: i32 = 4;
/// Rank 0 has finished the job: the other ranks end.
const DONE: i32 = 5;

/// The longest sleep between two polls of a waiting rank.
const MAX_NAP: Duration = Duration::from_micros(250);

/// An MPI job's ranks.
pub struct Ranks {
    _universe: Universe,
    world: SimpleCommunicator,
    /// Bytes this rank has sent (for `gapack bench --ranks`).
    sent: AtomicUsize,
}

impl Ranks {
    /// MPI started for this process, or `None` when it is not launched by
    /// an MPI launcher of more than one rank (a plain run, or `-np 1`).
    pub fn start() -> Option<Ranks> {
        // Started by a launcher (Open MPI, PMIx, Slurm's PMI): else no MPI.
        let launched = ["OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"]
            .iter()
            .any(|v| std::env::var_os(v).is_some());
        if !launched {
            return None;
        }
        let (universe, _) = mpi::initialize_with_threading(Threading::Funneled)?;
        let world = universe.world();
        (world.size() > 1).then(|| Ranks {
            _universe: universe,
            world,
            sent: AtomicUsize::new(0),
        })
    }

    /// This rank's number.
    pub fn rank(&self) -> usize {
        usize::try_from(self.world.rank()).unwrap_or(0)
    }

    /// Bytes every rank has sent so far, summed (every rank calls it).
    pub fn bytes_sent_by_all(&self) -> usize {
        let mine = self.sent.load(Ordering::Relaxed) as u64;
        let mut all = 0u64;
        self.world
            .all_reduce_into(&mine, &mut all, SystemOperation::sum());
        usize::try_from(all).unwrap_or(usize::MAX)
    }

    /// End every rank's process with `code` (a rank that fails takes the job down).
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }

    fn send(&self, to: usize, bytes: &[u8], tag: i32) {
        self.sent.fetch_add(bytes.len(), Ordering::Relaxed);
        self.world
            .process_at_rank(rank_of(to))
            .send_with_tag(bytes, tag);
    }

    /// Rank 0: tell the other ranks the job is over.
    pub fn done(&self) {
        for r in 1..self.world.size() as usize {
            self.send(r, &[], DONE);
        }
    }

    /// Another rank, its job run: wait for rank 0 to finish, then end.
    pub fn wait_done(&self) -> ! {
        let mut nap = Duration::from_micros(20);
        loop {
            self.end_if_done();
            std::thread::sleep(nap);
            nap = (nap * 2).min(MAX_NAP);
        }
    }

    /// A rank other than 0 that hears rank 0 is done ends its process: its
    /// copy of the job has finished, or can only be waiting for work rank 0
    /// will not send (rank 0 was stopped, or failed).
    fn end_if_done(&self) {
        if !self.leads()
            && self
                .world
                .process_at_rank(0)
                .immediate_probe_with_tag(DONE)
                .is_some()
        {
            // SAFETY: MPI was started by this thread and is not used after.
            unsafe {
                mpi::ffi::MPI_Finalize();
            }
            std::process::exit(0);
        }
    }

    /// The next message with `tag` (from `from`, or from any rank), polled.
    fn receive(&self, from: Option<usize>, tag: i32) -> (Vec<u8>, usize) {
        let mut nap = Duration::from_micros(20);
        loop {
            self.end_if_done();
            let probed = match from {
                Some(r) => self
                    .world
                    .process_at_rank(rank_of(r))
                    .immediate_matched_probe_with_tag(tag),
                None => self
                    .world
                    .any_process()
                    .immediate_matched_probe_with_tag(tag),
            };
            if let Some(found) = probed {
                let (bytes, status) = found.matched_receive_vec::<u8>();
                return (bytes, usize::try_from(status.source_rank()).unwrap_or(0));
            }
            std::thread::sleep(nap);
            nap = (nap * 2).min(MAX_NAP);
        }
    }

    /// Rank 0's side of a spread: deal pieces out while its own threads work.
    fn lead(&self, count: usize, task: &Task<'_>) -> Vec<Vec<u8>> {
        let next = AtomicUsize::new(0);
        let results = Mutex::new(vec![Vec::new(); count]);
        let store = |i: usize, bytes: Vec<u8>| {
            if let Ok(mut r) = results.lock() {
                r[i] = bytes;
            }
        };
        std::thread::scope(|s| {
            s.spawn(|| {
                (0..rayon::current_num_threads())
                    .into_par_iter()
                    .for_each(|_| {
                        loop {
                            let i = next.fetch_add(1, Ordering::Relaxed);
                            if i >= count {
                                break;
                            }
                            store(i, task(i));
                        }
                    });
            });
            let mut working = self.world.size() as usize - 1;
            while working > 0 {
                let (bytes, from) = self.receive(None, REQUEST);
                let Ok((done, want)) = postcard::from_bytes::<(Vec<(u32, Vec<u8>)>, u32)>(&bytes)
                else {
                    eprintln!("error: a request from rank {from} could not be decoded");
                    self.abort(1);
                };
                for (i, r) in done {
                    store(i as usize, r);
                }
                let chunk = self.deal(&next, count, want as usize);
                if chunk.is_empty() {
                    working -= 1;
                }
                let bytes = postcard::to_stdvec(&chunk).unwrap_or_default();
                self.send(from, &bytes, WORK);
            }
        });
        let all = results.into_inner().unwrap_or_default();
        let bytes = postcard::to_stdvec(&all).unwrap_or_default();
        for r in 1..self.world.size() as usize {
            self.send(r, &bytes, RESULTS);
        }
        all
    }

    /// Up to `want` of the pieces left, fewer as they run out (a share of
    /// what is left per rank), at least one while any is left.
    fn deal(&self, next: &AtomicUsize, count: usize, want: usize) -> Vec<u32> {
        let left = count.saturating_sub(next.load(Ordering::Relaxed));
        let take = want
            .min(left.div_ceil(2 * self.world.size() as usize))
            .max(1);
        let first = next.fetch_add(take, Ordering::Relaxed);
        (first..(first + take).min(count))
            .map(|i| i as u32)
            .collect()
    }

    /// Another rank's side: ask, work, send back, until rank 0 has no more.
    fn follow(&self, task: &Task<'_>) -> Vec<Vec<u8>> {
        let want = rayon::current_num_threads() as u32;
        let mut done: Vec<(u32, Vec<u8>)> = Vec::new();
        loop {
            let request = postcard::to_stdvec(&(&done, want)).unwrap_or_default();
            self.send(0, &request, REQUEST);
            let (bytes, _) = self.receive(Some(0), WORK);
            let chunk: Vec<u32> = postcard::from_bytes(&bytes).unwrap_or_default();
            if chunk.is_empty() {
                break;
            }
            done = chunk
                .into_par_iter()
                .map(|i| (i, task(i as usize)))
                .collect();
        }
        let (bytes, _) = self.receive(Some(0), RESULTS);
        match postcard::from_bytes(&bytes) {
            Ok(all) => all,
            Err(_) => {
                eprintln!("error: rank {} could not decode the results", self.rank());
                self.abort(1)
            }
        }
    }
}

impl Farm for Ranks {
    fn processes(&self) -> usize {
        self.world.size() as usize
    }

    fn leads(&self) -> bool {
        self.world.rank() == 0
    }

    fn spread(&self, count: usize, task: &Task<'_>) -> Vec<Vec<u8>> {
        if count == 0 {
            return Vec::new();
        }
        if self.leads() {
            self.lead(count, task)
        } else {
            self.follow(task)
        }
    }

    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8> {
        if self.leads() {
            for r in 1..self.world.size() as usize {
                self.send(r, &bytes, SHARE);
            }
            bytes
        } else {
            self.receive(Some(0), SHARE).0
        }
    }

    fn fail(&self, why: &str) -> ! {
        eprintln!("error: rank {}: {why}", self.rank());
        self.abort(1)
    }
}

fn rank_of(r: usize) -> i32 {
    i32::try_from(r).unwrap_or(i32::MAX)
}
