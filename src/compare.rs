//! Speed against accuracy: every generator on one scene, repeated over seeds.
//!
//! The advancing front runs with each spatial index and each contact rule
//! (two contacts, dense; one contact, loose); the comparison generators
//! with the scene's own settings. Every run is timed and measured with the
//! same [`measure`]; overlaps a method leaves are reported, not hidden.

use std::time::Instant;

use crate::Scene;
use serde::{Deserialize, Serialize};

use crate::cancel::Cancel;
use crate::farm::{self, Farm};
use crate::metrics::measure;
use crate::packer::{IndexKind, Method, PackError, pack_observed};

/// `[compare]`: which methods, and how many seeds each.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareSettings {
    /// The methods compared, in order.
    pub methods: Vec<Method>,
    /// Runs per method variant, on seeds `seed`, `seed + 1`, …
    pub repeats: usize,
}

impl Default for CompareSettings {
    fn default() -> Self {
        CompareSettings {
            methods: vec![
                Method::AdvancingFront,
                Method::Rsa,
                Method::Deposition,
                Method::Relaxation,
            ],
            repeats: 5,
        }
    }
}

/// One way of packing: a method and, for the advancing front, its index and contact rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variant {
    /// The generator.
    pub method: Method,
    /// Advancing front: the spatial index.
    pub index: IndexKind,
    /// Advancing front: share of one-contact placements (0 dense, 1 loose).
    pub one_contact_share: f64,
}

impl Variant {
    /// The variants `methods` expand to: the advancing front four times
    /// (MX quadtree and grid, two contacts and one), the others once.
    pub fn expand(methods: &[Method]) -> Vec<Variant> {
        let mut out = Vec::new();
        for &method in methods {
            if method == Method::AdvancingFront {
                for one_contact_share in [0.0, 1.0] {
                    for index in [IndexKind::MxQuadtree, IndexKind::Grid] {
                        out.push(Variant {
                            method,
                            index,
                            one_contact_share,
                        });
                    }
                }
            } else {
                out.push(Variant {
                    method,
                    index: IndexKind::Grid,
                    one_contact_share: 0.0,
                });
            }
        }
        out
    }

    /// The scene packed this way.
    pub fn apply(&self, scene: &Scene, seed: u64) -> Scene {
        let mut s = scene.clone();
        s.seed = seed;
        s.packer.method = self.method;
        if self.method == Method::AdvancingFront {
            s.packer.index = self.index;
            s.packer.one_contact_share = self.one_contact_share;
        }
        s
    }
}

/// One run: a variant on one seed, timed and measured.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct CompareRun {
    /// How it packed.
    pub variant: Variant,
    /// The seed.
    pub seed: u64,
    /// Time to pack (s), measurement excluded.
    pub seconds: f64,
    /// Disks packed.
    pub particles: usize,
    /// Porosity.
    pub porosity: f64,
    /// |porosity − target|, when a target is set.
    pub target_error: Option<f64>,
    /// KS distance of the sizes to the grading.
    pub psd_ks: f64,
    /// Largest overlap relative to the sum of the radii (0 if none).
    pub max_overlap: f64,
    /// Mean disk–disk contacts per disk.
    pub coordination: f64,
    /// Standard deviation of local porosity (windows of 5·d_max; NaN if fewer than two).
    pub local_porosity_std: f64,
}

/// Run every variant of `settings` on `scene`, `repeats` seeds each from
/// the scene's seed, spread over `farm`, calling `done` after each run in
/// order (for progress). Once `cancel` is raised the runs finished so far
/// are returned.
///
/// # Errors
/// The packer's, for a scene no disk of the grading fits in.
pub fn compare(
    scene: &Scene,
    settings: &CompareSettings,
    target: Option<f64>,
    cancel: &Cancel,
    farm: &dyn Farm,
    mut done: impl FnMut(&CompareRun),
) -> Result<Vec<CompareRun>, PackError> {
    let plan: Vec<(Variant, u64)> = Variant::expand(&settings.methods)
        .into_iter()
        .flat_map(|v| (0..settings.repeats as u64).map(move |k| (v, scene.seed.wrapping_add(k))))
        .collect();
    let mut runs = Vec::new();
    let mut failed = None;
    farm::waves(
        farm,
        plan.len(),
        || cancel.is_cancelled(),
        |i| {
            let (variant, seed) = plan[i];
            measured(&variant.apply(scene, seed), cancel)
        },
        |i, result| {
            let (variant, seed) = plan[i];
            match result {
                Ok(m) => {
                    let run = CompareRun {
                        variant,
                        seed,
                        seconds: m.seconds,
                        particles: m.particles,
                        porosity: m.porosity,
                        target_error: target.map(|t| (m.porosity - t).abs()),
                        psd_ks: m.psd_ks,
                        max_overlap: m.max_overlap,
                        coordination: m.coordination,
                        local_porosity_std: m.local_porosity_std,
                    };
                    done(&run);
                    runs.push(run);
                    true
                }
                Err(Halt::Cancelled) => false,
                Err(Halt::Failed) => {
                    failed = Some(variant.apply(scene, seed));
                    false
                }
            }
        },
    );
    if let Some(s) = failed {
        // The packer's own error, from the same (pure) run on this process.
        pack_observed(&s, &mut |_| {}, &Cancel::new())?;
    }
    Ok(runs)
}

/// What one run measured: what travels between processes.
#[derive(Serialize, Deserialize)]
struct Measured {
    seconds: f64,
    particles: usize,
    porosity: f64,
    psd_ks: f64,
    max_overlap: f64,
    coordination: f64,
    local_porosity_std: f64,
}

/// Why a run of a batch gave nothing.
#[derive(Serialize, Deserialize)]
enum Halt {
    /// The flag was raised.
    Cancelled,
    /// The packer failed (the error is made again where it is reported).
    Failed,
}

/// Pack and measure one scene, timed.
fn measured(s: &Scene, cancel: &Cancel) -> Result<Measured, Halt> {
    let start = Instant::now();
    let packing = match pack_observed(s, &mut |_| {}, cancel) {
        Ok(packing) => packing,
        Err(PackError::Cancelled(_)) => return Err(Halt::Cancelled),
        Err(_) => return Err(Halt::Failed),
    };
    let seconds = start.elapsed().as_secs_f64();
    let m = measure(&packing, s);
    Ok(Measured {
        seconds,
        particles: m.particles,
        porosity: m.porosity,
        psd_ks: m.psd_ks,
        max_overlap: m.max_overlap,
        coordination: m.coordination,
        local_porosity_std: m.local_porosity_std,
    })
}

/// The variants in `variants`, each once, in first-seen order (a chart's rows and colours).
pub fn distinct(variants: impl IntoIterator<Item = Variant>) -> Vec<Variant> {
    let mut out: Vec<Variant> = Vec::new();
    for v in variants {
        if !out.contains(&v) {
            out.push(v);
        }
    }
    out
}

/// The runs on the Pareto front of time against `error` (lower is better
/// for both), fastest first: no other run is both faster and more accurate.
pub fn pareto(runs: &[CompareRun], error: impl Fn(&CompareRun) -> f64) -> Vec<CompareRun> {
    let mut sorted: Vec<CompareRun> = runs.to_vec();
    sorted.sort_by(|a, b| {
        a.seconds
            .total_cmp(&b.seconds)
            .then(error(a).total_cmp(&error(b)))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in sorted {
        let e = error(&r);
        if e < best {
            best = e;
            front.push(r);
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::grading::Grading;

    #[test]
    fn the_advancing_front_expands_to_four_variants() {
        let v = Variant::expand(&[Method::AdvancingFront, Method::Rsa]);
        assert_eq!(v.len(), 5);
        assert_eq!(v[4].method, Method::Rsa);
    }

    #[test]
    fn pareto_keeps_runs_no_other_beats_on_both() {
        let scene = Scene::new(
            Domain::rectangle(10.0, 10.0).unwrap(),
            Grading::constant(1.0).unwrap(),
        )
        .with_seed(1);
        let settings = CompareSettings {
            methods: vec![Method::AdvancingFront, Method::Rsa],
            repeats: 2,
        };
        let runs = compare(
            &scene,
            &settings,
            Some(0.3),
            &Cancel::new(),
            &crate::farm::Local,
            |_| {},
        )
        .unwrap();
        assert_eq!(runs.len(), 10);
        let err = |r: &CompareRun| r.target_error.unwrap();
        let front = pareto(&runs, err);
        for f in &front {
            assert!(
                !runs
                    .iter()
                    .any(|r| r.seconds < f.seconds && err(r) < err(f))
            );
        }
        for pair in front.windows(2) {
            assert!(pair[0].seconds <= pair[1].seconds && err(&pair[1]) < err(&pair[0]));
        }
    }
}
