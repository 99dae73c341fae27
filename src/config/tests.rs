//! Tests of config parsing and validation: one per rule, checking the whole
//! one-line message (origin, line, column, key path, reason).
//!
//! The tests marked "builds" call the `Domain`/`Grading` constructors and the
//! scene checks; the others fail before any of them is called.

use super::*;
use crate::geometry::{Point, Shape, WallMode};
use crate::grading::Basis;
use crate::packer::{FrontRules, IndexKind};

/// The error `text` gives; fails the test if it parses.
fn err(text: &str) -> ConfigError {
    match parse(text, "t.toml") {
        Err(e) => e,
        Ok(scene) => panic!("accepted:\n{text}\nas {scene:?}"),
    }
}

/// Asserts the full message of the error `text` gives.
fn fails_with(text: &str, message: &str) {
    assert_eq!(err(text).to_string(), message, "for:\n{text}");
}

/// A rectangle scene with `domain` lines and `rest` appended after the grading.
fn rect(domain: &str, rest: &str) -> String {
    format!("[domain]\nshape = \"rectangle\"\n{domain}\n[grading]\nconstant = 1.2\n{rest}")
}

// ---- TOML syntax, unknown keys, types, missing keys -------------------------

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

// ---- Domain values ----------------------------------------------------------

#[test]
fn bad_sizes_are_refused_with_the_value() {
    let text = "seed = 7\n[domain]\nshape = \"rectangle\"\nwidth = -1\nheight = 30\n[grading]\nconstant = 1.2\n";
    fails_with(
        text,
        "t.toml:4:9: domain.width: must be a positive finite number, got -1",
    );
    for (value, shown) in [
        ("0", "0"),
        ("-0.0", "-0"),
        ("nan", "NaN"),
        ("inf", "inf"),
        ("-inf", "-inf"),
        ("+nan", "NaN"),
    ] {
        fails_with(
            &rect(&format!("width = 20\nheight = {value}"), ""),
            &format!("t.toml:4:10: domain.height: must be a positive finite number, got {shown}"),
        );
    }
    let circle = "[domain]\nshape = \"circle\"\nradius = nan\n[grading]\nconstant = 1\n";
    fails_with(
        circle,
        "t.toml:3:10: domain.radius: must be a positive finite number, got NaN",
    );
    let trapezoid = "[domain]\nshape = \"trapezoid\"\nbottom = 20\ntop = 0\nheight = 5\n[grading]\nconstant = 1\n";
    fails_with(
        trapezoid,
        "t.toml:4:7: domain.top: must be a positive finite number, got 0",
    );
}

#[test]
fn missing_domain_size_is_named() {
    fails_with(
        &rect("width = 20", ""),
        "t.toml:2:9: domain.height: missing; shape \"rectangle\" needs width, height",
    );
    fails_with(
        "[domain]\nshape = \"circle\"\n[grading]\nconstant = 1\n",
        "t.toml:2:9: domain.radius: missing; shape \"circle\" needs radius",
    );
    fails_with(
        "[domain]\nshape = \"polygon\"\n[grading]\nconstant = 1\n",
        "t.toml:2:9: domain.vertices: missing; shape \"polygon\" needs vertices = [[x, y], ...]",
    );
    fails_with(
        "[domain]\nshape = \"trapezoid\"\nbottom = 2\nheight = 3\n[grading]\nconstant = 1\n",
        "t.toml:2:9: domain.top: missing; shape \"trapezoid\" needs bottom, top, height",
    );
}

#[test]
fn key_of_another_shape_is_refused() {
    fails_with(
        &rect("width = 20\nheight = 30\nradius = 5", ""),
        "t.toml:5:10: domain.radius: not a key of shape \"rectangle\", which takes width, height",
    );
    // The first stray key in the file is named, whatever the field order.
    let e = err(
        "[domain]\nshape = \"circle\"\ntop = 3\nradius = 5\nwidth = 2\n[grading]\nconstant = 1\n",
    );
    assert_eq!(e.key(), Some("domain.top"));
    assert!(e.to_string().ends_with("which takes radius, center"), "{e}");
    let e = err(&rect("width = 20\nheight = 30\ncenter = [0, 0]", ""));
    assert_eq!(e.key(), Some("domain.center"));
}

#[test]
fn unknown_shape_lists_the_valid_ones() {
    fails_with(
        "[domain]\nshape = \"hexagon\"\n[grading]\nconstant = 1\n",
        "t.toml:2:9: domain.shape: unknown shape \"hexagon\"; valid: rectangle, polygon, circle, trapezoid",
    );
}

#[test]
fn walls_and_wall_disk() {
    fails_with(
        &rect("width = 20\nheight = 30\nwalls = \"soft\"", ""),
        "t.toml:5:9: domain.walls: unknown wall model \"soft\"; valid: exact, disks, periodic",
    );
    fails_with(
        &rect("width = 20\nheight = 30\nwall_disk = 1", ""),
        "t.toml:5:13: domain.wall_disk: applies only with walls = \"disks\"",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30\nwalls = \"disks\"\nwall_disk = -2",
            "",
        ),
        "t.toml:6:13: domain.wall_disk: must be a positive finite number, got -2",
    );
}

#[test]
fn periodic_walls_make_a_rectangle_a_periodic_cell() {
    let scene = parse(
        &rect("width = 20\nheight = 30\nwalls = \"periodic\"", ""),
        "t",
    )
    .expect("valid config")
    .scene;
    assert_eq!(scene.walls, WallMode::Periodic);
    let period = scene.domain.period().expect("a periodic cell");
    assert_eq!((period.x, period.y), (20.0, 30.0));
    // Any other wall model keeps the rectangle's walls.
    let walled = parse(&rect("width = 20\nheight = 30", ""), "t").expect("valid");
    assert!(!walled.scene.domain.is_periodic());
    // Its default [compare] leaves out deposition, which needs a floor.
    let methods = parse(
        &rect("width = 20\nheight = 30\nwalls = \"periodic\"", ""),
        "t",
    )
    .expect("valid")
    .compare
    .methods;
    assert!(!methods.contains(&crate::packer::Method::Deposition));
    assert!(methods.contains(&crate::packer::Method::Rsa));
}

#[test]
fn periodic_walls_are_refused_where_they_make_no_cell() {
    fails_with(
        "[domain]\nshape = \"circle\"\nradius = 10\nwalls = \"periodic\"\n[grading]\nconstant = 1\n",
        "t.toml:4:9: domain.walls: \"periodic\" needs shape = \"rectangle\" (only a rectangle tiles the plane as a periodic cell); shape \"circle\" has walls: use walls = \"exact\" or \"disks\"",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30\nwalls = \"periodic\"\nwall_disk = 0.1",
            "",
        ),
        "t.toml:6:13: domain.wall_disk: applies only with walls = \"disks\"",
    );
    // A disk could touch another and its image at once.
    fails_with(
        &rect("width = 2\nheight = 30\nwalls = \"periodic\"", ""),
        "t.toml:3:9: domain.width: the periodic cell's shorter side, 2 mm, is less than twice the largest diameter (1.2 mm): a disk could then touch another disk and its image at once, or its own image; pack a larger cell or smaller disks",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30\nwalls = \"periodic\"",
            "[packer]\nmethod = \"deposition\"\n",
        ),
        "t.toml:9:10: packer.method: \"deposition\" packs against walls and does not pack periodic cells (domain.walls = \"periodic\"); use \"advancing-front\", \"rsa\", \"relaxation\" or \"densify\"",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30\nwalls = \"periodic\"",
            "[compare]\nmethods = [\"rsa\", \"deposition\"]\n",
        ),
        "t.toml:9:19: compare.methods[1]: \"deposition\" packs against walls and does not pack periodic cells (domain.walls = \"periodic\"); leave it out",
    );
    fails_with(
        "[fracture]\nwidth_mm = 2\nheight_m = 0.01\nwalls = \"periodic\"\n[grading]\nconstant = 0.5\n",
        "t.toml:4:9: fracture.walls: a fracture is bounded by its faces, not a periodic cell; for a bulk sample without walls give a [domain] rectangle with walls = \"periodic\"",
    );
}

#[test]
fn non_finite_coordinates_are_refused() {
    fails_with(
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [nan, 0], [0, 1]]\n[grading]\nconstant = 1\n",
        "t.toml:3:21: domain.vertices[1]: must be a finite number, got NaN",
    );
    fails_with(
        "[domain]\nshape = \"circle\"\nradius = 4\ncenter = [0, inf]\n[grading]\nconstant = 1\n",
        "t.toml:4:10: domain.center: must be a finite number, got inf",
    );
}

// ---- Grading values ---------------------------------------------------------

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

// ---- Packer and limits --------------------------------------------------------

#[test]
fn unknown_packer_names_list_the_valid_ones() {
    let packer = |line: &str| rect("width = 20\nheight = 30", &format!("[packer]\n{line}\n"));
    fails_with(
        &packer("method = \"drop-and-roll\""),
        "t.toml:8:10: packer.method: unknown method \"drop-and-roll\"; valid: advancing-front, rsa, deposition, relaxation, densify",
    );
    fails_with(
        &packer("attempts = 0"),
        "t.toml:8:12: packer.attempts: must be a whole number in [1, 10000000], got 0",
    );
    fails_with(
        &packer("relaxation_iterations = 100000000"),
        "t.toml:8:25: packer.relaxation_iterations: must be a whole number in [1, 1000000], got 100000000",
    );
    fails_with(
        &packer("relaxation_porosity = 1.0"),
        "t.toml:8:23: packer.relaxation_porosity: must be in [0, 1), got 1",
    );
    fails_with(
        &packer("densify_porosity = -0.1"),
        "t.toml:8:20: packer.densify_porosity: must be in [0, 1), got -0.1",
    );
    fails_with(
        &packer("densify_iterations = 0"),
        "t.toml:8:22: packer.densify_iterations: must be a whole number in [1, 1000000], got 0",
    );
    fails_with(
        &packer("densify_porosity = \"0.17\""),
        "t.toml:8:20: packer.densify_porosity: invalid type: string \"0.17\", expected a number",
    );
    fails_with(
        &format!(
            "{}[optimise]\ntarget_porosity = 0.3\n",
            packer("method = \"rsa\"")
        ),
        "t.toml:8:10: packer.method: the genetic algorithm packs with the advancing front; [optimise] needs method = \"advancing-front\"",
    );
    fails_with(
        &packer("index = \"kd-tree\""),
        "t.toml:8:9: packer.index: unknown index \"kd-tree\"; valid: mx-quadtree, grid",
    );
    fails_with(
        &packer("contacts = 3"),
        "t.toml:8:12: packer.contacts: unknown contact count \"3\"; valid: 2, 1",
    );
    fails_with(
        &packer("one_contact_share = 1.5"),
        "t.toml:8:21: packer.one_contact_share: must be in [0, 1], got 1.5",
    );
    fails_with(
        &packer("contacts = 1\none_contact_share = 0.5"),
        "t.toml:9:21: packer.one_contact_share: give packer.contacts or packer.one_contact_share, not both",
    );
    fails_with(
        &packer("gap = -0.1"),
        "t.toml:8:7: packer.gap: must be in [0, 1], got -0.1",
    );
    fails_with(
        &packer("gap = nan"),
        "t.toml:8:7: packer.gap: must be in [0, 1], got NaN",
    );
    fails_with(
        &packer("rules = \"strict\""),
        "t.toml:8:9: packer.rules: unknown front rules \"strict\"; valid: robust, thesis",
    );
}

#[test]
fn memory_limit_must_be_positive() {
    fails_with(
        &rect("width = 20\nheight = 30", "[limits]\nmax_memory_mb = 0\n"),
        "t.toml:8:17: limits.max_memory_mb: must be a positive finite number, got 0",
    );
}

// ---- Builds: these call the Domain and Grading constructors ------------------

#[test]
fn builds_default_config() {
    let scene = parse(DEFAULT_CONFIG, DEFAULT_ORIGIN)
        .expect("the default config parses")
        .scene;
    assert_eq!(
        scene.domain.shape(),
        &Shape::Rectangle {
            width: 62.5,
            height: 8.6
        }
    );
    assert_eq!(scene.walls, WallMode::Exact);
    assert_eq!(scene.wall_disk_diameter, None);
    assert_eq!(scene.seed, 0);
    assert_eq!(scene.grading.d_min(), 1.2);
    assert_eq!(scene.grading.d_max(), 1.295);
    assert_eq!(scene.grading.basis(), Basis::Number);
    assert_eq!(scene.packer, crate::packer::PackerSettings::default());
}

#[test]
fn builds_with_integers_for_floats_and_all_settings() {
    let text = "seed = 7\n[domain]\nshape = \"polygon\"\nvertices = [[0,0],[20,0],[20,8],[8,8],[8,20],[0,20]]\nwalls = \"disks\"\nwall_disk = 1\n\
                [grading]\nuniform = [1, 2]\nbasis = \"mass3d\"\n\
                [packer]\nmethod = \"advancing-front\"\nindex = \"grid\"\ncontacts = 1\nrules = \"thesis\"\n\
                [limits]\nmax_memory_mb = 100\n";
    let scene = parse(text, "t.toml").expect("valid config").scene;
    assert_eq!(scene.seed, 7);
    assert_eq!(scene.walls, WallMode::Disks);
    assert_eq!(scene.wall_disk_diameter, Some(1.0));
    assert_eq!(scene.grading.basis(), Basis::Mass3d);
    assert_eq!(scene.packer.index, IndexKind::Grid);
    assert_eq!(scene.packer.one_contact_share, 1.0);
    assert_eq!(scene.packer.rules, FrontRules::Thesis);
    assert!((scene.domain.area() - 256.0).abs() < 1e-9);
}

#[test]
fn builds_circle_with_default_center() {
    let scene = parse(
        "[domain]\nshape = \"circle\"\nradius = 10\n[grading]\nconstant = 1\n",
        "t",
    )
    .expect("valid config")
    .scene;
    assert_eq!(
        scene.domain.shape(),
        &Shape::Circle {
            center: Point::new(0.0, 0.0),
            radius: 10.0
        }
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
fn builds_polygon_with_two_vertices_refused() {
    let e = err(
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 0]]\n[grading]\nconstant = 1\n",
    );
    assert!(matches!(e, ConfigError::Geometry { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.vertices"));
    assert_eq!(e.location().line, 3);
}

#[test]
fn builds_self_crossing_polygon_refused() {
    let e = err(
        "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 10], [10, 0], [0, 10]]\n[grading]\nconstant = 1\n",
    );
    assert!(
        matches!(
            e,
            ConfigError::Geometry {
                error: crate::geometry::GeometryError::SelfIntersecting { .. },
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(e.key(), Some("domain.vertices"));
    assert_eq!(e.location().line, 3);
}

#[test]
fn builds_domain_narrower_than_smallest_disk_refused() {
    let e = err(&rect("width = 1\nheight = 30", ""));
    let message = e.to_string();
    assert!(matches!(e, ConfigError::Scene { .. }), "{e}");
    assert!(
        message.starts_with("t.toml:3:9: domain.width: the domain is too narrow"),
        "{message}"
    );
    assert!(
        message.contains("1.0000 mm") && message.contains("1.2000 mm"),
        "{message}"
    );
    let e = err("[domain]\nshape = \"circle\"\nradius = 0.5\n[grading]\nconstant = 1.2\n");
    assert_eq!(e.key(), Some("domain.radius"));
}

#[test]
fn builds_scene_over_the_memory_limit_refused() {
    let big = rect(
        "width = 10000\nheight = 10000",
        "[limits]\nmax_particles = 10000000000\n",
    )
    .replace("constant = 1.2", "constant = 0.2");
    let e = err(&big);
    let message = e.to_string();
    assert!(matches!(e, ConfigError::Scene { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.width"));
    assert!(message.contains("over the limit of 4096 MB"), "{message}");
    assert!(message.contains("limits.max_memory_mb"), "{message}");
    assert!(
        message.ends_with("or run with --force to go ahead"),
        "{message}"
    );
    let forced = parse_with(&big, "t", ParseOptions { force: true });
    assert!(forced.is_ok(), "{forced:?}");
    // The same scene with a small explicit limit blames the limit.
    let e = err(&rect(
        "width = 100\nheight = 100",
        "[limits]\nmax_memory_mb = 0.001\n",
    ));
    assert_eq!(e.key(), Some("limits.max_memory_mb"));
    assert_eq!(e.location().line, 8);
    // And a limit high enough lets it through.
    let ok = big.replace("[limits]\n", "[limits]\nmax_memory_mb = 1e9\n");
    assert!(parse(&ok, "t").is_ok());
}

#[test]
fn builds_scene_too_fine_for_its_coordinates_refused() {
    // A circle 2 km from the origin: coordinates spaced 2.3e-10 mm apart,
    // 1 mm disks below 1e-6 of them. The centre sets the coordinate.
    fails_with(
        "[domain]\nshape = \"circle\"\nradius = 10\ncenter = [2e6, -5]\n[grading]\nconstant = 1\n",
        "t.toml:4:10: domain.center: the smallest diameter, 1 mm, is less than 0.000001 of the \
         largest coordinate, 2000010 mm: floating point spaces coordinates there 2.3e-10 mm \
         apart, too coarse to keep disks from overlapping; bring the domain nearer the origin, \
         or pack a smaller domain or larger disks",
    );
    // The vertex farthest out is named.
    let far = "[domain]\nshape = \"polygon\"\nvertices = [[0, 0], [10, 0], [3e6, 5], [0, 5]]\n\
               [grading]\nconstant = 1\n";
    let e = err(far);
    assert_eq!(e.key(), Some("domain.vertices[2]"));
    assert_eq!((e.location().line, e.location().column), (3, 30));
    // Sizes: a tiny grading in a plain rectangle blames its longer side;
    // a fracture, its height.
    let e = err(&rect("width = 20\nheight = 30", "").replace("constant = 1.2", "constant = 1e-5"));
    assert_eq!(e.key(), Some("domain.height"));
    let fracture =
        "[fracture]\nwidth_mm = 2\nheight_m = 5000\n[grading]\nuniform = [0.002, 0.004]\n";
    let e = err(fracture);
    assert_eq!(e.key(), Some("fracture.height_m"));
    assert_eq!(e.location().line, 3);
    // At the limit the scene is accepted: the packer keeps its disks apart there.
    let edge = "[domain]\nshape = \"circle\"\nradius = 10\ncenter = [999990, 0]\n\
                [grading]\nconstant = 1\n";
    assert!(parse(edge, "t").is_ok());
}

#[test]
fn builds_optimise_settings_with_defaults_and_refuses_absurd_runs() {
    let ok = parse(
        &rect(
            "width = 20\nheight = 20",
            "[optimize]\ntarget_porosity = 0.4\npopulation = 16\n",
        ),
        "t",
    )
    .expect("valid config");
    let s = ok.optimise.expect("[optimize] read as [optimise]");
    assert_eq!((s.target_porosity, s.population), (0.4, 16));
    assert_eq!(
        (s.tolerance, s.generations, s.max_psd_ks),
        (0.002, 200, 0.05)
    );
    fails_with(
        &rect("width = 20\nheight = 20", "[optimise]\npopulation = 8\n"),
        "t.toml:7:1: optimise.target_porosity: missing; [optimise] needs the porosity to reach, in [0, 1)",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 20",
            "[optimise]\ntarget_porosity = 1\n",
        ),
        "t.toml:8:19: optimise.target_porosity: must be in [0, 1), got 1",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 20",
            "[optimise]\ntarget_porosity = 0.3\npopulation = 1\n",
        ),
        "t.toml:9:14: optimise.population: must be a whole number ≥ 2, got 1",
    );
    // A million genes per genome times 200 genomes, searched on the whole
    // (window_disks = 0): refused with the estimate.
    let e = err(&rect(
        "width = 1000\nheight = 1000",
        "[optimise]\ntarget_porosity = 0.3\npopulation = 200\nwindow_disks = 0\n",
    ));
    assert!(matches!(e, ConfigError::Memory { .. }), "{e}");
    assert_eq!(e.key(), Some("optimise.population"));
    let message = e.to_string();
    assert!(message.contains("needs an estimated"), "{message}");
    assert!(message.contains("over the limit of 4096 MB"), "{message}");
    // Searched on a window of at most a quarter of it (the default for
    // 700,000 disks), the same run fits.
    let windowed = parse(
        &rect(
            "width = 1000\nheight = 1000",
            "[optimise]\ntarget_porosity = 0.3\npopulation = 200\n",
        ),
        "t.toml",
    )
    .unwrap();
    let whole = crate::ga::OptimiseSettings {
        window_disks: 0,
        ..windowed.optimise.unwrap()
    };
    let scene = &windowed.scene;
    assert!(windowed.optimise.unwrap().peak_bytes(scene) < 0.5 * whole.peak_bytes(scene));
}

// ---- [output] ----------------------------------------------------------------

#[test]
fn output_defaults_without_the_table() {
    let config = parse(&rect("width = 20\nheight = 30", ""), "t.toml").unwrap();
    assert_eq!(config.output, crate::output::OutputSettings::default());
    assert_eq!(
        config.output.formats,
        [
            crate::output::Format::Csv,
            crate::output::Format::Svg,
            crate::output::Format::Png
        ]
    );
}

#[test]
fn output_table_is_read() {
    let text = rect(
        "width = 20\nheight = 30",
        "[output]\ndir = \"out/run1\"\nformats = [\"lammps\", \"vtk\"]\ndensity = 2500.0\nunits = \"mm\"",
    );
    let output = parse(&text, "t.toml").unwrap().output;
    assert_eq!(output.dir.as_deref(), Some("out/run1"));
    assert_eq!(
        output.formats,
        [crate::output::Format::Lammps, crate::output::Format::Vtk]
    );
    assert_eq!(output.export.density, 2500.0);
    assert_eq!(output.export.units, crate::output::LengthUnit::Millimetre);
}

#[test]
fn unknown_format_is_named_with_the_valid_ones() {
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nformats = [\"csv\", \"stl\"]",
        ),
        "t.toml:8:19: output.formats[1]: unknown format \"stl\"; valid: csv, json, vtk, lammps, yade, pfc, mercury, esys, svg, png",
    );
}

#[test]
fn format_given_twice_is_refused() {
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nformats = [\"vtk\", \"vtk\"]",
        ),
        "t.toml:8:19: output.formats[1]: \"vtk\" is given twice",
    );
}

#[test]
fn output_density_and_units_are_checked() {
    fails_with(
        &rect("width = 20\nheight = 30", "[output]\ndensity = -1.0"),
        "t.toml:8:11: output.density: must be a positive finite number, got -1",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "[output]\nunits = \"km\""),
        "t.toml:8:9: output.units: unknown length unit \"km\"; valid: m, mm",
    );
    let e = err(&rect("width = 20\nheight = 30", "[output]\ndir = \" \""));
    assert_eq!(e.key(), Some("output.dir"));
}

#[test]
fn material_density_must_be_positive() {
    let e = err(&rect(
        "width = 20\nheight = 30",
        "[[materials]]\nname = \"sand\"\ndensity = 0.0",
    ));
    assert_eq!(e.key(), Some("materials[0].density"));
    assert!(
        e.to_string()
            .ends_with("must be a positive finite number, got 0"),
        "{e}"
    );
}

#[test]
fn builds_scene_over_the_particle_limit_refused_unless_forced() {
    let big = rect("width = 10000\nheight = 10000", "").replace("constant = 1.2", "constant = 0.2");
    fails_with(
        &big,
        "t.toml:3:9: domain.width: the scene holds up to an estimated 3.183e9 disks (about 7957.7 s to pack at 4.0e5 disks/s), over the limit of 20000000 disks; set limits.max_particles (default 20000000) to raise the limit, or run with --force to go ahead",
    );
    assert!(parse_with(&big, "t", ParseOptions { force: true }).is_ok());
    // An explicit limit is blamed, and checked as a whole number.
    let e = err(&rect(
        "width = 100\nheight = 100",
        "[limits]\nmax_particles = 1000\n",
    ));
    assert_eq!(e.key(), Some("limits.max_particles"));
    assert_eq!((e.location().line, e.location().column), (8, 17));
    assert!(
        e.to_string()
            .contains("over the limit of 1000 disks; raise it"),
        "{e}"
    );
    let e = err(&rect(
        "width = 100\nheight = 100",
        "[limits]\nmax_particles = 0\n",
    ));
    assert_eq!(e.key(), Some("limits.max_particles"));
}

// ---- Scenes that would need absurd time or memory ---------------------------

#[test]
fn wall_disks_finer_than_a_hundredth_of_d_min_are_refused() {
    // 20 µm wall disks for 1.2 mm particles: 4 million wall disks, minutes
    // of packing for 400 particles.
    fails_with(
        &rect(
            "width = 20\nheight = 20\nwalls = \"disks\"\nwall_disk = 0.00002",
            "",
        ),
        "t.toml:6:13: domain.wall_disk: must be at least 1/100 of the smallest diameter \
         (1.2 mm), 0.012 mm: finer wall disks only slow the packer, got 0.00002",
    );
    // A hundredth is accepted.
    let text = rect(
        "width = 20\nheight = 20\nwalls = \"disks\"\nwall_disk = 0.012",
        "",
    );
    assert!(parse(&text, "t.toml").is_ok());
    let text = "[fracture]\nwidth_mm = 8.6\nheight_m = 0.0625\nwalls = \"disks\"\nwall_disk = 1e-3\n\
                [grading]\nconstant = 1.2\n";
    assert_eq!(err(text).key(), Some("fracture.wall_disk"));
}

#[test]
fn too_many_wall_disks_are_refused_at_the_walls_key() {
    // A 2 mm × 300 m slot: 600 m of boundary in wall disks of 0.1 mm
    // (d_min/12) is 6 million wall disks, over the cap; it used to pass
    // validation and fail only when packed (or pack without walls with the
    // comparison methods).
    let e = err(&rect("width = 2\nheight = 300000\nwalls = \"disks\"", ""));
    assert!(matches!(e, ConfigError::Scene { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.walls"));
    assert_eq!((e.location().line, e.location().column), (5, 9));
    assert!(e.to_string().contains("more than 4194304 disks"), "{e}");
}

#[test]
fn wall_disks_that_leave_no_room_are_refused_at_the_width() {
    // 50 mm wall disks, centred on the walls of a 20 mm wide slot, cover it
    // (found by fuzzing: the advancing front packed 0 disks and relaxation
    // pushed 1500 disks about for seconds).
    let text = rect(
        "width = 20\nheight = 92\nwalls = \"disks\"\nwall_disk = 50",
        "",
    );
    let e = err(&text);
    assert_eq!(e.key(), Some("domain.width"));
    let message = e.to_string();
    assert!(
        message.contains("the largest disk that fits inside its walls has diameter 0.0000 mm")
            && message
                .contains("the wall disks (50.0000 mm, centred on the boundary) take that room"),
        "{message}"
    );
    // 18 mm wall disks leave 2 mm: room for the 1.2 mm disks.
    assert!(parse(&text.replace("wall_disk = 50", "wall_disk = 18"), "t.toml").is_ok());
}

// ---- Hostile shapes: fixed-length arrays, tables, areas ----------------------

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

/// Two materials laid out in steps, with `layers` as written.
fn steps(layers: &str) -> String {
    format!(
        "[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n[grading]\nconstant = 1\n\
         [[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n\
         [layering]\nprofile = \"steps\"\nlayers = {layers}\n"
    )
}

#[test]
fn steps_layers_are_a_name_and_a_thickness_exactly() {
    assert!(parse(&steps("[[\"a\", 0.5], [\"b\", 0.5]]"), "t.toml").is_ok());
    fails_with(
        &steps("[[\"a\", 1, 2], [\"b\", 1]]"),
        "t.toml:13:11: layering.layers[0]: invalid length 3, expected an array of a material name and a number",
    );
    let e = err(&steps("[[\"a\", \"thick\"], [\"b\", 1]]"));
    assert_eq!(e.key(), Some("layering.layers[0][1]"));
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
fn optimise_and_optimize_together_are_both_named() {
    // Was "duplicate field `optimise`" under an unrelated or empty key.
    fails_with(
        &rect(
            "width = 20\nheight = 20",
            "[optimise]\ntarget_porosity = 0.2\n[optimize]\ntarget_porosity = 0.3\n",
        ),
        "t.toml:9:1: optimize: [optimise] is given too: [optimise] and [optimize] are one table \
         under two spellings; give only one",
    );
    let e = err(&rect(
        "width = 20\nheight = 20",
        "[optimize]\ntarget_porosity = 0.2\n[optimise]\ntarget_porosity = 0.3\n",
    ));
    assert_eq!(e.key(), Some("optimise"));
    assert!(e.to_string().contains("[optimize] is given too"), "{e}");
}

#[test]
fn sizes_whose_area_overflows_or_underflows_name_the_key_in_area_terms() {
    // Was "domain.shape: polygon is degenerate: the area inf ..." for a rectangle.
    fails_with(
        &rect("width = 1e308\nheight = 10", ""),
        "t.toml:3:9: domain.width: out of range: the domain's area, width × height, overflows \
         to inf mm² (beyond 1.8e308, the largest number): the sizes are too large",
    );
    let e = err(&rect("width = 10\nheight = 1e308", ""));
    assert!(matches!(e, ConfigError::Area { .. }), "{e}");
    assert_eq!(e.key(), Some("domain.height"));
    // Underflow blames the smaller size.
    let e = err(&rect("width = 1e-150\nheight = 1e-200", "").replace("1.2", "1e-300"));
    assert_eq!(e.key(), Some("domain.height"));
    assert!(e.to_string().contains("underflows to 0 mm²"), "{e}");
    let e = err("[domain]\nshape = \"circle\"\nradius = 1e160\n[grading]\nconstant = 1\n");
    assert_eq!(e.key(), Some("domain.radius"));
    assert!(e.to_string().contains("π × radius², overflows"), "{e}");
    let e = err(
        "[domain]\nshape = \"trapezoid\"\nbottom = 1e300\ntop = 1e299\nheight = 1e10\n\
         [grading]\nconstant = 1\n",
    );
    assert_eq!(e.key(), Some("domain.bottom"));
    assert!(e.to_string().contains("(bottom + top) / 2 × height"), "{e}");
    // A fracture: its width (mm) times its length (mm).
    let e = err("[fracture]\nwidth_mm = 1e200\nheight_m = 1e200\n[grading]\nconstant = 1\n");
    assert_eq!(e.key(), Some("fracture.height_m"));
    assert!(e.to_string().contains("width × length, overflows"), "{e}");
}

// ---- Batch well names ---------------------------------------------------------

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

// ---- [layering] memory ----------------------------------------------------------

/// Two materials laid out linearly in a `side` mm square, with `layering` keys appended.
fn layered(side: u32, layering: &str) -> String {
    format!(
        "[domain]\nshape = \"rectangle\"\nwidth = {side}\nheight = {side}\n[grading]\nconstant = 1\n\
         [[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n\
         [layering]\nprofile = \"linear\"\n{layering}"
    )
}

#[test]
fn layering_population_is_bounded_by_the_memory_limit() {
    // A million genomes of ~130 genes passed validation and grew past 4 GB.
    let e = err(&layered(10, "population = 1000000\n"));
    assert!(matches!(e, ConfigError::Memory { .. }), "{e}");
    assert_eq!(e.key(), Some("layering.population"));
    assert_eq!((e.location().line, e.location().column), (13, 14));
    let message = e.to_string();
    assert!(
        message.contains("the layering search (1000000 genomes of up to 128 genes"),
        "{message}"
    );
    assert!(message.contains("over the limit of 4096 MB"), "{message}");
    // The defaults, and a large population on a small packing, pass.
    assert!(parse(&layered(10, ""), "t.toml").is_ok());
    assert!(parse(&layered(10, "population = 10000\n"), "t.toml").is_ok());
    // The limit given is blamed, and --force goes ahead.
    let text = layered(10, "population = 100000\n").replacen(
        "[[materials]]",
        "[limits]\nmax_memory_mb = 100\n[[materials]]",
        1,
    );
    let e = err(&text);
    assert_eq!(e.key(), Some("limits.max_memory_mb"));
    assert!(e.to_string().contains("over the limit of 100 MB"), "{e}");
    assert!(parse_with(&text, "t.toml", ParseOptions { force: true }).is_ok());
    // Size-graded mode runs no search: its population is not counted.
    let sizes = "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n\
                 [[materials]]\nname = \"a\"\n[materials.grading]\nconstant = 1\n\
                 [[materials]]\nname = \"b\"\n[materials.grading]\nconstant = 0.8\n\
                 [layering]\nmode = \"sizes\"\nprofile = \"linear\"\npopulation = 1000000\n";
    assert!(parse(sizes, "t.toml").is_ok());
}

#[test]
fn layering_generations_are_bounded_by_the_scores_they_keep() {
    // Every evaluation's score is kept: a hundred million generations of
    // 64 genomes is 7 billion scores, blamed on generations.
    let e = err(&layered(10, "generations = 100000000\n"));
    assert!(matches!(e, ConfigError::Memory { .. }), "{e}");
    assert_eq!(e.key(), Some("layering.generations"));
    // A limit given is the key to act on.
    let e = err(&layered(10, "population = 2000\n").replacen(
        "[[materials]]",
        "[limits]\nmax_memory_mb = 1\n[[materials]]",
        1,
    ));
    assert_eq!(e.key(), Some("limits.max_memory_mb"));
}

// ---- Relaxation tolerance against the write check ----------------------------

#[test]
fn relaxation_tolerance_above_the_write_check_is_refused_with_a_value_that_passes() {
    let packer = |rest: &str| {
        rect(
            "width = 20\nheight = 20",
            &format!("[packer]\nmethod = \"relaxation\"\nrelaxation_porosity = 0.5\n{rest}"),
        )
    };
    // The default passes the write check once the sweeps converge.
    let config = parse(&packer(""), "t.toml").unwrap();
    assert!(config.scene.packer.relaxation.tolerance <= crate::geometry::predicates::OVERLAP_REL);
    assert!(parse(&packer("relaxation_tolerance = 1e-9\n"), "t.toml").is_ok());
    fails_with(
        &packer("relaxation_tolerance = 1e-4\n"),
        "t.toml:10:24: packer.relaxation_tolerance: must be at most 1e-9 with method = \
         \"relaxation\": a packing is written only if no overlap exceeds 1e-9 of the radii sum, \
         and the sweeps stop at this tolerance; 5e-10 (the default) passes, got 0.0001",
    );
    // Another method packs without it: a comparison may still relax loosely.
    let rsa = rect(
        "width = 20\nheight = 20",
        "[packer]\nmethod = \"rsa\"\nrelaxation_tolerance = 1e-4\n",
    );
    assert!(parse(&rsa, "t.toml").is_ok());
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

#[test]
fn strips_are_auto_a_count_or_one_piece_by_default() {
    use crate::packer::Strips;
    let strips = |line: &str| {
        parse(&rect("width = 200\nheight = 100", line), "t")
            .expect("valid")
            .scene
            .packer
            .strips
    };
    assert_eq!(strips(""), Strips::Count(1));
    assert_eq!(strips("[packer]\nstrips = \"auto\""), Strips::Auto);
    assert_eq!(strips("[packer]\nstrips = 4"), Strips::Count(4));
    let packer = |line: &str| rect("width = 200\nheight = 100", &format!("[packer]\n{line}\n"));
    fails_with(
        &packer("strips = \"many\""),
        "t.toml:8:10: packer.strips: unknown strip setting \"many\"; valid: auto, a whole number of strips",
    );
    fails_with(
        &packer("strips = 0"),
        "t.toml:8:10: packer.strips: must be a whole number in [1, 100000], got 0",
    );
    // 200 mm across 30 strips: 6.7 mm each, under 8 diameters of 1.2 mm.
    fails_with(
        &packer("strips = 30"),
        "t.toml:8:10: packer.strips: must be at most 20 here: strips 6.6667 mm wide are narrower than 8 largest diameters (9.6000 mm), got 30",
    );
    fails_with(
        &packer("strips = 2\nmethod = \"rsa\""),
        "t.toml:8:10: packer.strips: the advancing front only",
    );
    fails_with(
        &rect(
            "width = 200\nheight = 100\nwalls = \"disks\"",
            "[packer]\nstrips = 2\n",
        ),
        "t.toml:9:10: packer.strips: strips need walls = \"exact\"",
    );
}
