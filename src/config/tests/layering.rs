//! `[[materials]]` and `[layering]`: properties, steps layers, memory.

use super::*;

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
    assert!(e.forceable(), "{e}");
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
    assert!(e.forceable(), "{e}");
    assert_eq!(e.key(), Some("layering.generations"));
    // A limit given is the key to act on.
    let e = err(&layered(10, "population = 2000\n").replacen(
        "[[materials]]",
        "[limits]\nmax_memory_mb = 1\n[[materials]]",
        1,
    ));
    assert_eq!(e.key(), Some("limits.max_memory_mb"));
}

/// Two materials of a 40 mm square laid out in `mode`, the second with
/// the shape table `shape` (none if empty) and `rest` appended.
fn shaped(mode: &str, shape: &str, rest: &str) -> String {
    let (grading, top) = if mode == "sizes" {
        ("", "")
    } else {
        ("[grading]\nuniform = [1, 1.6]\n", "")
    };
    let graded = |range: &str| {
        if mode == "sizes" {
            format!("[materials.grading]\nuniform = {range}\n")
        } else {
            String::new()
        }
    };
    format!(
        "[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 40\n{grading}{top}\
         [[materials]]\nname = \"matrix\"\n{}\
         [[materials]]\nname = \"inclusions\"\n{}{shape}\
         {rest}[layering]\nmode = \"{mode}\"\nprofile = \"linear\"\n",
        graded("[0.8, 1.2]"),
        graded("[1, 1.6]"),
    )
}

const ELONGATED: &str = "[materials.shape]\nkind = \"superellipse\"\naspect = [2.5, 3]\n";

#[test]
fn materials_of_different_shapes_in_materials_mode_are_refused_at_the_shape_table() {
    fails_with(
        &shaped("materials", ELONGATED, ""),
        "t.toml:11:1: materials[1].shape: materials \"matrix\" and \"inclusions\" have different particle shapes: in [layering] mode = \"materials\" the packing is made once and materials are assigned to its particles afterwards, so every material must have the same shape; use mode = \"sizes\" (each particle drawn with its material's shape as it is packed), or give the materials one [shape]",
    );
    // The same shape for both, or one [shape]: the layering GA's packing.
    let both = shaped("materials", "", "").replace(
        "[[materials]]\nname = \"inclusions\"\n",
        &format!("{ELONGATED}[[materials]]\nname = \"inclusions\"\n{ELONGATED}"),
    );
    let config = parse(&both, "t.toml").expect("one shape for both");
    let shape = config.scene.shape.expect("the materials' shape");
    assert_eq!(
        shape.family,
        crate::Family::Superellipse {
            aspect: crate::Spread::Range(2.5, 3.0),
            alpha: crate::Spread::Fixed(2.0),
            beta: crate::Spread::Fixed(2.0),
        }
    );
    assert!(config.scene.gradient.is_none());
}

#[test]
fn a_shape_per_material_in_sizes_mode_reaches_the_scene() {
    let config = parse(&shaped("sizes", ELONGATED, ""), "t.toml").expect("valid");
    // The matrix has no shape and there is no [shape]: circles.
    assert_eq!(config.scene.shape, Some(crate::ShapeSpec::ellipses(1.0)));
    let gradient = config.scene.gradient.expect("size-graded");
    let second = gradient.second_shape.expect("the inclusions' own shape");
    assert_eq!(
        second.family,
        crate::Family::Superellipse {
            aspect: crate::Spread::Range(2.5, 3.0),
            alpha: crate::Spread::Fixed(2.0),
            beta: crate::Spread::Fixed(2.0),
        }
    );
    // With a top-level [shape], the matrix takes it.
    let top = shaped("sizes", ELONGATED, "").replace(
        "[[materials]]\nname = \"matrix\"",
        "[shape]\nkind = \"superellipse\"\naspect = 1.2\n[[materials]]\nname = \"matrix\"",
    );
    let config = parse(&top, "t.toml").expect("valid");
    assert_eq!(config.scene.shape, Some(crate::ShapeSpec::ellipses(1.2)));
    // Without any shape, disks as before.
    let disks = parse(&shaped("sizes", "", ""), "t.toml").expect("valid");
    assert!(disks.scene.shape.is_none());
    assert!(disks.scene.gradient.expect("graded").second_shape.is_none());
}

#[test]
fn a_material_shape_is_checked_as_the_shape_table_is() {
    let e = err(&shaped(
        "sizes",
        "[materials.shape]\nkind = \"superellipse\"\naspect = 0.5\n",
        "",
    ));
    assert_eq!(e.key(), Some("materials[1].shape.aspect"), "{e}");
    assert!(e.to_string().starts_with("t.toml:15:10: "), "{e}");
    let e = err(&shaped(
        "sizes",
        ELONGATED,
        "[packer]\nmethod = \"deposition\"\n",
    ));
    assert_eq!(e.key(), Some("materials[1].shape"), "{e}");
    assert!(
        e.to_string()
            .contains("particle shapes cannot be packed with packer.method = \"deposition\""),
        "{e}"
    );
}
