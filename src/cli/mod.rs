//! Subcommands of the binary beyond the packing runs in `main.rs`.

pub mod inspect;
