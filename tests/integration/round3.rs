//! Faults a hostile probe found: `plot` and `verify` on piled disks (10⁴
//! and more copies of one disk, or centres a nanometre apart) take seconds,
//! not minutes; `compare` on a batch of windows is refused at the key's
//! line and column; `verify` names the overlapping pair by its file lines
//! whatever the table's line ends.

use crate::common;

use std::fmt::Write as _;
use std::fs;
use std::time::{Duration, Instant};

use common::{gapack, scratch};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

const SQUARE: &str =
    "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nuniform = [0.8, 1.2]\n";

/// A table of `n` disks of radius 0.5 at (5, 5), each moved by at most
/// `jitter` mm along each axis; with ids 0..n.
fn pile(n: usize, jitter: f64) -> String {
    let mut text = String::from("id,x,y,r\n");
    for k in 0..n {
        let t = k as f64;
        let (dx, dy) = (jitter * (t * 0.37).sin(), jitter * (t * 0.61).cos());
        writeln!(text, "{k},{:?},{:?},0.5", 5.0 + dx, 5.0 + dy).unwrap();
    }
    text
}

/// How long a run of today's code took on these piles (a debug build):
/// minutes. Well under it, each disk is not drawn or tested against all.
const PROMPT: Duration = Duration::from_secs(60);

#[test]
fn plot_without_a_config_draws_piled_disks_promptly() {
    // Without --config the frame is the disks' box: one disk, each copy
    // 1600 px across, 2·10⁶ pixels painted per copy.
    let dir = scratch("round3_plot_pile");
    for (name, jitter) in [("copies.csv", 0.0), ("near.csv", 1e-9)] {
        fs::write(dir.join(name), pile(20_000, jitter)).unwrap();
        let started = Instant::now();
        let out = gapack(&dir, &["plot", name, "--out", "pics", "--quiet"]);
        let took = started.elapsed();
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(took < PROMPT, "{name}: {took:?}");
        let png = fs::read(dir.join("pics/packing.png")).unwrap();
        assert!(png.starts_with(b"\x89PNG"), "{name}");
    }
}

#[test]
fn verify_judges_nearly_coincident_disks_promptly_and_names_the_deepest_pair() {
    let dir = scratch("round3_verify_pile");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    // 50 000 disks a nanometre apart (1.25·10⁹ overlapping pairs), and a
    // copy of disk 7 last: the deepest pair there is (overlap 1).
    let mut table = pile(50_000, 1e-9);
    let seventh = table.lines().nth(8).unwrap().replacen('7', "50000", 1);
    table.push_str(&seventh);
    table.push('\n');
    fs::write(dir.join("pile.csv"), table).unwrap();
    let started = Instant::now();
    let out = gapack(&dir, &["verify", "pile.csv", "--config", "sq.toml"]);
    let took = started.elapsed();
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(took < PROMPT, "{took:?}");
    let err = stderr(&out);
    assert!(
        err.contains(
            "overlap: disks 7 and 50000 (lines 9 and 50002) overlap by 1.0e0 of their radii sum (the deepest of at least "
        ),
        "{err}"
    );
    assert!(
        err.contains(
            " overlapping pairs: the disks pile up, and each disk's search stopped soon after its first overlap)"
        ),
        "{err}"
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("overlaps: at least "), "{said}");
}

#[test]
fn compare_refuses_a_batch_of_windows_at_the_extent_key() {
    let dir = scratch("round3_compare_windows");
    let config = "seed = 0\n[fracture]\nwidth_mm = 8\n  extent = \"window\"\n[[fracture.wells]]\nname = \"a\"\nheight_m = 0.02\n[[fracture.wells]]\nname = \"b\"\nheight_m = 0.03\n[grading]\nuniform = [1.0, 1.5]\n";
    fs::write(dir.join("w.toml"), config).unwrap();
    let out = gapack(&dir, &["compare", "w.toml"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(
        stderr(&out).trim_end(),
        "error: w.toml:4:3: fracture.extent: the compare job packs one scene whole with every generator and grows no windows, so with fracture.extent = \"window\" it would pack all 0.02 m of well \"a\" (and none of the other 1 of fracture.wells) instead of a window; set fracture.extent = \"full\" to compare on the whole fracture, or give a [domain] the size of a window (its first is 16·d_max = 24 mm long) to compare on one"
    );
}

#[test]
fn verify_names_the_pair_by_file_line_whatever_the_line_ends() {
    let dir = scratch("round3_verify_line_ends");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    // A comment, the header, disk 3, a blank line, disks 12 and 40
    // overlapping: lines 5 and 6 in every form.
    for (sep, name) in [
        (",", "csv"),
        (";", "semicolons"),
        ("\t", "tabs"),
        (" ", "blanks"),
    ] {
        let lf = format!(
            "# by hand\nid{sep}x{sep}y{sep}r\n3{sep}1{sep}1{sep}0.5\n\n12{sep}5{sep}5{sep}0.5\n40{sep}5.9{sep}5{sep}0.5\n"
        );
        for (end, ends) in [("\n", "lf"), ("\r\n", "crlf"), ("\r", "cr")] {
            let file = format!("{name}-{ends}.txt");
            fs::write(dir.join(&file), lf.replace('\n', end)).unwrap();
            let out = gapack(&dir, &["verify", &file, "--config", "sq.toml", "--quiet"]);
            assert_eq!(out.status.code(), Some(1), "{file}");
            let err = stderr(&out);
            assert!(
                err.contains(&format!(
                    "{file}: the packing is not valid: overlap: disks 12 and 40 (lines 5 and 6) overlap by 1.0e-1 of their radii sum"
                )),
                "{file}: {err}"
            );
        }
    }
}
