//! `[optimise]` (or `[optimize]`): its keys, defaults and memory.

use super::*;

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
    assert_eq!((s.target_porosity, s.stop.population), (0.4, 16));
    assert_eq!(
        (s.tolerance, s.stop.generations, s.max_psd_ks),
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
    assert!(e.forceable(), "{e}");
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
fn ga_tables_read_the_shared_keys_and_refuse_unknown_ones_at_their_place() {
    let layering = "[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\naxis = \"y\"\nprofile = \"linear\"\n";
    let stop =
        "population = 8\ngenerations = 5\nstagnation = 4\ntime_limit_s = 9\nmax_evaluations = 70\n";
    let expected = crate::ga::StopRules {
        population: 8,
        generations: 5,
        stagnation: 4,
        time_limit_s: 9.0,
        max_evaluations: Some(70),
    };
    let domain = "width = 10\nheight = 10";
    let optimise = format!("[optimise]\ntarget_porosity = 0.3\n{stop}window_disks = 3\n");
    let config = parse(&rect(domain, &optimise), "t.toml").unwrap();
    let settings = config.optimise.unwrap();
    assert_eq!((settings.stop, settings.window_disks), (expected, 3));
    let config = parse(
        &rect(domain, &format!("{layering}{stop}bins = 2\n")),
        "t.toml",
    )
    .unwrap();
    let settings = config.layering.unwrap();
    assert_eq!((settings.stop, settings.bins), (expected, 2));

    // An unknown key among the shared ones: refused at its line and column,
    // with every key of the table.
    fails_with(
        &rect(
            domain,
            "[optimise]\ntarget_porosity = 0.3\npopulation = 8\n  populaton = 8\n",
        ),
        "t.toml:10:3: optimise.populaton: unknown key `populaton`, expected one of `target_porosity`, `tolerance`, `population`, `generations`, `stagnation`, `time_limit_s`, `max_evaluations`, `window_disks`, `max_psd_ks`, `shape`",
    );
    fails_with(
        &rect(domain, &format!("{layering}stagnant = 3\n")),
        "t.toml:14:1: layering.stagnant: unknown key `stagnant`, expected one of `mode`, `axis`, `bins`, `profile`, `exponent`, `layers`, `table`, `tolerance`, `population`, `generations`, `stagnation`, `time_limit_s`, `max_evaluations`",
    );
    // A shared key of the wrong type, and one out of range, at the value.
    fails_with(
        &rect(domain, &format!("{layering}generations = \"many\"\n")),
        "t.toml:14:15: layering.generations: invalid type: string \"many\", expected a whole number",
    );
    fails_with(
        &rect(
            domain,
            "[optimise]\ntarget_porosity = 0.3\nstagnation = 0\n",
        ),
        "t.toml:9:14: optimise.stagnation: must be a whole number ≥ 1, got 0",
    );
}

#[test]
fn the_shape_search_takes_its_bounds_from_shape_and_checks_them() {
    let domain = "width = 40\nheight = 40";
    let shape = "[shape]\nkind = \"superellipse\"\naspect = [1.0, 2.5]\nalpha = [2.0, 3.0]\n";
    let search = "[optimise]\ntarget_porosity = 0.25\n[optimise.shape]\n";
    // Bounds from [shape] when not given, the constraints as given.
    let c = parse(
        &rect(domain, &format!("{shape}{search}min_sphericity = 0.7\n")),
        "t.toml",
    )
    .expect("valid");
    let b = c.optimise.and_then(|o| o.shape).expect("a shape search");
    assert_eq!((b.aspect, b.exponent), ([1.0, 2.5], [2.0, 3.0]));
    assert_eq!(
        (b.min_sphericity, b.min_roundness, b.spread),
        (0.7, 0.0, None)
    );
    assert_eq!(b.max_shape_ks, crate::ga::DEFAULT_MAX_SHAPE_KS);
    let c = parse(
        &rect(
            domain,
            &format!("{shape}{search}aspect = [1.2, 2]\nexponent = [2, 5]\nmax_shape_ks = 0.2\n"),
        ),
        "t.toml",
    )
    .expect("valid");
    let b = c.optimise.and_then(|o| o.shape).expect("a shape search");
    assert_eq!(
        (b.aspect, b.exponent, b.max_shape_ks),
        ([1.2, 2.0], [2.0, 5.0], 0.2)
    );
    // No [shape]: nothing to move.
    fails_with(
        &rect(domain, search),
        "t.toml:9:1: optimise.shape: needs a [shape] table: the search moves the particles' shape within these bounds",
    );
    // A range upside down, and below an aspect of 1.
    fails_with(
        &rect(domain, &format!("{shape}{search}aspect = [2, 1.5]\n")),
        "t.toml:14:10: optimise.shape.aspect[1]: must be at least the low end 2: a range is [low, high], got 1.5",
    );
    assert!(
        parse(
            &rect(domain, &format!("{shape}{search}exponent = [0.5, 2]\n")),
            "t.toml"
        )
        .expect_err("non-convex")
        .to_string()
        .starts_with("t.toml:14:12: optimise.shape.exponent[0]: must be at least 1")
    );
    // A spread to search needs aligned particles.
    fails_with(
        &rect(
            domain,
            &format!("{shape}{search}orientation_spread = [0, 20]\n"),
        ),
        "t.toml:14:22: optimise.shape.orientation_spread: applies only to shape.orientation = \"aligned\" (random orientations have no spread to move)",
    );
    // A bound not even the roundest shape allowed keeps.
    let long = "[shape]\nkind = \"superellipse\"\naspect = [2.0, 3.0]\n";
    fails_with(
        &rect(domain, &format!("{long}{search}min_sphericity = 0.8\n")),
        "t.toml:13:18: optimise.shape.min_sphericity: must be at most 0.707: the roundest shape the bounds allow (aspect 2, exponent 2) has 0.7071, got 0.8",
    );
    // Polygons keep their templates.
    let polygons =
        "[shape]\nkind = \"polygon\"\n[[shape.templates]]\nvertices = [[0, 0], [1, 0], [0, 1]]\n";
    assert!(
        parse(&rect(domain, &format!("{polygons}{search}")), "t.toml")
            .expect_err("polygons")
            .to_string()
            .contains(
                "optimise.shape: the search moves the aspect ratio and exponents of superellipses"
            )
    );
}
