//! The cancel token every long loop of the library honours: a flag that a
//! front end raises (Ctrl-C, an HTTP cancel, a `KeyboardInterrupt`) and an
//! optional deadline (a time cap).
//!
//! # Behavior
//! Clones share the flag; [`Cancel::with_deadline`] makes a token that also
//! stops at an instant, still sharing its parent's flag (a capped run inside
//! a job the user can cancel). Loops poll [`Cancel::check`] between units of
//! work — the packer every few thousand sizes, the GA between generations
//! and inside each evaluation, sweeps between runs — so that a cancel is
//! honoured within milliseconds and no thread is left running.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Why work stopped early.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, thiserror::Error, serde::Serialize, serde::Deserialize,
)]
pub enum Cancelled {
    /// The flag was raised.
    #[error("cancelled")]
    Flag,
    /// The deadline passed.
    #[error("the time cap passed")]
    Deadline,
}

/// A cancel flag and an optional deadline; cheap to clone and to poll.
#[derive(Debug, Clone, Default)]
pub struct Cancel {
    flag: Arc<AtomicBool>,
    /// The token this one was made from by [`Cancel::child`]: its flag stops this one too.
    outer: Option<Arc<Cancel>>,
    deadline: Option<Instant>,
}

impl Cancel {
    /// A token that is never raised until [`Cancel::cancel`] is called.
    pub fn new() -> Self {
        Cancel::default()
    }

    /// A token sharing this one's flag that also stops `after` from now
    /// (or at this token's own deadline, if that is sooner).
    pub fn with_deadline(&self, after: Duration) -> Cancel {
        let at = Instant::now().checked_add(after);
        let deadline = match (self.deadline, at) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        Cancel {
            flag: Arc::clone(&self.flag),
            outer: self.outer.clone(),
            deadline,
        }
    }

    /// A token with a flag of its own that also stops when this one does:
    /// a job can stop its own work (a failed checkpoint) without raising
    /// the front end's flag.
    pub fn child(&self) -> Cancel {
        Cancel {
            flag: Arc::default(),
            outer: Some(Arc::new(self.clone())),
            deadline: None,
        }
    }

    /// Raise the flag: every clone sees it.
    pub fn cancel(&self) {
        self.flag.store(true, Ordering::Relaxed);
    }

    /// Whether the flag (or an outer token's) is raised, the deadlines aside.
    pub fn is_raised(&self) -> bool {
        self.flag.load(Ordering::Relaxed) || self.outer.as_ref().is_some_and(|o| o.is_raised())
    }

    /// `Err` once the flag is raised or the deadline has passed.
    ///
    /// # Errors
    /// [`Cancelled::Flag`] or [`Cancelled::Deadline`].
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.is_raised() {
            return Err(Cancelled::Flag);
        }
        if let Some(outer) = &self.outer {
            outer.check()?;
        }
        match self.deadline {
            Some(at) if Instant::now() >= at => Err(Cancelled::Deadline),
            _ => Ok(()),
        }
    }

    /// Whether work should stop now.
    pub fn is_cancelled(&self) -> bool {
        self.check().is_err()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_flag_and_deadlines_stay_local() {
        let parent = Cancel::new();
        let capped = parent.with_deadline(Duration::ZERO);
        assert_eq!(capped.check(), Err(Cancelled::Deadline));
        assert_eq!(parent.check(), Ok(()));
        let clone = parent.clone();
        clone.cancel();
        assert_eq!(parent.check(), Err(Cancelled::Flag));
        assert_eq!(capped.check(), Err(Cancelled::Flag));
    }

    #[test]
    fn a_child_stops_with_its_parent_but_not_the_reverse() {
        let parent = Cancel::new();
        let child = parent.child();
        child.cancel();
        assert_eq!(child.check(), Err(Cancelled::Flag));
        assert_eq!(parent.check(), Ok(()));
        let other = parent.child();
        parent.cancel();
        assert_eq!(other.check(), Err(Cancelled::Flag));
    }

    #[test]
    fn a_later_deadline_does_not_extend_an_earlier_one() {
        let early = Cancel::new().with_deadline(Duration::ZERO);
        let late = early.with_deadline(Duration::from_secs(3600));
        assert_eq!(late.check(), Err(Cancelled::Deadline));
    }
}
