//! `gapack verify` on hand-written faulty tables: its error names the
//! deepest overlapping pair (and the disk farthest outside) by `id` and by
//! file line, so that `--quiet` runs and logs that keep only the error
//! still say where to look.

use crate::common;

use std::fs;

use common::{gapack, scratch};

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

const SQUARE: &str =
    "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nuniform = [0.8, 1.2]\n";

#[test]
fn the_error_names_the_deepest_pair_by_id_and_line() {
    let dir = scratch("verify_r3_pair");
    fs::write(dir.join("sq.toml"), SQUARE).unwrap();
    // Ids out of file order: 12 and 40 overlap by 0.1 of their radii sum,
    // 7 and 9 by 0.05; disk 3 is apart from all.
    fs::write(
        dir.join("bad.csv"),
        "id,x,y,r\n3,1,1,0.5\n7,3,8,0.5\n12,5,5,0.5\n9,3.95,8,0.5\n40,5.9,5,0.5\n",
    )
    .unwrap();
    let out = gapack(
        &dir,
        &["verify", "bad.csv", "--config", "sq.toml", "--quiet"],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains(
            "overlap: disks 12 and 40 (lines 4 and 6) overlap by 1.0e-1 of their radii sum (the deepest of 2 overlapping pairs)"
        ),
        "{err}"
    );
    assert!(!err.contains("outside"), "{err}");

    // Without an id column: the lines alone; a disk outside named too.
    fs::write(
        dir.join("plain.csv"),
        "x,y,r\n1,1,0.5\n5,5,0.5\n5.9,5,0.5\n9.8,2,0.5\n",
    )
    .unwrap();
    let out = gapack(&dir, &["verify", "plain.csv", "--config", "sq.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains(
            "overlap: the disks on lines 3 and 4 overlap by 1.0e-1 of their radii sum; outside: the disk on line 5: it reaches 3.0e-1 mm outside the domain"
        ),
        "{err}"
    );
}
