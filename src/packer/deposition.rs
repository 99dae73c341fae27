//! Ballistic deposition (the "rain" of seed 000, §4.5): each disk is
//! dropped at a random abscissa, falls straight down, and rolls down the
//! bed by steepest descent until two obstacles hold it.
//!
//! # Behavior
//! Sizes come in the order `pack` draws them. A disk starts at the top of
//! the domain above a random abscissa and falls until it touches a disk,
//! a wall or a corner. Resting on one obstacle it rolls downhill: around a
//! disk or corner until it touches another obstacle or passes the height of
//! the centre it rolls on (then it falls again); along a straight wall
//! until it touches something or leaves the wall's end (then it rolls over
//! the corner); inside a circular wall towards its lowest point. Held by
//! two obstacles it stays if gravity points between their contact normals,
//! and otherwise rolls on around the one it does not leave. A floor (a
//! horizontal wall) and the bottom of a circular wall hold a disk alone.
//! Every move is computed exactly (circle and line intersections), so the
//! disks do not overlap. The run stops when a size finds no column whose
//! top it can start from: the pile has reached the top of the domain.

use std::cell::Cell;

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use super::placed::{POSITION_STREAM, Placed, check_fits, radii, unless_stopped};
use super::{PackError, Packing};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::predicates::{intersect_circle_circle, intersect_circle_line};
use crate::geometry::{Disk, Point, Wall};

/// Abscissae tried for one size before the run stops.
const START_TRIES: usize = 64;

/// Moves (falls and rolls) one disk may make before it is left where it is.
const MAX_MOVES: usize = 512;

/// Relative margin that tells a contact being left from one being reached.
const EPS: f64 = 1e-9;

/// Pack `scene` by ballistic deposition.
///
/// # Errors
/// [`PackError::DomainTooNarrow`] when no disk of the grading fits;
/// [`PackError::TooManyWallDisks`] when the wall disks would be too many;
/// [`PackError::PeriodicMethod`] for a periodic cell (disks fall onto a floor).
pub fn pack_deposition(scene: &Scene, cancel: &Cancel) -> Result<Packing, PackError> {
    let stopped = Cell::new(None);
    check_fits(scene)?;
    // `check_fits` refuses a periodic cell for this method; one packed with
    // another method's settings is refused here.
    if scene.domain.is_periodic() {
        return Err(PackError::PeriodicMethod {
            method: "deposition",
        });
    }
    let mut placed = Placed::new(scene);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(scene.seed ^ POSITION_STREAM);
    let (lo, hi) = scene.domain.bounds();
    let walls = scene.domain.walls().to_vec();
    let corners: Vec<Disk> = walls
        .iter()
        .filter_map(|w| match *w {
            Wall::Segment { a, .. } => Some(Disk { c: a, r: 0.0 }),
            Wall::Circle { .. } => None,
        })
        .collect();
    'sizes: for r in radii(scene, cancel, &stopped) {
        placed.stats.sizes_drawn += 1;
        for _ in 0..START_TRIES {
            let x = lo.x + r + (hi.x - lo.x - 2.0 * r).max(0.0) * rng.r#gen::<f64>();
            let Some(start) = top_of_column(&placed, x, r, lo.y, hi.y) else {
                continue;
            };
            let world = World {
                placed: &placed,
                walls: &walls,
                corners: &corners,
                r,
            };
            let (p, moves) = world.settle(start);
            placed.stats.front_attempts += moves as u64;
            if moves >= MAX_MOVES {
                placed.stats.fallbacks += 1;
            }
            if placed.clear(p, r) {
                placed.insert(Disk { c: p, r })?;
                continue 'sizes;
            }
        }
        placed.stats.sizes_unplaced += 1;
        break;
    }
    unless_stopped(placed.into_packing(), &stopped)
}

/// The highest point of the vertical line at `x` where a disk of radius `r`
/// is inside the domain and clear of every disk, looking no deeper than
/// the wall disks reach below the top (deeper, the column is full).
fn top_of_column(placed: &Placed<'_>, x: f64, r: f64, y0: f64, y1: f64) -> Option<Point> {
    let step = (r / 4.0).max((y1 - y0) * 1e-9);
    let mut y = y1 - r;
    while y >= y0 + r {
        let p = Point::new(x, y);
        if placed.domain.signed_distance(p) >= r {
            let below = y - 2.0 * placed.wall_r - step;
            while y >= below.max(y0 + r) {
                let p = Point::new(x, y);
                if placed.clear(p, r) {
                    return Some(p);
                }
                y -= step.min(placed.wall_r.max(step * 1e-3));
            }
            return None;
        }
        y -= step;
    }
    None
}

/// What a disk touches.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Obstacle {
    /// A placed disk, or a polygon corner (radius 0).
    Disk(Disk),
    /// A straight wall, the domain on its left.
    Segment { a: Point, b: Point },
    /// A circular wall, the domain inside.
    Circle { c: Point, radius: f64 },
}

/// The scene as one falling disk of radius `r` sees it.
struct World<'a> {
    placed: &'a Placed<'a>,
    walls: &'a [Wall],
    corners: &'a [Disk],
    r: f64,
}

impl World<'_> {
    /// Let a disk fall from `p` and roll until it rests; its resting centre
    /// and the moves it made.
    fn settle(&self, mut p: Point) -> (Point, usize) {
        let mut contact = None;
        for moves in 1..=MAX_MOVES {
            let next = match contact {
                None => self.fall(p),
                Some(o) => self.roll(p, o),
            };
            match next {
                Step::Rest(q) => return (q, moves),
                Step::Touch(q, o) => {
                    p = q;
                    contact = Some(o);
                }
                Step::Free(q) => {
                    p = q;
                    contact = None;
                }
            }
        }
        (p, MAX_MOVES)
    }

    /// Everything within `reach` of the box `lo`–`hi`: disks, corners, walls.
    fn obstacles(&self, lo: Point, hi: Point) -> Vec<Obstacle> {
        let reach = self.r + self.placed.r_max;
        let (lo, hi) = (
            Point::new(lo.x - reach, lo.y - reach),
            Point::new(hi.x + reach, hi.y + reach),
        );
        let mut out = Vec::new();
        self.placed.visit(lo, hi, |d| out.push(Obstacle::Disk(d)));
        out.extend(self.corners.iter().map(|&d| Obstacle::Disk(d)));
        out.extend(self.walls.iter().map(|w| match *w {
            Wall::Segment { a, b } => Obstacle::Segment { a, b },
            Wall::Circle { center, radius } => Obstacle::Circle { c: center, radius },
        }));
        out
    }

    /// Fall straight down from `p` to the first obstacle.
    fn fall(&self, p: Point) -> Step {
        let r = self.r;
        let floor = self.placed.domain.bounds().0.y - 1.0;
        let near = self.obstacles(Point::new(p.x, floor), p);
        let mut best: Option<(f64, Obstacle)> = None;
        for o in near {
            let Some(y) = self.landing(p, o) else {
                continue;
            };
            if y <= p.y + EPS * r && best.is_none_or(|(b, _)| y > b) {
                best = Some((y, o));
            }
        }
        match best {
            Some((y, o)) => Step::Touch(Point::new(p.x, y.min(p.y)), o),
            // Nothing below: cannot happen inside a closed domain; stay.
            None => Step::Rest(p),
        }
    }

    /// The height at which a disk falling along x = p.x first touches `o`.
    fn landing(&self, p: Point, o: Obstacle) -> Option<f64> {
        let r = self.r;
        match o {
            Obstacle::Disk(d) => {
                let s = r + d.r;
                let dx = p.x - d.c.x;
                (dx.abs() < s && d.c.y < p.y).then(|| d.c.y + (s * s - dx * dx).sqrt())
            }
            Obstacle::Segment { a, b } => {
                let (n, t, len) = frame(a, b);
                // Only walls facing up hold a falling disk.
                if n.1 <= EPS {
                    return None;
                }
                let y = a.y + (r - (p.x - a.x) * n.0) / n.1;
                let q = Point::new(p.x, y);
                let s = (q.x - a.x) * t.0 + (q.y - a.y) * t.1;
                (s >= 0.0 && s <= len).then_some(y)
            }
            Obstacle::Circle { c, radius } => {
                let s = radius - r;
                let dx = p.x - c.x;
                (s > 0.0 && dx.abs() <= s).then(|| c.y - (s * s - dx * dx).sqrt())
            }
        }
    }

    /// Roll downhill from `p`, touching `o`.
    fn roll(&self, p: Point, o: Obstacle) -> Step {
        match o {
            Obstacle::Disk(d) => self.roll_on_disk(p, d),
            Obstacle::Segment { a, b } => self.slide(p, a, b),
            Obstacle::Circle { c, radius } => self.roll_in_circle(p, c, radius),
        }
    }

    /// Roll around disk (or corner) `d`: to the first obstacle, or off its side.
    fn roll_on_disk(&self, p: Point, d: Disk) -> Step {
        let rho = self.r + d.r;
        let (ux, uy) = ((p.x - d.c.x) / rho, (p.y - d.c.y) / rho);
        if uy <= EPS {
            // At or below the height of the centre: nothing holds it.
            return Step::Free(Point::new(p.x, p.y - EPS * self.r));
        }
        if ux.abs() <= EPS {
            return Step::Rest(p); // balanced on top
        }
        // Clockwise on the right side, counter-clockwise on the left, to the side point.
        let dir = if ux > 0.0 { -1.0 } else { 1.0 };
        let from = uy.atan2(ux);
        let to = if ux > 0.0 { 0.0 } else { std::f64::consts::PI };
        let sweep = (to - from).abs();
        let on = |angle: f64| Point::new(d.c.x + rho * angle.cos(), d.c.y + rho * angle.sin());
        let near = self.obstacles(
            Point::new(d.c.x - rho, d.c.y - rho),
            Point::new(d.c.x + rho, d.c.y + rho),
        );
        let mut first: Option<(f64, Point, Obstacle)> = None;
        for o in near {
            if o == Obstacle::Disk(d) {
                continue;
            }
            for q in self.loci_on_circle(d.c, rho, o) {
                let a = (q.y - d.c.y).atan2(q.x - d.c.x);
                let mut swept = dir * (a - from);
                if swept < -std::f64::consts::PI {
                    swept += std::f64::consts::TAU;
                }
                if swept > EPS && swept <= sweep && first.is_none_or(|(s, ..)| swept < s) {
                    first = Some((swept, q, o));
                }
            }
        }
        match first {
            Some((_, q, o)) => self.held(q, Obstacle::Disk(d), o),
            None => {
                let side = on(to);
                Step::Free(Point::new(side.x, side.y - EPS * self.r))
            }
        }
    }

    /// Slide down the straight wall `a`→`b` to the first obstacle, or over its end.
    fn slide(&self, p: Point, a: Point, b: Point) -> Step {
        let (_, t, len) = frame(a, b);
        if t.1.abs() <= EPS {
            return Step::Rest(p); // a floor
        }
        // Downhill along the wall, to the end of the wall on that side.
        let (ux, uy) = if t.1 < 0.0 { t } else { (-t.0, -t.1) };
        let s_now = (p.x - a.x) * t.0 + (p.y - a.y) * t.1;
        let run = if t.1 < 0.0 { len - s_now } else { s_now };
        let end = Point::new(p.x + ux * run, p.y + uy * run);
        let near = self.obstacles(
            Point::new(p.x.min(end.x), p.y.min(end.y)),
            Point::new(p.x.max(end.x), p.y.max(end.y)),
        );
        let mut first: Option<(f64, Point, Obstacle)> = None;
        let me = Obstacle::Segment { a, b };
        let ends = [a, b].map(|c| Obstacle::Disk(Disk { c, r: 0.0 }));
        for o in near {
            // Its own ends are reached where it ends: handled below.
            if o == me || ends.contains(&o) {
                continue;
            }
            for q in self.loci_on_line(p, (ux, uy), o) {
                let s = (q.x - p.x) * ux + (q.y - p.y) * uy;
                if s > EPS * self.r && s <= run && first.is_none_or(|(f, ..)| s < f) {
                    first = Some((s, q, o));
                }
            }
        }
        match first {
            Some((_, q, o)) => self.held(q, me, o),
            None => {
                // Over the end: roll on the corner there.
                let corner = if t.1 < 0.0 { b } else { a };
                Step::Touch(end, Obstacle::Disk(Disk { c: corner, r: 0.0 }))
            }
        }
    }

    /// Roll inside the circular wall towards its lowest point.
    fn roll_in_circle(&self, p: Point, c: Point, radius: f64) -> Step {
        let rho = radius - self.r;
        let (ux, uy) = ((p.x - c.x) / rho, (p.y - c.y) / rho);
        if ux.abs() <= EPS && uy < 0.0 {
            return Step::Rest(p);
        }
        let from = uy.atan2(ux);
        let to = -std::f64::consts::FRAC_PI_2;
        let dir = if ux > 0.0 { -1.0 } else { 1.0 };
        let mut sweep = dir * (to - from);
        if sweep < 0.0 {
            sweep += std::f64::consts::TAU;
        }
        let near = self.obstacles(
            Point::new(c.x - rho, c.y - rho),
            Point::new(c.x + rho, c.y + rho),
        );
        let me = Obstacle::Circle { c, radius };
        let mut first: Option<(f64, Point, Obstacle)> = None;
        for o in near {
            if o == me {
                continue;
            }
            for q in self.loci_on_circle(c, rho, o) {
                let a = (q.y - c.y).atan2(q.x - c.x);
                let mut swept = dir * (a - from);
                if swept < 0.0 {
                    swept += std::f64::consts::TAU;
                }
                if swept > EPS && swept <= sweep && first.is_none_or(|(s, ..)| swept < s) {
                    first = Some((swept, q, o));
                }
            }
        }
        match first {
            Some((_, q, o)) => self.held(q, me, o),
            None => Step::Rest(Point::new(c.x, c.y - rho)),
        }
    }

    /// Touching `a` and `b` at `p`: rest if gravity points between the
    /// contact normals, else roll on around the one it does not leave.
    fn held(&self, p: Point, a: Obstacle, b: Obstacle) -> Step {
        let (na, nb) = (self.normal(p, a), self.normal(p, b));
        let cross = |u: (f64, f64), v: (f64, f64)| u.0 * v.1 - u.1 * v.0;
        let up = (0.0, 1.0);
        let ab = cross(na, nb);
        if ab.abs() <= EPS {
            // One normal: a corner and the wall that starts there; go on along the wall.
            return match (a, b) {
                (_, Obstacle::Segment { .. }) => Step::Touch(p, b),
                _ => Step::Touch(p, a),
            };
        }
        if cross(na, up) * ab >= 0.0 && cross(up, nb) * ab >= 0.0 {
            return Step::Rest(p);
        }
        // Roll about the contact whose downhill motion moves away from the other.
        let downhill = |n: (f64, f64)| {
            let t = (-n.1, n.0);
            if t.1 <= 0.0 { t } else { (-t.0, -t.1) }
        };
        let leaves = |n: (f64, f64), other: (f64, f64)| {
            let t = downhill(n);
            t.0 * other.0 + t.1 * other.1 >= 0.0
        };
        if leaves(na, nb) {
            Step::Touch(p, a)
        } else if leaves(nb, na) {
            Step::Touch(p, b)
        } else {
            Step::Rest(p)
        }
    }

    /// Unit normal of contact `o` at centre `p`, pointing from `o` to the disk.
    fn normal(&self, p: Point, o: Obstacle) -> (f64, f64) {
        let unit = |x: f64, y: f64| {
            let l = (x * x + y * y).sqrt();
            if l > 0.0 { (x / l, y / l) } else { (0.0, 1.0) }
        };
        match o {
            Obstacle::Disk(d) => unit(p.x - d.c.x, p.y - d.c.y),
            Obstacle::Segment { a, b } => frame(a, b).0,
            Obstacle::Circle { c, .. } => unit(c.x - p.x, c.y - p.y),
        }
    }

    /// Centres on the circle (`c`, `rho`) where the disk touches `o`.
    fn loci_on_circle(&self, c: Point, rho: f64, o: Obstacle) -> Vec<Point> {
        let r = self.r;
        match o {
            Obstacle::Disk(d) => intersect_circle_circle(c, rho, d.c, r + d.r)
                .map(|p| p.to_vec())
                .unwrap_or_default(),
            Obstacle::Segment { a, b } => {
                let (n, t, len) = frame(a, b);
                let q = Point::new(a.x + n.0 * r, a.y + n.1 * r);
                intersect_circle_line(c, rho, q, t.0, t.1)
                    .map(|ts| {
                        ts.iter()
                            .filter(|&&s| s >= 0.0 && s <= len)
                            .map(|&s| Point::new(q.x + t.0 * s, q.y + t.1 * s))
                            .collect()
                    })
                    .unwrap_or_default()
            }
            Obstacle::Circle { c: wc, radius } => intersect_circle_circle(c, rho, wc, radius - r)
                .map(|p| p.to_vec())
                .unwrap_or_default(),
        }
    }

    /// Centres on the ray from `p` along unit `u` where the disk touches `o`.
    fn loci_on_line(&self, p: Point, u: (f64, f64), o: Obstacle) -> Vec<Point> {
        let r = self.r;
        let along = |ts: Option<[f64; 2]>| -> Vec<Point> {
            ts.map(|ts| {
                ts.iter()
                    .map(|&s| Point::new(p.x + u.0 * s, p.y + u.1 * s))
                    .collect()
            })
            .unwrap_or_default()
        };
        match o {
            Obstacle::Disk(d) => along(intersect_circle_line(d.c, r + d.r, p, u.0, u.1)),
            Obstacle::Circle { c, radius } => {
                along(intersect_circle_line(c, radius - r, p, u.0, u.1))
            }
            Obstacle::Segment { a, b } => {
                let (n, t, len) = frame(a, b);
                let denom = u.0 * n.0 + u.1 * n.1;
                if denom.abs() <= EPS {
                    return Vec::new();
                }
                // (p + s·u − a)·n = r
                let s = (r - ((p.x - a.x) * n.0 + (p.y - a.y) * n.1)) / denom;
                let q = Point::new(p.x + u.0 * s, p.y + u.1 * s);
                let foot = (q.x - a.x) * t.0 + (q.y - a.y) * t.1;
                if (0.0..=len).contains(&foot) {
                    vec![q]
                } else {
                    Vec::new()
                }
            }
        }
    }
}

/// One move of a disk.
enum Step {
    /// It stays here.
    Rest(Point),
    /// It touches this obstacle here and goes on from it.
    Touch(Point, Obstacle),
    /// It is free here and falls.
    Free(Point),
}

/// Inward unit normal, unit direction and length of the wall `a`→`b`.
fn frame(a: Point, b: Point) -> ((f64, f64), (f64, f64), f64) {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len = (dx * dx + dy * dy).sqrt();
    let t = (dx / len, dy / len);
    ((-t.1, t.0), t, len)
}
