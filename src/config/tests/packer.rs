//! `[packer]`: names, settings, relaxation tolerance, strips; the default config.

use super::*;
use crate::geometry::{Shape, WallMode};
use crate::grading::Basis;
use crate::packer::{FrontRules, IndexKind};

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
fn strips_are_auto_a_count_or_one_piece_by_default() {
    use crate::packer::Strips;
    let strips = |line: &str| {
        parse(&rect("width = 200\nheight = 100", line), "t")
            .expect("valid")
            .scene
            .packer
            .strips
    };
    assert_eq!(strips(""), Strips::Auto);
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

#[test]
fn strips_of_any_other_value_are_refused_by_their_rule() {
    let packer = |value: &str| {
        rect(
            "width = 200\nheight = 100",
            &format!("[packer]\nstrips = {value}\n"),
        )
    };
    let rule = "t.toml:8:10: packer.strips: must be a whole number in [1, 100000] or \"auto\", got";
    for (value, shown) in [
        ("2.5", "2.5"),
        ("3.0", "3.0"),
        ("nan", "nan"),
        ("true", "true"),
        ("[1]", "[1]"),
        ("{ a = 1 }", "{ a = 1 }"),
        ("1979-05-27", "1979-05-27"),
        (&format!("[{}]", ["1"; 30].join(", ")), "an array"),
    ] {
        fails_with(&packer(value), &format!("{rule} {shown}"));
    }
}
