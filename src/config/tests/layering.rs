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
