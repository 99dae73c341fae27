//! TOML syntax, unknown keys, types and missing keys; fixed-shape arrays, tables
//! written as arrays of tables, and where a key is located.

use super::*;

#[test]
fn syntax_error_names_line_column_and_key() {
    let e = err(&rect("width = 2e\nheight = 3", ""));
    assert!(matches!(e, ConfigError::Syntax { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.width"));
    assert_eq!((e.location().line, e.location().column), (3, 11));
    assert!(
        e.to_string()
            .starts_with("t.toml:3:11: domain.width: TOML syntax error: "),
        "{e}"
    );
}

#[test]
fn duplicate_key_is_a_syntax_error() {
    let e = err(&rect("width = 2\nwidth = 3\nheight = 3", ""));
    assert!(matches!(e, ConfigError::Syntax { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.width"));
    assert_eq!(e.location().line, 4);
}

#[test]
fn unknown_key_is_named_with_the_valid_ones() {
    let e = err(&rect("widht = 20\nheight = 30", ""));
    assert_eq!(e.key(), Some("domain.widht"));
    let message = e.to_string();
    assert!(
        message.starts_with(
            "t.toml:3:1: domain.widht: unknown key `widht`, expected one of `shape`, `width`"
        ),
        "{message}"
    );
}

#[test]
fn unknown_table_is_named() {
    let e = err(&rect("width = 20\nheight = 30", "[bogus]\nx = 1\n"));
    assert_eq!(e.key(), Some("bogus"));
    assert_eq!((e.location().line, e.location().column), (7, 2));
}

#[test]
fn unknown_key_in_inline_table_and_other_tables() {
    let e =
        err("domain = { shape = \"circle\", radius = 5, colour = 1 }\n[grading]\nconstant = 1\n");
    assert_eq!(e.key(), Some("domain.colour"));
    let e = err(&rect(
        "width = 20\nheight = 30",
        "[limits]\nmax_memory = 10\n",
    ));
    assert_eq!(e.key(), Some("limits.max_memory"));
    let e = err(&rect("width = 20\nheight = 30", "[packer]\ncontact = 2\n"));
    assert_eq!(e.key(), Some("packer.contact"));
    let e = err(&rect("width = 20\nheight = 30", "interpolaton = \"log\"\n"));
    assert_eq!(e.key(), Some("grading.interpolaton"));
}

#[test]
fn wrong_type_names_key_and_position() {
    fails_with(
        &rect("width = \"20\"\nheight = 30", ""),
        "t.toml:3:9: domain.width: invalid type: string \"20\", expected a number",
    );
    let e = err(&rect(
        "width = 20\nheight = 30",
        "[packer]\ncontacts = \"two\"\n",
    ));
    assert_eq!(e.key(), Some("packer.contacts"));
    assert_eq!(e.location().line, 8);
    let e = err("seed = -1\n");
    assert_eq!(e.key(), Some("seed"));
    assert!(
        e.to_string().contains("expected a whole number >= 0"),
        "{e}"
    );
    let e = err("domain = 5\n");
    assert_eq!(e.key(), Some("domain"));
    assert!(e.to_string().contains("expected a table"), "{e}");
}

#[test]
fn wrong_array_shapes_name_the_element() {
    let e = err(
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [1], [0, 1]]\n[grading]\nconstant = 1\n",
    );
    assert_eq!(e.key(), Some("domain.vertices[1]"));
    assert_eq!((e.location().line, e.location().column), (3, 21));
    let e = err(&rect("width = 20\nheight = 30", "")
        .replace("constant = 1.2", "table = [[1, 0], [2, \"x\"]]"));
    assert_eq!(e.key(), Some("grading.table[1][1]"));
}

#[test]
fn missing_tables_and_keys_are_named() {
    fails_with(
        "",
        "t.toml:1:1: domain: missing table [domain] (or [fracture])",
    );
    fails_with(
        "seed = 3\n[grading]\nconstant = 1\n",
        "t.toml:1:1: domain: missing table [domain] (or [fracture])",
    );
    fails_with(
        "[domain]\nwidth = 20\n[grading]\nconstant = 1\n",
        "t.toml:1:1: domain.shape: missing key",
    );
    fails_with(
        "seed = 1\n\n[domain]\nshape = \"circle\"\nradius = 3\n",
        "t.toml:1:1: grading: missing table [grading]",
    );
}

/// A polygon config with `vertices` as written.
fn polygon(vertices: &str) -> String {
    format!("[domain]\nshape = \"polygon\"\nvertices = {vertices}\n[grading]\nconstant = 1\n")
}

#[test]
fn fixed_length_arrays_with_extra_elements_are_refused_not_cut() {
    // Each of these was read as its first elements, the rest dropped unread.
    fails_with(
        &polygon("[[0, 0], [10, 0, \"junk\", [1, 2]], [10, 10], [0, 10]]"),
        "t.toml:3:21: domain.vertices[1]: invalid length 4, expected an array of 2 numbers",
    );
    fails_with(
        "[domain]\nshape = \"circle\"\nradius = 10\ncenter = [0, 0, 5]\n[grading]\nconstant = 1\n",
        "t.toml:4:10: domain.center: invalid length 3, expected an array of 2 numbers",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "").replace("constant = 1.2", "uniform = [1, 2, 3]"),
        "t.toml:6:11: grading.uniform: invalid length 3, expected an array of 2 numbers",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "")
            .replace("constant = 1.2", "table = [[1, 0], [2, 100, 7]]"),
        "t.toml:6:18: grading.table[1]: invalid length 3, expected an array of 2 numbers",
    );
    // A material's own grading goes through the same type.
    let text = "[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n\
                [[materials]]\nname = \"a\"\n[materials.grading]\nuniform = [1, 2, 3]\n";
    assert_eq!(err(text).key(), Some("materials[0].grading.uniform"));
}

#[test]
fn fixed_length_arrays_check_every_element_type_and_short_arrays() {
    let e = err(&polygon("[[0, 0], [10, \"junk\"], [10, 10]]"));
    assert_eq!(e.key(), Some("domain.vertices[1][1]"));
    assert!(
        e.to_string().contains("invalid type: string \"junk\""),
        "{e}"
    );
    fails_with(
        &polygon("[[0, 0], [10], [10, 10]]"),
        "t.toml:3:21: domain.vertices[1]: invalid length 1, expected an array of 2 numbers",
    );
    let e = err(&polygon("[[0, 0], 5, [10, 10]]"));
    assert_eq!(e.key(), Some("domain.vertices[1]"));
    assert!(
        e.to_string()
            .contains("invalid type: integer `5`, expected an array of 2 numbers"),
        "{e}"
    );
}

#[test]
fn a_table_written_as_an_array_of_tables_is_named() {
    // Serde filled the struct's fields by position: "domain[0]: invalid type:
    // table, expected a string".
    fails_with(
        "[[domain]]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1\n",
        "t.toml:1:1: domain: must be a table, not an array of tables: write [domain], not [[domain]]",
    );
    let e = err(&rect(
        "width = 20\nheight = 30",
        "[[packer]]\nmethod = \"rsa\"\n",
    ));
    assert_eq!(e.key(), Some("packer"));
    assert!(
        e.to_string().contains("write [packer], not [[packer]]"),
        "{e}"
    );
    // An array of values where a table belongs: no longer read by position
    // (this was a well named "a", 1 mm wide).
    let e = err("[fracture]\nheight_m = 0.05\nwells = [[\"a\", 1.0]]\n[grading]\nconstant = 0.2\n");
    assert_eq!(e.key(), Some("fracture.wells[0]"));
    assert!(
        e.to_string().ends_with("must be a table, not an array"),
        "{e}"
    );
}

#[test]
fn a_key_is_located_where_it_is_written() {
    let text = "seed = 1\n[output]\nformats = [\"csv\"]\n  dir = \"x\"\n";
    let at = super::key_location(text, "t.toml", "output.dir").expect("found");
    assert_eq!(at.to_string(), "t.toml:4:3");
    let dotted = "output.dir = \"x\"\n";
    let at = super::key_location(dotted, "t.toml", "output.dir").expect("found");
    assert_eq!(at.to_string(), "t.toml:1:8");
    assert_eq!(super::key_location(text, "t.toml", "output.density"), None);
    assert_eq!(
        super::key_location("[output\n", "t.toml", "output.dir"),
        None
    );
}

#[test]
fn a_date_is_named_as_a_date_not_a_table() {
    fails_with(
        &rect("width = 20\nheight = 30", "[packer]\ngap = 1979-05-27\n"),
        "t.toml:8:7: packer.gap: invalid type: date-time, expected a number",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[[materials]]\nname = \"a\"\nshape = 1979-05-27\n",
        ),
        "t.toml:9:9: materials[0].shape: invalid type: date-time, expected a table",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[shape]\nkind = \"superellipse\"\naspect = 1979-05-27\n",
        ),
        "t.toml:9:10: shape.aspect: invalid type: date-time, expected a table",
    );
}

/// The line and column of the error `text` gives, and its message.
fn place(text: &str) -> (usize, usize, String) {
    let e = err(text);
    assert!(matches!(e, ConfigError::Syntax { .. }), "{e}");
    (e.location().line, e.location().column, e.to_string())
}

#[test]
fn nesting_too_deep_is_placed_at_its_line() {
    let rest = "[packer]\ngap = 0.1\n\n";
    let keys = vec!["a"; 200].join(".");
    // A dotted key, and a table header, of 200 parts.
    for (line, column) in [(format!("{keys} = 1"), 1), (format!("[{keys}]"), 2)] {
        let (l, c, said) = place(&rect("width = 20\nheight = 30", &format!("{rest}{line}\n")));
        assert_eq!((l, c), (10, column), "{said}");
        assert!(said.contains("recursion limit"), "{said}");
    }
    // Arrays and inline tables nested 300 deep, on one line and on many.
    let arrays = format!("x = {}{}", "[".repeat(300), "]".repeat(300));
    let tables = format!("x = {}1{}", "{ a = ".repeat(300), " }".repeat(300));
    let lines = format!("x = {}{}", "[\n".repeat(300), "]\n".repeat(300));
    for (value, line) in [(arrays, 10), (tables, 10), (lines, 90)] {
        let (l, _, said) = place(&rect(
            "width = 20\nheight = 30",
            &format!("{rest}{value}\n"),
        ));
        assert_eq!(l, line, "{said}");
        assert!(said.contains("recursion"), "{said}");
        assert!(
            said.len() < 200,
            "the key path is not 80 levels deep: {said}"
        );
    }
}
