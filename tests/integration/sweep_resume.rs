//! `gapack sweep --resume` over a `sweep.csv` whose finished rows were
//! edited to values no run gives: those runs are run again, with a
//! warning naming each, and the table written holds no impossible value.

use crate::common;

use std::fs;

use common::{gapack, records, scratch};

/// A small rectangle packed at three gaps, one seed each.
const STUDY: &str = "seed = 3
[domain]
shape = \"rectangle\"
width = 12
height = 12
[grading]
uniform = [0.8, 1.2]
[packer]
gap = 0.0
[sweep]
\"packer.gap\" = [0.0, 0.05, 0.1]
";

/// `records` without the column `name`.
fn without(records: &[Vec<String>], name: &str) -> Vec<Vec<String>> {
    let at = records[0].iter().position(|h| h == name).expect("a column");
    records
        .iter()
        .map(|r| {
            let mut r = r.clone();
            r.remove(at);
            r
        })
        .collect()
}

#[test]
fn rows_edited_to_impossible_values_are_run_again() {
    let dir = scratch("sweep-impossible-rows");
    fs::write(dir.join("s.toml"), STUDY).unwrap();
    let first = gapack(&dir, &["sweep", "s.toml", "--out", "out", "--quiet"]);
    assert!(first.status.success(), "{first:?}");
    let table = dir.join("out/sweep.csv");
    let whole = records(&table);
    assert_eq!(whole.len(), 4, "a header and three runs: {whole:?}");
    let column = |name: &str| whole[0].iter().position(|h| h == name).unwrap();
    let (porosity, psd_ks) = (column("porosity"), column("psd_ks"));
    assert!(whole[1..].iter().all(|r| r[column("status")] == "finished"));

    // The second run's porosity -7, the third's KS distance NaN.
    let mut edited = whole.clone();
    edited[2][porosity] = "-7".to_owned();
    edited[3][psd_ks] = "NaN".to_owned();
    let mut writer = csv::Writer::from_path(&table).unwrap();
    for r in &edited {
        writer.write_record(r).unwrap();
    }
    writer.flush().unwrap();
    drop(writer);

    let out = gapack(&dir, &["sweep", "s.toml", "--out", "out", "--resume"]);
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{said}");
    for (run, why) in [
        (&whole[2][0], "porosity -7, outside [0, 1]"),
        (&whole[3][0], "psd_ks NaN, outside [0, 1]"),
    ] {
        assert!(
            said.contains(&format!("the finished row of run {run} has {why}")),
            "no warning for {run}: {said}"
        );
    }
    assert!(
        said.contains("(1 kept from the earlier sweep.csv)"),
        "{said}"
    );

    // The runs run again give their own values back; none is impossible.
    let again = records(&table);
    assert_eq!(without(&again, "seconds"), without(&whole, "seconds"));
    for r in &again[1..] {
        for at in [porosity, psd_ks] {
            let v: f64 = r[at].parse().expect("a number");
            assert!((0.0..=1.0).contains(&v), "{r:?}");
        }
    }
    let _ = fs::remove_dir_all(&dir);
}
