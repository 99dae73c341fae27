//! When the command line colours what it prints: `--color auto|always|never`
//! (auto: only on a terminal, and not when `NO_COLOR` is set to anything
//! but the empty string, nor with `TERM=dumb`), for clap's help and errors
//! and for the binary's own `error:` and `warning:` prefixes on stderr.

use std::ffi::OsString;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::ColorChoice;

/// Whether stderr gets colour, set once by [`init`].
static STDERR_COLOUR: AtomicBool = AtomicBool::new(false);

/// The `--color` the arguments give (the last one; none after `--`),
/// read before clap parses them so that clap's own errors follow it too;
/// `auto` when absent or not a valid choice (clap then says why).
pub fn choice_in(args: impl IntoIterator<Item = OsString>) -> ColorChoice {
    let mut choice = ColorChoice::Auto;
    let mut args = args.into_iter().skip(1);
    while let Some(arg) = args.next() {
        let Some(arg) = arg.to_str() else { continue };
        if arg == "--" {
            break;
        }
        let value = match arg.strip_prefix("--color") {
            Some("") => args.next().and_then(|v| v.into_string().ok()),
            Some(v) => v.strip_prefix('=').map(str::to_owned),
            None => None,
        };
        choice = match value.as_deref() {
            Some("always") => ColorChoice::Always,
            Some("never") => ColorChoice::Never,
            Some("auto") => ColorChoice::Auto,
            _ => choice,
        };
    }
    choice
}

/// Decide once whether stderr gets colour under `choice`.
pub fn init(choice: ColorChoice) {
    let on = match choice {
        ColorChoice::Always => true,
        ColorChoice::Never => false,
        ColorChoice::Auto => {
            let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
            let dumb = std::env::var_os("TERM").is_some_and(|t| t == "dumb");
            !no_color && !dumb && std::io::stderr().is_terminal()
        }
    };
    STDERR_COLOUR.store(on, Ordering::Relaxed);
}

/// `error:`, bold red when stderr gets colour (clap's own style).
pub fn error() -> &'static str {
    paint("\x1b[1;31merror:\x1b[0m", "error:")
}

/// `warning:`, bold yellow when stderr gets colour.
pub fn warning() -> &'static str {
    paint("\x1b[1;33mwarning:\x1b[0m", "warning:")
}

fn paint(coloured: &'static str, plain: &'static str) -> &'static str {
    if STDERR_COLOUR.load(Ordering::Relaxed) {
        coloured
    } else {
        plain
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn choice(args: &[&str]) -> ColorChoice {
        choice_in(args.iter().map(OsString::from))
    }

    #[test]
    fn the_last_color_flag_before_a_double_dash_counts() {
        assert_eq!(choice(&["gapack", "pack"]), ColorChoice::Auto);
        assert_eq!(choice(&["gapack", "--color", "never"]), ColorChoice::Never);
        assert_eq!(
            choice(&["gapack", "pack", "--color=always", "x.toml"]),
            ColorChoice::Always
        );
        assert_eq!(
            choice(&["gapack", "--color", "never", "--color", "always"]),
            ColorChoice::Always
        );
        assert_eq!(
            choice(&["gapack", "--color", "never", "--", "--color", "always"]),
            ColorChoice::Never
        );
        // A bad value leaves the choice as it was: clap refuses it.
        assert_eq!(choice(&["gapack", "--color", "red"]), ColorChoice::Auto);
        // `--colors` is another flag.
        assert_eq!(choice(&["gapack", "--colors=never"]), ColorChoice::Auto);
    }
}
