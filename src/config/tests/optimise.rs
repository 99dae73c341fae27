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
