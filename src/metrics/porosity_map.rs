//! The local porosity of a packing on a regular grid of cells, for a heat
//! map that shows where a packing is loose or dense, or on a slender domain
//! (a fracture) a profile along its length.

use super::shapes::ShapeMemo;
use super::{WINDOW_DIAMETERS, porosity};
use crate::geometry::predicates::{area_disk_box, area_polygon_box};
use crate::geometry::{Grain, Point};
use crate::packer::Packing;

/// Points of the polygon a particle that is not a disk is mapped as.
const GRAIN_POINTS: usize = 64;

/// A grain's outline in world axes about its centre as a polygon of
/// [`GRAIN_POINTS`] points, scaled about the centre to the particle's exact
/// `area`: a particle wholly in a cell counts exactly, one cut by a cell's
/// edge within about 10⁻³ of its area.
fn grain_polygon(grain: &Grain, area: f64) -> Vec<nalgebra::Vector2<f64>> {
    let t = grain.turned();
    let points: Vec<nalgebra::Vector2<f64>> = grain
        .outline
        .boundary(GRAIN_POINTS)
        .iter()
        .map(|p| t.to_world(*p))
        .collect();
    let m = points.len();
    let twice: f64 = (0..m)
        .map(|i| {
            let (p, q) = (points[i], points[(i + 1) % m]);
            p.x * q.y - q.x * p.y
        })
        .sum();
    let k = if twice > 0.0 {
        (2.0 * area / twice).sqrt()
    } else {
        1.0
    };
    points.into_iter().map(|p| p * k).collect()
}

/// Most cells along the longer side of the domain's bounds.
const MAX_CELLS: f64 = 200.0;
/// Fewest cells along the longer side of the domain's bounds.
const MIN_CELLS: f64 = 4.0;
/// A side of the bounds over this many times the other makes a domain
/// slender: its map is a profile along the longer side.
pub const SLENDER: f64 = 8.0;
/// Most cells of a profile.
const MAX_PROFILE_CELLS: f64 = 20_000.0;
/// A profile's cell with less than this share of its area in the domain is
/// not mapped (the tip of a wedge keeps its cells).
const PROFILE_MASK: f64 = 0.05;

/// Local porosity on a regular grid of cells covering the domain's bounds.
///
/// Cell `(col, row)` spans `[origin.x + col·cell, origin.x + (col + 1)·cell]`
/// × `[origin.y + row·cell_height, origin.y + (row + 1)·cell_height]`; the
/// values are stored row by row from the bottom: index `row · cols + col`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct PorosityMap {
    /// Lower-left corner of the grid (mm).
    pub origin: Point,
    /// Width of a cell (mm, along x).
    pub cell: f64,
    /// Height of a cell (mm, along y): `cell` (square cells) unless the
    /// map is a profile.
    pub cell_height: f64,
    /// Whether the map is a profile along a slender domain: one cell
    /// across its whole width, cells along its length.
    pub profile: bool,
    /// Cells along x.
    pub cols: usize,
    /// Cells along y.
    pub rows: usize,
    /// Porosity of each cell, 1 − solid / in-domain area, clamped to [0, 1];
    /// NaN for a cell with less than half its area in the domain (a
    /// profile's: less than 5 %).
    pub values: Vec<f64>,
}

/// The local porosity of `packing` on a grid of square cells, or along a
/// slender domain a profile.
///
/// # Behavior
/// The cells tile a box centred on the domain's bounds. Their side is
/// 5 largest packed diameters (the windows of [`crate::measure`]'s local
/// porosity), but at least 1/200 of the bounds' longer side (at most 200
/// cells along it) and at most 1/4 of it (at least 4 cells along it); with
/// no disk it is the 1/200.
///
/// A slender domain (bounds' longer side over `SLENDER` times the
/// shorter, a fracture) gets a profile instead: square cells there would be
/// far wider than the aperture (125 mm across a 2.3 mm slot) and mostly
/// outside it. One cell spans the whole width; along the length a cell is
/// as long as the width or 5 largest diameters, whichever is longer (at
/// most 20,000 cells). A cell is masked only below 5 % of its area in the
/// domain, so a wedge's narrow tip is mapped too.
///
/// Each cell's solid area is exact: the area of every packed disk inside
/// the cell, in closed form
/// (`area_disk_box`), so the
/// cells' solid areas add up to the packing's solid area. A particle that
/// is not a disk ([`Packing::grains`]) counts as its outline made a
/// polygon of 64 points of its exact area: whole in a cell, exactly; cut
/// by a cell's edge, within about 10⁻³ of its area. Its in-domain area
/// is exact too ([`crate::Domain::area_in_box`]: closed form for a circle,
/// the boundary clipped to the cell otherwise). A cell with less than half
/// its area in the domain gets NaN: a sliver of domain gives a porosity too
/// noisy to read. Overlapping disks (relaxation leaves a few) count twice,
/// which is why values are clamped to [0, 1].
///
/// In a periodic cell a disk crossing an edge is counted where each of its
/// images lies, clipped to the cell: the cells' solid areas still add up
/// to the packing's.
///
/// # Performance
/// A cell is at least 5 diameters wide, so a disk meets at most four cells
/// and is visited once: O(disks + cells × boundary vertices), no index.
///
/// # Example
/// ```
/// use gapack::{Disk, Domain, Packing, porosity_map};
/// let packing = Packing::of_disks(
///     Domain::rectangle(80.0, 40.0).unwrap(),
///     vec![Disk::new(5.0, 5.0, 1.0), Disk::new(75.0, 35.0, 2.0)],
/// );
/// let map = porosity_map(&packing);
/// // 5 largest diameters: cells of 20 mm, 4 × 2 of them.
/// assert_eq!((map.cell, map.cols, map.rows), (20.0, 4, 2));
/// assert!((map.values[0] - (1.0 - std::f64::consts::PI / 400.0)).abs() < 1e-12);
/// ```
pub fn porosity_map(packing: &Packing) -> PorosityMap {
    map_with_areas(packing).0
}

/// [`porosity_map`], with the solid area of the packed disks inside each
/// cell (wall disks are not solid) and each cell's area inside the domain
/// (mm², row by row like the values).
fn map_with_areas(packing: &Packing) -> (PorosityMap, Vec<f64>, Vec<f64>) {
    let domain = &packing.domain;
    let (lo, hi) = domain.bounds();
    let (width, height) = (hi.x - lo.x, hi.y - lo.y);
    let (longer, shorter) = (width.max(height), width.min(height));
    let d_max = packing.disks.iter().fold(0.0f64, |m, d| m.max(2.0 * d.r));
    let profile = longer > SLENDER * shorter;
    let (cw, ch) = if profile {
        let along = (WINDOW_DIAMETERS * d_max)
            .max(shorter)
            .max(longer / MAX_PROFILE_CELLS);
        if width > height {
            (along, height)
        } else {
            (width, along)
        }
    } else {
        let cell = (WINDOW_DIAMETERS * d_max).clamp(longer / MAX_CELLS, longer / MIN_CELLS);
        (cell, cell)
    };
    let cols = (width / cw).ceil().max(1.0) as usize;
    let rows = (height / ch).ceil().max(1.0) as usize;
    let origin = Point::new(
        lo.x - 0.5 * (cols as f64 * cw - width),
        lo.y - 0.5 * (rows as f64 * ch - height),
    );
    let corner = |col: usize, row: usize| (origin.x + col as f64 * cw, origin.y + row as f64 * ch);

    let mut solid = vec![0.0; cols * rows];
    // Index of the cell column (row) holding `v` along x (y), clamped to the grid.
    let index = |v: f64, o: f64, side: f64, n: usize| {
        ((v - o) / side).floor().clamp(0.0, (n - 1) as f64) as usize
    };
    let periodic = domain.is_periodic();
    let mut memo = ShapeMemo::default();
    for (i, d) in packing.disks.iter().enumerate() {
        // A particle that is not a disk: its outline as a polygon of exact
        // area about its centre, and its bounding circle.
        let outline = packing.grains.get(i).map(|g| {
            let (unit, scale) = memo.unit(&g.outline);
            (grain_polygon(g, d.area()), unit.circumradius * scale)
        });
        let reach = outline.as_ref().map_or(d.r, |o| o.1);
        // A periodic cell: each image of the disk that crosses into the
        // cell, clipped to it, so that the disk counts once, whole.
        let (dlo, dhi) = (
            Point::new(d.c.x - reach, d.c.y - reach),
            Point::new(d.c.x + reach, d.c.y + reach),
        );
        for v in domain.image_shifts(dlo, dhi) {
            let c = if periodic { d.c - v } else { d.c };
            let (c0, c1) = (
                index(c.x - reach, origin.x, cw, cols),
                index(c.x + reach, origin.x, cw, cols),
            );
            let (r0, r1) = (
                index(c.y - reach, origin.y, ch, rows),
                index(c.y + reach, origin.y, ch, rows),
            );
            let placed: Option<Vec<Point>> = outline
                .as_ref()
                .map(|(poly, _)| poly.iter().map(|p| c + p).collect());
            for row in r0..=r1 {
                for col in c0..=c1 {
                    let (x0, y0) = corner(col, row);
                    let (mut x1, mut y1) = (x0 + cw, y0 + ch);
                    let (mut x0, mut y0) = (x0, y0);
                    if periodic {
                        (x0, x1) = (x0.max(lo.x), x1.min(hi.x));
                        (y0, y1) = (y0.max(lo.y), y1.min(hi.y));
                        if x0 >= x1 || y0 >= y1 {
                            continue;
                        }
                    }
                    solid[row * cols + col] += match &placed {
                        Some(poly) => area_polygon_box(poly, x0, x1, y0, y1),
                        None => area_disk_box(c, d.r, x0, x1, y0, y1),
                    };
                }
            }
        }
    }

    let mut inside = Vec::with_capacity(cols * rows);
    for row in 0..rows {
        for col in 0..cols {
            let (x0, y0) = corner(col, row);
            inside.push(domain.area_in_box(x0, x0 + cw, y0, y0 + ch));
        }
    }
    let least = if profile { PROFILE_MASK } else { 0.5 } * cw * ch;
    let values = solid
        .iter()
        .zip(&inside)
        .map(|(&s, &a)| {
            if a < least {
                f64::NAN
            } else {
                porosity(s, a).clamp(0.0, 1.0)
            }
        })
        .collect();
    let map = PorosityMap {
        origin,
        cell: cw,
        cell_height: ch,
        profile,
        cols,
        rows,
        values,
    };
    (map, solid, inside)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;
    use crate::geometry::{Disk, Domain};
    use crate::grading::{Basis, Grading};
    use crate::packer::pack;

    fn packing(domain: Domain, disks: Vec<Disk>) -> Packing {
        Packing::of_disks(domain, disks)
    }

    fn packed(domain: Domain) -> Packing {
        let grading = Grading::uniform(0.5, 1.5, Basis::Number).expect("grading");
        let scene = Scene::new(domain, grading).with_seed(7);
        pack(&scene).expect("packs")
    }

    #[test]
    fn particles_that_are_not_disks_count_with_their_outlines() {
        // Ellipses 4 × 1 mm (area π, equivalent radius 1) in an 80 × 40 mm
        // rectangle of 10 mm cells: one wholly in a cell, one reaching
        // 0.5 mm across the edge x = 10 of its cell, where its equivalent
        // disk (x from 10.5 to 12.5) would not.
        let domain = Domain::rectangle(80.0, 40.0).expect("rectangle");
        let e = crate::geometry::Outline::superellipse(2.0, 0.5, 2.0, 2.0).expect("ellipse");
        let r = e.equivalent_radius();
        let p = Packing {
            grains: vec![Grain::new(e.clone(), 0.0), Grain::new(e, 0.0)],
            ..packing(
                domain,
                vec![Disk::new(35.0, 25.0, r), Disk::new(11.5, 5.0, r)],
            )
        };
        let (map, solid, _) = map_with_areas(&p);
        assert!((map.cell - 10.0).abs() < 1e-9 && map.cols == 8, "{map:?}");
        let area = std::f64::consts::PI;
        // Cell (3, 2) holds the whole one, exactly.
        assert!((solid[2 * 8 + 3] - area).abs() < 1e-12, "{solid:?}");
        // Cell (0, 0) the cap of the other beyond x = 10: the unit
        // circle's segment beyond 0.75, times ab = 1.
        let cap = 0.75f64.acos() - 0.75 * (1.0 - 0.5625f64).sqrt();
        assert!((solid[0] - cap).abs() < 0.05 * cap, "{} vs {cap}", solid[0]);
        assert!((solid[0] + solid[1] - area).abs() < 1e-12, "{solid:?}");
    }

    #[test]
    fn solid_areas_add_up_to_the_packing_s() {
        // 43 × 31 mm: cells of 5 · d_max do not tile it, so edge cells are partial.
        let p = packed(Domain::rectangle(43.0, 31.0).expect("rectangle"));
        let (map, solid, inside) = map_with_areas(&p);
        // Debug text: NaN (a masked cell) equals NaN there.
        assert_eq!(format!("{map:?}"), format!("{:?}", porosity_map(&p)));
        assert!(
            map.cols >= 4 && map.rows >= 3,
            "{} × {}",
            map.cols,
            map.rows
        );
        let total: f64 = p.disks.iter().map(Disk::area).sum();
        let summed: f64 = solid.iter().sum();
        assert!(
            ((summed - total) / total).abs() < 1e-9,
            "{summed} vs {total}"
        );
        // The in-domain areas add up to the rectangle's.
        let total_inside: f64 = inside.iter().sum();
        assert!(
            (total_inside / (43.0 * 31.0) - 1.0).abs() < 1e-12,
            "{total_inside}"
        );
        // Porosities in [0, 1]; the whole cells near the packing's own.
        let porosity = 1.0 - total / (43.0 * 31.0);
        for (i, v) in map.values.iter().enumerate() {
            if inside[i] == map.cell * map.cell {
                assert!((v - porosity).abs() < 0.15, "cell {i}: {v} vs {porosity}");
            }
            assert!(v.is_nan() || (0.0..=1.0).contains(v), "cell {i}: {v}");
        }
    }

    #[test]
    fn a_periodic_cell_counts_each_disk_once_whole() {
        // 43 × 31 mm: partial cells at the edges, disks crossing every edge.
        let grading = Grading::uniform(0.5, 1.5, Basis::Number).expect("grading");
        let domain = Domain::periodic_rectangle(43.0, 31.0).expect("cell");
        let scene = Scene::new(domain, grading)
            .with_walls(crate::geometry::WallMode::Periodic)
            .with_seed(7);
        let p = pack(&scene).expect("packs");
        let crossing = p
            .disks
            .iter()
            .filter(|d| d.c.x < d.r || d.c.x > 43.0 - d.r)
            .count();
        assert!(crossing > 5, "{crossing}");
        let (_, solid, inside) = map_with_areas(&p);
        let total: f64 = p.disks.iter().map(Disk::area).sum();
        let summed: f64 = solid.iter().sum();
        assert!(
            ((summed - total) / total).abs() < 1e-9,
            "{summed} vs {total}"
        );
        // No cell holds more solid than its part of the cell.
        for (s, a) in solid.iter().zip(&inside) {
            assert!(*s <= a * (1.0 + 1e-9), "{s} > {a}");
        }
    }

    #[test]
    fn the_cell_side_follows_the_disks_within_limits() {
        let rect = || Domain::rectangle(1000.0, 200.0).expect("rectangle");
        // 5 × 2 mm = 10 mm cells.
        let map = porosity_map(&packing(rect(), vec![Disk::new(5.0, 5.0, 1.0)]));
        assert_eq!((map.cell, map.cols, map.rows), (10.0, 100, 20));
        assert_eq!((map.cell_height, map.profile), (10.0, false));
        assert_eq!(map.values.len(), 2000);
        // Tiny disks: at most 200 cells along the longer side.
        let map = porosity_map(&packing(rect(), vec![Disk::new(5.0, 5.0, 0.01)]));
        assert_eq!((map.cell, map.cols, map.rows), (5.0, 200, 40));
        // No disk at all: the same, every cell empty.
        let map = porosity_map(&packing(rect(), Vec::new()));
        assert_eq!((map.cols, map.rows), (200, 40));
        assert!(map.values.iter().all(|&v| v == 1.0));
        // Huge disks: at least 4 cells along the longer side, centred on the bounds.
        let square = Domain::rectangle(10.0, 10.0).expect("square");
        let map = porosity_map(&packing(square, vec![Disk::new(5.0, 5.0, 4.0)]));
        assert_eq!((map.cell, map.cols, map.rows), (2.5, 4, 4));
        assert_eq!(map.origin, Point::new(0.0, 0.0));
    }

    /// A slender domain had square cells 5 d_max or 1/200 of its length
    /// wide: 125 mm across a 2.3 mm × 25 m slot, and on a wedge most cells
    /// more outside than inside, "not mapped". Now one cell spans the
    /// width, as long as the aperture or 5 d_max, and nearly all are mapped.
    #[test]
    fn a_slender_domain_gets_a_profile_with_cells_sized_to_its_aperture() {
        // A 2.3 mm slot 2 m long (along y), disks of 1.2 mm in a file.
        let slot = Domain::rectangle(2.3, 2000.0).expect("slot");
        let disks = (0..1600)
            .map(|i| Disk::new(1.15, 0.7 + 1.25 * f64::from(i), 0.6))
            .collect();
        let map = porosity_map(&packing(slot, disks));
        assert!(map.profile);
        assert_eq!((map.cols, map.cell), (1, 2.3));
        // 5 × 1.2 mm along the slot: 6 mm, a few apertures, not 125 mm.
        assert!((map.cell_height - 6.0).abs() < 1e-12, "{}", map.cell_height);
        assert_eq!(map.rows, (2000.0f64 / 6.0).ceil() as usize);
        assert!(map.values.iter().all(|v| v.is_finite()));
        // A wedge 3 → 0.9 mm over 150 mm: at most a few % not mapped.
        let wedge = Domain::polygon(&[
            Point::new(0.0, 0.0),
            Point::new(3.0, 0.0),
            Point::new(1.95, 150.0),
            Point::new(1.05, 150.0),
        ])
        .expect("wedge");
        let p = packed(wedge);
        let map = porosity_map(&p);
        assert!(map.profile && map.cols == 1);
        assert!(map.cell_height <= 5.0 * 3.0 + 1e-9, "{}", map.cell_height);
        let masked = map.values.iter().filter(|v| v.is_nan()).count();
        assert!(
            masked * 100 <= 3 * map.values.len(),
            "{masked} of {} not mapped",
            map.values.len()
        );
        // The cells' solid still adds up to the packing's.
        let (_, solid, _) = map_with_areas(&p);
        let total: f64 = p.disks.iter().map(Disk::area).sum();
        assert!((solid.iter().sum::<f64>() / total - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_cell_without_disks_is_all_pore() {
        let square = Domain::rectangle(20.0, 20.0).expect("square");
        // One disk of diameter 1: cells of 5 mm, the disk in the lower-left one.
        let map = porosity_map(&packing(square, vec![Disk::new(2.5, 2.5, 0.5)]));
        assert_eq!((map.cols, map.rows), (4, 4));
        let expected = 1.0 - std::f64::consts::PI * 0.25 / 25.0;
        assert!(
            (map.values[0] - expected).abs() < 1e-12,
            "{}",
            map.values[0]
        );
        assert!(
            map.values[1..].iter().all(|&v| v == 1.0),
            "{:?}",
            map.values
        );
    }

    #[test]
    fn cells_mostly_outside_a_circle_are_masked() {
        let p = packed(Domain::circle(Point::new(0.0, 0.0), 15.0).expect("circle"));
        let (map, solid, inside) = map_with_areas(&p);
        let (cols, rows) = (map.cols, map.rows);
        assert!(cols >= 4 && cols == rows, "{cols} × {rows}");
        // The four corner cells lie mostly outside the circle; the centre ones inside.
        for i in [0, cols - 1, (rows - 1) * cols, rows * cols - 1] {
            assert!(map.values[i].is_nan(), "corner {i}: {}", map.values[i]);
        }
        let centre = rows / 2 * cols + cols / 2;
        assert!(
            (0.0..0.5).contains(&map.values[centre]),
            "{}",
            map.values[centre]
        );
        // Masked cells are exactly those with less than half their area inside.
        for (v, a) in map.values.iter().zip(&inside) {
            assert_eq!(v.is_nan(), *a < 0.5 * map.cell * map.cell);
        }
        let total_inside: f64 = inside.iter().sum();
        assert!(
            (total_inside / p.domain.area() - 1.0).abs() < 1e-12,
            "{total_inside}"
        );
        let total: f64 = p.disks.iter().map(Disk::area).sum();
        let summed: f64 = solid.iter().sum();
        assert!(
            ((summed - total) / total).abs() < 1e-9,
            "{summed} vs {total}"
        );
    }
}
