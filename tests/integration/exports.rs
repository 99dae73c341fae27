//! DEM exports read back by small independent parsers: counts, every
//! position and radius, types and densities, and each format's structural
//! rules; the same packing always gives the same bytes.

use std::collections::{BTreeMap, BTreeSet};

use gapack::config::{self, Config};
use gapack::layering::Material;
use gapack::output::{
    ExportOptions, LengthUnit, OutputError, RunInfo, boundary_vtk, esys_geometry, lammps_data,
    mercury_data, packing_json, packing_vtk, pfc_commands, summary_json, yade_text,
};
use gapack::{Packing, measure, pack};

const RECTANGLE: &str = r#"
seed = 3
[domain]
shape = "rectangle"
width = 10
height = 8
[grading]
uniform = [0.8, 1.6]
"#;

const CIRCLE: &str = r#"
seed = 5
[domain]
shape = "circle"
radius = 6
center = [2, -1]
[grading]
uniform = [0.9, 1.5]
"#;

const DISK_WALLS: &str = r#"
seed = 7
[domain]
shape = "rectangle"
width = 9
height = 7
walls = "disks"
[grading]
uniform = [1.0, 1.4]
"#;

const L_SHAPE: &str = r#"
seed = 2
[domain]
shape = "polygon"
vertices = [[0, 0], [10, 0], [10, 4], [4, 4], [4, 10], [0, 10]]
[grading]
uniform = [0.8, 1.4]
"#;

const TRAPEZOID: &str = r#"
seed = 4
[domain]
shape = "trapezoid"
bottom = 10
top = 5
height = 8
[grading]
constant = 1.0
"#;

/// Two materials stacked along y, with densities in kg/m³.
const TWO_MATERIALS: &str = r#"
seed = 11
[domain]
shape = "rectangle"
width = 12
height = 12
[grading]
uniform = [1.0, 1.5]

[[materials]]
name = "ceramic"
density = 3900
youngs_modulus = 370.0

[[materials]]
name = "hard metal"
density = 7800

[layering]
axis = "y"
bins = 4
profile = "steps"
layers = [["hard metal", 0.5], ["ceramic", 0.5]]
"#;

/// The config and its packing; with materials, the lower half of the disks
/// (by centre) gets material 1 and the upper half material 0.
fn packed(text: &str) -> (Config, Packing) {
    let config = config::parse(text, "test").expect("valid config");
    let mut packing = pack(&config.scene).expect("packs");
    assert!(packing.disks.len() > 10, "too few disks to test");
    if !config.materials.is_empty() {
        let (lo, hi) = packing.domain.bounds();
        let mid = 0.5 * (lo.y + hi.y);
        packing.materials = packing
            .disks
            .iter()
            .map(|d| u16::from(d.c.y < mid))
            .collect();
    }
    (config, packing)
}

/// An export: the packing, the materials, the options to the file's bytes.
type Writer = fn(&Packing, &[Material], &ExportOptions) -> Result<Vec<u8>, OutputError>;

fn text(bytes: Result<Vec<u8>, OutputError>) -> String {
    String::from_utf8(bytes.expect("export renders")).expect("utf-8")
}

fn num(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| panic!("not a number: {s:?}"))
}

/// `got` (in the export's unit, `per_mm` per mm) equals `mm` to 1e-9, relative
/// (absolute below 1 mm).
fn same_length(got: f64, mm: f64, per_mm: f64) {
    let back = got / per_mm;
    assert!(
        (back - mm).abs() <= 1e-9 * mm.abs().max(1.0),
        "{got} reads back as {back} mm, expected {mm} mm"
    );
}

fn same(got: f64, want: f64) {
    assert!(
        (got - want).abs() <= 1e-9 * want.abs().max(1e-300),
        "{got} != {want}"
    );
}

fn opts(units: LengthUnit) -> ExportOptions {
    ExportOptions {
        units,
        ..ExportOptions::default()
    }
}

/// Expected density (kg/m³) of disk `i`.
fn expected_density(config: &Config, packing: &Packing, i: usize) -> f64 {
    if config.materials.is_empty() {
        return ExportOptions::default().density;
    }
    let m = &config.materials[usize::from(packing.materials[i])];
    m.properties
        .iter()
        .find(|(k, _)| k == "density")
        .map_or(ExportOptions::default().density, |(_, v)| *v)
}

/// Expected 1-based type of disk `i`.
fn expected_type(config: &Config, packing: &Packing, i: usize) -> usize {
    if config.materials.is_empty() {
        1
    } else {
        usize::from(packing.materials[i]) + 1
    }
}

/// Every scene of [`scenes`] exported by `write` in metres, then in
/// millimetres, handed to `check` with the unit and the file's text.
fn each_export(
    write: Writer,
    mut check: impl FnMut((&'static str, Config, Packing, LengthUnit, String)),
) {
    for units in [LengthUnit::Metre, LengthUnit::Millimetre] {
        for (name, config, packing) in scenes() {
            let raw = text(write(&packing, &config.materials, &opts(units)));
            check((name, config, packing, units, raw));
        }
    }
}

/// `packing.json` of `packing` for the run of `config`: its metrics
/// measured, `origin` as the config's path, `seconds` as the time taken.
fn json_of(
    config: &Config,
    packing: &Packing,
    origin: &str,
    seconds: f64,
) -> Result<Vec<u8>, OutputError> {
    packing_json(
        packing,
        &measure(packing, &config.scene),
        &run_of(config, origin, seconds),
    )
}

/// The run of `config` with its materials.
fn run_of<'a>(config: &'a Config, origin: &'a str, seconds: f64) -> RunInfo<'a> {
    RunInfo {
        materials: &config.materials,
        ..RunInfo::new(&config.scene, origin, seconds, &config.output)
    }
}

fn scenes() -> Vec<(&'static str, Config, Packing)> {
    [
        ("rectangle", RECTANGLE),
        ("circle", CIRCLE),
        ("polygon", L_SHAPE),
        ("trapezoid", TRAPEZOID),
        ("disk-walls", DISK_WALLS),
        ("two-materials", TWO_MATERIALS),
    ]
    .into_iter()
    .map(|(name, text)| {
        let (config, packing) = packed(text);
        (name, config, packing)
    })
    .collect()
}

// ---------------------------------------------------------------- VTK

/// A legacy VTK POLYDATA file as read back.
struct Vtk {
    points: Vec<[f64; 3]>,
    cells: Vec<Vec<usize>>,
    cell_keyword: String,
    scalars: BTreeMap<String, Vec<f64>>,
}

fn parse_vtk(text: &str) -> Vtk {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("# vtk DataFile Version 3.0"));
    let title = lines.next().expect("title");
    assert!(!title.is_empty() && title.len() < 256, "{title}");
    assert_eq!(lines.next(), Some("ASCII"));
    assert_eq!(lines.next(), Some("DATASET POLYDATA"));
    let header: Vec<&str> = lines.next().expect("POINTS").split(' ').collect();
    assert_eq!(header[0], "POINTS");
    assert_eq!(header[2], "double");
    let n: usize = header[1].parse().expect("point count");
    let points: Vec<[f64; 3]> = (0..n)
        .map(|_| {
            let v: Vec<f64> = lines.next().expect("point").split(' ').map(num).collect();
            assert_eq!(v.len(), 3);
            [v[0], v[1], v[2]]
        })
        .collect();
    let cells_header: Vec<&str> = lines.next().expect("cells").split(' ').collect();
    let cell_keyword = cells_header[0].to_owned();
    let count: usize = cells_header[1].parse().expect("cell count");
    let size: usize = cells_header[2].parse().expect("cell size");
    let cells: Vec<Vec<usize>> = (0..count)
        .map(|_| {
            let v: Vec<usize> = lines
                .next()
                .expect("cell")
                .split(' ')
                .map(|s| s.parse().expect("index"))
                .collect();
            assert_eq!(v[0] + 1, v.len(), "cell length prefix");
            assert!(v[1..].iter().all(|&i| i < n), "cell index out of range");
            v[1..].to_vec()
        })
        .collect();
    assert_eq!(
        size,
        cells.iter().map(|c| c.len() + 1).sum::<usize>(),
        "cell list size"
    );
    let mut scalars = BTreeMap::new();
    if let Some(data) = lines.next() {
        assert_eq!(data, format!("POINT_DATA {n}"));
        while let Some(line) = lines.next() {
            let h: Vec<&str> = line.split(' ').collect();
            assert_eq!((h[0], h.len(), h[3]), ("SCALARS", 4, "1"), "{line}");
            assert!(["double", "int"].contains(&h[2]), "{line}");
            assert_eq!(lines.next(), Some("LOOKUP_TABLE default"));
            let values: Vec<f64> = (0..n).map(|_| num(lines.next().expect("value"))).collect();
            assert!(scalars.insert(h[1].to_owned(), values).is_none(), "{line}");
        }
    }
    Vtk {
        points,
        cells,
        cell_keyword,
        scalars,
    }
}

#[test]
fn vtk_reads_back_disks_radii_materials_and_densities() {
    for (name, config, packing) in scenes() {
        let vtk = parse_vtk(&text(packing_vtk(
            &packing,
            &config.materials,
            &ExportOptions::default(),
        )));
        let n = packing.disks.len();
        assert_eq!(vtk.points.len(), n, "{name}");
        assert_eq!(vtk.cell_keyword, "VERTICES", "{name}");
        assert_eq!(vtk.cells.len(), n, "{name}");
        assert!(
            vtk.cells.iter().enumerate().all(|(i, c)| c == &[i]),
            "{name}"
        );
        let keys: Vec<&str> = vtk.scalars.keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            ["density", "diameter", "material_id", "radius"],
            "{name}"
        );
        for (i, d) in packing.disks.iter().enumerate() {
            // Lengths stay in mm whatever the export unit.
            same_length(vtk.points[i][0], d.c.x, 1.0);
            same_length(vtk.points[i][1], d.c.y, 1.0);
            assert_eq!(vtk.points[i][2], 0.0);
            same_length(vtk.scalars["radius"][i], d.r, 1.0);
            same_length(vtk.scalars["diameter"][i], 2.0 * d.r, 1.0);
            let id = if config.materials.is_empty() {
                0.0
            } else {
                expected_type(&config, &packing, i) as f64
            };
            assert_eq!(vtk.scalars["material_id"][i], id, "{name} disk {i}");
            same(
                vtk.scalars["density"][i],
                expected_density(&config, &packing, i),
            );
        }
    }
}

#[test]
fn vtk_boundary_is_one_closed_polyline_on_the_outline() {
    for (name, _, packing) in scenes() {
        let vtk = parse_vtk(&String::from_utf8(boundary_vtk(&packing)).expect("utf-8"));
        let outline = packing.domain.outline(256);
        assert_eq!(vtk.points.len(), outline.len(), "{name}");
        for (p, q) in vtk.points.iter().zip(&outline) {
            same_length(p[0], q.x, 1.0);
            same_length(p[1], q.y, 1.0);
        }
        assert_eq!(vtk.cell_keyword, "LINES", "{name}");
        assert_eq!(vtk.cells.len(), 1, "{name}");
        let ring = &vtk.cells[0];
        assert_eq!(ring.len(), outline.len() + 1, "{name}");
        assert_eq!(ring.first(), ring.last(), "{name}: not closed");
        let visited: BTreeSet<usize> = ring.iter().copied().collect();
        assert_eq!(visited.len(), outline.len(), "{name}");
        assert!(vtk.scalars.is_empty());
    }
}

// ---------------------------------------------------------------- LAMMPS

struct Lammps {
    header: BTreeMap<String, Vec<f64>>,
    atoms: Vec<Vec<f64>>,
}

/// Reads a data file as LAMMPS' `read_data` does: first line skipped,
/// `#` comments stripped, header keywords until the first section, a
/// section keyword, one skipped line, then the section's lines.
fn parse_lammps(text: &str) -> Lammps {
    assert!(
        text.lines().all(|l| l.len() < 254),
        "line over 254 characters"
    );
    let mut lines = text.lines().skip(1);
    let mut header = BTreeMap::new();
    let mut section = None;
    for line in lines.by_ref() {
        let content = line.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let words: Vec<&str> = content.split_whitespace().collect();
        let values: Vec<f64> = words.iter().map_while(|w| w.parse::<f64>().ok()).collect();
        if values.is_empty() {
            section = Some(line.to_owned());
            break;
        }
        let keyword = words[values.len()..].join(" ");
        assert!(
            ["atoms", "atom types", "xlo xhi", "ylo yhi", "zlo zhi"].contains(&keyword.as_str()),
            "unknown header keyword {keyword:?}"
        );
        assert!(header.insert(keyword, values).is_none(), "{line}");
    }
    let mut atoms = Vec::new();
    if let Some(section) = section {
        assert_eq!(section, "Atoms # sphere");
        assert_eq!(lines.next(), Some(""), "line after the section keyword");
        atoms = lines
            .map(|l| l.split(' ').map(num).collect::<Vec<f64>>())
            .collect();
    }
    Lammps { header, atoms }
}

#[test]
fn lammps_header_counts_box_and_atoms_match_the_packing() {
    each_export(lammps_data, |(name, config, packing, units, raw)| {
        let s = units.per_mm();
        let first = raw.lines().next().expect("comment line");
        let unit_note = match units {
            LengthUnit::Metre => "units si",
            LengthUnit::Millimetre => "lengths in mm",
        };
        assert!(first.contains(unit_note), "{name}: {first}");
        // LIGGGHTS with dimension 2 makes a disc's mass of the density,
        // LAMMPS a sphere's: the file says which.
        assert!(
            raw.lines().any(|l| l.starts_with("# mass from density:")
                && l.contains("LIGGGHTS with dimension 2, a disc of unit thickness")),
            "{name}"
        );
        let data = parse_lammps(&raw);
        let n = packing.disks.len();
        assert_eq!(data.header["atoms"], [n as f64], "{name}");
        let types = config.materials.len().max(1);
        assert_eq!(data.header["atom types"], [types as f64], "{name}");
        assert_eq!(data.atoms.len(), n, "{name}");
        let (xlo, xhi) = (data.header["xlo xhi"][0], data.header["xlo xhi"][1]);
        let (ylo, yhi) = (data.header["ylo yhi"][0], data.header["ylo yhi"][1]);
        let (zlo, zhi) = (data.header["zlo zhi"][0], data.header["zlo zhi"][1]);
        assert!(zlo < 0.0 && zhi > 0.0, "{name}: z range must straddle 0");
        let ids: BTreeSet<u64> = data.atoms.iter().map(|a| a[0] as u64).collect();
        assert_eq!(ids, (1..=n as u64).collect(), "{name}: ids 1..=N");
        for (i, (a, d)) in data.atoms.iter().zip(&packing.disks).enumerate() {
            assert_eq!(a.len(), 7, "{name}: id type diameter density x y z");
            assert_eq!(a[0], (i + 1) as f64);
            assert_eq!(a[1], expected_type(&config, &packing, i) as f64);
            assert!(a[1] >= 1.0 && a[1] <= types as f64);
            same_length(a[2], 2.0 * d.r, s);
            let per_cubic_unit = (0.001 / s).powi(3);
            same(
                a[3],
                expected_density(&config, &packing, i) * per_cubic_unit,
            );
            same_length(a[4], d.c.x, s);
            same_length(a[5], d.c.y, s);
            assert_eq!(a[6], 0.0);
            // Strictly inside in x and y (LAMMPS wants x < xhi with fixed walls).
            assert!(xlo <= a[4] && a[4] < xhi, "{name}: atom {i} outside x");
            assert!(ylo <= a[5] && a[5] < yhi, "{name}: atom {i} outside y");
            assert!(zlo <= a[6] && a[6] <= zhi);
            assert!(zhi >= 0.5 * a[2] - 1e-15, "{name}: z range under a radius");
        }
    });
}

// ---------------------------------------------------------------- YADE

#[test]
fn yade_lines_follow_the_format_line() {
    each_export(yade_text, |(name, config, packing, units, raw)| {
        let s = units.per_mm();
        let mut lines = raw.lines();
        let format = lines.next().expect("format line");
        let columns = if config.materials.is_empty() {
            assert_eq!(format, "#format x_y_z_r", "{name}");
            4
        } else {
            assert_eq!(format, "#format x_y_z_r_matId", "{name}");
            // Loading it without the materials fails in YADE ("Material
            // id out of range"): the file says what to do first.
            assert!(
                raw.contains(&format!(
                    "# append {} materials to O.materials in that order before ymport.text",
                    config.materials.len()
                )),
                "{name}"
            );
            5
        };
        let rows: Vec<Vec<f64>> = lines
            .filter(|l| {
                assert!(!l.trim().is_empty(), "{name}: blank line");
                !l.starts_with('#')
            })
            .map(|l| l.split(' ').map(num).collect())
            .collect();
        assert_eq!(rows.len(), packing.disks.len(), "{name}");
        for (i, (row, d)) in rows.iter().zip(&packing.disks).enumerate() {
            assert_eq!(row.len(), columns, "{name}: row {i}");
            same_length(row[0], d.c.x, s);
            same_length(row[1], d.c.y, s);
            assert_eq!(row[2], 0.0);
            same_length(row[3], d.r, s);
            if columns == 5 {
                // YADE's matId: the material's index from 0.
                assert_eq!(row[4], f64::from(packing.materials[i]), "{name}");
            }
        }
    });
}

// ---------------------------------------------------------------- PFC

#[test]
fn pfc_creates_one_ball_per_disk_inside_the_domain_extent() {
    each_export(pfc_commands, |(name, config, packing, units, raw)| {
        let s = units.per_mm();
        let mut extent = None;
        let mut balls = Vec::new();
        let mut densities = BTreeMap::new();
        let mut walls = Vec::new();
        let mut commands = Vec::new();
        for line in raw.lines() {
            if line.starts_with(';') {
                continue;
            }
            let w: Vec<&str> = line.split(' ').collect();
            commands.push(format!("{} {}", w[0], w.get(1).unwrap_or(&"")));
            match (w[0], w.get(1).copied()) {
                ("model", Some("domain")) => {
                    assert_eq!(w[2], "extent");
                    assert!(extent.is_none(), "{name}: two domain extents");
                    extent = Some([num(w[3]), num(w[4]), num(w[5]), num(w[6])]);
                }
                ("ball", Some("create")) => {
                    assert_eq!(
                        (w[2], w[4], w[6], w[8], w[10]),
                        ("id", "position-x", "position-y", "radius", "group"),
                        "{line}"
                    );
                    let group = w[11].trim_matches('\'').to_owned();
                    assert_eq!(w[11], format!("'{group}'"));
                    balls.push((
                        w[3].parse::<u64>().expect("id"),
                        num(w[5]),
                        num(w[7]),
                        num(w[9]),
                        group,
                    ));
                }
                ("ball", Some("attribute")) => {
                    assert_eq!((w[2], w[4], w[5]), ("density", "range", "group"), "{line}");
                    densities.insert(w[6].trim_matches('\'').to_owned(), num(w[3]));
                }
                ("wall", _) => walls.push(line.to_owned()),
                ("model", Some("new")) => {}
                _ => panic!("{name}: unexpected command {line}"),
            }
        }
        assert_eq!(commands[0], "model new", "{name}");
        assert_eq!(commands[1], "model domain", "{name}: domain before balls");
        let [xmin, xmax, ymin, ymax] = extent.expect("domain extent");
        assert_eq!(balls.len(), packing.disks.len(), "{name}");
        let ids: BTreeSet<u64> = balls.iter().map(|b| b.0).collect();
        assert_eq!(ids.len(), balls.len(), "{name}: ids not unique");
        let min_extent = (xmax - xmin).min(ymax - ymin);
        for (i, ((_, x, y, r, group), d)) in balls.iter().zip(&packing.disks).enumerate() {
            same_length(*x, d.c.x, s);
            same_length(*y, d.c.y, s);
            same_length(*r, d.r, s);
            assert!(xmin < x - r && x + r < xmax, "{name}: ball {i} outside x");
            assert!(ymin < y - r && y + r < ymax, "{name}: ball {i} outside y");
            assert!(*r < 0.25 * min_extent, "{name}: PFC refuses r ≥ extent/4");
            let want = if config.materials.is_empty() {
                "gapack"
            } else if packing.materials[i] == 0 {
                "ceramic"
            } else {
                "hard_metal"
            };
            assert_eq!(group, want, "{name}");
            same(
                densities[group],
                expected_density(&config, &packing, i) * ((0.001 / s).powi(3)),
            );
        }
        let (lo, hi) = packing.domain.bounds();
        assert!(xmin < lo.x * s && hi.x * s < xmax && ymin < lo.y * s && hi.y * s < ymax);
        if name == "circle" {
            assert_eq!(walls.len(), 1, "{name}");
            assert!(walls[0].starts_with("wall generate name 'domain' circle position ("));
        } else {
            assert_eq!(
                walls.len(),
                packing.domain.outline(0).len(),
                "{name}: one facet per edge"
            );
            assert!(walls[0].starts_with("wall create name 'domain' vertices ("));
            assert!(
                walls[1..]
                    .iter()
                    .all(|w| w.starts_with("wall addfacet name 'domain' vertex ("))
            );
        }
    });
}

/// The PFC wall of a packing with wall disks stands where the balls touch
/// them: the nearest ball touches it, none crosses it, on a rectangle, an L
/// (a reflex corner) and a circle.
#[test]
fn pfc_walls_of_wall_disks_touch_the_nearest_ball() {
    let shapes = [
        "shape = \"rectangle\"\nwidth = 20\nheight = 12",
        "shape = \"polygon\"\nvertices = [[0, 0], [20, 0], [20, 8], [8, 8], [8, 20], [0, 20]]",
        "shape = \"circle\"\nradius = 10",
    ];
    for shape in shapes {
        let (config, packing) = packed(&format!(
            "seed = 2\n[domain]\n{shape}\nwalls = \"disks\"\n[grading]\nuniform = [1.0, 1.6]\n"
        ));
        let raw = text(pfc_commands(
            &packing,
            &config.materials,
            &opts(LengthUnit::Millimetre),
        ));
        assert!(
            raw.contains("; walls = \"disks\": the wall disks are not exported"),
            "{shape}"
        );
        let point = |s: &str| {
            let (x, y) = s
                .trim_matches(|c| c == '(' || c == ')')
                .split_once(',')
                .unwrap();
            [num(x), num(y)]
        };
        // The clearance of a ball from the wall: its gap to the nearest facet
        // (or inside the circle).
        let mut gap: Box<dyn Fn(&gapack::Disk) -> f64> = Box::new(|_| f64::INFINITY);
        let mut facets = Vec::new();
        for line in raw.lines().filter(|l| l.starts_with("wall ")) {
            let w: Vec<&str> = line.split(' ').collect();
            match w[2] {
                "name" if w[4] == "circle" => {
                    let (c, radius) = (point(w[6]), num(w[8]));
                    gap = Box::new(move |d| radius - ((d.c.x - c[0]).hypot(d.c.y - c[1])) - d.r);
                }
                _ => {
                    let at: Vec<[f64; 2]> = w
                        .iter()
                        .filter(|s| s.starts_with('('))
                        .map(|s| point(s))
                        .collect();
                    facets.push((at[0], at[1]));
                }
            }
        }
        if !facets.is_empty() {
            gap = Box::new(move |d| {
                facets
                    .iter()
                    .map(|&(a, b)| {
                        let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [d.c.x - a[0], d.c.y - a[1]]);
                        let t = ((ap[0] * ab[0] + ap[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1]))
                            .clamp(0.0, 1.0);
                        (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1]) - d.r
                    })
                    .fold(f64::INFINITY, f64::min)
            });
        }
        let nearest = packing.disks.iter().map(&gap).fold(f64::INFINITY, f64::min);
        // Touching within the file's rounding, never crossing.
        assert!(
            nearest.abs() < 1e-9,
            "{shape}: nearest ball {nearest} mm from the wall"
        );
        // The wall disks' own clearance (about their radius) is what was taken out.
        assert!(
            raw.contains(" mm, where the balls touch the wall disks"),
            "{shape}"
        );
    }
}

// ---------------------------------------------------------------- MercuryDPM

#[test]
fn mercury_count_bounds_and_eight_columns() {
    each_export(mercury_data, |(name, config, packing, units, raw)| {
        let s = units.per_mm();
        let mut lines = raw.lines();
        let head: Vec<f64> = lines.next().expect("header").split(' ').map(num).collect();
        assert_eq!(head.len(), 6, "{name}: N time xmin ymin xmax ymax");
        assert_eq!(head[0], packing.disks.len() as f64, "{name}");
        assert_eq!(head[1], 0.0);
        let (xmin, ymin, xmax, ymax) = (head[2], head[3], head[4], head[5]);
        let rows: Vec<Vec<f64>> = lines.map(|l| l.split(' ').map(num).collect()).collect();
        assert_eq!(rows.len(), packing.disks.len(), "{name}");
        for (i, (row, d)) in rows.iter().zip(&packing.disks).enumerate() {
            assert_eq!(row.len(), 8, "{name}: x y vx vy r angle omega species");
            same_length(row[0], d.c.x, s);
            same_length(row[1], d.c.y, s);
            same_length(row[4], d.r, s);
            assert_eq!([row[2], row[3], row[5], row[6]], [0.0; 4]);
            let species = if config.materials.is_empty() {
                0.0
            } else {
                f64::from(packing.materials[i])
            };
            assert_eq!(row[7], species, "{name}");
            let eps = 1e-12 * (xmax - xmin).max(ymax - ymin);
            assert!(
                xmin <= row[0] - row[4] + eps && row[0] + row[4] <= xmax + eps,
                "{name}: {i}"
            );
            assert!(
                ymin <= row[1] - row[4] + eps && row[1] + row[4] <= ymax + eps,
                "{name}: {i}"
            );
        }
    });
}

// ---------------------------------------------------------------- ESyS-Particle

#[test]
fn esys_sections_in_order_with_counts_and_box() {
    each_export(esys_geometry, |(name, config, packing, units, raw)| {
        let s = units.per_mm();
        let lines: Vec<&str> = raw.lines().collect();
        let n = packing.disks.len();
        assert_eq!(lines.len(), n + 11, "{name}");
        assert_eq!(lines[0], "LSMGeometry 1.2");
        let bbox: Vec<&str> = lines[1].split(' ').collect();
        assert_eq!((bbox[0], bbox.len()), ("BoundingBox", 7), "{name}");
        let b: Vec<f64> = bbox[1..].iter().map(|v| num(v)).collect();
        assert_eq!(lines[2], "PeriodicBoundaries 0 0 0");
        assert_eq!(lines[3], "Dimension 2D");
        assert_eq!(lines[4], "BeginParticles");
        assert_eq!(lines[5], "Simple");
        assert_eq!(lines[6], n.to_string());
        assert_eq!(
            lines[7 + n..],
            ["EndParticles", "BeginConnect", "0", "EndConnect"]
        );
        assert!(b[2] < 0.0 && b[5] > 0.0, "{name}: z range");
        let mut ids = BTreeSet::new();
        for (i, (line, d)) in lines[7..7 + n].iter().zip(&packing.disks).enumerate() {
            let v: Vec<f64> = line.split(' ').map(num).collect();
            assert_eq!(v.len(), 6, "{name}: x y z r id tag");
            same_length(v[0], d.c.x, s);
            same_length(v[1], d.c.y, s);
            assert_eq!(v[2], 0.0);
            same_length(v[3], d.r, s);
            assert!(ids.insert(v[4] as u64), "{name}: repeated id");
            assert_eq!(v[4], i as f64);
            assert_eq!(v[5], expected_type(&config, &packing, i) as f64, "{name}");
            let eps = 1e-12 * (b[3] - b[0]).max(b[4] - b[1]);
            assert!(
                b[0] <= v[0] - v[3] + eps && v[0] + v[3] <= b[3] + eps,
                "{name}: {i} outside x"
            );
            assert!(
                b[1] <= v[1] - v[3] + eps && v[1] + v[3] <= b[4] + eps,
                "{name}: {i} outside y"
            );
        }
    });
}

// ---------------------------------------------------------------- JSON

#[test]
fn json_holds_domain_disks_and_the_summary() {
    for (name, config, packing) in scenes() {
        let metrics = measure(&packing, &config.scene);
        let run = run_of(&config, "test.toml", 0.25);
        let raw = packing_json(&packing, &metrics, &run).expect("renders");
        let doc: serde_json::Value = serde_json::from_slice(&raw).expect("valid JSON");
        assert_eq!(doc["units"], "mm");
        let domain = &doc["domain"];
        let shape = match name {
            "circle" | "polygon" | "trapezoid" => name,
            _ => "rectangle",
        };
        assert_eq!(domain["shape"], shape, "{name}");
        same(
            domain["area"].as_f64().expect("area"),
            packing.domain.area(),
        );
        let (lo, hi) = packing.domain.bounds();
        assert_eq!(domain["bounds"]["min"], serde_json::json!([lo.x, lo.y]));
        assert_eq!(domain["bounds"]["max"], serde_json::json!([hi.x, hi.y]));
        assert_eq!(
            domain["outline"].as_array().expect("outline").len(),
            packing.domain.outline(256).len()
        );
        match name {
            "circle" => {
                assert_eq!(domain["radius"], 6.0);
                assert_eq!(domain["center"], serde_json::json!([2.0, -1.0]));
            }
            "polygon" => assert_eq!(
                domain["vertices"],
                serde_json::json!([
                    [0.0, 0.0],
                    [10.0, 0.0],
                    [10.0, 4.0],
                    [4.0, 4.0],
                    [4.0, 10.0],
                    [0.0, 10.0]
                ])
            ),
            "trapezoid" => assert_eq!(
                [&domain["bottom"], &domain["top"], &domain["height"]],
                [10.0, 5.0, 8.0]
            ),
            _ => assert!(domain["width"].as_f64().is_some() && domain["height"].as_f64().is_some()),
        }
        let disks = doc["disks"].as_array().expect("disks");
        assert_eq!(disks.len(), packing.disks.len(), "{name}");
        for (i, (j, d)) in disks.iter().zip(&packing.disks).enumerate() {
            assert_eq!(j["id"], i, "{name}");
            same_length(j["x"].as_f64().expect("x"), d.c.x, 1.0);
            same_length(j["y"].as_f64().expect("y"), d.c.y, 1.0);
            same_length(j["r"].as_f64().expect("r"), d.r, 1.0);
            if config.materials.is_empty() {
                assert!(j.get("material").is_none(), "{name}");
            } else {
                let m = &config.materials[usize::from(packing.materials[i])];
                assert_eq!(j["material"], m.name.as_str(), "{name}");
            }
        }
        let summary: serde_json::Value =
            serde_json::from_slice(&summary_json(&packing, &metrics, &run).expect("summary"))
                .expect("valid summary");
        assert_eq!(doc["summary"], summary, "{name}");
        assert_eq!(doc["summary"]["config"], "test.toml");
    }
}

// ---------------------------------------------------------------- all formats

const WRITERS: [(&str, Writer); 6] = [
    ("vtk", packing_vtk),
    ("lammps", lammps_data),
    ("yade", yade_text),
    ("pfc", pfc_commands),
    ("mercury", mercury_data),
    ("esys", esys_geometry),
];

#[test]
fn same_packing_gives_the_same_bytes() {
    let (config, first) = packed(TWO_MATERIALS);
    let (_, second) = packed(TWO_MATERIALS);
    assert_eq!(first, second, "packing is not deterministic");
    for units in [LengthUnit::Metre, LengthUnit::Millimetre] {
        for (name, write) in WRITERS {
            let a = write(&first, &config.materials, &opts(units)).expect("renders");
            let b = write(&second, &config.materials, &opts(units)).expect("renders");
            assert_eq!(a, b, "{name}");
            assert!(a.ends_with(b"\n"), "{name}: last line unterminated");
        }
    }
    assert_eq!(boundary_vtk(&first), boundary_vtk(&second));
    assert_eq!(
        json_of(&config, &first, "test", 0.0).expect("json"),
        json_of(&config, &second, "test", 0.0).expect("json")
    );
}

#[test]
fn wall_disks_are_not_exported() {
    let (config, packing) = packed(DISK_WALLS);
    assert!(!packing.boundary.is_empty(), "the scene has no wall disks");
    let raw = text(esys_geometry(
        &packing,
        &config.materials,
        &opts(LengthUnit::Millimetre),
    ));
    let lines: Vec<&str> = raw.lines().collect();
    let n: usize = lines[6].parse().expect("count");
    assert_eq!(n, packing.disks.len());
    let centres: BTreeSet<(u64, u64)> = lines[7..7 + n]
        .iter()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(num).collect();
            (v[0].to_bits(), v[1].to_bits())
        })
        .collect();
    for w in &packing.boundary {
        assert!(
            !centres.contains(&(w.c.x.to_bits(), w.c.y.to_bits())),
            "wall disk at {} exported",
            w.c
        );
    }
}

#[test]
fn a_material_outside_the_list_is_refused() {
    let (config, mut packing) = packed(TWO_MATERIALS);
    packing.materials[3] = 2;
    for (name, write) in WRITERS {
        match write(&packing, &config.materials, &ExportOptions::default()) {
            Err(OutputError::UnknownMaterial {
                disk: 3,
                material: 2,
                count: 2,
            }) => {}
            other => panic!("{name}: {:?}", other.map(|b| b.len())),
        }
    }
    assert!(matches!(
        json_of(&config, &packing, "test", 0.0),
        Err(OutputError::UnknownMaterial { disk: 3, .. })
    ));
    // Without a list of materials the indices are not used.
    for (name, write) in WRITERS {
        assert!(
            write(&packing, &[], &ExportOptions::default()).is_ok(),
            "{name}"
        );
    }
}

#[test]
fn an_empty_packing_gives_valid_empty_files() {
    let (config, mut packing) = packed(TWO_MATERIALS);
    packing.disks.clear();
    packing.materials.clear();
    let m = &config.materials;
    let o = ExportOptions::default();
    let vtk = parse_vtk(&text(packing_vtk(&packing, m, &o)));
    assert!(vtk.points.is_empty() && vtk.cells.is_empty());
    let lammps = parse_lammps(&text(lammps_data(&packing, m, &o)));
    assert_eq!(lammps.header["atoms"], [0.0]);
    assert!(lammps.atoms.is_empty());
    let (zlo, zhi) = (lammps.header["zlo zhi"][0], lammps.header["zlo zhi"][1]);
    assert!(zlo < 0.0 && 0.0 < zhi);
    assert_eq!(text(yade_text(&packing, m, &o)).lines().count(), 3);
    let pfc = text(pfc_commands(&packing, m, &o));
    assert!(!pfc.contains("ball create"));
    assert!(pfc.contains("model domain extent"));
    let mercury = text(mercury_data(&packing, m, &o));
    assert_eq!(mercury.lines().count(), 1);
    assert!(mercury.starts_with("0 0 "));
    let esys = text(esys_geometry(&packing, m, &o));
    assert_eq!(esys.lines().nth(6), Some("0"));
    assert_eq!(esys.lines().count(), 11);
    let doc: serde_json::Value =
        serde_json::from_slice(&json_of(&config, &packing, "test", 0.0).expect("json"))
            .expect("valid JSON");
    assert_eq!(doc["disks"], serde_json::json!([]));
}
