//! `[fracture]`: the names of a batch's wells.

use super::*;

/// A batch of wells named `names`, 2 mm × 0.05 m each.
fn batch(names: &[&str]) -> String {
    let mut text = "[fracture]\nwidth_mm = 2\nheight_m = 0.05\n".to_owned();
    for name in names {
        text.push_str(&format!("[[fracture.wells]]\nname = {name:?}\n"));
    }
    text + "[grading]\nconstant = 0.5\n"
}

#[test]
fn well_names_that_are_the_batch_files_are_refused() {
    assert!(parse(&batch(&["north", "south"]), "t.toml").is_ok());
    fails_with(
        &batch(&["north", "wells.csv"]),
        "t.toml:7:8: fracture.wells[1].name: \"wells.csv\" would be a folder named like the \
         batch's own wells.csv beside the wells' folders; reserved: wells.csv, manifest.json, \
         checkpoint.json",
    );
    for name in [
        "manifest.json",
        "Manifest.JSON",
        "WELLS.csv",
        "checkpoint.json",
    ] {
        let e = err(&batch(&[name]));
        assert_eq!(e.key(), Some("fracture.wells[0].name"), "{name}");
        assert!(e.to_string().contains("reserved: "), "{name}: {e}");
    }
}

#[test]
fn well_names_that_collide_even_by_case_are_refused() {
    fails_with(
        &batch(&["North", "south", "north"]),
        "t.toml:9:8: fracture.wells[2].name: \"north\" and \"North\" (fracture.wells[0].name) \
         differ only in case: one folder on a case-insensitive file system; give each well a \
         distinct name",
    );
    fails_with(
        &batch(&["a", "a"]),
        "t.toml:7:8: fracture.wells[1].name: \"a\" is given twice (fracture.wells[0].name): \
         each well needs its own folder",
    );
    // Surrounding spaces are trimmed before the comparison.
    assert_eq!(
        err(&batch(&["a", " A "])).key(),
        Some("fracture.wells[1].name")
    );
}
