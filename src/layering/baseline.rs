//! A direct assignment of materials, without the GA: the reference the GA
//! starts from and is compared with.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::geometry::Disk;
use crate::scene::{Frame, Profile};

/// Assign a material to each disk by sweeping along the axis.
///
/// # Behavior
/// Disks are taken in order of their coordinate s; each adds its area times
/// the target fractions at its own s to every material's running debt, and
/// takes the material owed most (ties to the lower index). The cumulative
/// area of every material so follows the cumulative target along s: a step
/// profile gives sharp interfaces, a continuous one finely mixed layers.
/// Disks at the same s (a row across the axis) are randomised by a seeded
/// jitter of a quarter of the smallest disk's extent in s, so that rows do
/// not repeat one pattern. The result is one material index per disk, in
/// disk order, and depends only on the inputs and `seed`.
///
/// # Performance
/// One sort: O(n log n + n · materials).
pub fn baseline(
    disks: &[Disk],
    frame: &Frame,
    profile: &Profile,
    materials: usize,
    seed: u64,
) -> Vec<usize> {
    let materials = materials.max(1);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let r_min = disks.iter().map(|d| d.r).fold(f64::INFINITY, f64::min);
    let jitter = disks.first().map_or(0.0, |d| {
        let (a, b) = frame.span(&Disk { r: r_min, ..*d });
        0.25 * (b - a)
    });
    let mut order: Vec<(f64, usize)> = disks
        .iter()
        .enumerate()
        .map(|(i, d)| (frame.s(d.c) + jitter * (rng.r#gen::<f64>() - 0.5), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let mut debt = vec![0.0; materials];
    let mut target = vec![0.0; materials];
    let mut assignment = vec![0; disks.len()];
    for &(_, i) in &order {
        let area = disks[i].area();
        profile.fractions(frame.s(disks[i].c), &mut target);
        for (d, t) in debt.iter_mut().zip(&target) {
            *d += t * area;
        }
        let m = (0..materials)
            .max_by(|&a, &b| debt[a].total_cmp(&debt[b]).then(b.cmp(&a)))
            .unwrap_or(0);
        assignment[i] = m;
        debt[m] -= area;
    }
    assignment
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::layering::{Axis, BinAreas, rms_error};

    fn grid() -> Vec<Disk> {
        (0..40)
            .flat_map(|i| (0..40).map(move |j| Disk::new(0.5 + i as f64, 0.5 + j as f64, 0.45)))
            .collect()
    }

    #[test]
    fn baseline_follows_a_linear_profile_closely() {
        let disks = grid();
        let domain = Domain::rectangle(40.0, 40.0).unwrap();
        let frame = Frame::new(Axis::Y, &domain);
        let a = baseline(&disks, &frame, &Profile::Linear, 2, 1);
        assert_eq!(
            a,
            baseline(&disks, &frame, &Profile::Linear, 2, 1),
            "deterministic"
        );
        let bins = BinAreas::new(&disks, &frame, 8);
        let mut areas = vec![0.0; 16];
        bins.material_areas(2, |i| a[i], &mut areas);
        let rms = rms_error(&areas, &Profile::Linear.bin_targets(Axis::Y, 8, 2), 2);
        assert!(rms < 0.01, "rms {rms}");
    }

    #[test]
    fn steps_give_sharp_interfaces() {
        let disks = grid();
        let domain = Domain::rectangle(40.0, 40.0).unwrap();
        let frame = Frame::new(Axis::Y, &domain);
        let steps = Profile::Steps(vec![(1, 0.25), (0, 0.75)]);
        let a = baseline(&disks, &frame, &steps, 2, 3);
        for (d, m) in disks.iter().zip(&a) {
            assert_eq!(*m, usize::from(d.c.y < 10.0), "disk at y = {}", d.c.y);
        }
    }
}
