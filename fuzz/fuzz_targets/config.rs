//! Fuzz the config pipeline: TOML text → validated config → the scenes a run
//! builds → (for small scenes) the packing and its independent check.
//!
//! The contract: no input panics, hangs or allocates without bound. A config
//! that `parse` accepts must be one a run can start on; one it refuses must
//! give an error that formats.
#![no_main]

use gapack::check;
use gapack::config::{Config, parse};
use gapack::fracture::{Extent, settle};
use gapack::{estimated_peak_bytes, size_count};
use gapack::{Method, Scene, WallMode, measure, pack};
use libfuzzer_sys::fuzz_target;

/// Scenes expected to hold at most this many disks are packed and checked;
/// larger ones are only estimated (a run would take too long per input).
const PACK_DISKS: f64 = 2000.0;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match parse(text, "fuzz") {
        Ok(config) => run(&config),
        Err(error) => {
            // The message, its place and key are what the CLI prints.
            let message = error.to_string();
            assert!(message.starts_with("fuzz:"), "{message}");
            let at = error.location();
            assert!(at.line >= 1 && at.column >= 1, "{message}");
            let _ = error.key();
        }
    }
});

/// What a run builds from an accepted config, packing only small scenes.
fn run(config: &Config) {
    let mut budget = PACK_DISKS;
    let n = estimate(config, &config.scene);
    if let Some(run) = &config.fracture {
        for well in &run.wells {
            let n = estimate(config, &well.scene);
            // Also false for an infinite estimate.
            if n > budget || n.is_nan() {
                continue;
            }
            budget -= n;
            match run.extent {
                Extent::Full => pack_and_check(&well.scene),
                Extent::Window { tolerance } => {
                    if let Ok(window) = settle(well, tolerance, &gapack::Cancel::new()) {
                        assert_valid(&window.scene, &window.packing);
                    }
                }
            }
        }
    } else if n <= budget {
        pack_and_check(&config.scene);
    }
}

/// The estimates `gapack validate` and the memory checks use; returns the
/// expected disk count, wall disks included.
fn estimate(config: &Config, scene: &Scene) -> f64 {
    let disks = scene.estimated_disks();
    let _ = estimated_peak_bytes(scene);
    let _ = size_count(&scene.domain, scene.d_min());
    let _ = (scene.d_min(), scene.d_max());
    if let Some(optimise) = &config.optimise {
        let _ = optimise.peak_bytes(scene);
    }
    assert!(!disks.is_nan(), "estimated disks NaN for {scene:?}");
    let walls = match scene.walls {
        WallMode::Exact => 0.0,
        // Validation refuses a boundary over the wall-disk cap.
        WallMode::Disks => scene
            .domain
            .boundary_disk_count(scene.wall_disk())
            .expect("an accepted config's wall disks are within the cap")
            as f64,
    };
    disks + walls
}

fn pack_and_check(scene: &Scene) {
    // A packer error (no disk fits) is an answer, not a fault.
    if let Ok(packing) = pack(scene) {
        assert_valid(scene, &packing);
    }
}

/// Zero overlaps and every disk inside, per the independent check; the
/// metrics computed as a run would.
fn assert_valid(scene: &Scene, packing: &gapack::Packing) {
    let result = check(&packing.disks, &packing.domain, Some(&scene.grading));
    let _ = measure(packing, scene);
    // Wall disks are the walls: a packing with walls = "disks" has them.
    assert_eq!(
        packing.boundary.is_empty(),
        scene.walls == WallMode::Exact,
        "wall disks missing or stray: {} for {:?}",
        packing.boundary.len(),
        scene.walls
    );
    // Relaxation reports the overlap it leaves instead of guaranteeing none.
    if scene.packer.method != Method::Relaxation {
        assert!(
            result.valid(),
            "invalid packing: {result:?}\nscene: {scene:?}"
        );
    }
}
