//! The disks being densified and FIRE, the minimiser that moves them.
//!
//! # Behavior
//! Unit masses and unit stiffness: the energy is ½·δ² (mm²) per overlapping
//! contact, the force on a disk the sum of δ·n over its contacts, and the
//! time step dimensionless, so a scene scaled in length minimises through
//! the same steps. The disks are kept sorted by cell (re-sorted at every
//! rebuild of the lists), so each one's neighbours lie near it in memory;
//! `ids` remembers where each came from.

use std::borrow::Cow;

use nalgebra::Vector2;

use super::cells::{Cells, permute};
use super::walls::Boundary;
use super::{MARGIN, STOP};
use crate::cancel::Cancel;
use crate::geometry::{Disk, Domain, Point};
use crate::packer::PackError;
use crate::packer::index::{Grid, SpatialIndex};

type V2 = Vector2<f64>;

/// Skin of the neighbour lists, in mean radii: pairs within their contact
/// distance plus the skin are listed, and the lists are rebuilt once a disk
/// has moved half of it.
const SKIN_RADII: f64 = 0.5;

/// FIRE's parameters, as Bitzek et al. (2006) give them but for the time
/// steps, tuned on the reference scenes (a larger largest step made the
/// dense runs several times slower).
const DT_START: f64 = 0.05;
const DT_MAX: f64 = 0.5;
const DT_MIN: f64 = 0.002;
const N_DELAY: u32 = 5;
const F_INC: f64 = 1.1;
const F_DEC: f64 = 0.5;
const ALPHA_START: f64 = 0.1;
const F_ALPHA: f64 = 0.99;

/// A minimum counts as jammed once the largest force on a disk is below
/// this share of the root-mean-square overlap: the overlaps are held in
/// balance, not being pushed apart.
const JAMMED_FORCE: f64 = 1e-7;

/// Steps over which the energy must fall by [`STALL_FALL`], or the
/// minimum counts as jammed (twice running), at the disks' size.
pub(super) const STALL_WINDOW: u64 = 2500;

/// See [`STALL_WINDOW`].
const STALL_FALL: f64 = 0.75;

/// Steps between two looks at the cancel token.
const CANCEL_STEP: u64 = 32;

/// Steps between two points of a trace ([`System::trace`]).
const TRACE_STEP: u64 = 100;

/// How a minimisation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Outcome {
    /// No widened overlap left beyond [`STOP`].
    Converged,
    /// The overlaps are held in balance: a minimum above zero.
    Jammed,
    /// The step budget ran out first.
    OutOfSteps,
}

/// What one evaluation of the forces found.
#[derive(Debug, Clone, Copy, Default)]
struct Eval {
    /// Largest widened overlap, relative to the contact distance (or the radius at a wall).
    worst: f64,
    /// ½ Σ δ² (mm²).
    energy: f64,
    /// Overlapping contacts.
    contacts: u64,
}

/// The disks being densified: centres, radii, velocities, forces, and the
/// Verlet lists of their neighbours and walls, all by slot.
pub(super) struct System<'a> {
    domain: &'a Domain,
    boundary: Boundary,
    pos: Vec<V2>,
    r: Vec<f64>,
    vel: Vec<V2>,
    force: Vec<V2>,
    /// The index (in the order drawn) of the disk in each slot.
    ids: Vec<u32>,
    /// Centres at the last build of the lists, relative to `origin`.
    anchor: Vec<[f32; 2]>,
    /// The domain's lower corner.
    origin: V2,
    /// How far a centre may move before the lists are rebuilt, less the
    /// rounding of `anchor`.
    reach_2: f64,
    /// Radii factor of the energy: 1 but while searching for the densest scale.
    scale: f64,
    r_max: f64,
    skin: f64,
    /// Neighbours `j > i` of slot `i`: `nbr[start[i]..start[i + 1]]`.
    start: Vec<u32>,
    nbr: Vec<u32>,
    /// In a periodic cell: the image of each listed neighbour, an index
    /// into `shifts` (empty with walls).
    nbr_image: Vec<u8>,
    /// The lattice shifts of a periodic cell, by [`image_code`].
    shifts: [V2; 9],
    /// For each cell of the lists' grid (of the side given), whether every
    /// point of it lies farther inside the domain than any disk reaches a
    /// wall: its disks need no look at the walls. Made once per scale.
    deep: (f64, Vec<bool>),
    /// Disks near a wall: (slot, range in `feats`, whether its centre may
    /// leave the domain before the next build).
    near_walls: Vec<(u32, u32, u32, bool)>,
    feats: Vec<u32>,
    /// Wall disks (fixed) and a grid over them.
    fixed: &'a [Disk],
    fixed_grid: &'a Grid,
    fixed_r: f64,
    /// Disks near wall disks: (slot, range in `fixed_nbr`).
    near_fixed: Vec<(u32, u32, u32)>,
    fixed_nbr: Vec<u32>,
    /// When traced: (steps, [`System::clearance`]) every [`TRACE_STEP`] steps.
    trace: Option<Vec<(u64, f64)>>,
}

impl<'a> System<'a> {
    /// The disks of radii `r` at `centres` in `domain`, with the wall disks
    /// `fixed` (a grid over them, their largest radius `fixed_r`).
    pub fn new(
        domain: &'a Domain,
        centres: &[Point],
        r: Vec<f64>,
        fixed: (&'a [Disk], &'a Grid, f64),
    ) -> Self {
        let n = r.len();
        debug_assert!(n < 1 << 31);
        let mean = r.iter().sum::<f64>() / n as f64;
        let (lo, hi) = domain.bounds();
        let skin = SKIN_RADII * mean;
        // An anchor rounds a coordinate by half an f32 ulp of the extent.
        let extent = (hi.x - lo.x).max(hi.y - lo.y) + 4.0 * skin;
        let rounding = 2.0 * extent * f64::from(f32::EPSILON);
        let reach = (0.5 * skin - 2.0 * rounding).max(0.0);
        System {
            domain,
            boundary: Boundary::new(domain),
            pos: centres.iter().map(|p| p.coords).collect(),
            r_max: r.iter().fold(0.0f64, |m, &x| m.max(x)),
            r,
            vel: vec![V2::zeros(); n],
            force: vec![V2::zeros(); n],
            ids: (0..n as u32).collect(),
            anchor: vec![[0.0; 2]; n],
            origin: lo.coords,
            reach_2: reach * reach,
            scale: 1.0,
            skin,
            start: Vec::with_capacity(n + 1),
            nbr: Vec::new(),
            nbr_image: Vec::new(),
            shifts: domain.period().map_or([V2::zeros(); 9], |w| {
                std::array::from_fn(|c| {
                    V2::new((c % 3) as f64 - 1.0, (c / 3) as f64 - 1.0).component_mul(&w)
                })
            }),
            deep: (0.0, Vec::new()),
            near_walls: Vec::new(),
            feats: Vec::new(),
            fixed: fixed.0,
            fixed_grid: fixed.1,
            fixed_r: fixed.2,
            near_fixed: Vec::new(),
            fixed_nbr: Vec::new(),
            trace: None,
        }
    }

    /// Record the clearance every [`TRACE_STEP`] steps from now on.
    pub fn start_trace(&mut self) {
        self.trace = Some(Vec::new());
    }

    /// The (steps, clearance) recorded since [`System::start_trace`].
    pub fn trace(&self) -> &[(u64, f64)] {
        self.trace.as_deref().unwrap_or_default()
    }

    /// Radius factor of the energy: the scale widened by the margin.
    fn widen(&self) -> f64 {
        self.scale * (1.0 + MARGIN)
    }

    /// Sort the disks by cell and rebuild the neighbour and wall lists at
    /// the current centres.
    fn rebuild(&mut self) {
        let k = self.widen();
        let skin = self.skin;
        let (lo, hi) = self.domain.bounds();
        let side = 2.0 * self.r_max * k + skin;
        let periodic = self.domain.is_periodic();
        if periodic {
            for p in &mut self.pos {
                *p = self.domain.wrap(Point::from(*p)).coords;
            }
        }
        let (cells, mut order) = Cells::sort(&self.pos, lo.coords, hi.coords, side);
        {
            let (pos, vel, r, ids) = (&mut self.pos, &mut self.vel, &mut self.r, &mut self.ids);
            permute(&mut order, |a, b| {
                pos.swap(a, b);
                vel.swap(a, b);
                r.swap(a, b);
                ids.swap(a, b);
            });
        }
        drop(order);
        self.start.clear();
        self.nbr.clear();
        self.nbr_image.clear();
        for (i, &p) in self.pos.iter().enumerate() {
            self.start.push(self.nbr.len() as u32);
            let ri = self.r[i] * k;
            let (pos, r, nbr, image) = (&self.pos, &self.r, &mut self.nbr, &mut self.nbr_image);
            // The images of j near i are j + s for the shifts s of the box
            // around i (the zero shift alone with walls): found around i − s.
            let around = V2::new(side, side);
            let box_ = (Point::from(p - around), Point::from(p + around));
            for s in self.domain.image_shifts(box_.0, box_.1) {
                let code = image_code(s, &self.shifts);
                cells.visit_around(cells.clamp(p - s), |j| {
                    if j > i {
                        let reach = ri + r[j] * k + skin;
                        if (pos[j] + s - p).norm_squared() < reach * reach {
                            nbr.push(j as u32);
                            if periodic {
                                image.push(code);
                            }
                        }
                    }
                });
            }
        }
        self.start.push(self.nbr.len() as u32);
        self.near_walls.clear();
        self.feats.clear();
        if !periodic {
            self.wall_lists(&cells);
        }
        self.near_fixed.clear();
        self.fixed_nbr.clear();
        if !self.fixed.is_empty() {
            for (i, &p) in self.pos.iter().enumerate() {
                let ri = self.r[i] * k;
                let half = ri + self.fixed_r * (1.0 + MARGIN) + skin;
                let first = self.fixed_nbr.len() as u32;
                let (fixed, out) = (self.fixed, &mut self.fixed_nbr);
                self.fixed_grid.visit_box(
                    Point::new(p.x - half, p.y - half),
                    Point::new(p.x + half, p.y + half),
                    |j| {
                        let w = &fixed[j as usize];
                        let reach = ri + w.r * (1.0 + MARGIN) + skin;
                        if (w.c.coords - p).norm_squared() < reach * reach {
                            out.push(j);
                        }
                    },
                );
                let last = self.fixed_nbr.len() as u32;
                if last > first {
                    self.near_fixed.push((i as u32, first, last));
                }
            }
        }
        for (a, p) in self.anchor.iter_mut().zip(&self.pos) {
            let d = p - self.origin;
            *a = [d.x as f32, d.y as f32];
        }
    }

    /// The walls each disk near them may press on (`near_walls`, `feats`),
    /// at the current centres sorted into `cells`: a domain with walls.
    fn wall_lists(&mut self, cells: &Cells) {
        let (k, skin) = (self.widen(), self.skin);
        let outside_rule = self.boundary.needs_outside_rule();
        // A polygon of many edges costs a look at each per disk: the cells
        // deep inside are found once (the signed distance is 1-Lipschitz).
        if self.deep.0 != cells.side() {
            let reach = self.r_max * k + skin;
            let half_diagonal = std::f64::consts::FRAC_1_SQRT_2 * cells.side();
            self.deep = (
                cells.side(),
                (0..cells.count())
                    .map(|c| {
                        let centre = Point::from(cells.centre(c));
                        self.domain.signed_distance(centre) - half_diagonal > reach
                    })
                    .collect(),
            );
        }
        for (i, &p) in self.pos.iter().enumerate() {
            if self.deep.1[cells.index(cells.clamp(p))] {
                continue;
            }
            let first = self.feats.len() as u32;
            self.boundary.near(p, self.r[i] * k + skin, &mut self.feats);
            // A centre within a skin of the boundary may cross it before
            // the next build: its side is looked up at every step.
            let risky = outside_rule && self.domain.signed_distance(Point::from(p)) <= skin;
            let last = self.feats.len() as u32;
            if last > first || risky {
                self.near_walls.push((i as u32, first, last, risky));
            }
        }
    }

    /// The pair forces at the current centres (into `force`, set afresh),
    /// and what they found; `PERIODIC` reads each neighbour's image.
    fn pair_forces<const PERIODIC: bool>(&mut self) -> Eval {
        let k = self.widen();
        let mut e = Eval::default();
        let (pos, r, force) = (&self.pos, &self.r, &mut self.force);
        // Backwards: every contribution to slot i from a slot j > i is in
        // before i's own turn sets it, and those from j < i come after.
        for i in (0..pos.len()).rev() {
            let (pi, ri) = (pos[i], r[i] * k);
            let mut fi = V2::zeros();
            let (a, b) = (self.start[i] as usize, self.start[i + 1] as usize);
            for (n, &j) in self.nbr[a..b].iter().enumerate() {
                let j = j as usize;
                let d = if PERIODIC {
                    pos[j] + self.shifts[usize::from(self.nbr_image[a + n])] - pi
                } else {
                    pos[j] - pi
                };
                let sum = ri + r[j] * k;
                // Without a branch on whether the pair overlaps: about half
                // the listed pairs do, past any prediction.
                let dist = d.norm_squared().sqrt();
                let depth = (sum - dist).max(0.0);
                e.worst = e.worst.max(depth / sum);
                e.energy += 0.5 * depth * depth;
                e.contacts += u64::from(depth > 0.0);
                let push = if dist > 0.0 {
                    d * (depth / dist)
                } else {
                    coincident(i, j) * depth
                };
                fi -= push;
                force[j] += push;
            }
            force[i] = fi;
        }
        e
    }

    /// The forces at the current centres (into `force`), and what they found.
    fn forces(&mut self) -> Eval {
        let mut e = if self.domain.is_periodic() {
            self.pair_forces::<true>()
        } else {
            self.pair_forces::<false>()
        };
        let k = self.widen();
        let (pos, r, force) = (&self.pos, &self.r, &mut self.force);
        for &(i, a, b, risky) in &self.near_walls {
            let i = i as usize;
            let p = pos[i];
            let outside = risky && self.domain.signed_distance(Point::from(p)) <= 0.0;
            let w = self
                .boundary
                .force(p, r[i] * k, &self.feats[a as usize..b as usize], outside);
            if w.energy > 0.0 {
                e.worst = e.worst.max(w.worst);
                e.energy += w.energy;
                e.contacts += 1;
                force[i] += w.force;
            }
        }
        for &(i, a, b) in &self.near_fixed {
            let i = i as usize;
            let (pi, ri) = (pos[i], r[i] * k);
            for &j in &self.fixed_nbr[a as usize..b as usize] {
                let w = &self.fixed[j as usize];
                let d = pi - w.c.coords;
                let sum = ri + w.r * (1.0 + MARGIN);
                let dist_2 = d.norm_squared();
                if dist_2 >= sum * sum {
                    continue;
                }
                let dist = dist_2.sqrt();
                let depth = sum - dist;
                e.worst = e.worst.max(depth / sum);
                e.energy += 0.5 * depth * depth;
                e.contacts += 1;
                force[i] += if dist > 0.0 {
                    d * (depth / dist)
                } else {
                    coincident(i, j as usize) * depth
                };
            }
        }
        e
    }

    /// Minimise the energy at radii × `scale` with FIRE, from the current
    /// centres at rest, until no widened overlap is left, the disks jam, or
    /// `steps` (counting every step) reaches `budget`.
    ///
    /// # Errors
    /// [`PackError::Cancelled`] once `cancel` is raised (looked at every
    /// [`CANCEL_STEP`] steps).
    pub fn minimise(
        &mut self,
        scale: f64,
        budget: u64,
        window: u64,
        steps: &mut u64,
        cancel: &Cancel,
    ) -> Result<Outcome, PackError> {
        self.scale = scale;
        self.vel.iter_mut().for_each(|v| *v = V2::zeros());
        self.rebuild();
        let mut dt = DT_START;
        let mut alpha = ALPHA_START;
        let mut n_pos = 0u32;
        let mut v_2 = 0.0;
        let (mut since, mut last_e, mut stalls) = (0u64, f64::INFINITY, 0u32);
        loop {
            let eval = self.forces();
            if eval.worst <= STOP {
                return Ok(Outcome::Converged);
            }
            let (power, f_2, f_max_2) = self.norms();
            let overlap_2 = 2.0 * eval.energy / eval.contacts.max(1) as f64;
            if f_max_2 < JAMMED_FORCE * JAMMED_FORCE * overlap_2 {
                return Ok(Outcome::Jammed);
            }
            since += 1;
            if since == window {
                stalls = if eval.energy > STALL_FALL * last_e {
                    stalls + 1
                } else {
                    0
                };
                if stalls == 2 {
                    return Ok(Outcome::Jammed);
                }
                (since, last_e) = (0, eval.energy);
            }
            if *steps >= budget {
                return Ok(Outcome::OutOfSteps);
            }
            if steps.is_multiple_of(CANCEL_STEP) {
                cancel.check()?;
            }
            if self.trace.is_some() && steps.is_multiple_of(TRACE_STEP) {
                let c = self.clearance();
                if let Some(t) = self.trace.as_mut() {
                    t.push((*steps, c));
                }
            }
            *steps += 1;
            let back = power <= 0.0;
            if back {
                n_pos = 0;
                dt = (dt * F_DEC).max(DT_MIN);
                alpha = ALPHA_START;
            } else {
                n_pos += 1;
                if n_pos > N_DELAY {
                    dt = (dt * F_INC).min(DT_MAX);
                    alpha *= F_ALPHA;
                }
            }
            // |v + dt·F|², from the sums already made (v = 0 going back).
            let (v_2_old, p) = if back { (0.0, 0.0) } else { (v_2, power) };
            let v_new_2 = (v_2_old + 2.0 * dt * p + dt * dt * f_2).max(0.0);
            let mix = if f_2 > 0.0 {
                alpha * (v_new_2 / f_2).sqrt()
            } else {
                0.0
            };
            v_2 = 0.0;
            let mut stale = false;
            for (((x, v), f), a) in self
                .pos
                .iter_mut()
                .zip(&mut self.vel)
                .zip(&self.force)
                .zip(&self.anchor)
            {
                if back {
                    // Back half a step, and stop (Guénolé et al. 2020).
                    *x -= *v * (0.5 * dt);
                    *v = V2::zeros();
                }
                // Semi-implicit Euler, the velocity turned towards the force.
                *v = (*v + f * dt) * (1.0 - alpha) + f * mix;
                *x += *v * dt;
                v_2 += v.norm_squared();
                let moved = *x - self.origin - V2::new(f64::from(a[0]), f64::from(a[1]));
                stale |= moved.norm_squared() > self.reach_2;
            }
            if stale {
                self.rebuild();
            }
        }
    }

    /// F·v, |F|² and the largest |F_i|².
    fn norms(&self) -> (f64, f64, f64) {
        let mut out = (0.0, 0.0, 0.0f64);
        for (f, v) in self.force.iter().zip(&self.vel) {
            let f_2 = f.norm_squared();
            out.0 += f.dot(v);
            out.1 += f_2;
            out.2 = out.2.max(f_2);
        }
        out
    }

    /// The disks at their true size, in the order drawn (in a periodic
    /// cell, each centre in the cell).
    pub fn disks(&self) -> Vec<Disk> {
        let mut out = vec![Disk::new(0.0, 0.0, 1.0); self.pos.len()];
        for ((p, &r), &id) in self.pos.iter().zip(&self.r).zip(&self.ids) {
            out[id as usize] = Disk {
                c: self.domain.wrap(Point::from(*p)),
                r,
            };
        }
        out
    }

    /// The largest factor the radii could be scaled by, at the current
    /// centres, with no overlap and every disk inside: an exact count with
    /// a fresh neighbour search, the domain's own signed distance, and the
    /// wall disks.
    pub fn clearance(&self) -> f64 {
        let (lo, hi) = self.domain.bounds();
        let side = 2.0 * self.r_max;
        // In a periodic cell, the centres put back in the cell first.
        let pos: Cow<'_, [V2]> = if self.domain.is_periodic() {
            Cow::Owned(
                self.pos
                    .iter()
                    .map(|&p| self.domain.wrap(Point::from(p)).coords)
                    .collect(),
            )
        } else {
            Cow::Borrowed(&self.pos)
        };
        let (cells, order) = Cells::sort(&pos, lo.coords, hi.coords, side);
        let at = |slot: usize| order[slot] as usize;
        let around = V2::new(side, side);
        let mut s = f64::INFINITY;
        for slot in 0..order.len() {
            let i = at(slot);
            let (p, ri) = (pos[i], self.r[i]);
            let box_ = (Point::from(p - around), Point::from(p + around));
            for shift in self.domain.image_shifts(box_.0, box_.1) {
                cells.visit_around(cells.clamp(p - shift), |other| {
                    if other > slot {
                        let j = at(other);
                        s = s.min((pos[j] + shift - p).norm() / (ri + self.r[j]));
                    }
                });
            }
            if !self.domain.is_periodic() {
                s = s.min(self.domain.signed_distance(Point::from(p)) / ri);
            }
            let half = ri + self.fixed_r;
            self.fixed_grid.visit_box(
                Point::new(p.x - half, p.y - half),
                Point::new(p.x + half, p.y + half),
                |j| {
                    let w = &self.fixed[j as usize];
                    s = s.min(((w.c.coords - p).norm() - w.r) / ri);
                },
            );
        }
        s
    }
}

/// The index in `shifts` (a 3 × 3 table of whole periods) of `shift`.
fn image_code(shift: V2, shifts: &[V2; 9]) -> u8 {
    (0..9u8)
        .find(|&c| shifts[usize::from(c)] == shift)
        .unwrap_or(4)
}

/// A direction to push apart disks `i` and `j` whose centres coincide, set by the pair.
fn coincident(i: usize, j: usize) -> V2 {
    let a = (i * 7919 + j) as f64;
    V2::new(a.cos(), a.sin())
}
