//! The `gapack` binary end to end: bad inputs fail cleanly, good ones write
//! the three outputs, and the same seed gives the same bytes.
//!
//! Every test runs in its own scratch directory under `target/`; the tests
//! named `packs_*` and `shipped_configs_parse` need the packer, domains and
//! gradings, the others fail before those are called.

use crate::common;

use std::fs;
use std::path::Path;

use common::{gapack, refuses, scratch};

fn rect(size: &str, grading: &str) -> String {
    format!("[domain]\nshape = \"rectangle\"\n{size}\n[grading]\n{grading}\n")
}

#[test]
fn refuses_unknown_key() {
    refuses(
        "unknown-key",
        &rect("width = 20\nheight = 30\ncolour = 1", "constant = 1.2"),
        "domain.colour",
        "5:1",
    );
}

#[test]
fn refuses_wrong_type() {
    refuses(
        "wrong-type",
        &rect("width = \"wide\"\nheight = 30", "constant = 1.2"),
        "domain.width",
        "3:9",
    );
}

#[test]
fn refuses_toml_syntax_error() {
    refuses(
        "syntax",
        &rect("width = 20\nheight = 30 mm", "constant = 1.2"),
        "domain.height",
        "4:10",
    );
}

#[test]
fn refuses_missing_domain_size() {
    refuses(
        "missing-size",
        &rect("width = 20", "constant = 1.2"),
        "domain.height",
        "2:9",
    );
}

#[test]
fn refuses_bad_sizes() {
    for (i, value) in ["0", "-5", "nan", "inf", "-inf"].iter().enumerate() {
        refuses(
            &format!("bad-size-{i}"),
            &rect(&format!("width = {value}\nheight = 30"), "constant = 1.2"),
            "domain.width",
            "3:9",
        );
    }
}

#[test]
fn refuses_unknown_name_listing_valid_ones() {
    let dir = scratch("unknown-name");
    fs::write(
        dir.join("bad.toml"),
        rect(
            "width = 20\nheight = 30",
            "constant = 1.2\n[packer]\nindex = \"octree\"",
        ),
    )
    .expect("write config");
    let out = gapack(&dir, &["pack", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("packer.index") && stderr.contains("valid: mx-quadtree, grid"),
        "{stderr}"
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn refuses_missing_config_file() {
    let dir = scratch("missing-file");
    let out = gapack(&dir, &["pack", "nowhere.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with("error: cannot read nowhere.toml"),
        "{stderr}"
    );
    assert!(!dir.join("out").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn refuses_bad_arguments() {
    let dir = scratch("bad-args");
    let out = gapack(&dir, &["pack", "--seed", "minus-one"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.join("out").exists());
    let out = gapack(&dir, &["unpack"]);
    assert_eq!(out.status.code(), Some(2));
    let _ = fs::remove_dir_all(&dir);
}

// ---- These need the Domain and Grading constructors --------------------------

#[test]
fn refuses_decreasing_grading_table() {
    refuses(
        "table-decreasing",
        &rect(
            "width = 20\nheight = 30",
            "table = [[1.2, 0], [1.4, 60], [1.3, 100]]",
        ),
        "grading.table",
        "6:9",
    );
}

#[test]
fn refuses_grading_table_not_ending_at_100() {
    refuses(
        "table-short",
        &rect("width = 20\nheight = 30", "table = [[1.2, 0], [1.4, 60]]"),
        "grading.table",
        "6:9",
    );
}

#[test]
fn refuses_polygon_with_two_vertices() {
    refuses(
        "polygon-two",
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 0]]\n[grading]\nconstant = 1.2\n",
        "domain.vertices",
        "3:12",
    );
}

#[test]
fn refuses_self_crossing_polygon() {
    let dir = scratch("polygon-crossing");
    let config = "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 10], [10, 0], [0, 10]]\n[grading]\nconstant = 1.2\n";
    fs::write(dir.join("bad.toml"), config).expect("write config");
    let out = gapack(&dir, &["pack", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with("error: bad.toml:3:") && stderr.contains("domain.vertices: "),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(!dir.join("out").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn refuses_domain_narrower_than_smallest_disk() {
    refuses(
        "narrow",
        &rect("width = 1\nheight = 30", "constant = 1.2"),
        "domain.width",
        "3:9",
    );
}

#[test]
fn refuses_scene_over_memory_limit() {
    // 10 m × 10 m of 0.2 mm disks: billions of disks.
    refuses(
        "too-large",
        &rect("width = 10000\nheight = 10000", "constant = 0.2"),
        "domain.width",
        "3:9",
    );
}

#[test]
fn shipped_configs_parse() {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("configs");
    let mut count = 0;
    for entry in fs::read_dir(&dir).expect("configs/ exists") {
        let path = entry.expect("dir entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = fs::read_to_string(&path).expect("read config");
            if let Err(e) = gapack::config::parse(&text, &path.display().to_string()) {
                panic!("{e}");
            }
            count += 1;
        }
    }
    assert!(count >= 7, "only {count} configs found");
}

// ---- These need the packer ----------------------------------------------------

#[test]
fn packs_default_scene() {
    let dir = scratch("default");
    let out = gapack(&dir, &["pack", "--out", "result"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("result: ") && stdout.contains(" disks, porosity "),
        "{stdout}"
    );
    assert_eq!(stdout.lines().count(), 1, "{stdout}");

    let csv = fs::read_to_string(dir.join("result/packing.csv")).expect("packing.csv");
    assert!(csv.starts_with("id,x,y,r\n0,"), "{csv}");
    let rows = csv.lines().count() - 1;
    assert!(rows > 100, "{rows} disks");

    let summary = fs::read_to_string(dir.join("result/summary.json")).expect("summary.json");
    let summary: serde_json::Value = serde_json::from_str(&summary).expect("valid JSON");
    for key in [
        "particles",
        "porosity",
        "domain_area",
        "solid_area",
        "psd_ks",
        "max_overlap",
        "min_wall_clearance",
        "coordination",
        "local_porosity_std",
        "largest_hole",
        "seconds",
        "seed",
        "method",
        "index",
        "one_contact_share",
        "gap",
        "max_deferred",
        "isolated",
        "rules",
        "walls",
        "shape",
        "config",
        "gapack_version",
        "stats",
        "grading",
    ] {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(summary["particles"].as_u64(), Some(rows as u64));
    assert_eq!(summary["config"], "embedded default");
    // Tangent disks: zero overlap up to rounding.
    let overlap = summary["max_overlap"]
        .as_f64()
        .expect("max_overlap is a number");
    assert!(overlap < 1e-9, "max_overlap {overlap}");

    let svg = fs::read_to_string(dir.join("result/packing.svg")).expect("packing.svg");
    assert!(
        svg.contains("<svg") && svg.matches("<circle").count() == rows,
        "{rows} disks"
    );
    // The default formats (csv, svg, png) and nothing else, in particular no leftover temporary file.
    let mut written: Vec<String> = fs::read_dir(dir.join("result"))
        .expect("read result")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(
        written,
        [
            "manifest.json",
            "packing.csv",
            "packing.png",
            "packing.svg",
            "porosity_map.png",
            "porosity_map.svg",
            "psd.png",
            "psd.svg",
            "summary.json"
        ]
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn packs_into_default_directories_quietly() {
    let dir = scratch("default-dirs");
    let out = gapack(&dir, &["pack", "--quiet"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty());
    assert!(dir.join("out/default/packing.csv").is_file());
    fs::write(
        dir.join("mine.toml"),
        rect("width = 10\nheight = 10", "constant = 1.2"),
    )
    .expect("write config");
    let out = gapack(&dir, &["pack", "mine.toml", "--quiet"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("out/mine/summary.json").is_file());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn packs_same_seed_to_same_bytes() {
    let dir = scratch("seeds");
    let csv = |out: &str, seed: &str| {
        let run = gapack(&dir, &["pack", "--quiet", "--out", out, "--seed", seed]);
        assert_eq!(
            run.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        fs::read(dir.join(out).join("packing.csv")).expect("packing.csv")
    };
    let a = csv("a", "11");
    let b = csv("b", "11");
    let c = csv("c", "12");
    assert!(a == b, "same seed, different packing.csv");
    assert!(a != c, "different seeds, same packing.csv");
    let summary = fs::read_to_string(dir.join("c/summary.json")).expect("summary.json");
    assert!(summary.contains("\"seed\": 12"), "{summary}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn packs_but_write_failure_leaves_no_new_output() {
    let dir = scratch("write-failure");
    // A directory where packing.csv should go: its rename fails.
    fs::create_dir_all(dir.join("result/packing.csv")).expect("create blocker");
    let out = gapack(&dir, &["pack", "--out", "result"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.starts_with("error: cannot write the outputs: cannot replace result"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.stdout.is_empty());
    let left: Vec<_> = fs::read_dir(dir.join("result"))
        .expect("read result")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(left, ["packing.csv"], "only the blocker may remain");
    let _ = fs::remove_dir_all(&dir);
}

// ============================================================================
// Hostile configs (branch h16-config): each refused with exit 2 and one line
// naming file:line:column and the key, before anything runs; and a relaxation
// pack that the write check now accepts.
// ============================================================================

/// Run `gapack validate bad.toml` on `config`: it must fail with exit 2 and
/// one line starting `error: bad.toml:{at}: {key}: ` and containing `words`.
fn validate_refuses(name: &str, config: &str, at: &str, key: &str, words: &str) {
    let dir = scratch(name);
    fs::write(dir.join("bad.toml"), config).expect("write config");
    let out = gapack(&dir, &["validate", "bad.toml"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {stderr}");
    assert_eq!(stderr.lines().count(), 1, "{name}: {stderr}");
    let head = format!("error: bad.toml:{at}: {key}: ");
    assert!(
        stderr.starts_with(&head),
        "{name}: expected {head:?}: {stderr}"
    );
    assert!(
        stderr.contains(words),
        "{name}: expected {words:?}: {stderr}"
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn hostile_arrays_with_extra_elements_are_refused() {
    validate_refuses(
        "h16-vertices",
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 0, \"junk\", [1, 2]], [10, 10]]\n\
         [grading]\nconstant = 1\n",
        "3:21",
        "domain.vertices[1]",
        "invalid length 4, expected an array of 2 numbers",
    );
    validate_refuses(
        "h16-center",
        "[domain]\nshape = \"circle\"\nradius = 10\ncenter = [0, 0, 5]\n[grading]\nconstant = 1\n",
        "4:10",
        "domain.center",
        "invalid length 3",
    );
    validate_refuses(
        "h16-uniform",
        &rect("width = 20\nheight = 30", "uniform = [1, 2, 3]"),
        "6:11",
        "grading.uniform",
        "invalid length 3",
    );
    validate_refuses(
        "h16-table-row",
        &rect("width = 20\nheight = 30", "table = [[1, 0, 5], [2, 100]]"),
        "6:10",
        "grading.table[0]",
        "invalid length 3",
    );
}

#[test]
fn hostile_tables_and_sizes_get_messages_naming_their_keys() {
    validate_refuses(
        "h16-array-of-domains",
        "[[domain]]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1\n",
        "1:1",
        "domain",
        "must be a table, not an array of tables: write [domain], not [[domain]]",
    );
    validate_refuses(
        "h16-both-spellings",
        &format!(
            "{}[optimise]\ntarget_porosity = 0.2\n[optimize]\ntarget_porosity = 0.2\n",
            rect("width = 20\nheight = 30", "constant = 1.2")
        ),
        "9:1",
        "optimize",
        "[optimise] is given too",
    );
    validate_refuses(
        "h16-huge-width",
        &rect("width = 1e308\nheight = 10", "constant = 1"),
        "3:9",
        "domain.width",
        "the domain's area, width × height, overflows to inf mm²",
    );
}

#[test]
fn hostile_layering_population_is_refused_against_the_memory_limit() {
    validate_refuses(
        "h16-layering-population",
        &format!(
            "{}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n\
             [layering]\nprofile = \"linear\"\npopulation = 1000000\n",
            rect("width = 50\nheight = 50", "constant = 1.2")
        ),
        "13:14",
        "layering.population",
        "over the limit of 4096 MB",
    );
}

#[test]
fn hostile_well_names_are_refused() {
    let batch = |names: &[&str]| {
        let mut text = "[fracture]\nwidth_mm = 2\nheight_m = 0.05\n".to_owned();
        for name in names {
            text.push_str(&format!("[[fracture.wells]]\nname = {name:?}\n"));
        }
        text + "[grading]\nconstant = 0.5\n"
    };
    validate_refuses(
        "h16-well-wells-csv",
        &batch(&["a", "wells.csv"]),
        "7:8",
        "fracture.wells[1].name",
        "reserved: wells.csv, manifest.json",
    );
    validate_refuses(
        "h16-well-manifest",
        &batch(&["MANIFEST.json"]),
        "5:8",
        "fracture.wells[0].name",
        "the batch's own manifest.json",
    );
    validate_refuses(
        "h16-well-case",
        &batch(&["North", "north"]),
        "7:8",
        "fracture.wells[1].name",
        "differ only in case",
    );
}

#[test]
fn relaxation_with_its_default_tolerance_writes_a_loose_scene() {
    let dir = scratch("h16-relaxation");
    let text = format!(
        "{}[packer]\nmethod = \"relaxation\"\nrelaxation_porosity = 0.5\n",
        rect("width = 30\nheight = 30", "uniform = [1.0, 1.5]")
    );
    fs::write(dir.join("r.toml"), &text).expect("write config");
    let out = gapack(&dir, &["pack", "r.toml", "--out", "out", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(dir.join("out/packing.csv").exists());
    // A tolerance the write check cannot pass is refused at its key.
    fs::write(dir.join("bad.toml"), text + "relaxation_tolerance = 1e-4\n").expect("write config");
    let out = gapack(&dir, &["pack", "bad.toml", "--out", "bad"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.starts_with(
            "error: bad.toml:10:24: packer.relaxation_tolerance: must be at most 1e-9"
        ) && stderr.contains("5e-10 (the default) passes"),
        "{stderr}"
    );
    assert!(!dir.join("bad").exists());
}

// ---------------------------------------------------------------------------
// A closed stdout (`gapack … | head -1`): no panic, the command's own exit code.
// ---------------------------------------------------------------------------

/// Run `gapack` in `dir` with its stdout a pipe whose reading end is closed
/// before it starts, so that its first line already meets a broken pipe.
fn gapack_into_a_closed_pipe(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    std::process::Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(args)
        .current_dir(dir)
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("run gapack")
}

const CLOSED_PIPE_SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

#[test]
fn a_closed_stdout_ends_validate_verify_and_plot_quietly_with_their_own_exit_codes() {
    let dir = scratch("closed-stdout");
    fs::write(dir.join("sq.toml"), CLOSED_PIPE_SQUARE).expect("config");
    // Two overlapping disks: verify fails, and must still say so by its code.
    fs::write(dir.join("bad.csv"), "x,y,r\n5,5,1\n5.5,5,1\n9,9,0.75\n").expect("table");
    for (args, code) in [
        (vec!["validate", "sq.toml"], 0),
        (vec!["verify", "bad.csv", "--config", "sq.toml"], 1),
        (vec!["plot", "bad.csv", "--out", "pictures"], 0),
    ] {
        let out = gapack_into_a_closed_pipe(&dir, &args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        assert!(!stderr.contains("Broken pipe"), "{args:?}: {stderr}");
    }
    assert!(dir.join("pictures/packing.png").is_file());
    let _ = fs::remove_dir_all(&dir);
}

// ---------------------------------------------------------------------------
// Hardening (h16-c): limits that are limits, bounded work, bounded polygons.
// ---------------------------------------------------------------------------

/// A 20 mm square of 0.02–4 mm by mass: "at most 6,366" disks by the old
/// mean-area bound, 7,841 packed.
const WIDE_BY_MASS: &str = "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [0.02, 4.0]\nbasis = \"mass\"\n";

#[test]
fn hardening_a_particle_limit_under_the_true_bound_is_refused_and_holds_when_forced() {
    // validate said "at most 8,294" under max_particles = 9000, and pack
    // wrote 10,333 disks. The bound is now area / smallest disk area, and
    // a forced run stops at the limit instead of passing it.
    let dir = scratch("hardening-limits");
    let config = format!("{WIDE_BY_MASS}[limits]\nmax_particles = 5000\n");
    fs::write(dir.join("wide.toml"), config).unwrap();
    let refused = gapack(&dir, &["validate", "wide.toml"]);
    assert_eq!(refused.status.code(), Some(2));
    let message = String::from_utf8_lossy(&refused.stderr).to_string();
    assert!(
        message.starts_with("error: wide.toml:10:17: limits.max_particles: the scene holds up to an estimated 1.273e6 disks"),
        "{message}"
    );
    let forced = gapack(&dir, &["pack", "wide.toml", "--force", "--quiet"]);
    assert_eq!(forced.status.code(), Some(1));
    let message = String::from_utf8_lossy(&forced.stderr).to_string();
    assert!(
        message.contains("reached the particle limit of 5000 disks before the domain was full"),
        "{message}"
    );
    assert!(!dir.join("out/wide/packing.csv").exists());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn hardening_a_polygon_of_100000_vertices_is_refused_at_once_naming_its_key() {
    // validate took 74 s, and pack did not finish in 300 s.
    let dir = scratch("hardening-polygon");
    let vertices: Vec<String> = (0..100_000)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 100_000.0;
            let r = 20.0 * (1.0 + 0.03 * (37.0 * t).sin());
            format!("[{:.9},{:.9}]", 25.0 + r * t.cos(), 25.0 + r * t.sin())
        })
        .collect();
    let config = format!(
        "[domain]\nshape = \"polygon\"\nvertices = [{}]\n[grading]\nuniform = [0.5, 1.0]\n",
        vertices.join(",")
    );
    fs::write(dir.join("poly.toml"), config).unwrap();
    for command in ["validate", "pack"] {
        let out = gapack(
            &dir,
            &[command, "poly.toml", "--quiet"][..if command == "pack" { 3 } else { 2 }],
        );
        assert_eq!(out.status.code(), Some(2), "{command}");
        let message = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(
            message.starts_with("error: poly.toml:3:12: domain.vertices: a polygon may have at most 4096 vertices, got 100000"),
            "{command}: {message}"
        );
    }
    let _ = fs::remove_dir_all(&dir);
}

/// The help says what each command writes and does on Ctrl-C, shows the
/// `optimize` spelling, and `verify --quiet` answers by its exit code alone.
#[test]
fn help_tells_the_whole_story_and_verify_can_be_quiet() {
    let dir = scratch("cli-help");
    let help = |args: &[&str]| {
        let out = gapack(&dir, args);
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    assert!(help(&["--help"]).contains("[alias: optimize]"));
    let pack = help(&["pack", "--help"]);
    for what in [
        "packing.csv",
        "VTK",
        "LAMMPS",
        "YADE",
        "PFC",
        "MercuryDPM",
        "ESyS-Particle",
    ] {
        assert!(pack.contains(what), "pack --help names {what}");
    }
    assert!(!pack.contains("of the search"), "{pack}");
    for command in ["optimise", "layer", "compare", "stability", "sweep"] {
        assert!(help(&[command, "--help"]).contains("Ctrl-C"), "{command}");
    }
    fs::write(
        dir.join("sq.toml"),
        rect("width = 10\nheight = 10", "constant = 2.0"),
    )
    .unwrap();
    fs::write(dir.join("good.csv"), "x,y,r\n2,2,1\n6,6,1\n").unwrap();
    fs::write(dir.join("bad.csv"), "x,y,r\n2,2,1\n2.5,2,1\n").unwrap();
    for (file, code) in [("good.csv", 0), ("bad.csv", 1)] {
        let out = gapack(&dir, &["verify", file, "--config", "sq.toml", "--quiet"]);
        assert_eq!(out.status.code(), Some(code), "{file}");
        assert!(
            out.stdout.is_empty(),
            "{file}: {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

/// A run far larger than a typical one, or a density in g/cm³, is said
/// before the run starts.
#[test]
fn units_mistakes_are_said_before_the_run() {
    let dir = scratch("cli-units");
    fs::write(
        dir.join("tall.toml"),
        "[fracture]\nwidth_mm = 10\nheight_m = 300\n[grading]\nconstant = 1.0\n",
    )
    .unwrap();
    let out = gapack(&dir, &["validate", "tall.toml"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("warning: tall.toml: this run is estimated at about 3,055,775 disks and")
            && text.contains("keys ending in _m (metres)"),
        "{text}"
    );
    fs::write(
        dir.join("light.toml"),
        format!(
            "{}[output]\ndensity = 2.65\nformats = [\"csv\"]\n",
            rect("width = 10\nheight = 10", "constant = 1.0")
        ),
    )
    .unwrap();
    let out = gapack(&dir, &["pack", "light.toml"]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("output.density = 2.65 kg/m³") && err.contains("2650 kg/m³"),
        "{err}"
    );
    // A typical run says neither.
    let out = gapack(&dir, &["validate", "light.toml"]);
    assert!(!String::from_utf8_lossy(&out.stdout).contains("estimated at about"));
}

/// `gapack bench` at its smallest size: both indexes, in turns, pack the
/// same disks (the index changes the speed, not the packing), and each row
/// has a time and a rate that agree.
#[test]
fn bench_measures_both_indexes_on_the_same_packing() {
    let dir = scratch("bench-indexes");
    let out = gapack(
        &dir,
        &["bench", "--max", "10000", "--repeats", "2", "--out", "b"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = fs::read_to_string(dir.join("b/bench.csv")).expect("bench.csv");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2, "{csv}");
    assert_eq!((rows[0][2], rows[1][2]), ("mx-quadtree", "grid"));
    for col in [0, 3, 5, 6] {
        assert_eq!(rows[0][col], rows[1][col], "column {col}: {csv}");
    }
    let disks: f64 = rows[0][5].parse().unwrap();
    assert!((9_000.0..11_000.0).contains(&disks), "{csv}");
    for row in &rows {
        let (seconds, rate): (f64, f64) = (row[7].parse().unwrap(), row[8].parse().unwrap());
        assert!(
            seconds > 0.0 && (rate * seconds - disks).abs() < 1e-6 * disks,
            "{csv}"
        );
    }
}

/// `--timings` prints where the run's time went: each step once, in the
/// order run, every figure a non-negative number of seconds, and the ratio
/// of what follows the packing to the packing, consistent with them.
#[test]
fn timings_split_the_run_into_its_steps() {
    let dir = common::scratch("timings");
    fs::write(
        dir.join("t.toml"),
        rect("width = 60\nheight = 60", "constant = 1.0"),
    )
    .expect("write config");
    let run = common::gapack(&dir, &["pack", "t.toml", "--timings", "--quiet"]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = String::from_utf8_lossy(&run.stdout);
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("timings: "))
        .unwrap_or_else(|| panic!("no timings line in {out:?}"));
    let (steps, ratio) = line.split_once("; after packing ").expect("a ratio");
    let mut seconds = Vec::new();
    for (part, name) in steps.split(", ").zip(["pack", "measure", "write"]) {
        let value = part
            .strip_prefix(name)
            .and_then(|v| v.strip_suffix(" s"))
            .unwrap_or_else(|| panic!("{part:?} is not {name}"));
        let value: f64 = value.trim().parse().expect("seconds");
        assert!(value >= 0.0, "{part}");
        seconds.push(value);
    }
    assert_eq!(seconds.len(), 3, "{line}");
    let ratio: f64 = ratio
        .strip_suffix(" × the packing")
        .expect("ratio")
        .parse()
        .expect("a number");
    // The printed seconds are rounded to 10 ms: the ratio agrees with them
    // to that rounding whenever the packing took a measurable time.
    if seconds[0] >= 0.05 {
        let expect = (seconds[1] + seconds[2]) / seconds[0];
        assert!((ratio - expect).abs() <= 0.02 / seconds[0] + 0.01, "{line}");
    }
    // Without the flag, no such line.
    let plain = common::gapack(&dir, &["pack", "t.toml", "--out", "plain"]);
    assert!(!String::from_utf8_lossy(&plain.stdout).contains("timings:"));
}
