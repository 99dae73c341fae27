//! What the reference renderings share: the export set-up of today's
//! writers, and the text built whole in memory as they used to build it.

use std::fmt::{self, Write};

pub(super) use crate::output::export::common::{
    Export, Num, Row, VERSION, density, extent, labels, type_count, type_id,
};

/// A text file built line by line in memory.
pub(super) struct Text(String);

impl Text {
    /// An empty text with room for about `lines` lines.
    pub(super) fn with_lines(lines: usize) -> Self {
        Text(String::with_capacity(lines.saturating_mul(64)))
    }

    /// Append one line (`\n`-terminated).
    pub(super) fn line(&mut self, args: fmt::Arguments<'_>) {
        // Writing to a String cannot fail.
        let _ = self.0.write_fmt(args);
        self.0.push('\n');
    }

    /// The text as bytes.
    pub(super) fn into_bytes(self) -> Vec<u8> {
        self.0.into_bytes()
    }
}
