//! `[shape]`: each form of each key, the defaults, every refusal, and the
//! scenes this version cannot pack shapes in.

use super::*;
use crate::geometry::{Outline, Point};
use crate::scene::{Family, Orientation, Proppant, ShapeSpec, SizeMeasure, Spread};

/// A 40 mm square of 1.2 mm disks with `shape` lines under `[shape]` (line 8 on).
fn with_shape(shape: &str) -> String {
    rect("width = 40\nheight = 40", &format!("[shape]\n{shape}\n"))
}

/// The shape `text` parses to; fails the test if it is refused or has none.
fn shape_of(text: &str) -> ShapeSpec {
    match parse(text, "t.toml") {
        Ok(config) => config.scene.shape.expect("a [shape]"),
        Err(e) => panic!("refused:\n{text}\n{e}"),
    }
}

/// A superellipse family of these quantities.
fn superellipse(aspect: Spread, alpha: Spread, beta: Spread) -> Family {
    Family::Superellipse {
        aspect,
        alpha,
        beta,
    }
}

#[test]
fn a_config_without_shape_packs_disks() {
    let config = parse(&rect("width = 40\nheight = 40", ""), "t.toml").expect("valid");
    assert_eq!(config.scene.shape, None);
    let default = parse(DEFAULT_CONFIG, DEFAULT_ORIGIN).expect("valid");
    assert_eq!(default.scene.shape, None);
}

#[test]
fn a_fixed_aspect_gives_ellipses_turned_at_random_sized_by_sieve() {
    let spec = shape_of(&with_shape("kind = \"superellipse\"\naspect = 1.5"));
    assert_eq!(spec, ShapeSpec::ellipses(1.5));
    // An integer is a number too.
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = 2\nalpha = 4",
    ));
    assert_eq!(spec, ShapeSpec::superellipses(2.0, 4.0));
}

#[test]
fn ranges_and_tables_of_shares_parse_and_beta_follows_alpha() {
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = [1.2, 2.0]\nalpha = { values = [2, 4], shares = [0.25, 0.75] }",
    ));
    let alpha = Spread::Shares(vec![(2.0, 0.25), (4.0, 0.75)]);
    assert_eq!(
        spec.family,
        superellipse(Spread::Range(1.2, 2.0), alpha.clone(), alpha)
    );
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = 1.5\nalpha = [1, 3]\nbeta = 6",
    ));
    assert_eq!(
        spec.family,
        superellipse(
            Spread::Fixed(1.5),
            Spread::Range(1.0, 3.0),
            Spread::Fixed(6.0)
        )
    );
    // A range may be a single value; shares may be given to 1e-9.
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = [1.5, 1.5]\nbeta = { values = [1, 2, 3], shares = [0.3333333333, 0.3333333333, 0.3333333334] }",
    ));
    let Family::Superellipse { aspect, beta, .. } = spec.family else {
        panic!("{spec:?}");
    };
    assert_eq!(aspect, Spread::Range(1.5, 1.5));
    assert!(matches!(beta, Spread::Shares(rows) if rows.len() == 3));
}

#[test]
fn orientation_and_size_parse() {
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = 3\norientation = \"aligned\"\nangle = 30.0\nspread = 10\nsize = \"equivalent\"",
    ));
    assert_eq!(
        spec.orientation,
        Orientation::Aligned {
            mean: 30f64.to_radians(),
            spread: 10f64.to_radians()
        }
    );
    assert_eq!(spec.size, SizeMeasure::Equivalent);
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = 3\norientation = \"aligned\"",
    ));
    assert_eq!(
        spec.orientation,
        Orientation::Aligned {
            mean: 0.0,
            spread: 0.0
        }
    );
    assert_eq!(spec.size, SizeMeasure::Sieve);
    let spec = shape_of(&with_shape(
        "kind = \"superellipse\"\naspect = 3\norientation = \"random\"\nsize = \"sieve\"",
    ));
    assert_eq!(
        (spec.orientation, spec.size),
        (Orientation::Random, SizeMeasure::Sieve)
    );
}

/// The outline of a template as the config gives it.
fn template(index: u16, vertices: &[[f64; 2]], rounding: f64) -> Outline {
    let points: Vec<Point> = vertices.iter().map(|p| Point::new(p[0], p[1])).collect();
    Outline::polygon(index, &points, rounding).expect("a convex template")
}

#[test]
fn polygon_templates_parse_with_their_shares() {
    let spec = shape_of(&with_shape(
        "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [2, 0], [2, 1], [0, 1]]\nrounding = 0.1\nshare = 0.6\n[[shape.templates]]\nvertices = [[0, 0], [0, 1], [1, 0]]\nshare = 0.4",
    ));
    let rectangle = template(0, &[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]], 0.1);
    // Clockwise is accepted as well.
    let clockwise = template(1, &[[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]], 0.0);
    assert_eq!(
        spec.family,
        Family::Polygons {
            templates: vec![(rectangle.clone(), 0.6), (clockwise, 0.4)]
        }
    );
    let triangle = template(1, &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], 0.0);
    // Without shares, equal ones.
    let spec = shape_of(&with_shape(
        "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [2, 0], [2, 1], [0, 1]]\nrounding = 0.1\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]",
    ));
    assert_eq!(
        spec.family,
        Family::Polygons {
            templates: vec![(rectangle, 0.5), (triangle, 0.5)]
        }
    );
}

#[test]
fn exponents_below_one_are_refused_as_not_convex() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 1.5\nalpha = 0.5"),
        "t.toml:10:9: shape.alpha: must be at least 1: an exponent below 1 makes the particle non-convex (its sides curve inwards), and gapack certifies no overlap between non-convex particles; use exponents of 1 or more, got 0.5",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 1.5\nbeta = [0.8, 2]"),
        "t.toml:10:9: shape.beta[0]: must be at least 1: an exponent below 1 makes the particle non-convex (its sides curve inwards), and gapack certifies no overlap between non-convex particles; use exponents of 1 or more, got 0.8",
    );
}

#[test]
fn aspects_and_exponents_outside_their_bounds_are_refused() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 0.5"),
        "t.toml:9:10: shape.aspect: must be at least 1 (the long axis over the short one, a/b), got 0.5",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = [2, 25]"),
        "t.toml:9:14: shape.aspect[1]: must be at most 20: thinner particles make the contact solving lose precision, got 25",
    );
    fails_with(
        &with_shape(
            "kind = \"superellipse\"\naspect = 2\nalpha = { values = [2, 60], shares = [0.5, 0.5] }",
        ),
        "t.toml:10:24: shape.alpha.values[1]: must be at most 50: blockier particles make the contact solving lose precision, got 60",
    );
}

#[test]
fn values_that_are_not_positive_and_finite_are_refused() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = -1"),
        "t.toml:9:10: shape.aspect: must be a positive finite number, got -1",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = nan"),
        "t.toml:9:10: shape.aspect: must be a positive finite number, got NaN",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\nalpha = [2, inf]"),
        "t.toml:10:13: shape.alpha[1]: must be a positive finite number, got inf",
    );
    fails_with(
        &with_shape(
            "kind = \"superellipse\"\naspect = 2\nalpha = { values = [2, 3], shares = [1, 0] }",
        ),
        "t.toml:10:41: shape.alpha.shares[1]: must be a positive finite number, got 0",
    );
}

#[test]
fn backward_ranges_and_malformed_forms_are_refused() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = [2, 1.5]"),
        "t.toml:9:14: shape.aspect[1]: must be at least the low end 2: a range is [low, high], got 1.5",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = [1, 2, 3]"),
        "t.toml:9:10: shape.aspect: invalid length 3, expected a range [low, high] of 2 numbers",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = \"long\""),
        "t.toml:9:10: shape.aspect: invalid type: string \"long\", expected a number, a range [low, high] or a table { values = [...], shares = [...] }",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = { values = [1.5, 2], shares = [1] }"),
        "t.toml:9:40: shape.aspect.shares: has 1 shares for 2 values: give one share per value",
    );
}

#[test]
fn shares_must_sum_to_one() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = { values = [1.5, 2], shares = [0.5, 0.4] }"),
        "t.toml:9:46: shape.aspect.shares[1]: must be 0.5 for the shares to sum to 1 (within 1e-9; they sum to 0.9), got 0.4",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]\nshare = 0.7\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [1, 1], [0, 1]]\nshare = 0.7",
        ),
        "t.toml:14:9: shape.templates[1].share: must be 0.3 for the shares to sum to 1 (within 1e-9; they sum to 1.4), got 0.7",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]\nshare = 1.2\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [1, 1], [0, 1]]\nshare = 0.1",
        ),
        "t.toml:14:9: shape.templates[1].share: must be smaller: the shares must sum to 1 (within 1e-9), and those before it sum to 1.2 already, got 0.1",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]\nshare = 0.5\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [1, 1], [0, 1]]",
        ),
        "t.toml:12:1: shape.templates[1].share: missing; give every template a share, or none (equal shares)",
    );
}

#[test]
fn unknown_names_and_keys_are_refused() {
    fails_with(
        &with_shape("kind = \"blob\"\naspect = 2"),
        "t.toml:8:8: shape.kind: unknown particle shape \"blob\"; valid: superellipse, polygon",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\norientation = \"sideways\""),
        "t.toml:10:15: shape.orientation: unknown orientation \"sideways\"; valid: random, aligned",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\nsize = \"volume\""),
        "t.toml:10:8: shape.size: unknown size measure \"volume\"; valid: sieve, equivalent",
    );
    let e = err(&with_shape(
        "kind = \"superellipse\"\naspect = 2\ncolour = 1",
    ));
    assert_eq!(e.key(), Some("shape.colour"), "{e}");
    assert_eq!((e.location().line, e.location().column), (10, 1), "{e}");
    assert!(
        e.to_string()
            .contains("unknown key `colour`, expected one of `kind`, `aspect`"),
        "{e}"
    );
    fails_with(
        &with_shape("aspect = 2"),
        "t.toml:7:1: shape.kind: missing; give kind = \"superellipse\" or \"polygon\" with its outline, or a proppant's preset (ceramic, resin-coated-sand, angular-sand)",
    );
}

#[test]
fn keys_of_the_other_family_or_orientation_are_refused() {
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\nangle = 30"),
        "t.toml:10:9: shape.angle: applies only to orientation = \"aligned\" (random orientations have no mean angle or spread)",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\norientation = \"random\"\nspread = 5"),
        "t.toml:11:10: shape.spread: applies only to orientation = \"aligned\" (random orientations have no mean angle or spread)",
    );
    fails_with(
        &with_shape("kind = \"superellipse\"\naspect = 2\norientation = \"aligned\"\nspread = -5"),
        "t.toml:11:10: shape.spread: must be a finite number ≥ 0 (degrees), got -5",
    );
    fails_with(
        &with_shape("kind = \"superellipse\""),
        "t.toml:7:1: shape.aspect: missing; kind = \"superellipse\" needs its aspect ratio a/b (1 for a round outline)",
    );
    fails_with(
        &with_shape("kind = \"polygon\"\naspect = 2"),
        "t.toml:9:10: shape.aspect: applies only to kind = \"superellipse\" (a polygon's outline is its template's)",
    );
    fails_with(
        &with_shape("kind = \"polygon\""),
        "t.toml:7:1: shape.templates: missing; kind = \"polygon\" needs at least one [[shape.templates]] with its vertices",
    );
    fails_with(
        &with_shape(
            "kind = \"superellipse\"\naspect = 2\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]",
        ),
        "t.toml:10:1: shape.templates: applies only to kind = \"polygon\"",
    );
}

#[test]
fn templates_that_are_not_convex_polygons_are_refused() {
    fails_with(
        &with_shape("kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0]]"),
        "t.toml:10:12: shape.templates[0].vertices: polygon template: needs at least 3 vertices, has 2",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [2, 0], [1, 0.5], [2, 2], [0, 2]]",
        ),
        "t.toml:10:12: shape.templates[0].vertices: polygon template: is not strictly convex at vertex 3 (1, 0.5): every corner must turn left, by more than a straight angle's rounding",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]\nrounding = -0.1",
        ),
        "t.toml:11:12: shape.templates[0].rounding: must be a finite number ≥ 0 (in the template's units), got -0.1",
    );
    fails_with(
        &with_shape(
            "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [1, nan]]",
        ),
        "t.toml:10:29: shape.templates[0].vertices[2]: must be a finite number, got NaN",
    );
    let e = err(&with_shape(
        "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [30, 0], [30, 1], [0, 1]]",
    ));
    assert_eq!(e.key(), Some("shape.templates[0].vertices"), "{e}");
    assert!(
        e.to_string().contains(
            "must be a particle of aspect at most 20 (greatest over least width): thinner particles make the contact solving lose precision, got 30"
        ),
        "{e}"
    );
}

/// The refusal of a shape in a scene this version cannot pack it in.
fn unsupported(what: &str) -> String {
    format!(
        "t.toml:7:1: shape: particle shapes cannot be packed with {what}; particle shapes are packed in this version with packer.method = \"advancing-front\" (two or one contact) or \"rsa\", in a [domain] or [fracture] with walls = \"exact\", or as a periodic cell"
    )
}

#[test]
fn methods_walls_and_strips_that_do_not_pack_shapes_are_refused() {
    let ellipses = "kind = \"superellipse\"\naspect = 1.5\n";
    for method in ["deposition", "relaxation", "densify"] {
        fails_with(
            &with_shape(&format!("{ellipses}[packer]\nmethod = \"{method}\"")),
            &unsupported(&format!("packer.method = \"{method}\"")),
        );
    }
    fails_with(
        &with_shape(&format!("{ellipses}[packer]\nstrips = 4")),
        &unsupported("packer.strips (packing in strips)"),
    );
    fails_with(
        &with_shape(&format!("{ellipses}[packer]\nfill = \"right\"")),
        &unsupported(
            "packer.fill = \"right\" (the scene mirrored and packed as disks); leave fill = \"up\"",
        ),
    );
    fails_with(
        &with_shape(&format!("{ellipses}[packer]\ncontacts = 1\ngap = 0.5")),
        &unsupported(
            "packer.gap (the one-contact clearance is kept between disks only; shapes at one contact keep none)",
        ),
    );
    fails_with(
        &with_shape(&format!("{ellipses}[packer]\nrules = \"thesis\"")),
        &unsupported(
            "packer.rules = \"thesis\" (shapes follow the robust rules: failing fronts parked, sizes deferred)",
        ),
    );
    fails_with(
        &rect(
            "width = 40\nheight = 40\nwalls = \"disks\"",
            &format!("[shape]\n{ellipses}"),
        ),
        &unsupported("walls = \"disks\" (wall disks would need shape-aware wall particles; use walls = \"exact\")")
            .replace("t.toml:7:1", "t.toml:8:1"),
    );
    // The two methods, both contact rules, periodic cells and circles pack
    // shapes; `strips = "auto"` (the default) packs them in one piece.
    for packer in [
        "method = \"advancing-front\"\ncontacts = 1",
        "contacts = 2",
        "method = \"rsa\"",
        "strips = 1",
        "strips = \"auto\"",
        "fill = \"up\"",
    ] {
        shape_of(&with_shape(&format!("{ellipses}[packer]\n{packer}")));
    }
    shape_of(&rect(
        "width = 40\nheight = 40\nwalls = \"periodic\"",
        &format!("[shape]\n{ellipses}"),
    ));
    let circle = format!(
        "[domain]\nshape = \"circle\"\nradius = 20\n[grading]\nuniform = [1, 2]\n[shape]\n{ellipses}"
    );
    shape_of(&circle);
}

#[test]
fn materials_and_their_layering_take_shapes() {
    let ellipses = "[shape]\nkind = \"superellipse\"\naspect = 1.5\n";
    // Tested further in `layering`.
    let spec = shape_of(&rect(
        "width = 40\nheight = 40",
        &format!(
            "{ellipses}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\nprofile = \"linear\"\n"
        ),
    ));
    assert_eq!(spec, ShapeSpec::ellipses(1.5));
}

#[test]
fn fractures_and_wells_take_shapes_filling_up() {
    let ellipses = "[shape]\nkind = \"superellipse\"\naspect = 1.5\n";
    let fracture = format!(
        "[fracture]\nwidth_mm = 8.6\nheight_m = 0.0625\n[grading]\nuniform = [0.4, 0.8]\n{ellipses}"
    );
    let config = parse(&fracture, "t.toml").expect("a fracture of ellipses");
    assert_eq!(config.scene.shape, Some(ShapeSpec::ellipses(1.5)));
    let wells = "[fracture]\nextent = \"window\"\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 2.6\nheight_m = 1\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 4.2\nheight_m = 1\n";
    let batch = format!("{wells}[grading]\nconstant = 1.2\n[shape]\npreset = \"ceramic\"\n");
    let config = parse(&batch, "t.toml").expect("wells of a preset");
    let run = config.fracture.expect("a fracture run");
    assert_eq!(run.wells.len(), 2);
    for well in &run.wells {
        assert_eq!(
            well.scene.shape,
            Some(Proppant::Ceramic.shape()),
            "{}",
            well.name
        );
    }
    // A well's own fill = "right" packs disks: refused at the key.
    let right = batch.replace("height_m = 1\n[[", "height_m = 1\nfill = \"right\"\n[[");
    fails_with(
        &right,
        "t.toml:7:8: fracture.wells[0].fill: \"right\" mirrors the scene and packs it as disks, which particle shapes ([shape]) cannot be; leave fill = \"up\"",
    );
    // The fracture's wall disks are refused as a domain's are.
    let disks = batch.replace(
        "extent = \"window\"",
        "extent = \"window\"\nwalls = \"disks\"",
    );
    let e = err(&disks);
    assert_eq!(e.key(), Some("shape"), "{e}");
    assert!(e.to_string().contains("walls = \"disks\""), "{e}");
}

#[test]
fn presets_give_their_proppant_and_take_size_and_orientation() {
    for p in Proppant::ALL {
        let spec = shape_of(&with_shape(&format!("preset = \"{}\"", p.name())));
        assert_eq!(spec, p.shape());
    }
    let spec = shape_of(&with_shape(
        "preset = \"angular-sand\"\nsize = \"equivalent\"\norientation = \"aligned\"\nangle = 90",
    ));
    assert_eq!(spec.family, Proppant::AngularSand.family());
    assert_eq!(spec.size, SizeMeasure::Equivalent);
    assert_eq!(
        spec.orientation,
        Orientation::Aligned {
            mean: 90f64.to_radians(),
            spread: 0.0
        }
    );
    fails_with(
        &with_shape("preset = \"ceramic\"\naspect = 1.5"),
        "t.toml:9:10: shape.aspect: preset = \"ceramic\" gives the particles' outline: give a preset, or kind with aspect, alpha, beta or templates, not both (a preset takes size and orientation)",
    );
    let e = err(&with_shape("kind = \"polygon\"\npreset = \"angular-sand\""));
    assert_eq!(e.key(), Some("shape.kind"), "{e}");
    let e = err(&with_shape(
        "preset = \"ceramic\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]",
    ));
    assert_eq!(e.key(), Some("shape.templates"), "{e}");
    fails_with(
        &with_shape("preset = \"glass\""),
        "t.toml:8:10: shape.preset: unknown proppant preset \"glass\"; valid: ceramic, resin-coated-sand, angular-sand",
    );
}

#[test]
fn the_particle_bound_holds_for_shapes() {
    let disks = parse(&rect("width = 40\nheight = 40", ""), "t.toml").expect("valid");
    let bound = disks.scene.max_disks();
    assert_eq!(
        bound,
        (1600.0 / (std::f64::consts::FRAC_PI_4 * 1.44)).ceil(),
        "disks are unchanged"
    );
    // Superellipses sized by sieve, and any shape by equivalent diameter,
    // cover at least the disk of their size.
    let ellipses = shape_of(&with_shape("kind = \"superellipse\"\naspect = [1, 3]"));
    let scene = disks.scene.clone().with_shape(ellipses);
    assert!(scene.max_disks() >= bound && scene.max_disks() <= bound + 1.0);
    // Sieve-sized triangles may be smaller than their disk: the bound grows
    // by (π/4)/(1/√3).
    let text = with_shape(
        "kind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [2, 0], [1, 1.7320508075688772]]",
    );
    let triangles = parse(&text, "t.toml").expect("valid");
    let pal = std::f64::consts::FRAC_PI_4 * 3f64.sqrt();
    let grown = triangles.scene.max_disks();
    assert!(grown >= (1600.0 / (std::f64::consts::FRAC_PI_4 * 1.44) * pal).floor());
    assert!(grown <= (1600.0 / (std::f64::consts::FRAC_PI_4 * 1.44) * pal).ceil() + 1.0);
    // The bound holds: no triangle of the scene is smaller than the domain over it.
    let spec = triangles.scene.shape.as_ref().expect("a shape");
    let Family::Polygons { templates } = &spec.family else {
        panic!("{spec:?}");
    };
    let unit = &templates[0].0;
    let smallest = unit.scaled(1.2 / spec.measure(unit)).area();
    assert!(
        1600.0 / smallest <= grown,
        "{} > {grown}",
        1600.0 / smallest
    );
    // And the estimate counts the larger area of sieve-sized ellipses.
    let ellipses = shape_of(&with_shape("kind = \"superellipse\"\naspect = 2"));
    let estimate = disks.scene.clone().with_shape(ellipses).estimated_disks();
    assert!((estimate * 2.0 / disks.scene.estimated_disks() - 1.0).abs() < 1e-6);
}
