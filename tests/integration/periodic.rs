//! Periodic cells (`walls = "periodic"`): a rectangle without walls, each
//! disk crossing an edge present again, as its image, across the opposite
//! one. Packings are checked here by brute force over the nine images of
//! every pair, independently of the packer's index and of `gapack::check`:
//! no overlap counting images, every centre in the cell, the porosity from
//! the disks' areas, contacts across the edges counted, the same disks for
//! the same seed. Then `check` and `gapack verify` on an overlap that
//! exists only across an edge, the exports' declarations of the periodic
//! box, the pictures, and the refusals.

use crate::common;

use std::fs;

use common::{gapack, scratch};
use gapack::config::{self, ConfigError};
use gapack::output::{
    ExportOptions, OutputSettings, RunInfo, boundary_vtk, esys_geometry, lammps_data, mercury_data,
    packing_json, packing_svg, packing_vtk, pfc_commands, summary_json, yade_text,
};
use gapack::{
    Basis, Disk, Domain, Fill, Grading, IndexKind, Method, OVERLAP_REL, PackError, Packing, Point,
    Scene, WallMode, check, measure, pack, porosity_map,
};

/// Contact gap of `gapack::measure`, relative to the radii sum.
const CONTACT_REL: f64 = 1e-6;

/// What the brute force finds in a periodic cell `w` × `h`: pairs (a disk
/// with itself too) overlapping by more than [`OVERLAP_REL`] at some image,
/// the deepest overlap, and the contacts (gap within [`CONTACT_REL`]), each
/// image of a pair counted once.
struct Brute {
    overlaps: usize,
    worst: f64,
    contacts: usize,
}

fn brute(disks: &[Disk], w: f64, h: f64) -> Brute {
    let mut b = Brute {
        overlaps: 0,
        worst: f64::NEG_INFINITY,
        contacts: 0,
    };
    for (i, p) in disks.iter().enumerate() {
        for (j, q) in disks.iter().enumerate().skip(i) {
            for ky in -1..=1 {
                for kx in -1..=1 {
                    // A disk and its own image: each opposite pair of shifts once.
                    if i == j && (ky, kx) <= (0, 0) {
                        continue;
                    }
                    let dx = q.c.x + f64::from(kx) * w - p.c.x;
                    let dy = q.c.y + f64::from(ky) * h - p.c.y;
                    let sum = p.r + q.r;
                    let overlap = (sum - (dx * dx + dy * dy).sqrt()) / sum;
                    b.worst = b.worst.max(overlap);
                    b.overlaps += usize::from(overlap > OVERLAP_REL);
                    b.contacts += usize::from(overlap >= -CONTACT_REL);
                }
            }
        }
    }
    b
}

/// A periodic scene of a `w` × `h` cell filled with `grading`.
fn cell(w: f64, h: f64, grading: Grading, seed: u64) -> Scene {
    Scene::new(Domain::rectangle(w, h).unwrap(), grading)
        .with_walls(WallMode::Periodic)
        .with_seed(seed)
}

/// Uniform by number between `lo` and `hi` mm.
fn uniform(lo: f64, hi: f64) -> Grading {
    Grading::uniform(lo, hi, Basis::Number).unwrap()
}

/// Everything a periodic packing must be, checked by brute force; returns
/// its porosity.
fn assert_periodic_packing(scene: &Scene, what: &str) -> f64 {
    let p = pack(scene).unwrap_or_else(|e| panic!("{what}: {e}"));
    let period = scene.domain.period().expect("a periodic cell");
    let (w, h) = (period.x, period.y);
    let fits = (w * h / (std::f64::consts::PI * scene.d_max() * scene.d_max())).floor();
    assert!(
        p.disks.len() as f64 >= fits,
        "{what}: {} disks, fewer than the {fits} largest ones the cell holds loosely",
        p.disks.len()
    );
    assert_eq!(p.walls, WallMode::Periodic, "{what}");
    assert!(
        p.boundary.is_empty(),
        "{what}: wall disks in a periodic cell"
    );
    // Every centre stored in the half-open cell.
    for (i, d) in p.disks.iter().enumerate() {
        assert!(
            (0.0..w).contains(&d.c.x) && (0.0..h).contains(&d.c.y),
            "{what}: disk {i} at {:?} outside the cell",
            d.c
        );
    }
    // No overlap with any image of any disk.
    let b = brute(&p.disks, w, h);
    assert_eq!(
        b.overlaps, 0,
        "{what}: {} overlaps, the deepest {:.2e}",
        b.overlaps, b.worst
    );
    // The independent check agrees, and so does its porosity: each disk once.
    let c = check(&p.disks, &p.domain, Some(&scene.grading));
    assert!(c.valid(), "{what}: {c:?}");
    let solid: f64 = p.disks.iter().map(Disk::area).sum();
    let porosity = 1.0 - solid / (w * h);
    assert!((c.porosity - porosity).abs() < 1e-12, "{what}");
    // Coordination counts the contacts across the edges too.
    let m = measure(&p, scene);
    assert!((m.porosity - porosity).abs() < 1e-12, "{what}");
    let expected = 2.0 * b.contacts as f64 / p.disks.len() as f64;
    assert!(
        (m.coordination - expected).abs() < 1e-12,
        "{what}: coordination {} against {expected} by brute force",
        m.coordination
    );
    assert!(m.max_overlap <= OVERLAP_REL, "{what}: {}", m.max_overlap);
    assert!(m.min_wall_clearance.is_nan(), "{what}: a cell has no wall");
    // The same scene gives the same disks.
    assert_eq!(
        pack(scene).unwrap().disks,
        p.disks,
        "{what}: not deterministic"
    );
    porosity
}

#[test]
fn random_cells_pack_without_overlap_with_any_image() {
    // Gradings from nearly constant to d_max / d_min = 10, by number and by
    // mass; cells from just over the smallest allowed (2 d_max) to 40 d_max,
    // square and elongated; both indexes, both fills, dense and loose.
    let gradings = [
        (1.0, 1.02, Basis::Number),
        (1.0, 1.66, Basis::Number),
        (0.5, 2.0, Basis::Number),
        (0.4, 4.0, Basis::Mass),
        (0.3, 3.0, Basis::Number),
    ];
    let mut porosities = Vec::new();
    for seed in 0..40u64 {
        let (lo, hi, basis) = gradings[seed as usize % gradings.len()];
        let grading = Grading::uniform(lo, hi, basis).unwrap();
        // Cell sides in largest diameters, from the seed.
        let sides = [2.05, 3.0, 7.5, 12.0, 25.0, 40.0];
        let (a, b) = (
            sides[(seed as usize / 5) % sides.len()],
            sides[(seed as usize / 2 + 3) % sides.len()],
        );
        let (w, h) = (a * hi, b * hi);
        let mut scene = cell(w, h, grading, seed);
        scene.packer.index = if seed % 2 == 0 {
            IndexKind::MxQuadtree
        } else {
            IndexKind::Grid
        };
        if seed % 3 == 1 {
            scene.packer.fill = Fill::Right;
        }
        if seed % 7 == 3 {
            scene.packer.one_contact_share = 0.5;
            scene.packer.gap = 0.3;
        }
        let what = format!(
            "seed {seed}: {w:.2} × {h:.2} mm, d {lo}–{hi} by {basis:?}, {:?}, {:?}, share {}",
            scene.packer.index, scene.packer.fill, scene.packer.one_contact_share
        );
        let porosity = assert_periodic_packing(&scene, &what);
        if scene.packer.one_contact_share == 0.0 && a >= 12.0 && b >= 12.0 {
            porosities.push((what, porosity));
        }
    }
    // Dense packs of the larger cells: no wall to loosen them.
    assert!(!porosities.is_empty());
    for (what, porosity) in &porosities {
        assert!(*porosity < 0.26, "{what}: porosity {porosity}");
    }
}

#[test]
fn a_periodic_cell_packs_denser_than_the_same_rectangle_with_walls() {
    // 50 × 100 mm, 1–1.66 mm: no wall effect along four edges.
    let mut gained = 0.0;
    for seed in 0..3 {
        let periodic = cell(50.0, 100.0, uniform(1.0, 1.66), seed);
        let walled =
            Scene::new(Domain::rectangle(50.0, 100.0).unwrap(), uniform(1.0, 1.66)).with_seed(seed);
        let phi = |s: &Scene| gapack::measure(&pack(s).unwrap(), s).porosity;
        gained += phi(&walled) - phi(&periodic);
    }
    assert!(gained / 3.0 > 0.004, "{}", gained / 3.0);
}

#[test]
fn rsa_and_relaxation_use_the_images_and_deposition_is_refused() {
    let scene = cell(20.0, 15.0, uniform(1.0, 1.66), 3);
    let rsa = pack(&scene.clone().with_method(Method::Rsa)).unwrap();
    assert!(rsa.disks.len() > 50);
    assert_eq!(brute(&rsa.disks, 20.0, 15.0).overlaps, 0);
    // Some disks cross an edge: the centres are drawn over the whole cell.
    let crossing = rsa
        .disks
        .iter()
        .filter(|d| d.c.x < d.r || d.c.x > 20.0 - d.r || d.c.y < d.r || d.c.y > 15.0 - d.r)
        .count();
    assert!(crossing > 0);
    let relaxed = pack(&scene.clone().with_method(Method::Relaxation)).unwrap();
    let b = brute(&relaxed.disks, 20.0, 15.0);
    assert_eq!(b.overlaps, 0, "the deepest {:.2e}", b.worst);
    assert!(
        relaxed
            .disks
            .iter()
            .all(|d| (0.0..20.0).contains(&d.c.x) && (0.0..15.0).contains(&d.c.y))
    );
    assert_eq!(
        pack(&scene.with_method(Method::Deposition)).unwrap_err(),
        PackError::PeriodicMethod {
            method: "deposition"
        }
    );
}

#[test]
fn densify_packs_random_cells_at_dense_targets_or_names_the_densest_reached() {
    let gradings = [(1.0, 1.66), (0.5, 2.0), (1.0, 1.02), (0.4, 2.4)];
    let mut packed = 0;
    for seed in 0..12u64 {
        let (lo, hi) = gradings[seed as usize % gradings.len()];
        let sides = [7.5, 12.0, 20.0];
        let (w, h) = (
            sides[seed as usize % 3] * hi,
            sides[(seed as usize / 3) % 3] * hi,
        );
        let target = 0.15 + 0.005 * (seed % 9) as f64;
        let mut scene = cell(w, h, uniform(lo, hi), seed).with_method(Method::Densify);
        scene.packer.densify.porosity = target;
        let what = format!("seed {seed}: {w:.1} × {h:.1} mm, d {lo}–{hi}, target {target}");
        match pack(&scene) {
            Ok(_) => {
                let porosity = assert_periodic_packing(&scene, &what);
                // Within one disk of the target: the count sets the porosity.
                let one = std::f64::consts::PI * hi * hi / 4.0 / (w * h);
                assert!((porosity - target).abs() <= one, "{what}: {porosity}");
                packed += 1;
            }
            Err(PackError::DensityUnreached { reached, .. }) => {
                // Honest: the densest reached is looser than the target,
                // and near the jamming of disks (porosity about 0.16).
                assert!(reached > target && reached < 0.2, "{what}: {reached}");
            }
            Err(e) => panic!("{what}: {e}"),
        }
    }
    assert!(packed >= 6, "only {packed} of 12 packed");
}

#[test]
fn scenes_built_in_code_must_be_periodic_cells() {
    let grading = uniform(1.0, 1.5);
    let circle = Scene::new(
        Domain::circle(Point::new(0.0, 0.0), 10.0).unwrap(),
        grading.clone(),
    )
    .with_walls(WallMode::Periodic);
    assert_eq!(
        pack(&circle).unwrap_err(),
        PackError::NotPeriodic { shape: "circle" }
    );
    // A periodic cell with walls asked for.
    let mut walled = cell(10.0, 10.0, grading.clone(), 0);
    walled.walls = WallMode::Exact;
    assert_eq!(
        pack(&walled).unwrap_err(),
        PackError::PeriodicWalls { walls: "exact" }
    );
    // Setting the walls back makes it a rectangle with walls again.
    let rectangle = cell(10.0, 10.0, grading.clone(), 0).with_walls(WallMode::Exact);
    assert!(!rectangle.domain.is_periodic());
    assert!(pack(&rectangle).is_ok());
    // A periodic domain given to a scene makes its walls periodic.
    let scene = Scene::new(Domain::rectangle(5.0, 5.0).unwrap(), grading.clone())
        .with_domain(Domain::periodic_rectangle(12.0, 9.0).unwrap());
    assert_eq!(scene.walls, WallMode::Periodic);
    // Under twice the largest diameter: a disk could touch two images of one other.
    assert!(matches!(
        pack(&cell(2.9, 10.0, grading, 0)),
        Err(PackError::PeriodicCellTooSmall { .. })
    ));
}

/// Two disks of radius 1 that meet only across the edge x = 0 / x = `w`
/// (their centres `w` − 2 apart inside the cell), overlapping there by
/// `overlap` of their radii sum.
fn across_x(w: f64, overlap: f64) -> Vec<Disk> {
    let gap = 2.0 * (1.0 - overlap);
    vec![
        Disk::new(0.5, 5.0, 1.0),
        Disk::new(w - (gap - 0.5), 5.0, 1.0),
    ]
}

#[test]
fn check_catches_an_overlap_that_exists_only_across_an_edge() {
    let w = 20.0;
    let periodic = Domain::periodic_rectangle(w, 10.0).unwrap();
    // Overlapping by 1e-6 of the radii sum across x = 0: found, once.
    let disks = across_x(w, 1e-6);
    let c = check(&disks, &periodic, None);
    assert_eq!(c.overlaps, 1, "{c:?}");
    let (a, b, depth) = c.worst_overlap.unwrap();
    assert_eq!((a, b), (0, 1));
    assert!((depth - 1e-6).abs() < 1e-9, "{depth}");
    // Each disk crosses an edge, yet its centre is in the cell: not outside.
    assert_eq!(c.outside, 0);
    // Touching exactly: valid.
    assert!(check(&across_x(w, 0.0), &periodic, None).valid());
    // Across y = 0, and across a corner.
    let across_y = [Disk::new(4.0, 0.3, 1.0), Disk::new(4.0, 10.0 - 1.69, 1.0)];
    assert_eq!(check(&across_y, &periodic, None).overlaps, 1);
    let corner = [
        Disk::new(0.4, 0.4, 1.0),
        Disk::new(w - 0.4, 10.0 - 0.4, 0.5),
    ];
    assert_eq!(check(&corner, &periodic, None).overlaps, 1);
    // A centre outside the cell is a fault, as a disk outside a wall is.
    let out = [Disk::new(-0.5, 5.0, 1.0), Disk::new(10.0, 5.0, 1.0)];
    let c = check(&out, &periodic, None);
    assert_eq!((c.outside, c.worst_outside), (1, Some((0, 0.5))));
    // A disk wider than the cell overlaps its own image.
    let narrow = Domain::periodic_rectangle(1.5, 10.0).unwrap();
    assert_eq!(
        check(&[Disk::new(0.75, 5.0, 1.0)], &narrow, None).overlaps,
        1
    );
}

#[test]
fn check_finds_every_overlap_the_brute_force_finds() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(19);
    let (w, h) = (30.0, 20.0);
    let domain = Domain::periodic_rectangle(w, h).unwrap();
    for _ in 0..20 {
        let disks: Vec<Disk> = (0..300)
            .map(|_| {
                Disk::new(
                    rng.gen_range(0.0..w),
                    rng.gen_range(0.0..h),
                    rng.gen_range(0.05..1.0),
                )
            })
            .collect();
        let c = check(&disks, &domain, None);
        assert_eq!(c.overlaps, brute(&disks, w, h).overlaps);
        assert!(c.overlaps > 0);
    }
}

#[test]
fn a_ring_across_the_edge_has_two_contacts_per_disk() {
    // Ten touching disks of diameter 2 along y = 5 in a cell 20 mm wide: the
    // last touches the first across x = 20.
    let disks: Vec<Disk> = (0..10)
        .map(|k| Disk::new(1.0 + 2.0 * f64::from(k), 5.0, 1.0))
        .collect();
    let scene = cell(20.0, 10.0, Grading::constant(2.0).unwrap(), 0);
    let mut packing = Packing::of_disks(scene.domain.clone(), disks.clone());
    packing.walls = WallMode::Periodic;
    let m = measure(&packing, &scene);
    assert_eq!(m.coordination, 2.0);
    assert_eq!(m.isolated, 0);
    assert!((m.porosity - (1.0 - 10.0 * std::f64::consts::PI / 200.0)).abs() < 1e-12);
    // With walls, the ends of the row have one contact each.
    let walled = Scene::new(
        Domain::rectangle(20.0, 10.0).unwrap(),
        scene.grading.clone(),
    );
    let m = measure(&Packing::of_disks(walled.domain.clone(), disks), &walled);
    assert!((m.coordination - 1.8).abs() < 1e-12, "{}", m.coordination);
}

#[test]
fn the_porosity_map_counts_the_disks_across_the_edges() {
    // One disk on the cell's corner: a quarter of it in each corner's cell.
    let scene = cell(40.0, 40.0, Grading::constant(2.0).unwrap(), 0);
    let mut packing = Packing::of_disks(scene.domain.clone(), vec![Disk::new(0.0, 0.0, 1.0)]);
    packing.walls = WallMode::Periodic;
    let map = porosity_map(&packing);
    assert_eq!((map.cols, map.rows), (4, 4));
    let quarter = 1.0 - std::f64::consts::PI / 4.0 / (map.cell * map.cell);
    for i in [0, 3, 12, 15] {
        assert!(
            (map.values[i] - quarter).abs() < 1e-12,
            "cell {i}: {}",
            map.values[i]
        );
    }
    assert!(map.values[5] == 1.0);
}

/// A packed periodic scene with its measure, for the exports.
fn packed() -> (Scene, Packing) {
    let scene = cell(20.0, 12.0, uniform(1.0, 1.66), 5);
    let packing = pack(&scene).unwrap();
    (scene, packing)
}

fn text(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).expect("UTF-8")
}

#[test]
fn exports_declare_the_periodic_box() {
    let (scene, packing) = packed();
    let opts = ExportOptions::default();
    let output = OutputSettings::default();
    let metrics = measure(&packing, &scene);
    let run = RunInfo::new(&scene, "cell.toml", 0.1, &output);
    // Millimetres in the exports' default unit (metres): 20 mm = 0.02 m.
    let lammps = text(lammps_data(&packing, &[], &opts).unwrap());
    assert!(
        lammps.contains("\n0 0.02 xlo xhi\n0 0.012 ylo yhi\n"),
        "{lammps}"
    );
    assert!(
        lammps.contains("\n# periodic cell: boundary p p p"),
        "{lammps}"
    );
    let yade = text(yade_text(&packing, &[], &opts).unwrap());
    let declared = yade
        .lines()
        .find(|l| l.starts_with("# periodic cell: O.periodic = True; O.cell.setBox(0.02, 0.012, "))
        .unwrap_or_else(|| panic!("{yade}"));
    // The depth: four largest diameters, so that no sphere meets its z
    // image and YADE's collider takes the spheres' enlarged boxes.
    let depth: f64 = declared
        .trim_end_matches(')')
        .rsplit(", ")
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let d_max = packing.disks.iter().fold(0.0f64, |m, d| m.max(2.0 * d.r));
    assert!((depth - 4.0 * d_max * 1e-3).abs() < 1e-15, "{depth}");
    let pfc = text(pfc_commands(&packing, &[], &opts).unwrap());
    assert!(
        pfc.contains("\nmodel domain extent 0 0.02 0 0.012 condition periodic periodic\n"),
        "{pfc}"
    );
    assert!(
        !pfc.contains("wall "),
        "PFC refuses walls across a periodic domain"
    );
    let vtk = text(packing_vtk(&packing, &[], &opts).unwrap());
    assert!(
        vtk.contains("DATASET POLYDATA\nFIELD FieldData 2\nperiodic 1 1 int\n1\ncell 4 1 double\n0 20 0 12\nPOINTS "),
        "{}",
        &vtk[..300]
    );
    assert!(text(boundary_vtk(&packing)).contains("periodic cell"));
    let json: serde_json::Value =
        serde_json::from_slice(&packing_json(&packing, &metrics, &run).unwrap()).unwrap();
    assert_eq!(json["domain"]["periodic"], true);
    assert_eq!(json["domain"]["period"], serde_json::json!([20.0, 12.0]));
    assert_eq!(json["summary"]["walls"], "periodic");
    let summary: serde_json::Value =
        serde_json::from_slice(&summary_json(&packing, &metrics, &run).unwrap()).unwrap();
    assert_eq!(summary["walls"], "periodic");
    assert!(summary["min_wall_clearance"].is_null());
    let esys = text(esys_geometry(&packing, &[], &opts).unwrap());
    assert!(esys.contains("\nPeriodicBoundaries 1 1 0\n"), "{esys}");
    assert!(esys.contains("\nBoundingBox 0 0 -"), "{esys}");
    let mercury = text(mercury_data(&packing, &[], &opts).unwrap());
    let first = mercury.lines().next().unwrap();
    assert!(first.ends_with(" 0 0 0 0.02 0.012"), "{first}");
    // A rectangle with walls declares none of it.
    let walled = Packing::of_disks(Domain::rectangle(20.0, 12.0).unwrap(), Vec::new());
    assert!(!text(lammps_data(&walled, &[], &opts).unwrap()).contains("periodic"));
    assert!(text(esys_geometry(&walled, &[], &opts).unwrap()).contains("PeriodicBoundaries 0 0 0"));
    assert!(!text(packing_vtk(&walled, &[], &opts).unwrap()).contains("FIELD"));
}

#[test]
fn the_drawing_clips_the_images_to_a_dashed_cell() {
    let (_, packing) = packed();
    let svg = packing_svg(&packing, &[], (1.0, 1.66));
    assert!(svg.contains(r#"<clipPath id="cell">"#), "{svg}");
    assert!(svg.contains(r#"clip-path="url(#cell)""#));
    assert!(svg.contains("stroke-dasharray"));
    assert!(svg.contains("periodic cell"));
    // Every disk once, and each crossing an edge once more per image in the cell.
    let crossing: usize = packing
        .disks
        .iter()
        .map(|d| {
            let x = usize::from(d.c.x < d.r || d.c.x > 20.0 - d.r);
            let y = usize::from(d.c.y < d.r || d.c.y > 12.0 - d.r);
            (1 + x) * (1 + y) - 1
        })
        .sum();
    assert!(crossing > 0);
    assert_eq!(
        svg.matches("<circle ").count(),
        packing.disks.len() + crossing
    );
    // The view is the cell, not the disks sticking out of it.
    assert!(
        svg.contains(r#"viewBox="-0.36 -0.36 20.72 12.72""#),
        "{}",
        &svg[..300]
    );
}

#[test]
fn a_circle_with_periodic_walls_is_refused_at_its_key() {
    let text = "[domain]\nshape = \"circle\"\nradius = 20\nwalls = \"periodic\"\n\n[grading]\nuniform = [1.0, 1.66]\n";
    let error = config::parse(text, "circle.toml").unwrap_err();
    assert!(
        matches!(error, ConfigError::NotApplicable { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message
            .starts_with("circle.toml:4:9: domain.walls: \"periodic\" needs shape = \"rectangle\""),
        "{message}"
    );
    // The same from the command line, which names the file.
    let dir = scratch("periodic-circle");
    fs::write(dir.join("circle.toml"), text).unwrap();
    let out = gapack(&dir, &["validate", "circle.toml"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("circle.toml:4:9: domain.walls:"),
        "{stderr}"
    );
}

#[test]
fn verify_catches_an_overlap_across_an_edge() {
    let dir = scratch("periodic-verify");
    fs::write(
        dir.join("cell.toml"),
        "[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 10\nwalls = \"periodic\"\n[grading]\nconstant = 2\n",
    )
    .unwrap();
    let csv = |disks: &[Disk]| {
        let mut s = String::from("x,y,r\n");
        for d in disks {
            s.push_str(&format!("{},{},{}\n", d.c.x, d.c.y, d.r));
        }
        s
    };
    fs::write(dir.join("bad.csv"), csv(&across_x(20.0, 1e-6))).unwrap();
    let out = gapack(&dir, &["verify", "bad.csv", "--config", "cell.toml"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success(), "{stdout}");
    assert!(
        stdout.contains("overlaps: 1 pair, images across the periodic edges included"),
        "{stdout}"
    );
    fs::write(dir.join("good.csv"), csv(&across_x(20.0, 0.0))).unwrap();
    let out = gapack(&dir, &["verify", "good.csv", "--config", "cell.toml"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(
        stdout.contains("containment: every centre inside the periodic cell"),
        "{stdout}"
    );
}
