//! Contacts: two disks touch when their gap is at most [`CONTACT_REL`] of
//! their radii sum (overlapping disks touch too); the coordination number
//! is the mean number of contacts per disk.

use crate::geometry::Disk;
use crate::geometry::Point;
use crate::geometry::predicates::{CONTACT_REL, overlap_disk_disk};
use crate::packer::index::{Grid, SpatialIndex};

/// Visit the disks near `all[i]`, for its contacts and overlaps.
///
/// # Behavior
/// Calls `f(j, overlap, touching)` for every `j ≠ i` that `other` accepts
/// and `grid` (an index of `all` by position) holds in the box of half side
/// `all[i].r + r_max` around its centre, and perhaps a few beyond: `overlap`
/// is relative to the radii sum (negative: a gap), `touching` says whether
/// the two are in contact.
pub(crate) fn visit_near(
    grid: &Grid,
    all: &[Disk],
    r_max: f64,
    i: usize,
    other: impl Fn(usize) -> bool,
    mut f: impl FnMut(usize, f64, bool),
) {
    let d = all[i];
    let half = d.r + r_max;
    let (lo, hi) = (
        Point::new(d.c.x - half, d.c.y - half),
        Point::new(d.c.x + half, d.c.y + half),
    );
    grid.visit_box(lo, hi, |j| {
        let j = j as usize;
        if j == i || !other(j) {
            return;
        }
        let o = all[j];
        let overlap = overlap_disk_disk(d.c, d.r, o.c, o.r);
        f(j, overlap, overlap >= -CONTACT_REL);
    });
}

/// The coordination number: `ends` contact ends (a contact between two
/// counted disks has two) over `disks` disks; 0 with no disk.
pub fn coordination(ends: usize, disks: usize) -> f64 {
    if disks == 0 {
        0.0
    } else {
        ends as f64 / disks as f64
    }
}
