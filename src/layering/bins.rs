//! The area fractions a packing achieves in bins along the axis.

use crate::geometry::{Disk, Grain, Point};
use crate::scene::Frame;

/// Points of the polygon a particle that is not a disk is clipped as: its
/// outline's inscribed polygonisation, whose area falls short of an
/// ellipse's by about 2π²/(3n²) of it (7·10⁻⁴ at 96 points), and is scaled
/// back to the particle's true area.
const OUTLINE_POINTS: usize = 96;

/// The area of every disk in every bin it reaches, computed once: the
/// packing's geometry stays fixed while materials are assigned.
///
/// # Performance
/// Exact areas (slabs or annuli, see [`Frame::area_between`]) for each disk
/// and bin it meets; a disk meets one or two bins when bins are wider than
/// the disks. Summing an assignment is then one pass over those entries.
#[derive(Debug, Clone)]
pub struct BinAreas {
    bins: usize,
    /// Entries of disk i: `entries[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    /// (bin, area in that bin) pairs.
    entries: Vec<(usize, f64)>,
}

impl BinAreas {
    /// Split the area of each of `disks` among `bins` equal bins of s.
    pub fn new(disks: &[Disk], frame: &Frame, bins: usize) -> Self {
        let bins = bins.max(1);
        let mut starts = Vec::with_capacity(disks.len() + 1);
        let mut entries = Vec::with_capacity(disks.len() * 2);
        starts.push(0);
        let bin_of = |s: f64| ((s * bins as f64).floor().max(0.0) as usize).min(bins - 1);
        for d in disks {
            let (a, b) = frame.span(d);
            let (first, last) = (bin_of(a), bin_of(b));
            if first == last {
                entries.push((first, d.area()));
            } else {
                for bin in first..=last {
                    // The outer bins reach beyond [0, 1] so no sliver is lost.
                    let lo = if bin == 0 {
                        a.min(0.0)
                    } else {
                        bin as f64 / bins as f64
                    };
                    let hi = if bin == bins - 1 {
                        b.max(1.0)
                    } else {
                        (bin + 1) as f64 / bins as f64
                    };
                    let area = frame.area_between(d, lo, hi);
                    if area > 0.0 {
                        entries.push((bin, area));
                    }
                }
            }
            starts.push(entries.len());
        }
        BinAreas {
            bins,
            starts,
            entries,
        }
    }

    /// Split the area of each particle of a packing among `bins` equal
    /// bins of s: the `disks`' areas ([`BinAreas::new`]) when `grains` is
    /// empty, else each particle's own outline (`grains[i]` centred at
    /// `disks[i]`, whose radius is its area-equivalent one), clipped.
    ///
    /// # Behavior
    /// A grain is clipped by its outline, not by its area-equivalent
    /// circle nor given whole to the bin of its centre: an elongated
    /// particle lying across a bin boundary puts its area on both sides as
    /// it really lies (its circle would put too much near its centre, and
    /// the centre's bin all of it). The outline is a polygon of
    /// `OUTLINE_POINTS` points on it, clipped by slabs (x, y) or annuli
    /// (radial) exactly, and its pieces scaled so they add up to the
    /// grain's true area (the polygon is inscribed, slightly smaller).
    pub fn of_particles(disks: &[Disk], grains: &[Grain], frame: &Frame, bins: usize) -> Self {
        if grains.is_empty() {
            return BinAreas::new(disks, frame, bins);
        }
        let bins = bins.max(1);
        let mut starts = Vec::with_capacity(disks.len() + 1);
        let mut entries = Vec::with_capacity(disks.len() * 2);
        starts.push(0);
        let bin_of = |s: f64| ((s * bins as f64).floor().max(0.0) as usize).min(bins - 1);
        let mut polygon: Vec<Point> = Vec::with_capacity(OUTLINE_POINTS);
        for (d, g) in disks.iter().zip(grains) {
            let true_area = d.area();
            let turned = g.turned();
            polygon.clear();
            polygon.extend(
                g.outline
                    .boundary(OUTLINE_POINTS)
                    .into_iter()
                    .map(|p| d.c + turned.to_world(p)),
            );
            let (a, b) = frame.polygon_span(&polygon);
            let (first, last) = (bin_of(a), bin_of(b));
            let whole = frame.polygon_area_below(&polygon, b.max(1.0) + 1.0);
            if first == last || whole <= 0.0 {
                entries.push((first, true_area));
            } else {
                let scale = true_area / whole;
                let below = |s: f64| frame.polygon_area_below(&polygon, s);
                let mut under = 0.0;
                for bin in first..=last {
                    // The outer bins reach beyond [0, 1] so no sliver is lost.
                    let upto = if bin == bins - 1 {
                        whole
                    } else {
                        below((bin + 1) as f64 / bins as f64)
                    };
                    let area = (upto - under) * scale;
                    under = upto;
                    if area > 0.0 {
                        entries.push((bin, area));
                    }
                }
            }
            starts.push(entries.len());
        }
        BinAreas {
            bins,
            starts,
            entries,
        }
    }

    /// Number of bins.
    pub fn bins(&self) -> usize {
        self.bins
    }

    /// Number of disks.
    pub fn disks(&self) -> usize {
        self.starts.len() - 1
    }

    /// The bins disk `i` reaches, with its area in each.
    pub fn of(&self, i: usize) -> &[(usize, f64)] {
        &self.entries[self.starts[i]..self.starts[i + 1]]
    }

    /// Area of each material in each bin (flat: bin b at `b·materials..`)
    /// for the material of each disk given by `material`, into `out`.
    pub fn material_areas(
        &self,
        materials: usize,
        material: impl Fn(usize) -> usize,
        out: &mut [f64],
    ) {
        out.fill(0.0);
        for i in 0..self.disks() {
            let m = material(i);
            for &(bin, area) in self.of(i) {
                out[bin * materials + m] += area;
            }
        }
    }
}

/// Root-mean-square difference between the achieved fractions (from the
/// material areas per bin, `areas`) and the `targets`, over every material
/// of every bin holding some solid; 0 if none does.
pub fn rms_error(areas: &[f64], targets: &[f64], materials: usize) -> f64 {
    let (mut sum, mut count) = (0.0, 0usize);
    for (bin_areas, bin_targets) in areas.chunks(materials).zip(targets.chunks(materials)) {
        let solid: f64 = bin_areas.iter().sum();
        if solid <= 0.0 {
            continue;
        }
        for (a, t) in bin_areas.iter().zip(bin_targets) {
            sum += (a / solid - t).powi(2);
            count += 1;
        }
    }
    if count == 0 {
        0.0
    } else {
        (sum / count as f64).sqrt()
    }
}

/// One bin of a profile report.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileRow {
    /// Bin index, from 0.
    pub bin: usize,
    /// Mid-point of the bin in s.
    pub s: f64,
    /// Target fraction of each material.
    pub target: Vec<f64>,
    /// Achieved fraction of each material (NaN in a bin with no solid).
    pub achieved: Vec<f64>,
}

/// The rows of a profile report from material areas per bin and targets.
pub fn profile_rows(areas: &[f64], targets: &[f64], materials: usize) -> Vec<ProfileRow> {
    areas
        .chunks(materials)
        .zip(targets.chunks(materials))
        .enumerate()
        .map(|(bin, (a, t))| {
            let bins = areas.len() / materials;
            let solid: f64 = a.iter().sum();
            ProfileRow {
                bin,
                s: (bin as f64 + 0.5) / bins as f64,
                target: t.to_vec(),
                achieved: a
                    .iter()
                    .map(|x| if solid > 0.0 { x / solid } else { f64::NAN })
                    .collect(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::layering::Axis;

    #[test]
    fn bin_areas_conserve_each_disk() {
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        let disks = [
            Disk::new(1.0, 1.0, 0.9),
            Disk::new(5.0, 5.0, 1.2),
            Disk::new(9.2, 9.2, 0.8),
        ];
        for axis in [Axis::X, Axis::Y, Axis::Radial] {
            let areas = BinAreas::new(&disks, &Frame::new(axis, &domain), 7);
            for (i, d) in disks.iter().enumerate() {
                let total: f64 = areas.of(i).iter().map(|e| e.1).sum();
                assert!(
                    (total - d.area()).abs() < 1e-8,
                    "{axis:?} disk {i}: {total}"
                );
            }
        }
    }

    #[test]
    fn bin_areas_of_grains_follow_their_outlines() {
        use crate::geometry::Outline;
        let domain = Domain::rectangle(10.0, 10.0).unwrap();
        // An ellipse 4 × 0.5 lying along x across the bins of x at 2 mm,
        // and the same standing along y: along x the lying one spreads
        // over three bins, the standing one stays in its own.
        let ellipse = Outline::superellipse(2.0, 0.25, 2.0, 2.0).unwrap();
        let grains = vec![
            Grain::new(ellipse.clone(), 0.0),
            Grain::new(ellipse.clone(), std::f64::consts::FRAC_PI_2),
        ];
        let disks: Vec<Disk> = [(5.0, 5.0), (3.0, 5.0)]
            .iter()
            .map(|&(x, y)| Disk::new(x, y, ellipse.equivalent_radius()))
            .collect();
        let areas = BinAreas::of_particles(&disks, &grains, &Frame::new(Axis::X, &domain), 5);
        for i in 0..2 {
            let total: f64 = areas.of(i).iter().map(|e| e.1).sum();
            assert!((total - ellipse.area()).abs() < 1e-9, "grain {i}: {total}");
        }
        let lying: Vec<usize> = areas.of(0).iter().map(|e| e.0).collect();
        assert_eq!(lying, [1, 2, 3]);
        // Its middle bin (4 ≤ x < 6) holds the ellipse between x = ±1:
        // (ab)(2·asin(1/2) + sin(2·asin(1/2))) of its πab.
        let middle = areas.of(0)[1].1;
        let expected = 0.5 * (std::f64::consts::FRAC_PI_3 + 3f64.sqrt() / 2.0);
        assert!((middle - expected).abs() < 2e-3 * expected, "{middle}");
        assert_eq!(areas.of(1).len(), 1);
        // Radial: the areas add up too.
        let radial = BinAreas::of_particles(&disks, &grains, &Frame::new(Axis::Radial, &domain), 6);
        let total: f64 = radial.of(0).iter().map(|e| e.1).sum();
        assert!((total - ellipse.area()).abs() < 1e-9);
        assert!(radial.of(0).len() >= 2);
    }

    #[test]
    fn rms_error_is_zero_on_target_and_skips_empty_bins() {
        let areas = [3.0, 1.0, 0.0, 0.0, 1.0, 1.0];
        let on = [0.75, 0.25, 0.3, 0.7, 0.5, 0.5];
        assert!(rms_error(&areas, &on, 2) < 1e-15);
        let off = [0.5, 0.5, 0.3, 0.7, 0.5, 0.5];
        // Two bins hold solid: errors 0.25, 0.25, 0, 0.
        assert!((rms_error(&areas, &off, 2) - (0.125f64 / 4.0).sqrt()).abs() < 1e-12);
        let rows = profile_rows(&areas, &on, 2);
        assert!(rows[1].achieved[0].is_nan());
        assert_eq!(rows[2].s, 5.0 / 6.0);
    }
}
