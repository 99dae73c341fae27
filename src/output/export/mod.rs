//! Exports for DEM codes and viewers: one file per format, each checked
//! first and then written where it goes as it is produced (its rows
//! formatted in parallel blocks), never held whole; or rendered in memory. Only the packed disks are
//! exported, never the wall disks.

mod binary;
mod clumps;
mod common;
mod esys;
mod json;
mod lammps;
mod lammps_clumps;
mod liggghts;
mod mercury;
mod npz;
mod outline;
mod pfc;
mod vtk;
mod vtp;
mod yade;

pub(crate) use esys::esys_geometry_writer;
pub use esys::{ESYS_GEOMETRY, esys_geometry};
pub(crate) use json::packing_json_writer;
pub use json::{PACKING_JSON, packing_json};
pub(crate) use lammps::lammps_data_writer;
pub use lammps::{LAMMPS_DATA, lammps_data};
pub use lammps_clumps::{
    LAMMPS_CLUMPS_DATA, LIGGGHTS_CLUMPS_DATA, lammps_clumps_data, liggghts_clumps_data,
};
pub(crate) use lammps_clumps::{lammps_clumps_data_writer, liggghts_clumps_data_writer};
pub use liggghts::{SUPERQUADRIC_DATA, SUPERQUADRIC_INPUT, superquadric_data, superquadric_input};
pub(crate) use liggghts::{superquadric_data_writer, superquadric_input_writer};
pub(crate) use mercury::mercury_data_writer;
pub use mercury::{MERCURY_DATA, mercury_data};
pub use npz::{PACKING_NPZ, write_packing_npz, write_packing_npz_with};
pub(crate) use pfc::pfc_commands_writer;
pub use pfc::{PFC_COMMANDS, pfc_commands};
pub(crate) use vtk::packing_vtk_writer;
pub use vtk::{BOUNDARY_VTK, PACKING_VTK, boundary_vtk, packing_vtk};
pub use vtp::{PACKING_VTP, write_packing_vtp, write_packing_vtp_with};
pub use yade::{YADE_SCRIPT, YADE_TEXT, yade_script, yade_text};
pub(crate) use yade::{yade_script_writer, yade_text_writer};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain, Grain, Outline, Point};
    use crate::layering::Material;
    use crate::output::format::{ExportOptions, LengthUnit};
    use crate::output::{OutputError, RunInfo};
    use crate::packer::Packing;
    use crate::{measure, pack};
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// A random outline: a superquadric (alpha = beta >= 2), another
    /// superellipse or a rounded polygon, as `kind` asks (0, 1, 2).
    fn outline(rng: &mut Xoshiro256PlusPlus, kind: u8) -> Outline {
        let a = rng.gen_range(0.3..1.5);
        let b = rng.gen_range(0.3..1.5);
        match kind {
            0 => {
                let n = rng.gen_range(2.0..6.0);
                Outline::superellipse(a, b, n, n).expect("valid")
            }
            1 => Outline::superellipse(a, b, rng.gen_range(1.2..5.0), rng.gen_range(1.2..5.0))
                .expect("valid"),
            _ => {
                let square = [
                    Point::new(-a, -b),
                    Point::new(a, -b),
                    Point::new(a, b),
                    Point::new(-a, b),
                ];
                let rounding = if rng.gen_bool(0.5) {
                    0.0
                } else {
                    0.05 * a.min(b)
                };
                Outline::polygon(3, &square, rounding).expect("valid")
            }
        }
    }

    /// A random packing (overlaps allowed: the exports do not check them)
    /// of `n` disks, or of grains whose kinds are drawn from `kinds`, with
    /// `materials` materials, periodic or with wall disks.
    fn scene(
        rng: &mut Xoshiro256PlusPlus,
        n: usize,
        kinds: Option<&[u8]>,
        materials: usize,
    ) -> Packing {
        let (w, h) = (rng.gen_range(5.0..50.0), rng.gen_range(5.0..50.0));
        let domain = match rng.gen_range(0..3) {
            0 => Domain::periodic_rectangle(w, h).expect("valid"),
            1 => Domain::circle(Point::new(w / 2.0, w / 2.0), w / 2.0).expect("valid"),
            _ => Domain::rectangle(w, h).expect("valid"),
        };
        let disks: Vec<Disk> = (0..n)
            .map(|_| {
                Disk::new(
                    rng.gen_range(0.0..w),
                    rng.gen_range(0.0..h),
                    rng.gen_range(0.05..1.5),
                )
            })
            .collect();
        let mut packing = Packing::of_disks(domain.clone(), disks);
        if !domain.is_periodic() && rng.gen_bool(0.5) {
            packing.boundary = domain.boundary_disks(0.5);
        }
        if let Some(kinds) = kinds {
            packing.grains = (0..n)
                .map(|_| {
                    let kind = kinds[rng.gen_range(0..kinds.len())];
                    Grain::new(outline(rng, kind), rng.gen_range(-3.2..3.2))
                })
                .collect();
            for (d, g) in packing.disks.iter_mut().zip(&packing.grains) {
                d.r = g.outline.equivalent_radius();
            }
        }
        if materials > 0 {
            packing.materials = (0..n).map(|_| rng.gen_range(0..materials as u16)).collect();
        }
        packing
    }

    /// `count` materials, some with a density.
    fn materials(count: usize) -> Vec<Material> {
        (0..count)
            .map(|i| Material {
                name: format!("m {i}"),
                properties: if i % 2 == 0 {
                    vec![("density".to_owned(), 1000.0 + 700.0 * i as f64)]
                } else {
                    Vec::new()
                },
            })
            .collect()
    }

    type Render = fn(&Packing, &[Material], &ExportOptions) -> Result<Vec<u8>, OutputError>;

    /// Every DEM export, streamed.
    const EXPORTS: [(&str, Render); 12] = [
        ("vtk", packing_vtk),
        ("lammps", lammps_data),
        ("yade", yade_text),
        ("yade script", yade_script),
        ("pfc", pfc_commands),
        ("mercury", mercury_data),
        ("esys", esys_geometry),
        ("sq data", superquadric_data),
        ("sq input", superquadric_input),
        ("lammps clumps", lammps_clumps_data),
        ("liggghts clumps", liggghts_clumps_data),
        ("boundary", |p, _, _| Ok(boundary_vtk(p))),
    ];

    /// The bytes each export wrote for each scene of these tests: its
    /// length (or `error`) and crc32, by scene and export
    /// (`golden.txt`, made by the in-memory renderers the streamed
    /// exports replaced, which they matched byte for byte).
    fn golden(what: &str, name: &str) -> String {
        include_str!("golden.txt")
            .lines()
            .find_map(|line| {
                let rest = line.strip_prefix(what)?.strip_prefix('|')?;
                rest.strip_prefix(name)?
                    .strip_prefix('|')
                    .map(str::to_owned)
            })
            .unwrap_or_else(|| panic!("no golden bytes for {what}, {name}"))
    }

    /// The length and crc32 of what a rendering gave, as `golden.txt` has them.
    fn digest(made: &Result<Vec<u8>, String>) -> String {
        match made {
            Ok(bytes) => format!("{}|{:08x}", bytes.len(), crc32fast::hash(bytes)),
            Err(e) => format!("error|{:08x}", crc32fast::hash(e.as_bytes())),
        }
    }

    /// Asserts every export of `packing` streams the golden bytes (or
    /// error) on 1 and 3 threads.
    fn same_bytes(packing: &Packing, materials: &[Material], opts: &ExportOptions, what: &str) {
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            for (name, streamed) in EXPORTS {
                let got = pool
                    .install(|| streamed(packing, materials, opts))
                    .map_err(|e| e.to_string());
                let (got, want) = (digest(&got), golden(what, name));
                assert!(
                    got == want,
                    "{name}, {what}, {threads} threads: {got}, golden.txt has {want}"
                );
            }
        }
    }

    #[test]
    fn streamed_exports_are_the_golden_bytes_on_random_scenes() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(45);
        let all_kinds: [&[u8]; 4] = [&[0], &[1], &[2], &[0, 1, 2]];
        for round in 0..24 {
            let count = [0, 1, 3][round % 3];
            let m = materials(count);
            let opts = ExportOptions {
                units: if rng.gen_bool(0.5) {
                    LengthUnit::Metre
                } else {
                    LengthUnit::Millimetre
                },
                ..ExportOptions::default()
            };
            let n = rng.gen_range(0..40);
            let kinds = (round % 2 == 1).then(|| all_kinds[rng.gen_range(0..4)]);
            let packing = scene(&mut rng, n, kinds, count);
            same_bytes(&packing, &m, &opts, &format!("round {round}"));
        }
        // An unknown material.
        let packing = scene(&mut rng, 300, None, 3);
        same_bytes(&packing, &materials(3), &ExportOptions::default(), "many");
        same_bytes(
            &packing,
            &materials(2),
            &ExportOptions::default(),
            "unknown",
        );
        let grains = scene(&mut rng, 100, Some(&[0]), 0);
        same_bytes(&grains, &[], &ExportOptions::default(), "more grains");
    }

    #[test]
    fn streamed_packing_json_is_the_golden_bytes() {
        let config = crate::config::parse(
            "[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 40\n[grading]\nconstant = 1.0\n",
            "t.toml",
        )
        .expect("valid config");
        let packing = pack(&config.scene).expect("packs");
        let metrics = measure(&packing, &config.scene);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let mut grained = packing.clone();
        grained.grains = (0..packing.disks.len())
            .map(|i| Grain::new(outline(&mut rng, (i % 3) as u8), 0.1 * i as f64))
            .collect();
        let mut with_materials = packing.clone();
        with_materials.materials = (0..packing.disks.len()).map(|i| (i % 2) as u16).collect();
        let two = materials(2);
        for (k, (p, m)) in [
            (&packing, &[][..]),
            (&grained, &[][..]),
            (&with_materials, &two[..]),
        ]
        .into_iter()
        .enumerate()
        {
            let mut run = RunInfo::new(&config.scene, "t.toml", 0.0, &config.output);
            run.materials = m;
            for threads in [1, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool");
                let got = pool
                    .install(|| packing_json(p, &metrics, &run))
                    .map_err(|e| e.to_string());
                let (got, want) = (digest(&got), golden(&format!("json {k}"), "packing.json"));
                assert!(
                    got == want,
                    "{k}, {threads} threads: {got}, golden.txt has {want}"
                );
            }
        }
        let mut run = RunInfo::new(&config.scene, "t.toml", 0.0, &config.output);
        run.materials = &two[..1];
        assert!(matches!(
            packing_json(&with_materials, &metrics, &run),
            Err(OutputError::UnknownMaterial { .. })
        ));
    }
}
