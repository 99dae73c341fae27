//! `gapack validate`, `gapack verify` and the `[output]` table end to end:
//! what they print, their exit codes, and their faults located to the line
//! and column.

use crate::common;

use std::fs;

use common::{gapack, scratch};

fn stdout(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

const SQUARE: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nuniform = [1.0, 2.0]\n";

#[test]
fn validate_prints_the_scene_without_packing() {
    let dir = scratch("validate");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    let out = gapack(&dir, &["validate", "sq.toml"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.starts_with("sq.toml: valid\n"), "{text}");
    for expected in [
        "job: pack",
        "grading: d 1 to 2 mm",
        "domain: rectangle 20 × 20 mm, area 400 mm², walls exact: about ",
        "peak memory about ",
        "output: out/sq (csv, svg, png; summary.json and manifest.json always)",
    ] {
        assert!(
            text.contains(expected),
            "{expected:?} missing from:\n{text}"
        );
    }
    assert!(!dir.join("out").exists(), "validate must not write");
}

#[test]
fn validate_refuses_a_bad_config_with_its_location() {
    let dir = scratch("validate-bad");
    fs::write(
        dir.join("bad.toml"),
        format!("{SQUARE}[output]\nformats = [\"csv\", \"gif\"]\n"),
    )
    .unwrap();
    let out = gapack(&dir, &["validate", "bad.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: bad.toml:9:19: output.formats[1]: unknown format \"gif\"; valid: csv, json, vtk, vtp, npz, lammps, yade, pfc, mercury, liggghts-superquadric, esys, lammps-clumps, liggghts-clumps, svg, png\n"
    );
}

#[test]
fn verify_passes_gapack_s_own_packing_and_fails_a_broken_one() {
    let dir = scratch("verify");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    let packed = gapack(&dir, &["pack", "sq.toml", "--quiet"]);
    assert!(packed.status.success(), "{}", stderr(&packed));
    let ok = gapack(
        &dir,
        &["verify", "out/sq/packing.csv", "--config", "sq.toml"],
    );
    assert!(ok.status.success(), "{}{}", stdout(&ok), stderr(&ok));
    let text = stdout(&ok);
    assert!(
        text.starts_with("out/sq/packing.csv against sq.toml: valid"),
        "{text}"
    );
    assert!(text.contains("overlaps: none"), "{text}");
    assert!(text.contains("every disk inside the domain"), "{text}");
    assert!(text.contains(": kept"), "{text}");

    // Move one disk onto its neighbour: an overlap, and exit code 1.
    let csv = fs::read_to_string(dir.join("out/sq/packing.csv")).unwrap();
    let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
    let second: Vec<String> = lines[2].split(',').map(str::to_owned).collect();
    let first: Vec<String> = lines[1].split(',').map(str::to_owned).collect();
    lines[2] = format!("{},{},{},{}", second[0], first[1], first[2], second[3]);
    fs::write(dir.join("broken.csv"), lines.join("\n")).unwrap();
    let bad = gapack(&dir, &["verify", "broken.csv", "--config", "sq.toml"]);
    assert_eq!(bad.status.code(), Some(1), "{}", stdout(&bad));
    assert!(stdout(&bad).contains("FAILED"));
    assert!(
        stdout(&bad).contains("overlaps: 1 pair"),
        "{}",
        stdout(&bad)
    );
    // Named by their ids and file lines (the header is line 1).
    assert!(
        stdout(&bad).contains(&format!(
            "disk id {} (line 2) and disk id {} (line 3)",
            first[0], second[0]
        )),
        "{}",
        stdout(&bad)
    );
    assert!(
        stderr(&bad).contains("the packing is not valid"),
        "{}",
        stderr(&bad)
    );

    // A disk outside the domain.
    fs::write(dir.join("out.csv"), "x,y,r\n19.5,10,1.0\n").unwrap();
    let out = gapack(&dir, &["verify", "out.csv", "--config", "sq.toml"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stdout(&out).contains(
            "containment: 1 disk reaches outside; the farthest by 5.000e-1 mm (the disk on line 2)"
        ),
        "{}",
        stdout(&out)
    );

    // The same packing with semicolons: read alike, valid.
    fs::write(dir.join("semi.csv"), csv.replace(',', ";")).unwrap();
    let semi = gapack(&dir, &["verify", "semi.csv", "--config", "sq.toml"]);
    assert!(semi.status.success(), "{}", stdout(&semi));

    // Against another scene's config: the disks do not fit, said so
    // rather than as a negative porosity.
    fs::write(
        dir.join("small.toml"),
        SQUARE
            .replace("width = 20", "width = 8")
            .replace("height = 20", "height = 8"),
    )
    .unwrap();
    let wrong = gapack(
        &dir,
        &["verify", "out/sq/packing.csv", "--config", "small.toml"],
    );
    assert_eq!(wrong.status.code(), Some(1));
    assert!(
        stdout(&wrong).contains("the disks do not fit in this config's domain")
            && !stdout(&wrong).contains("porosity -"),
        "{}",
        stdout(&wrong)
    );
}

#[test]
fn verify_reads_other_tools_tables_and_checks_the_grading() {
    let dir = scratch("verify-foreign");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    // 100 disks of 1 mm on a 2 mm lattice: valid, but far from uniform 1-2 mm.
    let mut csv = String::from("Diameter,X,Y\n");
    for i in 0..100 {
        csv += &format!(
            "1.0,{},{}\n",
            1.0 + 2.0 * (i % 10) as f64,
            1.0 + 2.0 * (i / 10) as f64
        );
    }
    fs::write(dir.join("lattice.csv"), csv).unwrap();
    let out = gapack(&dir, &["verify", "lattice.csv", "--config", "sq.toml"]);
    assert_eq!(out.status.code(), Some(1), "{}", stdout(&out));
    let text = stdout(&out);
    assert!(text.contains("overlaps: none"), "{text}");
    assert!(text.contains(": bent"), "{text}");
    assert!(stderr(&out).contains("do not follow the config's grading"));
}

#[test]
fn verify_refuses_bad_tables_with_file_line_and_column() {
    let dir = scratch("verify-bad");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    for (name, text, message) in [
        (
            "letters.csv",
            "id,x,y,r\n0,1,1,0.5\n1,3,abc,0.5\n",
            "error: letters.csv:3:5: column y: expected a number, got \"abc\"\n",
        ),
        (
            "columns.csv",
            "id,x,r\n0,1,0.5\n",
            "error: columns.csv:1:1: missing column y; the header has: id, x, r\n",
        ),
        (
            "short.csv",
            "id,x,y,r\n0,1,1,0.5\n1,3,3\n",
            "error: short.csv:3:1: expected 4 fields like the header, got 3\n",
        ),
        (
            "empty.csv",
            "x,y,r\n",
            "error: empty.csv:2:1: no disks: the table has no rows\n",
        ),
    ] {
        fs::write(dir.join(name), text).unwrap();
        let out = gapack(&dir, &["verify", name, "--config", "sq.toml"]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        assert_eq!(stderr(&out), message, "{name}");
        assert!(out.stdout.is_empty(), "{name}");
    }
    let missing = gapack(&dir, &["verify", "nothing.csv", "--config", "sq.toml"]);
    assert_eq!(missing.status.code(), Some(2));
    assert!(stderr(&missing).starts_with("error: cannot read nothing.csv: "));
}

#[test]
fn verify_needs_the_well_of_a_batch() {
    let dir = scratch("verify-well");
    let config = "[fracture]\nwalls = \"exact\"\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 8.0\nheight_m = 0.05\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 10.0\nheight_m = 0.05\n[grading]\nuniform = [1.0, 1.2]\n";
    fs::write(dir.join("w.toml"), config).unwrap();
    let packed = gapack(&dir, &["pack", "w.toml", "--quiet"]);
    assert!(packed.status.success(), "{}", stderr(&packed));
    let none = gapack(
        &dir,
        &["verify", "out/w/a/packing.csv", "--config", "w.toml"],
    );
    assert_eq!(none.status.code(), Some(2));
    assert!(
        stderr(&none).contains("name the packing's with --well (a, b)"),
        "{}",
        stderr(&none)
    );
    let a = gapack(
        &dir,
        &[
            "verify",
            "out/w/a/packing.csv",
            "--config",
            "w.toml",
            "--well",
            "a",
        ],
    );
    assert!(a.status.success(), "{}", stdout(&a));
    // Well b is wider: a's packing fits in it, but b's does not fit in a.
    let b_in_a = gapack(
        &dir,
        &[
            "verify",
            "out/w/b/packing.csv",
            "--config",
            "w.toml",
            "--well",
            "a",
        ],
    );
    assert_eq!(b_in_a.status.code(), Some(1), "{}", stdout(&b_in_a));
}

#[test]
fn output_dir_of_the_config_is_used_and_an_unwritable_one_fails_cleanly() {
    let dir = scratch("output-dir");
    fs::write(
        dir.join("sq.toml"),
        format!("{SQUARE}[output]\ndir = \"results/run1\"\nformats = [\"csv\"]\n"),
    )
    .unwrap();
    let out = gapack(&dir, &["pack", "sq.toml", "--quiet"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut written: Vec<String> = fs::read_dir(dir.join("results/run1"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["manifest.json", "packing.csv", "summary.json"]);

    // A file where the directory should be.
    fs::write(dir.join("blocked"), "a file").unwrap();
    let blocked = gapack(
        &dir,
        &["pack", "sq.toml", "--out", "blocked/run", "--quiet"],
    );
    assert_eq!(blocked.status.code(), Some(1));
    assert!(
        stderr(&blocked).starts_with(
            "error: cannot write the outputs: cannot create directory blocked: a file is in the way"
        ),
        "{}",
        stderr(&blocked)
    );
    assert_eq!(fs::read_to_string(dir.join("blocked")).unwrap(), "a file");
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

/// A well-formed SVG document: its root element opens and closes, with a size.
fn assert_svg(text: &str, name: &str) {
    assert!(text.contains("<svg"), "{name}: no <svg");
    assert!(text.trim_end().ends_with("</svg>"), "{name}: not closed");
    assert!(
        text.contains("width=\"") && text.contains("height=\""),
        "{name}: no size"
    );
}

#[test]
fn every_format_is_written_and_the_pictures_are_valid_images() {
    let dir = scratch("all-formats");
    fs::write(
        dir.join("sq.toml"),
        format!(
            "{SQUARE}[output]\nformats = [\"csv\", \"json\", \"vtk\", \"lammps\", \"yade\", \"pfc\", \"mercury\", \"esys\", \"lammps-clumps\", \"liggghts-clumps\", \"svg\", \"png\"]\ndensity = 2500.0\n"
        ),
    )
    .unwrap();
    let out = gapack(&dir, &["pack", "sq.toml", "--quiet"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut written: Vec<String> = fs::read_dir(dir.join("out/sq"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(
        written,
        [
            "boundary.vtk",
            "manifest.json",
            "packing.clumps.lammps",
            "packing.clumps.liggghts",
            "packing.csv",
            "packing.geo",
            "packing.json",
            "packing.lammps",
            "packing.mercury.data",
            "packing.p2dat",
            "packing.png",
            "packing.svg",
            "packing.vtk",
            "packing.yade.txt",
            "porosity_map.png",
            "porosity_map.svg",
            "psd.png",
            "psd.svg",
            "summary.json",
        ]
    );
    let read = |name: &str| fs::read(dir.join("out/sq").join(name)).unwrap();
    // A square domain: 1600 px high including an 80 px legend strip, so the square is 1520 px.
    assert_eq!(png_size(&read("packing.png")), (1520, 1600));
    assert_eq!(png_size(&read("psd.png")), (900, 560));
    let (w, h) = png_size(&read("porosity_map.png"));
    assert!(w > 400 && h > 400, "{w} × {h}");
    for svg in ["packing.svg", "psd.svg", "porosity_map.svg"] {
        assert_svg(&String::from_utf8(read(svg)).unwrap(), svg);
    }
    // The default density reaches the LAMMPS file (kg/m³ with lengths in metres).
    let lammps = String::from_utf8(read("packing.lammps")).unwrap();
    let atoms = lammps.split("Atoms # sphere").nth(1).unwrap();
    let first: Vec<&str> = atoms
        .lines()
        .find(|l| !l.trim().is_empty())
        .unwrap()
        .split_whitespace()
        .collect();
    assert_eq!(first[3], "2500");
    // Disks: one sphere per molecule, the same atoms for LAMMPS and LIGGGHTS.
    let clumps = |name: &str| {
        let text = String::from_utf8(read(name)).unwrap();
        text.split_once("Atoms # hybrid").unwrap().1.to_owned()
    };
    let liggghts = clumps("packing.clumps.liggghts");
    assert_eq!(liggghts, clumps("packing.clumps.lammps"));
    let disks = String::from_utf8(read("packing.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert_eq!(liggghts.lines().filter(|l| !l.is_empty()).count(), disks);
}

#[test]
fn plot_draws_a_table_from_any_tool_and_refuses_a_bad_one() {
    let dir = scratch("plot");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    fs::write(
        dir.join("foreign.csv"),
        "# from another code\nx,y,diameter,material\n1,1,2,sand\n3.5,1,1.5,clay\n",
    )
    .unwrap();
    let out = gapack(&dir, &["plot", "foreign.csv"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        stdout(&out),
        ".: packing, psd and porosity_map (.svg, .png) of foreign.csv (2 disks of 2 materials); without --config the domain drawn is the disks' bounding box, and the porosities shown are of that box\n"
    );
    for name in ["packing", "psd", "porosity_map"] {
        png_size(&fs::read(dir.join(format!("{name}.png"))).unwrap());
        assert_svg(
            &fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap(),
            name,
        );
    }
    // With the config: its domain frames the picture, its grading is the PSD's target.
    let with = gapack(
        &dir,
        &[
            "plot",
            "foreign.csv",
            "--config",
            "sq.toml",
            "--out",
            "pics",
            "--quiet",
        ],
    );
    assert!(with.status.success(), "{}", stderr(&with));
    assert!(with.stdout.is_empty());
    assert!(
        fs::read_to_string(dir.join("pics/psd.svg"))
            .unwrap()
            .contains("target")
    );

    fs::write(dir.join("bad.csv"), "x,y,r\n1,1,0.5\n2,2,oops\n").unwrap();
    let bad = gapack(&dir, &["plot", "bad.csv", "--out", "nothing"]);
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(
        stderr(&bad),
        "error: bad.csv:3:5: column r: expected a number, got \"oops\"\n"
    );
    assert!(!dir.join("nothing").exists(), "nothing may be written");
}

#[test]
fn a_scene_over_the_limits_is_refused_with_its_estimate_unless_forced() {
    // The estimate is the true upper bound, area / smallest disk area (510
    // disks here; the square packs about 160). Forced, the scene runs, and
    // the limit still holds during the run.
    let dir = scratch("limits");
    fs::write(
        dir.join("sq.toml"),
        format!("{SQUARE}[limits]\nmax_particles = 300\n"),
    )
    .unwrap();
    let refused = gapack(&dir, &["pack", "sq.toml"]);
    assert_eq!(refused.status.code(), Some(2));
    let message = stderr(&refused);
    assert!(
        message.starts_with("error: sq.toml:9:17: limits.max_particles: the scene holds up to an estimated 5.100e2 disks (about 0.0 s to pack"),
        "{message}"
    );
    assert!(
        message.contains("or run with --force to go ahead"),
        "{message}"
    );
    assert!(!dir.join("out").exists());
    let validate = gapack(&dir, &["validate", "sq.toml"]);
    assert_eq!(validate.status.code(), Some(2));
    let forced = gapack(&dir, &["validate", "sq.toml", "--force"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    let packed = gapack(&dir, &["pack", "sq.toml", "--force", "--quiet"]);
    assert!(packed.status.success(), "{}", stderr(&packed));
    assert!(dir.join("out/sq/packing.csv").exists());
    // Under a limit the packing would pass, the forced run stops at it.
    fs::write(
        dir.join("few.toml"),
        format!("{SQUARE}[limits]\nmax_particles = 50\n"),
    )
    .unwrap();
    let stopped = gapack(&dir, &["pack", "few.toml", "--force", "--quiet"]);
    assert_eq!(stopped.status.code(), Some(1));
    assert!(
        stderr(&stopped).contains("reached the particle limit of 50 disks"),
        "{}",
        stderr(&stopped)
    );
    assert!(!dir.join("out/few/packing.csv").exists());
}

// ---------------------------------------------------------------------------
// Hostile tables and window runs: degenerate sizes, ambiguous columns, too
// few disks for a grading check, a window checked against its own area.
// ---------------------------------------------------------------------------

/// A one-row table with a subnormal, a tiny or a huge radius drove the
/// grading chart's log axis past 4 GB (or into an endless loop): it is now
/// refused where it is read, with the row and column, by verify and plot.
#[test]
fn plot_and_verify_refuse_sizes_out_of_any_physical_range() {
    let dir = scratch("hostile-sizes");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    for (r, message) in [
        ("5e-324", "a radius must lie in [5e-7, 5e5] mm, got 5e-324"),
        ("1e-300", "a radius must lie in [5e-7, 5e5] mm, got 1e-300"),
        ("1e300", "a radius must lie in [5e-7, 5e5] mm, got 1e300"),
    ] {
        fs::write(dir.join("one.csv"), format!("x,y,r\n10,10,{r}\n")).unwrap();
        for args in [
            vec![
                "plot", "one.csv", "--config", "sq.toml", "--out", "pictures",
            ],
            vec!["plot", "one.csv", "--out", "pictures"],
            vec!["verify", "one.csv", "--config", "sq.toml"],
        ] {
            let out = gapack(&dir, &args);
            assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
            assert_eq!(
                stderr(&out),
                format!("error: one.csv:2:7: column r: {message}\n"),
                "{args:?}"
            );
        }
    }
    // Sizes a million apart are refused at the smallest; at the limits the
    // charts draw (a log axis of six decades).
    fs::write(dir.join("wide.csv"), "x,y,d\n5,5,1e-6\n10,10,2\n").unwrap();
    let out = gapack(&dir, &["plot", "wide.csv", "--out", "pictures"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("error: wide.csv:2:5: column d: 1e-6 is more than 1e6 times smaller than the largest diameter, 2e0 (line 3)"),
        "{}",
        stderr(&out)
    );
    fs::write(dir.join("edge.csv"), "x,y,d\n5,5,2e-6\n10,10,2\n").unwrap();
    let out = gapack(
        &dir,
        &[
            "plot", "edge.csv", "--config", "sq.toml", "--out", "pictures",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("pictures/psd.svg").is_file());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn verify_refuses_two_columns_for_one_part_naming_them() {
    let dir = scratch("ambiguous-columns");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    for (header, message) in [
        (
            "x,y,r,d",
            "both.csv:1:7: columns \"r\" and \"d\" both give the disk size (fields 3 and 4); keep one",
        ),
        (
            "x,y,x,r",
            "both.csv:1:5: column \"x\" appears twice (fields 1 and 3); keep one",
        ),
    ] {
        fs::write(dir.join("both.csv"), format!("{header}\n5,5,1,2\n")).unwrap();
        let out = gapack(&dir, &["verify", "both.csv", "--config", "sq.toml"]);
        assert_eq!(out.status.code(), Some(2), "{header}");
        assert_eq!(stderr(&out), format!("error: {message}\n"));
        assert!(out.stdout.is_empty());
    }
    let _ = fs::remove_dir_all(&dir);
}

/// With two disks the KS limit exceeds 1: no sizes could fail, so the
/// grading is reported as not checked, not as kept.
#[test]
fn verify_does_not_pass_a_grading_it_cannot_check() {
    let dir = scratch("too-few-for-grading");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    // 10 mm disks against a 1-2 mm grading.
    fs::write(dir.join("two.csv"), "x,y,d\n5,5,10\n15,15,8\n").unwrap();
    let out = gapack(&dir, &["verify", "two.csv", "--config", "sq.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.starts_with("two.csv against sq.toml: valid, grading not checked\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "  grading: not checked: a grading check needs at least 3 disks, the table has 2"
        ),
        "{text}"
    );
    assert!(!text.contains("kept"), "{text}");
    // A third disk makes the check possible, and it fails.
    fs::write(dir.join("three.csv"), "x,y,d\n5,5,9\n15,15,8\n5,15,9\n").unwrap();
    let out = gapack(&dir, &["verify", "three.csv", "--config", "sq.toml"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stdout(&out).contains(": bent"), "{}", stdout(&out));
    let _ = fs::remove_dir_all(&dir);
}

/// A window run packs the fracture's first metres only: verify (and plot)
/// take the window its summary.json records, not the whole fracture.
#[test]
fn verify_checks_a_window_packing_against_the_window() {
    let dir = scratch("verify-window");
    let config = "seed = 2\n[fracture]\nextent = \"window\"\nwindow_tolerance = 0.01\n\
        width_mm = 2.6\nheight_m = 1.0\n[grading]\npreset = \"20/40\"\nbasis = \"mass\"\n";
    fs::write(dir.join("win.toml"), config).unwrap();
    let out = gapack(&dir, &["pack", "win.toml", "--out", "run", "--quiet"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("run/summary.json")).unwrap()).unwrap();
    let porosity = summary["porosity"].as_f64().unwrap();
    let area = summary["domain_area"].as_f64().unwrap();
    let length = summary["fracture"]["window"]["length_mm"].as_f64().unwrap();
    assert!(
        length < 1000.0,
        "the window is the whole fracture: {summary}"
    );

    let out = gapack(&dir, &["verify", "run/packing.csv", "--config", "win.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains(&format!(
            "  domain: the window of \"fracture\", its first {length} mm of 1000 mm, as run/summary.json records\n"
        )),
        "{text}"
    );
    assert!(
        text.contains(&format!(", porosity {porosity:.4} (solid ")),
        "verify's porosity is not the run's {porosity}:\n{text}"
    );
    assert!(text.contains(&format!(" of {area:.4} mm²)")), "{text}");

    // Away from its run's summary, a window packing is not silently checked
    // against the whole fracture.
    fs::copy(dir.join("run/packing.csv"), dir.join("moved.csv")).unwrap();
    let out = gapack(&dir, &["verify", "moved.csv", "--config", "win.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        "error: win.toml packs windows (extent = \"window\"): the length of \"fracture\"'s window is in its run's summary.json, and ./summary.json has none for it; verify the packing in the folder its run wrote\n"
    );
    let out = gapack(
        &dir,
        &["plot", "run/packing.csv", "--config", "win.toml", "--quiet"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let _ = fs::remove_dir_all(&dir);
}
