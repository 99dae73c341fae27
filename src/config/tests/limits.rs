//! `[limits]`: the memory and particle limits, and `force`.

use super::*;

#[test]
fn memory_limit_must_be_positive() {
    fails_with(
        &rect("width = 20\nheight = 30", "[limits]\nmax_memory_mb = 0\n"),
        "t.toml:8:17: limits.max_memory_mb: must be a positive finite number, got 0",
    );
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
    // The library names the config key; how to force is each front end's to say.
    assert!(
        message.ends_with("set limits.max_memory_mb (default 4096) to raise the limit"),
        "{message}"
    );
    assert!(e.forceable(), "{e}");
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
fn builds_scene_over_the_particle_limit_refused_unless_forced() {
    let big = rect("width = 10000\nheight = 10000", "").replace("constant = 1.2", "constant = 0.2");
    fails_with(
        &big,
        "t.toml:3:9: domain.width: the scene holds up to an estimated 3.183e9 disks (about 7957.7 s to pack at 4.0e5 disks/s), over the limit of 20000000 disks; set limits.max_particles (default 20000000) to raise the limit",
    );
    assert!(err(&big).forceable());
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
    // A bad limit is no refusal that force skips.
    assert!(!e.forceable(), "{e}");
}
