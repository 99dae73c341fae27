//! Starts: the first particle of a run (or of a new start when every front
//! is parked or closed), on the walls' corners or at a periodic cell's centre.

use nalgebra::Vector2;

use super::Front;
use crate::geometry::{Point, Wall};
use crate::packer::advancing_front::offset_crossing;
use crate::packer::grains::contact::{GAP_REL, Newcomer, Obstacle};
use crate::packer::index::SpatialIndex;

impl<I: SpatialIndex> Front<'_, I> {
    /// Whether the run has no particle to grow from yet.
    pub(super) fn needs_seed(&self) -> bool {
        if self.periodic {
            self.bodies.len() < 2
        } else {
            self.bodies.is_empty()
        }
    }
    /// A first particle: with walls at the lowest clear wall–wall corner
    /// of its bounding circle, slid down then left until it touches; in a
    /// periodic cell at the centre, then the second slid against the first.
    pub(super) fn seed(&mut self, new: &Newcomer) -> Option<Point> {
        if self.periodic {
            return match self.bodies.len() {
                0 => Some(self.scene.domain.centroid()),
                1 => {
                    let f = &self.bodies[0];
                    let from = f.c + Vector2::new(f.reach + new.reach, 0.0);
                    let to = f.c;
                    self.slide_clear(new, from, to)
                }
                _ => None,
            };
        }
        let mut spots = Vec::new();
        let r = new.reach;
        for (i, a) in self.walls.iter().enumerate() {
            for b in &self.walls[i + 1..] {
                corner(a, b, r, &mut spots);
            }
            if let Obstacle::Circle(o, radius) = *a {
                spots.push(Point::new(o.x, o.y - (radius - r)));
            }
        }
        spots.sort_unstable_by(|a, b| {
            (a.y, a.x)
                .partial_cmp(&(b.y, b.x))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for s in spots {
            if !self.clear(new, s, &[]) {
                continue;
            }
            let down = self.slide_clear(new, s, s - Vector2::new(0.0, 2.0 * r))?;
            return self.slide_clear(new, down, down - Vector2::new(2.0 * r, 0.0));
        }
        None
    }

    /// The farthest clear point from `from` towards `to`, by bisection
    /// (`None` when `from` is not clear).
    fn slide_clear(&mut self, new: &Newcomer, from: Point, to: Point) -> Option<Point> {
        if !self.clear(new, from, &[]) {
            return None;
        }
        if self.clear(new, to, &[]) {
            return Some(to);
        }
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let resolution = GAP_REL * new.reach / (to - from).norm().max(f64::MIN_POSITIVE);
        for _ in 0..64 {
            if hi - lo <= resolution {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if self.clear(new, from + (to - from) * mid, &[]) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(from + (to - from) * lo)
    }
}

/// The centre of a disk of radius `r` touching both straight walls inside
/// (their inward offset lines' crossing, on both segments).
fn corner(a: &Obstacle, b: &Obstacle, r: f64, out: &mut Vec<Point>) {
    let wall = |w: &Obstacle| match *w {
        Obstacle::Segment(a, b) => Some(Wall::Segment { a, b }),
        _ => None,
    };
    let (Some(wa), Some(wb)) = (wall(a), wall(b)) else {
        return;
    };
    let Some(c) = offset_crossing(&wa, &wb, r) else {
        return;
    };
    if c.t >= -r && c.t <= c.len_a + r && c.s >= -r && c.s <= c.len_b + r {
        out.push(c.at);
    }
}
