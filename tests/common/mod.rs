//! Scene builders shared by the integration tests.
#![allow(dead_code)]

use gapack::{Domain, Grading, PackerSettings, Scene, WallMode};

/// Table 3.4 of the thesis: the proppant grading of the fracture case.
pub fn table_3_4() -> Grading {
    let t = [
        (1.200, 0.0),
        (1.215, 11.0),
        (1.225, 21.0),
        (1.235, 31.0),
        (1.245, 43.0),
        (1.255, 54.0),
        (1.265, 65.0),
        (1.275, 77.0),
        (1.285, 89.0),
        (1.295, 100.0),
    ];
    Grading::from_table(&t, Default::default(), Default::default()).unwrap()
}

/// A scene with default packer settings.
pub fn scene(domain: Domain, grading: Grading, walls: WallMode, seed: u64) -> Scene {
    Scene {
        domain,
        walls,
        wall_disk_diameter: None,
        grading,
        packer: PackerSettings::default(),
        seed,
    }
}

/// Porosity of a packing without the full metrics.
pub fn porosity(p: &gapack::Packing) -> f64 {
    1.0 - p.disks.iter().map(|d| d.area()).sum::<f64>() / p.domain.area()
}
