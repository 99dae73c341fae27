//! The area fractions a packing achieves in bins along the axis.

use crate::geometry::Disk;
use crate::scene::Frame;

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
