//! Rows run left to right in the tiles of strips (`Part::raster`): where
//! a row starts (the tightest corner along the face on its left) and how
//! the next one is started at its left end instead of turning back.

use super::Front;
use super::candidates::lowest_first;
use super::closure::NO_WITNESS;
use crate::geometry::Point;
use crate::packer::index::SpatialIndex;

/// Fronts whose spots the first disk of a row chooses among (see
/// `Front::row_start`).
const ROW_START_FRONTS: usize = 6;

/// How far right of the leftmost front those lie, at most, in largest
/// radii: a diameter, the face's row end and the disks beside it.
const ROW_START_REACH: f64 = 2.0;

/// How much higher than the lowest of their spots the one chosen may lie,
/// in largest radii. On 1000 mm of Table 3.4 (seeds 1 and 2), the cells
/// within 3 largest diameters of the seams spread about 1.21 times as much
/// as in the bulk at 0.5, 1.20 at 1, 1.22 at 1.5, 1.25 at 2 and 1.28 at
/// 0.25 (1.29 with the lowest spot of the leftmost front; 1.33 with the
/// lowest spot of the same fronts, whatever its gap).
const ROW_START_RISE: f64 = 1.0;

impl<I: SpatialIndex> Front<'_, I> {
    /// The first disk of a row (rows left to right, see [`Front::restart`]):
    /// the front `f` on top and those under it, leftmost first, within
    /// [`ROW_START_REACH`] largest radii right of it (at most
    /// [`ROW_START_FRONTS`] of them) offer their spots; among those no
    /// higher than the lowest by [`ROW_START_RISE`] largest radii, the one
    /// leaving the least gap to a third obstacle wins (then the lowest):
    /// the row starts in the tightest corner along the face on its left,
    /// where the lowest spot alone often leaves a gap no size fills. The
    /// front chosen goes on top, with its spot; every front tried forgets
    /// its spots (none assumed this one taken), so it is attempted in full
    /// next time. `None`: no spot.
    pub(super) fn row_start(&mut self, f: u32, r: f64) -> Option<(u32, Point)> {
        let x_max = self.obs[f as usize].c.x + ROW_START_REACH * self.r_max;
        let mut spots = std::mem::take(&mut self.row_spots);
        spots.clear();
        let mut own = Vec::new();
        let mut tried = 0;
        let mut k = self.fronts.len();
        while k > 0 && tried < ROW_START_FRONTS {
            k -= 1;
            let g = self.fronts[k];
            if self.obs[g as usize].c.x > x_max {
                break;
            }
            if r >= f64::from(self.bound[g as usize]) || self.witnesses_closed(g) {
                continue;
            }
            self.stats.front_attempts += 1;
            own.clear();
            self.nested_spots(g, r, &mut own);
            self.note_refused(g);
            self.forget(g);
            tried += 1;
            spots.extend(own.iter().map(|&(p, gap)| (g, p, gap)));
        }
        let low = spots.iter().fold(f64::INFINITY, |m, s| m.min(s.1.y));
        let rise = ROW_START_RISE * self.r_max;
        let best = spots
            .iter()
            .filter(|s| s.1.y <= low + rise)
            .min_by(|a, b| a.2.total_cmp(&b.2).then(lowest_first(a.1, b.1)))
            .map(|&(g, p, _)| (g, p));
        self.row_spots = spots;
        let (g, p) = best?;
        if let Some(k) = self.fronts.iter().rposition(|&h| h == g) {
            self.fronts.remove(k);
            self.fronts.push(g);
        }
        Some((g, p))
    }

    /// Forget what front `f`'s last attempt learnt of its room: it is
    /// attempted in full next time, and handed on fresh.
    fn forget(&mut self, f: u32) {
        self.witness[f as usize] = NO_WITNESS;
        if let Some(h) = self.handoff.get_mut(&f) {
            *h = None;
        }
    }

    /// Whether, rows running left to right, front `f`'s spot `p` would
    /// start the next row back from its end (up and to the left).
    pub(super) fn turns_back(&self, f: u32, p: Point) -> bool {
        let c = self.obs[f as usize].c;
        self.raster && !self.restarted && p.x < c.x && p.y > c.y
    }

    /// Start the next row at its left end: the fronts no higher than a
    /// largest diameter above front `f` (where the row ended) go on top of
    /// the stack, leftmost on top, and the next spot found is taken
    /// wherever it lies. Fronts whose witnesses are covered leave first
    /// (they would without an attempt when on top): the stack stays the
    /// packing's surface, not every disk placed. What `f`'s attempt learnt
    /// of its room assumed its spot taken: it is forgotten.
    pub(super) fn restart(&mut self, f: u32) {
        self.forget(f);
        let mut stack = std::mem::take(&mut self.fronts);
        stack.retain(|&g| !self.witnesses_closed(g));
        let cap = self.obs[f as usize].c.y + 2.0 * self.r_max;
        let obs = &self.obs;
        let (mut low, high): (Vec<u32>, Vec<u32>) =
            stack.iter().partition(|&&g| obs[g as usize].c.y <= cap);
        self.stats.work += stack.len() as u64;
        low.sort_by(|&a, &b| {
            let (a, b) = (obs[a as usize].c, obs[b as usize].c);
            b.x.total_cmp(&a.x).then(b.y.total_cmp(&a.y))
        });
        stack.clear();
        stack.extend(high);
        stack.extend(low);
        self.fronts = stack;
        self.restarted = true;
    }
}
