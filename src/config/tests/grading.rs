//! `[grading]`: one curve, its keys and values, the constructor's refusals.

use super::*;

#[test]
fn grading_needs_exactly_one_curve() {
    fails_with(
        &rect("width = 20\nheight = 30", "").replace("constant = 1.2\n", "basis = \"mass\"\n"),
        "t.toml:5:1: grading.table: missing; [grading] needs exactly one of table, uniform, constant, preset",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "uniform = [1, 2]\n"),
        "t.toml:7:11: grading.uniform: give only one of table, uniform, constant, preset (`constant` is given too)",
    );
}

#[test]
fn curve_keys_that_do_not_apply() {
    fails_with(
        &rect("width = 20\nheight = 30", "interpolation = \"log\"\n"),
        "t.toml:7:17: grading.interpolation: applies only to a table or a preset",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "basis = \"mass\"\n"),
        "t.toml:7:9: grading.basis: does not apply to a constant size",
    );
}

#[test]
fn unknown_grading_names_list_the_valid_ones() {
    let table = |extra: &str| {
        rect("width = 20\nheight = 30", "").replace(
            "constant = 1.2\n",
            &format!("table = [[1, 0], [2, 100]]\n{extra}\n"),
        )
    };
    fails_with(
        &table("interpolation = \"cubic\""),
        "t.toml:7:17: grading.interpolation: unknown interpolation \"cubic\"; valid: log, linear",
    );
    fails_with(
        &table("basis = \"volume\""),
        "t.toml:7:9: grading.basis: unknown basis \"volume\"; valid: number, mass, mass3d",
    );
}

#[test]
fn bad_grading_values_are_refused() {
    let with = |curve: &str| rect("width = 20\nheight = 30", "").replace("constant = 1.2", curve);
    fails_with(
        &with("constant = -1.2"),
        "t.toml:6:12: grading.constant: must be a positive finite number, got -1.2",
    );
    fails_with(
        &with("uniform = [1.2, inf]"),
        "t.toml:6:11: grading.uniform: must be a positive finite number, got inf",
    );
    fails_with(
        &with("table = [[1.2, 0], [nan, 100]]"),
        "t.toml:6:20: grading.table[1]: must be a finite number, got NaN",
    );
}

#[test]
fn builds_decreasing_table_refused() {
    let e = err(&rect("width = 20\nheight = 30", "").replace(
        "constant = 1.2",
        "table = [[1.2, 0], [1.1, 50], [1.3, 100]]",
    ));
    assert!(matches!(e, ConfigError::Grading { .. }), "{e}");
    assert_eq!(e.key(), Some("grading.table"));
    assert_eq!((e.location().line, e.location().column), (6, 9));
}

#[test]
fn builds_table_not_ending_at_100_refused() {
    let e = err(&rect("width = 20\nheight = 30", "")
        .replace("constant = 1.2", "table = [[1.2, 0], [1.3, 90]]"));
    assert!(matches!(e, ConfigError::Grading { .. }), "{e}");
    assert_eq!(e.key(), Some("grading.table"));
}

#[test]
fn builds_unknown_preset_refused() {
    let e =
        err(&rect("width = 20\nheight = 30", "").replace("constant = 1.2", "preset = \"7/11\""));
    assert!(matches!(e, ConfigError::Grading { .. }), "{e}");
    assert_eq!(e.key(), Some("grading.preset"));
    assert_eq!((e.location().line, e.location().column), (6, 10));
}

#[test]
fn sizes_that_dwarf_the_domain_blame_the_grading_and_name_millimetres() {
    let text = "[domain]\nshape = \"rectangle\"\nwidth = 50\nheight = 50\n[grading]\ntable = [[425, 0], [850, 100]]\n";
    let message = parse(text, "t.toml").unwrap_err().to_string();
    assert!(
        message.starts_with("t.toml:6:9: grading.table: the domain is too narrow"),
        "{message}"
    );
    assert!(
        message.contains("8.5 times") && message.contains("millimetres"),
        "{message}"
    );
    // A near miss is still the domain's.
    let slot =
        "[domain]\nshape = \"rectangle\"\nwidth = 2.3\nheight = 50\n[grading]\nconstant = 2.5\n";
    let message = parse(slot, "t.toml").unwrap_err().to_string();
    assert!(
        message.starts_with("t.toml:3:9: domain.width: the domain is too narrow"),
        "{message}"
    );
}
