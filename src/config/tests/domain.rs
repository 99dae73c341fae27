//! `[domain]`: sizes, shapes, walls, coordinates; the scene checks its
//! constructor and the walls make.

use super::*;
use crate::geometry::{Point, Shape, WallMode};

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
