//! Witnesses: the spots a front that took a particle still had, and the
//! test that lets it leave without an attempt once they are covered.

use std::ops::ControlFlow;

use nalgebra::Vector2;

use super::Front;
use crate::geometry::Outline;
use crate::packer::grains::contact::{Newcomer, Obstacle, clear_of};
use crate::packer::index::SpatialIndex;

/// Spots a front remembers after a placement, at most.
pub(super) const WITNESSES: usize = 4;

/// A front on the stack and the spots it still had after it took a
/// particle (its *witnesses*): the screen's other candidates (solved, or
/// estimated where left unsolved) as centres about the front's. When the
/// front comes up again and particles placed since cover the smallest
/// particle's inner disk at each of them, it leaves without an attempt,
/// as the disk front's fronts do: almost every front takes one particle
/// and fails at its next attempt, which was half the work of a run. The
/// stack holds most particles at some time: 24 bytes an entry.
#[derive(Debug, Clone, Copy)]
pub(super) struct Entry {
    pub(super) front: u32,
    /// Particles placed when the witnesses were found (those placed since
    /// can cover them); [`ATTEMPT`]: none kept, the front is attempted (a
    /// fresh or woken front, or one whose attempt was not screened).
    pub(super) since: u32,
    /// Offsets from the front's centre in units of [`Front::unit`];
    /// [`NO_SPOT`] marks an unused slot.
    pub(super) at: [[i16; 2]; WITNESSES],
}

/// [`Entry::since`] of a front kept without witnesses.
pub(super) const ATTEMPT: u32 = u32::MAX;

/// An unused witness slot.
pub(super) const NO_SPOT: [i16; 2] = [i16::MIN; 2];

impl Entry {
    pub(super) fn attempt(front: u32) -> Self {
        Entry {
            front,
            since: ATTEMPT,
            at: [NO_SPOT; WITNESSES],
        }
    }
}

/// Only the spots found for a size within this factor of the smallest
/// drawn are remembered (the disk front's retiring factor).
pub(super) const WITNESS_BAND: f64 = 1.1;

impl<I: SpatialIndex> Front<'_, I> {
    /// Whether a spot front `front` remembers may still hold a particle: no
    /// particle placed since it was found covers the smallest particle's
    /// inner disk about it (any particle at the spot would hold that disk).
    pub(super) fn any_alive(&mut self, w: &Entry) -> bool {
        self.stats.witness_checks += 1;
        let rho = self.inner_small;
        let disk = Outline::Superellipse {
            a: rho,
            b: rho,
            alpha: 2.0,
            beta: 2.0,
        };
        let probe = Newcomer {
            outline: &disk,
            cos: 1.0,
            sin: 0.0,
            reach: rho,
            inner: rho,
            slack: 0.0,
            sampled: None,
        };
        let c = self.halos[w.front as usize].c;
        let unit = self.unit;
        let half = rho + self.reach_max;
        let (bodies, halos) = (&self.bodies, &self.halos);
        let mut work = 0u64;
        let alive = w.at.iter().filter(|&&d| d != NO_SPOT).any(|d| {
            let q = c + unit * Vector2::new(f64::from(d[0]), f64::from(d[1]));
            self.visit(q, half, |id, v| {
                if id < w.since {
                    return ControlFlow::Continue(());
                }
                work += 1;
                let g = &halos[id as usize];
                let d2 = (g.c + v - q).norm_squared();
                let (far, near) = (g.reach + rho, g.inner + rho);
                if d2 >= far * far
                    || (d2 >= near * near && clear_of(bodies, &Obstacle::Body(id, v), &probe, q))
                {
                    ControlFlow::Continue(())
                } else {
                    ControlFlow::Break(())
                }
            })
            .is_continue()
        });
        self.stats.work += work;
        alive
    }
}
