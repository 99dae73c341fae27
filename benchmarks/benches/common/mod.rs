//! The scene the benchmarks pack: the thesis' Table 3.4 grading in a square.

use gapack::{Domain, Grading, PackerSettings, Scene};

/// The square of Table 3.4 disks (exact walls, seed 1) sized to hold about
/// `n` disks at the bulk porosity 0.18, packed with `packer`.
pub fn square(n: f64, packer: PackerSettings) -> Scene {
    let grading = Grading::from_table(
        gapack::THESIS_TABLE_3_4,
        Default::default(),
        Default::default(),
    )
    .expect("valid table");
    let side = (n * grading.mean_disk_area() / 0.82).sqrt();
    Scene::new(Domain::rectangle(side, side).expect("valid side"), grading)
        .with_packer(packer)
        .with_seed(1)
}
