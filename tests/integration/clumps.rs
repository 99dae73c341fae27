//! Clumps of disks standing for non-disk particles, loaded by the DEM codes
//! themselves: LAMMPS reads `packing.clumps.lammps` with `fix rigid
//! molecule` and finds no contact between clumps, YADE runs
//! `packing.yade.py` and finds no interaction between clumps; each check is
//! first shown to fail on the packing with one particle pushed into its
//! neighbour. PFC's command file is checked for its clumps.
//!
//! Needs Debian's `lammps` (`lmp`) and `yade`; without them each test says
//! how to run it and passes, unless `GAPACK_DEM_TESTS=required`, when it
//! fails.

use std::path::Path;
use std::process::Command;

use gapack::output::{ExportOptions, lammps_clumps_data, pfc_commands, yade_script};
use gapack::{Disk, Domain, Grain, Outline, Packing, Point};

use crate::common::scratch;

/// Semi-axes of the ellipses (mm).
const A: f64 = 3.0;
const B: f64 = 1.0;
/// Normal stiffness of LAMMPS' contacts (N/m): a force is KN × overlap.
const KN: f64 = 1.0e5;

/// Whether `program` runs; if not, passes with a message unless the DEM
/// tests are required.
fn have(program: &str, package: &str) -> bool {
    let found = Command::new("sh")
        .args(["-c", &format!("command -v {program}")])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        let how =
            format!("apt-get install -y {package}, then `cargo test --test integration clumps::`");
        assert!(
            std::env::var("GAPACK_DEM_TESTS").as_deref() != Ok("required"),
            "DEM tests required, but {program} is missing: {how}"
        );
        eprintln!("clump round trip skipped: {program} is not installed; {how}");
    }
    found
}

/// Ellipses of aspect 3 touching side by side and end to end (4 × 3), and
/// one turned upright touching the last column's end; `push` moves the
/// first one towards its neighbour above (side to side, where the largest
/// disks of both clumps reach the outline) by that share of `B`.
fn ellipses(push: f64) -> Packing {
    let outline = Outline::superellipse(A, B, 2.0, 2.0).unwrap();
    let mut grains = Vec::new();
    let mut centres = Vec::new();
    for i in 0..4 {
        for j in 0..3 {
            grains.push(Grain::new(outline.clone(), 0.0));
            centres.push(Point::new(
                4.0 + 2.0 * A * i as f64,
                3.0 + 2.0 * B * j as f64,
            ));
        }
    }
    grains.push(Grain::new(outline.clone(), std::f64::consts::FRAC_PI_2));
    centres.push(Point::new(4.0 + 2.0 * A * 3.0 + A + B, 3.0 + 2.0 * B));
    centres[0].y += push * B;
    let r = outline.equivalent_radius();
    let disks = centres.iter().map(|c| Disk::new(c.x, c.y, r)).collect();
    let mut packing = Packing::of_disks(Domain::rectangle(40.0, 12.0).unwrap(), disks);
    packing.grains = grains;
    packing
}

fn run(program: &[&str], dir: &Path) -> String {
    let out = Command::new(program[0])
        .args(&program[1..])
        .current_dir(dir)
        .output()
        .expect("run the DEM program");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success() && !stdout.contains("ERROR"),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

const LAMMPS_INPUT: &str = "\
units          si
dimension      2
boundary       f f p
atom_style     hybrid sphere molecular
atom_modify    map array
read_data      packing.clumps.lammps
comm_modify    vel yes
pair_style     gran/hooke 1.0e5 NULL 0.0 NULL 0.5 0
pair_coeff     * *
neighbor       0.0001 bin
neigh_modify   exclude molecule/intra all
fix            bodies all rigid molecule
fix            flat all enforce2d
compute        pairs all pair/local force
compute        fmax all reduce max c_pairs
thermo_style   custom step atoms c_fmax
thermo_modify  format float %.17g
run            0
";

/// LAMMPS' atom count, rigid bodies and deepest overlap between clumps (m).
fn lammps(packing: &Packing, dir: &Path) -> (usize, usize, f64) {
    let data = lammps_clumps_data(packing, &[], &ExportOptions::default()).unwrap();
    std::fs::write(dir.join("packing.clumps.lammps"), data).unwrap();
    std::fs::write(dir.join("in.run"), LAMMPS_INPUT).unwrap();
    let out = run(
        &["lmp", "-in", "in.run", "-log", "none", "-echo", "none"],
        dir,
    );
    let bodies = out
        .lines()
        .find_map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (w.get(1..3) == Some(&["rigid", "bodies"][..])).then(|| w[0].parse().unwrap())
        })
        .expect("LAMMPS reports its rigid bodies");
    let lines: Vec<&str> = out.lines().collect();
    let head = lines
        .iter()
        .position(|l| l.split_whitespace().collect::<Vec<_>>() == ["Step", "Atoms", "c_fmax"])
        .expect("thermo header");
    let w: Vec<&str> = lines[head + 1].split_whitespace().collect();
    let fmax: f64 = w[2].parse().unwrap();
    // No pair at all within the cut-off reduces to -1e20.
    (w[1].parse().unwrap(), bodies, fmax.max(0.0) / KN)
}

#[test]
fn lammps_reads_the_clumps_and_finds_no_overlap_between_them() {
    if !have("lmp", "lammps") {
        return;
    }
    let bad = scratch("clumps-lammps-bad");
    let (_, _, deepest) = lammps(&ellipses(0.01), &bad);
    assert!(deepest > 0.0, "the pushed particle overlaps its neighbour");
    let dir = scratch("clumps-lammps");
    let packing = ellipses(0.0);
    let (atoms, bodies, deepest) = lammps(&packing, &dir);
    let text = std::fs::read_to_string(dir.join("packing.clumps.lammps")).unwrap();
    let written = text
        .lines()
        .find_map(|l| l.strip_suffix(" atoms"))
        .unwrap()
        .parse::<usize>()
        .unwrap();
    println!(
        "LAMMPS: {atoms} atoms in {bodies} rigid bodies, deepest overlap between clumps {deepest:e} m"
    );
    assert_eq!(atoms, written);
    assert_eq!(bodies, packing.grains.len());
    assert!(atoms > bodies);
    assert_eq!(deepest, 0.0);
}

const YADE_DRIVER: &str = "\
exec(open('packing.yade.py').read())
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=0.0),
]
O.dt = 1e-9
O.step()
deep = 0.0
for i in O.interactions:
    if i.isReal and O.bodies[i.id1].clumpId != O.bodies[i.id2].clumpId:
        deep = max(deep, i.geom.penetrationDepth)
clumps = sum(1 for b in O.bodies if b.isClump)
members = sum(1 for b in O.bodies if b.isClumpMember)
print('GAPACK %d %d %d %.17g' % (len(gapack_clumps), clumps, members, deep))
";

/// YADE's clumps appended, clumps in the scene, their spheres and the
/// deepest penetration between clumps after one step at rest (m).
fn yade(packing: &Packing, dir: &Path) -> (usize, usize, usize, f64) {
    let script = yade_script(packing, &[], &ExportOptions::default()).unwrap();
    std::fs::write(dir.join("packing.yade.py"), script).unwrap();
    std::fs::write(dir.join("driver.py"), YADE_DRIVER).unwrap();
    let out = run(&["yade", "-x", "-n", "driver.py"], dir);
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("GAPACK "))
        .expect("the driver's line");
    let w: Vec<&str> = line.split_whitespace().collect();
    (
        w[0].parse().unwrap(),
        w[1].parse().unwrap(),
        w[2].parse().unwrap(),
        w[3].parse().unwrap(),
    )
}

#[test]
fn yade_appends_the_clumps_and_finds_no_overlap_between_them() {
    if !have("yade", "yade") {
        return;
    }
    let bad = scratch("clumps-yade-bad");
    let (_, _, _, deepest) = yade(&ellipses(0.01), &bad);
    assert!(deepest > 0.0, "the pushed particle overlaps its neighbour");
    let dir = scratch("clumps-yade");
    let packing = ellipses(0.0);
    let (appended, clumps, members, deepest) = yade(&packing, &dir);
    println!(
        "YADE: {clumps} clumps of {members} spheres, deepest penetration between clumps {deepest:e} m"
    );
    assert_eq!(appended, packing.grains.len());
    assert_eq!(clumps, packing.grains.len());
    assert!(members > clumps);
    assert_eq!(deepest, 0.0);
}

#[test]
fn pfc_writes_one_clump_per_particle() {
    let packing = ellipses(0.0);
    let text =
        String::from_utf8(pfc_commands(&packing, &[], &ExportOptions::default()).unwrap()).unwrap();
    let creates: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("clump create"))
        .collect();
    assert_eq!(creates.len(), packing.grains.len());
    assert!(!text.contains("ball create"));
    assert!(text.contains("clump attribute density 2650 range group 'gapack'"));
    assert!(
        text.lines()
            .nth(1)
            .unwrap()
            .starts_with("; clumps: 13 clumps of")
    );
    // Each clump's pebble lines: as many as it says, all continued but the last.
    let lines: Vec<&str> = text.lines().collect();
    for (at, line) in lines
        .iter()
        .enumerate()
        .filter(|(_, l)| l.starts_with("clump create"))
    {
        let k: usize = line
            .split_whitespace()
            .rev()
            .nth(1)
            .unwrap()
            .parse()
            .unwrap();
        assert!(line.ends_with(" ..."));
        for (j, pebble) in lines[at + 1..=at + k].iter().enumerate() {
            let w: Vec<&str> = pebble.split_whitespace().collect();
            assert!(w[0].parse::<f64>().unwrap() > 0.0);
            assert!(w[1].starts_with('(') && w[1].ends_with(')'));
            assert_eq!(pebble.ends_with(" ..."), j + 1 < k, "{pebble}");
        }
    }
    // Disks stay balls.
    let disks = Packing::of_disks(packing.domain.clone(), packing.disks.clone());
    let plain =
        String::from_utf8(pfc_commands(&disks, &[], &ExportOptions::default()).unwrap()).unwrap();
    assert!(!plain.contains("clump"));
}
