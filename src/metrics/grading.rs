//! How closely a packing's sizes follow the grading asked: one KS distance
//! per grading curve (in size-graded mode, each material against its own
//! curve) and, for a size-graded packing, against the blend of the curves.

use super::shapes::ShapeMemo;
use crate::Scene;
use crate::grading::{Basis, Grading};
use crate::packer::Packing;
use crate::scene::SizeMeasure;

/// The size of each packed particle that the grading gives, in packing
/// order: a disk's diameter; a grain's least width or area-equivalent
/// diameter, as the scene's `[shape]` measures it
/// ([`crate::scene::ShapeSpec::measure`]; the area-equivalent diameter, each
/// disk's, when the scene has none). Every grading fidelity in the crate
/// is measured on these sizes.
///
/// # Performance
/// A grain's size is measured once per distinct outline up to scale.
pub fn grading_sizes(packing: &Packing, scene: &Scene) -> Vec<f64> {
    sizes_with(packing, scene, &mut ShapeMemo::default())
}

/// A size measured on an outline, to 12 significant digits: the least
/// width is found numerically (within about 10⁻¹³ of the size), and a
/// grading with a vertical step (a constant size) must see the size drawn
/// on the step, not a rounding below it.
fn measured(size: f64) -> f64 {
    if !(size.is_finite() && size > 0.0) {
        return size;
    }
    let k = 10f64.powi(11 - size.log10().floor() as i32);
    (size * k).round() / k
}

/// [`grading_sizes`] through `memo`.
fn sizes_with(packing: &Packing, scene: &Scene, memo: &mut ShapeMemo) -> Vec<f64> {
    let measure = scene.shape.as_ref().map(|s| s.size);
    match measure {
        // In size-graded mode each material's particles by its own shape's measure.
        Some(_) if packing.materials.len() == packing.grains.len() => packing
            .grains
            .iter()
            .zip(&packing.materials)
            .map(|(g, &m)| {
                let m = scene
                    .material_shape(usize::from(m))
                    .map_or(SizeMeasure::Equivalent, |s| s.size);
                measured(memo.size(&g.outline, m))
            })
            .collect(),
        Some(m) if !packing.grains.is_empty() => packing
            .grains
            .iter()
            .map(|g| measured(memo.size(&g.outline, m)))
            .collect(),
        _ if !packing.grains.is_empty() => packing
            .grains
            .iter()
            .map(|g| measured(memo.size(&g.outline, SizeMeasure::Equivalent)))
            .collect(),
        _ => packing.disks.iter().map(|d| 2.0 * d.r).collect(),
    }
}

/// The sizes ([`grading_sizes`]) of the particles grading curve `curve` of
/// `scene` sized: in size-graded mode those of material `curve`, otherwise
/// every particle.
pub fn curve_diameters(packing: &Packing, scene: &Scene, curve: usize) -> Vec<f64> {
    of_curve(packing, scene, curve, grading_sizes(packing, scene))
}

/// Of `sizes` (one per particle), those of curve `curve`.
fn of_curve(packing: &Packing, scene: &Scene, curve: usize, mut sizes: Vec<f64>) -> Vec<f64> {
    // Only size-graded scenes tie a material to a curve; materials laid
    // out on a finished packing all share the one grading.
    if scene.gradient.is_some() {
        let mut materials = packing.materials.iter().chain(std::iter::repeat(&0));
        sizes.retain(|_| materials.next().is_some_and(|&m| usize::from(m) == curve));
    }
    sizes
}

/// Kolmogorov–Smirnov distance of each of `scene`'s grading curves to the
/// particles it sized, in curve order (one curve unless size-graded; a
/// material without particles counts 0).
pub fn psd_ks_by_curve(packing: &Packing, scene: &Scene) -> Vec<f64> {
    by_curve_with(packing, scene, &mut ShapeMemo::default())
}

/// [`psd_ks_by_curve`] through `memo`.
fn by_curve_with(packing: &Packing, scene: &Scene, memo: &mut ShapeMemo) -> Vec<f64> {
    let graded = scene.gradient.is_some();
    let mut sizes = sizes_with(packing, scene, memo);
    if !graded {
        // One curve sizes every particle: the sizes themselves are sorted,
        // no copy (10⁸ of them are 800 MB).
        return vec![scene.grading.ks_distance_sorting(&mut sizes)];
    }
    scene
        .curves()
        .enumerate()
        .map(|(m, curve)| {
            let mut own = of_curve(packing, scene, m, sizes.clone());
            if own.is_empty() {
                0.0
            } else {
                curve.ks_distance_sorting(&mut own)
            }
        })
        .collect()
}

/// Kolmogorov–Smirnov distance of a packing's sizes to `scene`'s grading; in
/// size-graded mode, the larger of each material's distance to its own curve.
pub fn psd_ks(packing: &Packing, scene: &Scene) -> f64 {
    psd_ks_with(packing, scene, &mut ShapeMemo::default())
}

/// [`psd_ks`] through `memo`.
pub(super) fn psd_ks_with(packing: &Packing, scene: &Scene, memo: &mut ShapeMemo) -> f64 {
    by_curve_with(packing, scene, memo)
        .into_iter()
        .fold(0.0, f64::max)
}

/// The grading of a size-graded packing as a whole: each material's curve
/// weighted by that material's share of the packed disks, counted in the
/// curves' basis (the profile decides the shares; this blend asks whether
/// the sizes within them follow the curves).
#[derive(Debug, Clone, PartialEq)]
pub struct Blend {
    /// Each curve and its weight (the weights sum to 1).
    parts: Vec<(Grading, f64)>,
    /// The basis the curves share.
    basis: Basis,
}

impl Blend {
    /// The blend of `scene`'s curves over `packing`; `None` unless the
    /// scene is size-graded, its curves share one basis and a disk is packed.
    pub fn of(packing: &Packing, scene: &Scene) -> Option<Blend> {
        scene.gradient.as_ref()?;
        let basis = scene.grading.basis();
        if scene.curves().any(|c| c.basis() != basis) {
            return None;
        }
        let k = basis.exponent();
        let sizes = grading_sizes(packing, scene);
        let weights: Vec<f64> = (0..scene.curves().count())
            .map(|m| {
                of_curve(packing, scene, m, sizes.clone())
                    .iter()
                    .map(|d| d.powi(k))
                    .sum()
            })
            .collect();
        let total: f64 = weights.iter().sum();
        (total > 0.0 && total.is_finite()).then(|| Blend {
            parts: scene
                .curves()
                .cloned()
                .zip(weights.iter().map(|w| w / total))
                .collect(),
            basis,
        })
    }

    /// Share of the blend (in its basis) passing diameter `d`.
    pub fn cdf(&self, d: f64) -> f64 {
        self.parts.iter().map(|(g, w)| w * g.cdf(d)).sum()
    }

    /// Kolmogorov–Smirnov distance of `diameters` (weighted in the blend's
    /// basis) to the blend, as [`Grading::ks_distance`] counts it: 1 for
    /// no diameter or one that is not positive and finite.
    pub fn ks_distance(&self, diameters: &[f64]) -> f64 {
        if diameters.is_empty() || diameters.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
            return 1.0;
        }
        let mut sorted = diameters.to_vec();
        sorted.sort_unstable_by(f64::total_cmp);
        let k = self.basis.exponent();
        let largest = sorted.last().copied().unwrap_or(1.0);
        let weight = |d: f64| (d / largest).powi(k);
        let total: f64 = sorted.iter().map(|&d| weight(d)).sum();
        let (mut below, mut seen, mut distance) = (0.0, 0, 0.0f64);
        for group in sorted.chunk_by(|a, b| a == b) {
            let d = group[0];
            let through = below + group.iter().map(|&x| weight(x)).sum::<f64>();
            seen += group.len();
            let after = if seen == sorted.len() {
                1.0
            } else {
                through / total
            };
            // Just below d, a step of a curve at d has not happened yet.
            distance = distance
                .max((below / total - self.cdf(d.next_down())).abs())
                .max((after - self.cdf(d)).abs());
            below = through;
        }
        distance.min(1.0)
    }
}

/// Kolmogorov–Smirnov distance of all of a size-graded packing's disks to
/// the [`Blend`] of its curves; `None` where [`Blend::of`] is.
pub fn psd_ks_blend(packing: &Packing, scene: &Scene) -> Option<f64> {
    let diameters = grading_sizes(packing, scene);
    Blend::of(packing, scene).map(|b| b.ks_distance(&diameters))
}
