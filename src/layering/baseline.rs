//! A direct assignment of materials, without the GA: the reference the GA
//! starts from and is compared with.

use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::profile::Frame;
use crate::geometry::Disk;

/// Assign a material to each disk: disks go to the bin their centre lies in;
/// within a bin, in a seeded random order, each disk takes the material
/// furthest below its share of the bin's solid area (`targets`, flat by
/// bin as from [`crate::layering::Profile::bin_targets`]).
///
/// # Behavior
/// Ties go to the lower material index. The result is one material index
/// per disk, in disk order, and depends only on the inputs and `seed`.
///
/// # Performance
/// One sort-free pass: O(n · materials).
pub fn baseline(
    disks: &[Disk],
    frame: &Frame,
    bins: usize,
    targets: &[f64],
    materials: usize,
    seed: u64,
) -> Vec<usize> {
    let bins = bins.max(1);
    let materials = materials.max(1);
    let mut by_bin: Vec<Vec<usize>> = vec![Vec::new(); bins];
    for (i, d) in disks.iter().enumerate() {
        let bin = ((frame.s(d.c) * bins as f64) as usize).min(bins - 1);
        by_bin[bin].push(i);
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut assignment = vec![0; disks.len()];
    let mut deficit = vec![0.0; materials];
    for (bin, members) in by_bin.iter_mut().enumerate() {
        members.shuffle(&mut rng);
        let solid: f64 = members.iter().map(|&i| disks[i].area()).sum();
        for (m, d) in deficit.iter_mut().enumerate() {
            *d = targets.get(bin * materials + m).copied().unwrap_or(0.0) * solid;
        }
        for &i in members.iter() {
            let m = (0..materials)
                .max_by(|&a, &b| deficit[a].total_cmp(&deficit[b]).then(b.cmp(&a)))
                .unwrap_or(0);
            assignment[i] = m;
            deficit[m] -= disks[i].area();
        }
    }
    assignment
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::layering::{Axis, BinAreas, Profile, rms_error};

    #[test]
    fn baseline_follows_a_linear_profile_closely() {
        // A grid of equal disks in a 40 mm square, linear along y in 8 bins.
        let disks: Vec<Disk> = (0..40)
            .flat_map(|i| (0..40).map(move |j| Disk::new(0.5 + i as f64, 0.5 + j as f64, 0.45)))
            .collect();
        let domain = Domain::rectangle(40.0, 40.0).unwrap();
        let frame = Frame::new(Axis::Y, &domain);
        let targets = Profile::Linear.bin_targets(Axis::Y, 8, 2);
        let a = baseline(&disks, &frame, 8, &targets, 2, 1);
        assert_eq!(
            a,
            baseline(&disks, &frame, 8, &targets, 2, 1),
            "deterministic"
        );
        let bins = BinAreas::new(&disks, &frame, 8);
        let mut areas = vec![0.0; 16];
        bins.material_areas(2, |i| a[i], &mut areas);
        let rms = rms_error(&areas, &targets, 2);
        assert!(rms < 0.01, "rms {rms}");
    }
}
