//! The command-line conventions: shell completions that load, a manual page
//! `man` renders, `--json` objects that hold what `summary.json` holds,
//! colour that follows `--color` and `NO_COLOR`, the commit in
//! `--version`, and the exit codes `--help` and docs/usage.md list.

use crate::common;

use std::fs::{self, File};
use std::io::{Read, Write};
use std::os::fd::FromRawFd;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::{gapack, scratch};
use serde_json::{Map, Value};

const BIN: &str = env!("CARGO_BIN_EXE_gapack");

/// A 20 mm square of 1–2 mm disks: packs in milliseconds.
const SMALL: &str = "seed = 3\n[domain]\nshape = \"rectangle\"\nwidth = 20\nheight = 20\n\
                     [grading]\nuniform = [1.0, 2.0]\n";

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Stdout of a run that must succeed.
fn stdout_of(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}\n{}{}",
        out.status.code(),
        text(&out.stdout),
        text(&out.stderr)
    );
    text(&out.stdout)
}

/// The one JSON object of a `--json` run's stdout: a single line, and
/// nothing else on stdout.
fn json_object(out: &Output) -> Map<String, Value> {
    let stdout = text(&out.stdout);
    assert_eq!(stdout.lines().count(), 1, "one line on stdout: {stdout}");
    match serde_json::from_str(&stdout) {
        Ok(Value::Object(map)) => map,
        other => panic!("not one JSON object: {other:?}\n{stdout}"),
    }
}

fn read_object(path: &Path) -> Map<String, Value> {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).expect("summary.json is an object")
}

/// A job's `--json` object against the `summary.json` it wrote: every entry
/// of the file is in the object with the same value, the object's own
/// entries are `job`, `out`, `files`, `lines` and `interrupted`, and its
/// first result line names the folder and the porosity of the summary.
fn assert_holds_summary(object: &Map<String, Value>, dir: &Path, job: &str) {
    let summary = read_object(&dir.join("summary.json"));
    for (key, value) in &summary {
        assert_eq!(object.get(key), Some(value), "{job}: key {key}");
    }
    for key in object.keys() {
        assert!(
            summary.contains_key(key)
                || ["job", "out", "files", "lines", "interrupted"].contains(&key.as_str()),
            "{job}: {key} is neither summary.json's nor documented"
        );
    }
    assert_eq!(object["job"], job);
    assert_eq!(object["interrupted"], false);
    let out = object["out"].as_str().expect("out");
    assert!(dir.ends_with(out), "{out}");
    let files: Vec<&str> = object["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f.as_str().expect("a file name"))
        .collect();
    for file in ["summary.json", "manifest.json", "packing.csv"] {
        assert!(files.contains(&file), "{job}: {file} in {files:?}");
    }
    let first = object["lines"][0].as_str().expect("a result line");
    let porosity = summary["porosity"].as_f64().expect("porosity");
    assert!(
        first.starts_with(&format!("{out}: ")) && first.contains(&format!("{porosity:.4}")),
        "{job}: {first} (porosity {porosity})"
    );
}

#[test]
fn bash_loads_the_completions_and_completes_subcommands() {
    let script = format!(
        "source <('{BIN}' completions bash) && complete -p gapack && \
         COMP_WORDS=(gapack opt) && COMP_CWORD=1 && COMP_LINE='gapack opt' && COMP_POINT=10 && \
         _gapack gapack opt gapack && printf 'reply %s\\n' \"${{COMPREPLY[@]}}\""
    );
    let out = Command::new("bash")
        .args(["--norc", "--noprofile", "-c", &script])
        .output()
        .expect("run bash");
    let stdout = stdout_of(&out);
    assert!(
        stdout
            .lines()
            .next()
            .is_some_and(|l| l.starts_with("complete ") && l.ends_with(" gapack")),
        "{stdout}"
    );
    // `opt` completes to the subcommand and its alias, and nothing else.
    let replies: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("reply "))
        .collect();
    assert!(replies.contains(&"optimise"), "{stdout}");
    assert!(replies.iter().all(|r| r.starts_with("opt")), "{stdout}");
}

#[test]
fn every_shell_gets_a_script_naming_the_subcommands() {
    let dir = scratch("conventions-shells");
    for shell in ["zsh", "fish", "powershell", "elvish"] {
        let script = stdout_of(&gapack(&dir, &["completions", shell]));
        for word in ["pack", "optimise", "verify", "completions", "json", "color"] {
            assert!(script.contains(word), "{shell}: no {word}");
        }
    }
    let out = gapack(&dir, &["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    let _ = fs::remove_dir_all(&dir);
}

/// `man -l -` reading `page`, as plain text 100 columns wide.
fn render(page: &[u8]) -> Option<String> {
    let mut child = match Command::new("man")
        .args(["-l", "-"])
        .env("MANWIDTH", "100")
        .env("MANPAGER", "cat")
        .env("PAGER", "cat")
        .env("MAN_KEEP_FORMATTING", "")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(child) => child,
        Err(e) => {
            println!("skipped: `man` cannot run here ({e}); install man-db");
            return None;
        }
    };
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(page)
        .expect("feed man");
    let out = child.wait_with_output().expect("man runs");
    Some(stdout_of(&out))
}

#[test]
fn man_renders_the_page_and_writes_one_per_command() {
    let dir = scratch("conventions-man");
    let page = gapack(&dir, &["man"]);
    let roff = stdout_of(&page);
    assert!(
        roff.starts_with(".ie") || roff.contains(".TH gapack"),
        "{roff}"
    );
    if let Some(shown) = render(&page.stdout) {
        for words in [
            "NAME",
            "gapack",
            "SUBCOMMANDS",
            "optimise",
            "Exit status",
            "130",
        ] {
            assert!(shown.contains(words), "no {words} in\n{shown}");
        }
    }
    let listed = stdout_of(&gapack(&dir, &["man", "--dir", "pages"]));
    let mut names: Vec<String> = fs::read_dir(dir.join("pages"))
        .expect("pages written")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for name in [
        "gapack.1",
        "gapack-pack.1",
        "gapack-verify.1",
        "gapack-user-add.1",
    ] {
        assert!(names.iter().any(|n| n == name), "{name} in {names:?}");
    }
    assert!(
        !names.iter().any(|n| n.starts_with("gapack-help")),
        "{names:?}"
    );
    assert_eq!(listed.lines().count(), names.len(), "{listed}");
    let pack = fs::read(dir.join("pages/gapack-pack.1")).expect("gapack-pack.1");
    if let Some(shown) = render(&pack) {
        assert!(
            shown.contains("gapack-pack") && shown.contains("--json"),
            "{shown}"
        );
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn pack_json_is_its_summary() {
    let dir = scratch("conventions-pack-json");
    fs::write(dir.join("small.toml"), SMALL).unwrap();
    let out = gapack(
        &dir,
        &["pack", "small.toml", "--out", "o", "--json", "--timings"],
    );
    let object = json_object(&out);
    assert_holds_summary(&object, &dir.join("o"), "pack");
    // The timings went to stderr, with nothing else on stdout.
    assert!(
        text(&out.stderr).contains("timings: "),
        "{}",
        text(&out.stderr)
    );
    // The human lines are the object's.
    let plain = stdout_of(&gapack(&dir, &["pack", "small.toml", "--out", "o"]));
    let lines: Vec<&str> = plain.lines().collect();
    assert_eq!(lines.len(), object["lines"].as_array().unwrap().len());
    let refused = gapack(&dir, &["pack", "small.toml", "--json", "--quiet"]);
    assert_eq!(refused.status.code(), Some(2));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn optimise_json_is_its_summary() {
    let dir = scratch("conventions-optimise-json");
    let config = format!(
        "{SMALL}[optimise]\ntarget_porosity = 0.95\npopulation = 4\ngenerations = 50\n\
         stagnation = 100\nmax_evaluations = 12\n"
    );
    fs::write(dir.join("search.toml"), config).unwrap();
    let object = json_object(&gapack(
        &dir,
        &["optimise", "search.toml", "--out", "o", "--json"],
    ));
    assert_holds_summary(&object, &dir.join("o"), "optimise");
    for key in ["best_porosity", "target_porosity", "verdict", "evaluations"] {
        assert!(object.contains_key(key), "{key}");
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn layer_json_is_its_summary() {
    let dir = scratch("conventions-layer-json");
    let config = format!(
        "{SMALL}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n\
         [layering]\naxis = \"y\"\nbins = 4\nprofile = \"linear\"\n"
    );
    fs::write(dir.join("layers.toml"), config).unwrap();
    let object = json_object(&gapack(
        &dir,
        &["layer", "layers.toml", "--out", "o", "--json"],
    ));
    assert_holds_summary(&object, &dir.join("o"), "layer");
    assert!(object["profile_rms_error"].is_f64(), "{object:?}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn validate_json_is_the_plan_it_prints() {
    let dir = scratch("conventions-validate-json");
    fs::write(
        dir.join("small.toml"),
        format!("{SMALL}[optimise]\ntarget_porosity = 0.3\n"),
    )
    .unwrap();
    let args = ["validate", "small.toml", "--job", "pack", "--seed", "9"];
    let object = json_object(&gapack(&dir, &[&args[..], &["--json"]].concat()));
    assert_eq!(object["config"], "small.toml");
    assert_eq!(object["valid"], true);
    assert_eq!(object["job"], "pack");
    assert_eq!(object["seed"], 9);
    assert_eq!(object["out"], "out/small");
    // pack ignores the [optimise] table, and says so.
    let warnings = object["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().contains("[optimise]")),
        "{warnings:?}"
    );
    let plain = stdout_of(&gapack(&dir, &args));
    let mut expected = vec!["small.toml: valid".to_owned()];
    for line in object["plan"].as_array().unwrap() {
        expected.push(format!("  {}", line.as_str().unwrap()));
    }
    assert_eq!(plain.lines().collect::<Vec<_>>(), expected);
    // A bad config: nothing on stdout, exit 2.
    fs::write(dir.join("bad.toml"), "[domain]\nshape = \"rectangle\"\n").unwrap();
    let bad = gapack(&dir, &["validate", "bad.toml", "--json"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(bad.stdout.is_empty());
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn verify_json_tells_the_findings_and_keeps_the_exit_code() {
    let dir = scratch("conventions-verify-json");
    fs::write(dir.join("small.toml"), SMALL).unwrap();
    stdout_of(&gapack(
        &dir,
        &["pack", "small.toml", "--out", "o", "--quiet"],
    ));
    let args = ["verify", "o/packing.csv", "--config", "small.toml"];
    let object = json_object(&gapack(&dir, &[&args[..], &["--json"]].concat()));
    let summary = read_object(&dir.join("o/summary.json"));
    assert_eq!(object["valid"], true);
    assert_eq!(object["particles"], summary["particles"]);
    let porosity = object["porosity"].as_f64().unwrap();
    assert!((porosity - summary["porosity"].as_f64().unwrap()).abs() < 1e-6);
    assert_eq!(object["overlaps"], 0);
    assert_eq!(object["deepest_overlap"], Value::Null);
    let plain = stdout_of(&gapack(&dir, &args));
    let mut expected = vec![format!(
        "o/packing.csv against small.toml: {}",
        object["verdict"].as_str().unwrap()
    )];
    for line in object["findings"].as_array().unwrap() {
        expected.push(format!("  {}", line.as_str().unwrap()));
    }
    assert_eq!(plain.lines().collect::<Vec<_>>(), expected);

    // Two disks one on the other: not valid, exit 1, the object still printed.
    fs::write(dir.join("bad.csv"), "x,y,r\n5,5,1\n5.5,5,1\n").unwrap();
    let out = gapack(
        &dir,
        &["verify", "bad.csv", "--config", "small.toml", "--json"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let object = json_object(&out);
    assert_eq!(object["valid"], false);
    assert_eq!(object["verdict"], "FAILED");
    assert_eq!(object["overlaps"], 1);
    assert!(
        object["deepest_overlap"].as_f64().unwrap() > 0.2,
        "{object:?}"
    );
    assert!(text(&out.stderr).contains("not valid"));
    let _ = fs::remove_dir_all(&dir);
}

/// Run gapack with `args` and `env`, its stderr on a pseudo-terminal: what it wrote there.
fn stderr_on_terminal(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> String {
    let (mut master, mut slave) = (0, 0);
    // SAFETY: openpty fills two fresh descriptors, which the Files below own.
    let made = unsafe {
        libc::openpty(
            &mut master,
            &mut slave,
            std::ptr::null_mut(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert_eq!(made, 0, "openpty");
    // SAFETY: both descriptors were just opened and are owned by nothing else.
    let (mut master, slave) = unsafe { (File::from_raw_fd(master), File::from_raw_fd(slave)) };
    let mut command = Command::new(BIN);
    command
        .args(args)
        .env_remove("NO_COLOR")
        .env("TERM", "xterm")
        .envs(env.iter().copied())
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::from(slave));
    let status = command.status().expect("run gapack");
    assert!(!status.success());
    // The terminal's last writer gone, reading it ends (EIO) after its text.
    drop(command);
    let mut bytes = Vec::new();
    let mut chunk = [0u8; 4096];
    while let Ok(n) = master.read(&mut chunk) {
        if n == 0 {
            break;
        }
        bytes.extend_from_slice(&chunk[..n]);
    }
    text(&bytes)
}

#[test]
fn colour_follows_the_flag_no_color_and_the_terminal() {
    let dir = scratch("conventions-colour");
    let esc = |s: &str| s.contains('\u{1b}');
    let stderr = |args: &[&str], env: &[(&str, &str)]| {
        let out = Command::new(BIN)
            .args(args)
            .env_remove("NO_COLOR")
            .envs(env.iter().copied())
            .current_dir(&dir)
            .output()
            .expect("run gapack");
        assert!(!out.status.success());
        text(&out.stderr)
    };
    // Our own error (a missing config) and clap's (an unknown command).
    for args in [&["pack", "nowhere.toml"][..], &["unpack"][..]] {
        let with = |flag: &[&'static str]| [flag, args].concat();
        let always = stderr(&with(&["--color", "always"]), &[]);
        assert!(esc(&always), "{args:?}: {always}");
        assert!(esc(&stderr(
            &with(&["--color=always"]),
            &[("NO_COLOR", "1")]
        )));
        assert!(!esc(&stderr(&with(&["--color", "never"]), &[])), "{args:?}");
        assert!(!esc(&stderr(args, &[("NO_COLOR", "1")])), "{args:?}");
        // auto, through a pipe: none.
        assert!(!esc(&stderr(args, &[])), "{args:?}");
        // auto on a terminal: colour, unless NO_COLOR is set (empty counts as unset).
        let shown = stderr_on_terminal(&dir, args, &[]);
        assert!(
            esc(&shown) && shown.contains("error"),
            "{args:?}: {shown:?}"
        );
        assert!(esc(&stderr_on_terminal(&dir, args, &[("NO_COLOR", "")])));
        let plain = stderr_on_terminal(&dir, args, &[("NO_COLOR", "1")]);
        assert!(
            !esc(&plain) && plain.contains("error"),
            "{args:?}: {plain:?}"
        );
        let never = stderr_on_terminal(&dir, &with(&["--color", "never"]), &[]);
        assert!(!esc(&never), "{args:?}: {never:?}");
    }
    let bad = Command::new(BIN)
        .args(["--color", "red", "pack"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn version_names_the_commit() {
    let out = Command::new(BIN).arg("--version").output().unwrap();
    let version = stdout_of(&out);
    let rest = version
        .trim_end()
        .strip_prefix(&format!("gapack {} (commit ", env!("CARGO_PKG_VERSION")))
        .and_then(|r| r.strip_suffix(')'))
        .unwrap_or_else(|| panic!("{version}"));
    assert!(
        rest == "unknown" || (rest.len() >= 7 && rest.chars().all(|c| c.is_ascii_hexdigit())),
        "{version}"
    );
    // Built in this checkout: its HEAD.
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| text(&o.stdout).trim().to_owned())
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let top = git(&["rev-parse", "--show-toplevel"]).map(|t| Path::new(&t).canonicalize().ok());
    if top.flatten() == root.canonicalize().ok()
        && let Some(head) = git(&["rev-parse", "--short=12", "HEAD"])
    {
        assert_eq!(rest, head, "{version}");
    } else {
        println!("not a git checkout: the commit is not compared");
    }
}

/// The codes of the lines `  N    meaning` after `Exit status:` in `--help`.
fn codes_in_help(help: &str) -> Vec<u32> {
    let after = help
        .split("Exit status:")
        .nth(1)
        .expect("an exit status block");
    after
        .lines()
        .filter_map(|l| {
            l.strip_prefix("  ")?
                .split_whitespace()
                .next()?
                .parse()
                .ok()
        })
        .collect()
}

#[test]
fn help_and_usage_list_the_same_exit_codes() {
    let help = stdout_of(&Command::new(BIN).arg("--help").output().unwrap());
    let codes = codes_in_help(&help);
    assert_eq!(codes, [0, 1, 2, 101, 130], "{help}");
    let usage = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/usage.md"))
        .expect("docs/usage.md");
    let table = usage
        .split("### Exit codes")
        .nth(1)
        .expect("an exit codes section");
    let documented: Vec<u32> = table
        .lines()
        .filter_map(|l| l.strip_prefix("| ")?.split(' ').next()?.parse().ok())
        .collect();
    assert_eq!(documented, codes);
    // The codes are the ones returned: bad input 2, a failed verify 1.
    let dir = scratch("conventions-exit");
    assert_eq!(
        gapack(&dir, &["pack", "nowhere.toml"]).status.code(),
        Some(2)
    );
    assert_eq!(gapack(&dir, &["--bogus"]).status.code(), Some(2));
    assert_eq!(gapack(&dir, &["--help"]).status.code(), Some(0));
    let _ = fs::remove_dir_all(&dir);
}
