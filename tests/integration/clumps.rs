//! Clumps of disks standing for non-disk particles, loaded by the DEM codes
//! themselves: LAMMPS reads `packing.clumps.lammps` and LIGGGHTS
//! `packing.clumps.liggghts`, each with `fix rigid molecule`, and finds no
//! contact between clumps, YADE runs `packing.yade.py` and finds no
//! interaction between clumps; each check is first shown to fail on the
//! packing with one particle pushed into its neighbour. PFC's command file
//! is checked for its clumps.
//!
//! Needs Debian's `lammps` (`lmp`), `liggghts` and `yade`; without them
//! each test says how to run it and passes, unless
//! `GAPACK_DEM_TESTS=required`, when it fails.

use std::path::Path;
use std::process::Command;

use gapack::output::{
    ExportOptions, lammps_clumps_data, liggghts_clumps_data, pfc_commands, yade_script,
};
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

/// A run of `data` (written as `name`) with `input` by `program`: its
/// atom count, its rigid bodies and the thermo line's third column, the
/// deepest contact between clumps, or 0 without any (a reduction over no
/// contact at all gives -1e20).
fn rigid_run(
    program: &str,
    name: &str,
    data: Vec<u8>,
    input: &str,
    dir: &Path,
) -> (usize, usize, f64) {
    std::fs::write(dir.join(name), data).unwrap();
    std::fs::write(dir.join("in.run"), input).unwrap();
    let out = run(
        &[program, "-in", "in.run", "-log", "none", "-echo", "none"],
        dir,
    );
    let bodies = out
        .lines()
        .find_map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (w.get(1..3) == Some(&["rigid", "bodies"][..])).then(|| w[0].parse().unwrap())
        })
        .expect("the run reports its rigid bodies");
    let lines: Vec<&str> = out.lines().collect();
    let head = lines
        .iter()
        .position(|l| l.split_whitespace().take(2).eq(["Step", "Atoms"]))
        .expect("thermo header");
    let w: Vec<&str> = lines[head + 1].split_whitespace().collect();
    let deepest: f64 = w[2].parse().unwrap();
    (w[1].parse().unwrap(), bodies, deepest.max(0.0))
}

/// LAMMPS' atom count, rigid bodies and deepest overlap between clumps (m),
/// from the largest contact force.
fn lammps(packing: &Packing, dir: &Path) -> (usize, usize, f64) {
    let data = lammps_clumps_data(packing, &[], &ExportOptions::default()).unwrap();
    let (atoms, bodies, fmax) = rigid_run("lmp", "packing.clumps.lammps", data, LAMMPS_INPUT, dir);
    (atoms, bodies, fmax / KN)
}

/// One code's round trip of the ellipses through `file`: with one pushed
/// into its neighbour the code finds an overlap, as placed none; every
/// particle is one rigid body of the atoms the file holds.
fn round_trip(name: &str, file: &str, code: fn(&Packing, &Path) -> (usize, usize, f64)) {
    let tag = name.to_lowercase();
    let bad = scratch(&format!("clumps-{tag}-bad"));
    let (_, _, pushed) = code(&ellipses(0.01), &bad);
    assert!(pushed > 0.0, "the pushed particle overlaps its neighbour");
    let dir = scratch(&format!("clumps-{tag}"));
    let packing = ellipses(0.0);
    let (atoms, bodies, deepest) = code(&packing, &dir);
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let written = text
        .lines()
        .find_map(|l| l.strip_suffix(" atoms"))
        .unwrap()
        .parse::<usize>()
        .unwrap();
    println!(
        "{name}: {atoms} atoms in {bodies} rigid bodies, deepest overlap between clumps {deepest:e} m (one pushed 1 %: {pushed:e} m)"
    );
    assert_eq!(atoms, written);
    assert_eq!(bodies, packing.grains.len());
    assert!(atoms > bodies);
    assert_eq!(deepest, 0.0);
}

#[test]
fn lammps_reads_the_clumps_and_finds_no_overlap_between_them() {
    if !have("lmp", "lammps") {
        return;
    }
    round_trip("LAMMPS", "packing.clumps.lammps", lammps);
}

/// A 3D LIGGGHTS run of the clumps at rest: Hertz contacts, every
/// molecule one rigid body kept in the plane, and the deepest overlap
/// (`delta`, m) of any contact between two bodies (contacts within a body
/// are excluded from the neighbour lists).
const LIGGGHTS_INPUT: &str = "\
units          si
atom_style     hybrid sphere molecular
atom_modify    map array
boundary       f f f
newton         off
communicate    single vel yes
read_data      packing.clumps.liggghts
neighbor       0.0001 bin
neigh_modify   delay 0 exclude molecule all
fix            m1 all property/global youngsModulus peratomtype 1.0e7
fix            m2 all property/global poissonsRatio peratomtype 0.3
fix            m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix            m4 all property/global coefficientFriction peratomtypepair 1 0.5
pair_style     gran model hertz tangential history
pair_coeff     * *
timestep       1.0e-7
fix            bodies all rigid molecule force * on on off torque * off off on
compute        pairs all pair/gran/local id delta
compute        deep all reduce max c_pairs[4]
thermo_style   custom step atoms c_deep
thermo_modify  format float %.17g
run            0
";

/// LIGGGHTS' atom count, rigid bodies and deepest overlap between clumps (m).
fn liggghts(packing: &Packing, dir: &Path) -> (usize, usize, f64) {
    let data = liggghts_clumps_data(packing, &[], &ExportOptions::default()).unwrap();
    rigid_run(
        "liggghts",
        "packing.clumps.liggghts",
        data,
        LIGGGHTS_INPUT,
        dir,
    )
}

#[test]
fn liggghts_reads_the_clumps_and_finds_no_overlap_between_them() {
    if !have("liggghts", "liggghts") {
        return;
    }
    round_trip("LIGGGHTS", "packing.clumps.liggghts", liggghts);
    // The same atoms as the LAMMPS file: only the header's words differ.
    let packing = ellipses(0.0);
    let file = |data: Vec<u8>| {
        let text = String::from_utf8(data).unwrap();
        text.split_once("Atoms # hybrid").unwrap().1.to_owned()
    };
    let opts = ExportOptions::default();
    assert_eq!(
        file(liggghts_clumps_data(&packing, &[], &opts).unwrap()),
        file(lammps_clumps_data(&packing, &[], &opts).unwrap())
    );
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
