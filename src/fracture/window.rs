//! Representative windows: pack only as much of a fracture as its porosity
//! and coordination number need.
//!
//! # Behavior
//! The window is the fracture's first `L` mm from the wellbore. It starts at
//! [`FIRST_DIAMETERS`] largest diameters and doubles until the estimates of
//! two windows in a row agree within the tolerance, or the window is the
//! whole fracture. Each window is measured in its *core*: the window less
//! [`END_DIAMETERS`] largest diameters at each end, where the window's own
//! end walls (which the real fracture does not have there) order the pack.
//! The side walls are the fracture's own and stay in. Particles that are
//! not disks are measured on their outlines: each one's area inside each
//! block, and contacts between outlines (the rules of `metrics`).
//!
//! With the default fill (up, along the fracture) a window's pack is the
//! full pack's first stretch, disk for disk, until the window's top wall
//! comes within reach: the same seed draws the same sizes in the same order.

use std::time::Instant;

use super::{Fracture, Well};
use crate::Scene;
use crate::cancel::Cancel;
use crate::geometry::predicates::area_disk_box;
use crate::geometry::{Disk, GeometryError, Point};
use crate::metrics::{self, porosity, visit_near};
use crate::packer::index::{Grid, SpatialIndex};
use crate::packer::{PackError, Packing, pack_observed};

/// Largest diameters left out of the measure at each end of a window.
pub const END_DIAMETERS: f64 = 3.0;

/// Length of the first window, in largest diameters: a core of ten.
pub const FIRST_DIAMETERS: f64 = 2.0 * END_DIAMETERS + 10.0;

/// Length of the blocks the core is cut into for the spread, in largest diameters.
pub const BLOCK_DIAMETERS: f64 = 5.0;

/// Fewest blocks whose scatter gives a spread: fewer say too little of it
/// (a 41 mm window of a layered pack showed a quarter of its true scatter).
pub const MIN_BLOCKS: usize = 8;

/// Why a window cannot be packed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WindowError {
    /// The window's domain cannot be built.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// The window cannot be packed.
    #[error(transparent)]
    Pack(#[from] PackError),
}

/// One window packed and measured.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub struct WindowStep {
    /// Window length along the fracture (mm).
    pub length: f64,
    /// Disks packed in the window.
    pub particles: usize,
    /// Porosity of the core (the particles' area inside it: disks clipped
    /// exactly, other outlines within 3·10⁻⁵ of the area of each one cut).
    pub porosity: f64,
    /// Mean contacts with other particles of the particles centred in the core.
    pub coordination: f64,
    /// Standard error of the core porosity: the standard deviation of its
    /// blocks' porosities over the square root of their number (NaN with
    /// fewer than `MIN_BLOCKS` blocks).
    pub spread: f64,
    /// Time to pack and measure this window (s).
    pub seconds: f64,
}

/// The result of [`settle`]: every window tried and the last one's packing.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Window {
    /// The windows, shortest first; the last gives the estimate.
    pub steps: Vec<WindowStep>,
    /// Whether the estimates settled before the window reached the whole fracture.
    pub settled: bool,
    /// The last window's scene (the fracture cut to its length).
    pub scene: Scene,
    /// The last window's packing.
    pub packing: Packing,
    /// Time of all the windows together (s).
    pub seconds: f64,
}

impl Window {
    /// The last window: the estimate (`settle` always makes one).
    pub fn last(&self) -> Option<&WindowStep> {
        self.steps.last()
    }
}

/// Grow a window of `well`'s fracture until porosity (absolute) and
/// coordination number (relative) settle within `tolerance`.
///
/// # Behavior
/// Settled means: the core porosities of the last two windows differ by at
/// most `tolerance`, their coordination numbers by at most `tolerance` of
/// the last, and twice the last porosity's spread (a 95 % interval of the
/// estimate) is at most `tolerance`. A
/// fracture shorter than the next window is packed whole (and measured in
/// its core like any window); `settled` then says whether it settled.
///
/// # Errors
/// The packer's, for a window no disk fits in or once `cancel` is raised;
/// the domain's, for a fracture whose sizes are not positive.
pub fn settle(well: &Well, tolerance: f64, cancel: &Cancel) -> Result<Window, WindowError> {
    let start = Instant::now();
    let d_max = well.scene.d_max();
    let mut length = (FIRST_DIAMETERS * d_max).min(well.fracture.length);
    let mut steps: Vec<WindowStep> = Vec::new();
    loop {
        let begun = Instant::now();
        let cut = well.fracture.cut(length);
        let scene = well.scene.clone().with_domain(cut.domain()?);
        let packing = pack_observed(&scene, &mut |_| {}, cancel)?;
        let step = measure_core(&packing, &cut, d_max, begun);
        let settled = steps.last().is_some_and(|prev| {
            (step.porosity - prev.porosity).abs() <= tolerance
                && (step.coordination - prev.coordination).abs() <= tolerance * step.coordination
                && 2.0 * step.spread <= tolerance
        });
        steps.push(step);
        let whole = length >= well.fracture.length;
        if settled || whole {
            return Ok(Window {
                steps,
                settled,
                scene,
                packing,
                seconds: start.elapsed().as_secs_f64(),
            });
        }
        length = (2.0 * length).min(well.fracture.length);
    }
}

/// Measure a window's core: porosity, coordination and spread.
fn measure_core(packing: &Packing, cut: &Fracture, d_max: f64, begun: Instant) -> WindowStep {
    let end = (END_DIAMETERS * d_max).min(cut.length / 4.0);
    let (y0, y1) = (end, cut.length - end);
    let blocks = ((y1 - y0) / (BLOCK_DIAMETERS * d_max)).floor().max(1.0) as usize;
    let block = (y1 - y0) / blocks as f64;
    let (solid, coordination) = if packing.grains.is_empty() {
        (
            disk_solid(&packing.disks, cut.width, y0, block, blocks),
            coordination(&packing.disks, y0, y1),
        )
    } else {
        grain_solid(packing, cut.width, y0, y1, block, blocks)
    };
    // The aperture at each block's middle (a window is parallel-walled,
    // but measuring a tapered one stays right).
    let area = |b: usize| {
        let y = y0 + (b as f64 + 0.5) * block;
        let w = match cut.tip_width {
            None => cut.width,
            Some(tip) => cut.width + (tip - cut.width) * y / cut.length,
        };
        w * block
    };
    let porosities: Vec<f64> = (0..blocks).map(|b| porosity(solid[b], area(b))).collect();
    let total: f64 = (0..blocks).map(area).sum();
    let porosity = porosity(solid.iter().sum(), total);
    let spread = if blocks < MIN_BLOCKS {
        f64::NAN
    } else {
        let n = blocks as f64;
        let mean = porosities.iter().sum::<f64>() / n;
        let var = porosities.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (var / n).sqrt()
    };
    WindowStep {
        length: cut.length,
        particles: packing.disks.len(),
        porosity,
        coordination,
        spread,
        seconds: begun.elapsed().as_secs_f64(),
    }
}

/// The disks' area in each of `blocks` blocks of length `block` from `y0`
/// across the aperture `0..width`, each disk clipped exactly.
fn disk_solid(disks: &[Disk], width: f64, y0: f64, block: f64, blocks: usize) -> Vec<f64> {
    let mut solid = vec![0.0; blocks];
    for d in disks {
        let first = ((d.c.y - d.r - y0) / block).floor().max(0.0) as usize;
        let last = ((d.c.y + d.r - y0) / block).floor();
        if last < 0.0 || first >= blocks {
            continue;
        }
        for (b, s) in solid
            .iter_mut()
            .enumerate()
            .take((last as usize).min(blocks - 1) + 1)
            .skip(first)
        {
            let (b0, b1) = (y0 + b as f64 * block, y0 + (b + 1) as f64 * block);
            *s += area_disk_box(d.c, d.r, 0.0, width, b0, b1);
        }
    }
    solid
}

/// A packing of grains' solid area in each block (as [`disk_solid`]'s)
/// and the mean contacts of the particles centred in `y0..y1`, measured
/// on the particles' outlines, not their area-equivalent disks (which
/// neither cover the same ground nor touch where the outlines do).
fn grain_solid(
    packing: &Packing,
    width: f64,
    y0: f64,
    y1: f64,
    block: f64,
    blocks: usize,
) -> (Vec<f64>, f64) {
    let boxes: Vec<[f64; 4]> = (0..blocks)
        .map(|b| {
            let (b0, b1) = (y0 + b as f64 * block, y0 + (b + 1) as f64 * block);
            [0.0, width, b0, b1]
        })
        .collect();
    let (solid, ends) = metrics::grain_parts(packing, &boxes);
    let (mut counted, mut contacts) = (0usize, 0usize);
    for (d, e) in packing.disks.iter().zip(&ends) {
        if (y0..y1).contains(&d.c.y) {
            counted += 1;
            contacts += *e as usize;
        }
    }
    (solid, metrics::coordination(contacts, counted))
}

/// Mean contacts with other disks of the disks centred in `y0..y1`.
fn coordination(disks: &[Disk], y0: f64, y1: f64) -> f64 {
    let r_max = disks.iter().fold(0.0f64, |m, d| m.max(d.r));
    if disks.is_empty() || r_max <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (
        Point::new(f64::MAX, f64::MAX),
        Point::new(f64::MIN, f64::MIN),
    );
    for d in disks {
        lo = Point::new(lo.x.min(d.c.x), lo.y.min(d.c.y));
        hi = Point::new(hi.x.max(d.c.x), hi.y.max(d.c.y));
    }
    let mut grid = Grid::new(lo, hi, 2.0 * r_max);
    for (id, d) in disks.iter().enumerate() {
        grid.insert(id as u32, d.c);
    }
    let (mut counted, mut contacts) = (0usize, 0usize);
    for (i, d) in disks.iter().enumerate() {
        if !(y0..y1).contains(&d.c.y) {
            continue;
        }
        counted += 1;
        visit_near(
            &grid,
            disks,
            r_max,
            i,
            |_| true,
            |_, _, touching| {
                contacts += usize::from(touching);
            },
        );
    }
    metrics::coordination(contacts, counted)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::geometry::{Grain, Outline};
    use crate::grading::Grading;

    fn well(width: f64, length: f64) -> Well {
        let fracture = Fracture {
            width,
            length,
            tip_width: None,
        };
        Well {
            name: "w".to_owned(),
            fracture,
            scene: Scene::new(
                fracture.domain().unwrap(),
                Grading::uniform(1.2, 1.3, crate::Basis::Number).unwrap(),
            )
            .with_seed(3),
        }
    }

    #[test]
    fn core_of_a_square_lattice_is_measured_exactly() {
        // Disks of diameter 1 on a unit square lattice: porosity 1 − π/4 in
        // every block (8 blocks of 5 mm in the 40 mm core).
        let disks: Vec<Disk> = (0..46)
            .flat_map(|j| {
                (0..3).map(move |i| Disk {
                    c: Point::new(0.5 + f64::from(i), 0.5 + f64::from(j)),
                    r: 0.5,
                })
            })
            .collect();
        let cut = Fracture {
            width: 3.0,
            length: 46.0,
            tip_width: None,
        };
        let packing = Packing::of_disks(cut.domain().unwrap(), disks);
        let step = measure_core(&packing, &cut, 1.0, Instant::now());
        assert!((step.porosity - (1.0 - std::f64::consts::FRAC_PI_4)).abs() < 1e-9);
        // Corner columns touch 3 disks, the middle one 4.
        assert!((step.coordination - 10.0 / 3.0).abs() < 1e-9);
        assert!(step.spread < 1e-9);
    }

    #[test]
    fn core_of_a_lattice_of_squares_is_measured_on_their_outlines() {
        // Unit squares on a unit lattice fill the slot: porosity 0; each
        // touches its neighbours by a side and by a corner (8 in the
        // middle column, 5 in a column along a face): 6 on average.
        let square = Outline::polygon(
            0,
            &[
                Point::new(-0.5, -0.5),
                Point::new(0.5, -0.5),
                Point::new(0.5, 0.5),
                Point::new(-0.5, 0.5),
            ],
            0.0,
        )
        .unwrap();
        let centres: Vec<Point> = (0..46)
            .flat_map(|j| (0..3).map(move |i| Point::new(0.5 + f64::from(i), 0.5 + f64::from(j))))
            .collect();
        let grains = vec![Grain::new(square, 0.0); centres.len()];
        let cut = Fracture {
            width: 3.0,
            length: 46.0,
            tip_width: None,
        };
        let packing = Packing::of_grains(cut.domain().unwrap(), grains, &centres);
        let step = measure_core(&packing, &cut, 1.0, Instant::now());
        assert!(step.porosity.abs() < 1e-9, "{}", step.porosity);
        assert!(
            (step.coordination - 6.0).abs() < 1e-9,
            "{}",
            step.coordination
        );
        assert!(step.spread < 1e-9);
        // Their area-equivalent disks (radius 1/√π) cross the faces: about
        // 1.5 % of the slot would be lost there.
        let disks = Packing::of_disks(cut.domain().unwrap(), packing.disks.clone());
        let as_disks = measure_core(&disks, &cut, 1.0, Instant::now());
        assert!(as_disks.porosity > 0.01, "{as_disks:?}");
    }

    #[test]
    fn windows_double_until_settled_and_stay_short_of_a_long_fracture() {
        let w = well(4.0, 20000.0);
        let window = settle(&w, 0.005, &Cancel::new()).unwrap();
        assert!(window.settled);
        let lengths: Vec<f64> = window.steps.iter().map(|s| s.length).collect();
        for pair in lengths.windows(2) {
            assert!((pair[1] - 2.0 * pair[0]).abs() < 1e-9);
        }
        assert!(window.last().unwrap().length < 20000.0 / 4.0, "{lengths:?}");
        let [a, b] = [
            &window.steps[window.steps.len() - 2],
            window.last().unwrap(),
        ];
        assert!((a.porosity - b.porosity).abs() <= 0.005);
        assert_eq!(window.packing.disks.len(), b.particles);
    }

    #[test]
    fn a_short_fracture_is_packed_whole() {
        let w = well(4.0, 30.0);
        let window = settle(&w, 1e-6, &Cancel::new()).unwrap();
        assert!(!window.settled);
        assert_eq!(window.last().unwrap().length, 30.0);
    }
}
