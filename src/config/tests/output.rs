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
        "t.toml:8:19: output.formats[1]: unknown format \"stl\"; valid: csv, json, vtk, vtp, npz, lammps, yade, pfc, mercury, liggghts-superquadric, esys, lammps-clumps, liggghts-clumps, svg, png",
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
fn clump_keys_are_read_and_checked() {
    let text = rect(
        "width = 20\nheight = 30",
        "[output]\nclump_coverage = 0.95\nclump_max_disks = 64",
    );
    let clumps = parse(&text, "t.toml").unwrap().output.export.clumps;
    assert_eq!(clumps.coverage, 0.95);
    assert_eq!(clumps.max_disks, 64);
    let defaults = parse(&rect("width = 20\nheight = 30", ""), "t.toml")
        .unwrap()
        .output
        .export
        .clumps;
    assert_eq!(defaults, crate::output::ClumpOptions::default());
    assert_eq!((defaults.coverage, defaults.max_disks), (0.9, 32));
    for bad in ["0.0", "0.995", "1.0", "-0.5", "nan"] {
        let e = err(&rect(
            "width = 20\nheight = 30",
            &format!("[output]\nclump_coverage = {bad}"),
        ));
        assert_eq!(e.key(), Some("output.clump_coverage"), "{bad}");
    }
    fails_with(
        &rect("width = 20\nheight = 30", "[output]\nclump_coverage = 1.0"),
        "t.toml:8:18: output.clump_coverage: must be in (0, 0.99], got 1",
    );
    for bad in ["0", "-3", "1025"] {
        let e = err(&rect(
            "width = 20\nheight = 30",
            &format!("[output]\nclump_max_disks = {bad}"),
        ));
        assert_eq!(e.key(), Some("output.clump_max_disks"), "{bad}");
    }
    let e = err(&rect(
        "width = 20\nheight = 30",
        "[output]\nclump_max_disks = 2.5",
    ));
    assert_eq!(e.key(), Some("output.clump_max_disks"));
}

#[test]
fn output_vtp_compression_is_read_by_name() {
    let plain = parse(&rect("width = 20\nheight = 30", ""), "t.toml").unwrap();
    assert_eq!(
        plain.output.vtp_compression,
        crate::output::VtpCompression::None
    );
    let config = parse(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nvtp_compression = \"zlib\"",
        ),
        "t.toml",
    )
    .unwrap();
    assert_eq!(
        config.output.vtp_compression,
        crate::output::VtpCompression::Zlib
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nvtp_compression = \"gzip\"",
        ),
        "t.toml:8:19: output.vtp_compression: unknown vtp compression \"gzip\"; valid: none, zlib",
    );
}

#[test]
fn output_colour_is_read_by_name() {
    let config = parse(
        &rect("width = 20\nheight = 30", "[output]\ncolour = \"size\""),
        "t.toml",
    )
    .unwrap();
    assert_eq!(config.output.colour, Some(crate::output::Colouring::Size));
    fails_with(
        &rect("width = 20\nheight = 30", "[output]\ncolour = \"hue\""),
        "t.toml:8:10: output.colour: unknown colouring \"hue\"; valid: size, material, orientation",
    );
}

/// Disks have no orientation, and a config without materials none to
/// colour by: both refused where the key is, with what to do instead.
#[test]
fn output_colour_needs_what_it_shows() {
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\ncolour = \"orientation\"",
        ),
        "t.toml:8:10: output.colour: \"orientation\" colours particles by the angle of their long axis, and disks have none: add a [shape] table, or use colour = \"size\" or \"material\"",
    );
    fails_with(
        &rect("width = 20\nheight = 30", "[output]\ncolour = \"material\""),
        "t.toml:8:10: output.colour: \"material\" colours particles by their material, and the config names none: add [[materials]], or use colour = \"size\"",
    );
}

/// With particles that are not disks and with materials, each colouring
/// is taken (read through the `[output]` check, a `[shape]` table being
/// read elsewhere).
#[test]
fn output_colour_is_taken_when_it_applies() {
    use crate::output::Colouring;
    for (name, colour) in [
        ("size", Colouring::Size),
        ("material", Colouring::Material),
        ("orientation", Colouring::Orientation),
    ] {
        let text = format!("[output]\ncolour = \"{name}\"\n");
        let raw: crate::config::raw::RawConfig = toml::from_str(&text).unwrap();
        let validator = crate::config::validate::Validator {
            text: &text,
            origin: "t.toml",
            force: false,
        };
        let settings = validator.output(raw.output.as_ref(), true, true).unwrap();
        assert_eq!(settings.colour, Some(colour));
        // Disks without materials: only size.
        assert_eq!(
            validator.output(raw.output.as_ref(), false, false).is_ok(),
            colour == Colouring::Size
        );
    }
}

/// `per_particle`: known names, each once, and only where a table holds
/// them; none by default.
#[test]
fn output_per_particle_is_read_and_checked() {
    let plain = parse(&rect("width = 20\nheight = 30", ""), "t.toml").unwrap();
    assert!(plain.output.per_particle.is_empty());
    let config = parse(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nper_particle = [\"h6\"]",
        ),
        "t.toml",
    )
    .unwrap();
    assert_eq!(config.output.per_particle, [crate::output::PerParticle::H6]);
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nper_particle = [\"h6\", \"h7\"]",
        ),
        "t.toml:8:23: output.per_particle[1]: unknown per-particle column \"h7\"; valid: h6",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nper_particle = [\"h6\", \"h6\"]",
        ),
        "t.toml:8:23: output.per_particle[1]: \"h6\" is given twice",
    );
    fails_with(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nformats = [\"vtk\"]\nper_particle = [\"h6\"]",
        ),
        "t.toml:9:16: output.per_particle: the columns go into packing.csv, packing.vtp and packing.npz, and formats asks for none of them: add \"csv\", \"vtp\" or \"npz\" to formats",
    );
    // An empty list asks for nothing, whatever the formats.
    let none = parse(
        &rect(
            "width = 20\nheight = 30",
            "[output]\nformats = []\nper_particle = []",
        ),
        "t.toml",
    )
    .unwrap();
    assert!(none.output.per_particle.is_empty());
}
