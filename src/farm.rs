//! Where a job's independent pieces of work run: this process's threads
//! ([`Local`]), or shared out over the ranks of an MPI job (the binary's
//! `mpi` feature implements [`Farm`] for that).
//!
//! # Behavior
//! Every process of a farm runs the same job from the same plan, step for
//! step: the job is deterministic, so each reaches the same [`map`] with
//! the same work. There the work is shared out (each piece done once, by
//! whichever process asks for it first) and every process gets every
//! result, in order, so all go on alike. What a process cannot know alike —
//! the clock, a Ctrl-C — is decided by the leading process ([`agree`],
//! [`share`]), which alone writes files and reports.
//!
//! With one process, [`map`] is a rayon map over the pieces and nothing is
//! encoded; with several, results travel as `postcard` bytes (exact: a
//! float keeps its bit pattern). Either way the results are those of the
//! same pure functions of the same inputs, so the job's files are the same
//! byte for byte, whatever the number of processes and threads.

use rayon::prelude::*;
use serde::Serialize;
use serde::de::DeserializeOwned;

/// A piece of work of a [`Farm::spread`]: its index in, its encoded result out.
pub type Task<'a> = dyn Fn(usize) -> Vec<u8> + Sync + 'a;

/// The processes a job runs on.
pub trait Farm {
    /// How many processes run the job (1 for [`Local`]).
    fn processes(&self) -> usize;

    /// Whether this process leads: writes the files and reports.
    fn leads(&self) -> bool;

    /// Run `task(i)` for every `i` in `0..count`, each once, spread over the
    /// processes (and their threads), and give every process every result
    /// in index order. Every process calls it at the same point of the job
    /// with the same `count`.
    fn spread(&self, count: usize, task: &Task<'_>) -> Vec<Vec<u8>>;

    /// The leading process's `bytes`, on every process.
    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8>;

    /// Stop every process: a result could not be decoded (a transport
    /// fault). Never returns.
    fn fail(&self, why: &str) -> !;
}

/// One process: its threads do the work.
#[derive(Debug, Clone, Copy, Default)]
pub struct Local;

impl Farm for Local {
    fn processes(&self) -> usize {
        1
    }

    fn leads(&self) -> bool {
        true
    }

    fn spread(&self, count: usize, task: &Task<'_>) -> Vec<Vec<u8>> {
        (0..count).into_par_iter().map(task).collect()
    }

    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8> {
        bytes
    }

    fn fail(&self, why: &str) -> ! {
        // No bytes are decoded in one process: nothing calls this.
        unreachable!("{why}")
    }
}

/// `task(i)` for every `i` in `0..count`, spread over `farm`, in index order.
pub fn map<R, F>(farm: &dyn Farm, count: usize, task: F) -> Vec<R>
where
    R: Serialize + DeserializeOwned + Send,
    F: Fn(usize) -> R + Sync,
{
    if farm.processes() == 1 {
        return (0..count).into_par_iter().map(&task).collect();
    }
    let encoded = farm.spread(count, &|i| encode(&task(i)));
    encoded.iter().map(|bytes| decode(farm, bytes)).collect()
}

/// Pieces of work per process and thread in one wave of [`waves`].
const WAVE_PER_WORKER: usize = 4;

/// [`map`] over `0..count` in waves, so that a long batch reports as it
/// goes: after each wave `done(i, result)` is called for its pieces in
/// index order, and returns `false` to stop there. `stop()` is asked before
/// each wave (the leading process's answer) and after each piece told (this
/// process's: the leading process stops there, and the others, left waiting
/// for work, are ended with it). The results do not depend on the size of
/// the waves.
pub fn waves<R, F>(
    farm: &dyn Farm,
    count: usize,
    stop: impl Fn() -> bool,
    task: F,
    mut done: impl FnMut(usize, R) -> bool,
) where
    R: Serialize + DeserializeOwned + Send,
    F: Fn(usize) -> R + Sync,
{
    let wave = (farm.processes() * rayon::current_num_threads() * WAVE_PER_WORKER).max(1);
    let mut first = 0;
    while first < count {
        if agree(farm, stop()) {
            return;
        }
        let n = wave.min(count - first);
        let results = map(farm, n, |k| task(first + k));
        for (k, r) in results.into_iter().enumerate() {
            if !done(first + k, r) || stop() {
                return;
            }
        }
        first += n;
    }
}

/// The leading process's `value`, on every process.
pub fn share<T: Serialize + DeserializeOwned>(farm: &dyn Farm, value: T) -> T {
    if farm.processes() == 1 {
        return value;
    }
    let bytes = farm.broadcast(encode(&value));
    decode(farm, &bytes)
}

/// The leading process's `flag`, on every process: a decision that rests on
/// the clock or a signal.
pub fn agree(farm: &dyn Farm, flag: bool) -> bool {
    share(farm, flag)
}

fn encode<T: Serialize>(value: &T) -> Vec<u8> {
    // Encoding to a vector fails only for types postcard cannot express
    // (maps of unknown length); ours are plain structs, enums and vectors.
    postcard::to_stdvec(value).unwrap_or_default()
}

fn decode<T: DeserializeOwned>(farm: &dyn Farm, bytes: &[u8]) -> T {
    match postcard::from_bytes(bytes) {
        Ok(value) => value,
        Err(e) => farm.fail(&format!(
            "a result from another process could not be decoded ({e}); every process must run the same gapack build"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// Three make-believe processes in one: each piece is encoded and
    /// decoded as between processes, and the order of work is reversed.
    struct Loopback {
        done: Mutex<Vec<usize>>,
    }

    impl Farm for Loopback {
        fn processes(&self) -> usize {
            3
        }
        fn leads(&self) -> bool {
            true
        }
        fn spread(&self, count: usize, task: &Task<'_>) -> Vec<Vec<u8>> {
            let mut out = vec![Vec::new(); count];
            for i in (0..count).rev() {
                self.done.lock().unwrap().push(i);
                out[i] = task(i);
            }
            out
        }
        fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8> {
            bytes
        }
        fn fail(&self, why: &str) -> ! {
            panic!("{why}")
        }
    }

    #[test]
    fn results_come_back_in_order_with_every_bit_of_every_float() {
        let odd = [
            f64::NAN,
            f64::INFINITY,
            -0.0,
            0.1 + 0.2,
            f64::MIN_POSITIVE / 3.0,
        ];
        let farm = Loopback {
            done: Mutex::new(Vec::new()),
        };
        let task = |i: usize| (i, odd[i % odd.len()], Some(vec![i as u32; i]));
        let spread: Vec<(usize, f64, Option<Vec<u32>>)> = map(&farm, 12, task);
        let local: Vec<(usize, f64, Option<Vec<u32>>)> = map(&Local, 12, task);
        assert_eq!(farm.done.lock().unwrap().len(), 12, "each piece once");
        for (a, b) in spread.iter().zip(&local) {
            assert_eq!(a.0, b.0);
            assert_eq!(a.1.to_bits(), b.1.to_bits());
            assert_eq!(a.2, b.2);
        }
        assert!(share(&farm, true) && !agree(&farm, false));
    }
}
