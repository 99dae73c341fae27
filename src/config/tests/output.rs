//! `[output]`: directory, formats, density and units.

use super::*;

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
        "t.toml:8:19: output.formats[1]: unknown format \"stl\"; valid: csv, json, vtk, lammps, yade, pfc, mercury, liggghts-superquadric, esys, svg, png",
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
