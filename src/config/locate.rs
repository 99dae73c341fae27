//! Turning a TOML parser or serde error into one [`ConfigError`] naming the key at fault.

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::error::{ConfigError, Location};
use super::raw::NOT_AN_ARRAY_OF_TABLES;

/// The config error for a failed `toml::from_str`, with line, column and key path.
pub(crate) fn from_toml_error(err: &toml::de::Error, text: &str, origin: &str) -> ConfigError {
    // The parser gives no place for a key of too many dotted parts: the
    // key with the most is the one at fault.
    let span = err
        .span()
        .unwrap_or_else(|| deepest_key(text).map_or(0..0, |at| at..at));
    let at = Location::at(origin, text, span.start);
    let (tree, _) = DeTable::parse_recoverable(text);
    let mut nodes = Vec::new();
    collect_table(tree.get_ref(), "", &mut nodes);
    let message = err.message();

    if DeTable::parse(text).is_err() {
        let key = innermost(&nodes, span.start)
            .map(str::to_owned)
            .or_else(|| key_on_line(text, span.start, &nodes));
        return ConfigError::Syntax {
            at,
            // A path as deep as the nesting that broke the parser says
            // nothing the place does not.
            key: key.filter(|k| k.matches(['.', '[']).count() < MAX_KEY_PARTS),
            message: message.to_owned(),
        };
    }
    if let Some(field) = quoted_after(message, "missing field ") {
        // The span is the table that lacks the key (empty at the top level).
        let table = nodes
            .iter()
            .filter(|n| n.is_table && !span.is_empty() && n.span.start == span.start)
            .map(|n| n.path.as_str())
            .next()
            .unwrap_or("");
        // Every required top-level key is a table.
        let message = if table.is_empty() {
            format!("missing table [{field}]")
        } else {
            "missing key".to_owned()
        };
        return ConfigError::Schema {
            at,
            key: join(table, field),
            message,
        };
    }
    if message == NOT_AN_ARRAY_OF_TABLES {
        // The array and its first table start at the same place: the key is
        // the array's (`domain`, not `domain[0]`).
        let key = nodes
            .iter()
            .filter(|n| n.span == span)
            .map(|n| n.path.as_str())
            .min_by_key(|p| p.len())
            .or_else(|| innermost(&nodes, span.start))
            .unwrap_or("")
            .to_owned();
        return ConfigError::Schema {
            at,
            message: format!("{message}: write [{key}], not [[{key}]]"),
            key,
        };
    }
    let key = innermost(&nodes, span.start).unwrap_or("").to_owned();
    if nodes
        .iter()
        .any(|n| n.is_datetime && n.span.start == span.start)
    {
        // serde sees a date as a table with one private key: say what it is.
        let message = match quoted_after(message, "unknown field ") {
            Some(_) => "invalid type: date-time, expected a table".to_owned(),
            None => plain_types(&message.replace("invalid type: map", "invalid type: date-time")),
        };
        return ConfigError::Schema { at, key, message };
    }
    let message = match quoted_after(message, "unknown field ") {
        Some(field) => {
            let rest = message
                .split_once(", ")
                .map_or(String::new(), |(_, r)| format!(", {r}"));
            format!("unknown key `{field}`{rest}")
        }
        None => plain_types(message),
    };
    ConfigError::Schema { at, key, message }
}

/// A key or value of the parsed tree, with its path (`domain.vertices[2]`).
/// Where key `path` (`output.dir`) is written in `text`: the place of
/// its key, for a fault found after parsing by a caller with its own rules
/// (a service that refuses a key the CLI accepts). `None` if the text does
/// not parse or has no such key.
#[must_use]
pub fn key_location(text: &str, origin: &str, path: &str) -> Option<Location> {
    let tree = DeTable::parse(text).ok()?;
    let mut nodes = Vec::new();
    collect_table(tree.get_ref(), "", &mut nodes);
    nodes
        .iter()
        .filter(|n| n.path == path)
        .map(|n| n.span.start)
        .min()
        .map(|start| Location::at(origin, text, start))
}

struct Node {
    span: Range<usize>,
    path: String,
    is_table: bool,
    is_datetime: bool,
}

fn collect_table(table: &DeTable<'_>, path: &str, out: &mut Vec<Node>) {
    for (key, value) in table.iter() {
        let path = join(path, key.get_ref());
        out.push(Node {
            span: key.span(),
            path: path.clone(),
            is_table: false,
            is_datetime: false,
        });
        collect_value(value, path, out);
    }
}

fn collect_value(value: &Spanned<DeValue<'_>>, path: String, out: &mut Vec<Node>) {
    match value.get_ref() {
        DeValue::Table(table) => collect_table(table, &path, out),
        DeValue::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                collect_value(item, format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
    out.push(Node {
        span: value.span(),
        path,
        is_table: matches!(value.get_ref(), DeValue::Table(_)),
        is_datetime: matches!(value.get_ref(), DeValue::Datetime(_)),
    });
}

/// The path of the smallest key or value whose span holds `pos` (end included,
/// so an error just after a value still names it).
fn innermost(nodes: &[Node], pos: usize) -> Option<&str> {
    nodes
        .iter()
        .filter(|n| n.span.start <= pos && pos <= n.span.end)
        .min_by_key(|n| n.span.end - n.span.start)
        .map(|n| n.path.as_str())
}

/// For an error the parsed tree does not cover (a duplicate key, say): the
/// bare key written at the start of the error's line, under the last table
/// header before it.
fn key_on_line(text: &str, pos: usize, nodes: &[Node]) -> Option<String> {
    let before = text.get(..pos)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = text.get(line_start..)?.lines().next()?;
    let key = line.split_once('=')?.0.trim();
    let bare = |c: char| c.is_ascii_alphanumeric() || "_-.".contains(c);
    if key.is_empty() || !key.chars().all(bare) {
        return None;
    }
    let header = nodes
        .iter()
        .filter(|n| n.is_table && n.span.end <= line_start)
        .filter(|n| text.get(n.span.start..).is_some_and(|t| t.starts_with('[')))
        .max_by_key(|n| n.span.start)
        .map_or("", |n| n.path.as_str());
    Some(join(header, key))
}

/// Most parts (dotted keys and indices) of a key path a syntax error names.
const MAX_KEY_PARTS: usize = 16;

/// The byte offset of the key of most dotted parts in `text` (`a.b."c".d`,
/// in a table header or before `=`), if any key has more than one part:
/// where the TOML parser's nesting limit on keys, which it reports without
/// a place, was met.
fn deepest_key(text: &str) -> Option<usize> {
    let mut best: Option<(usize, usize)> = None;
    let mut line_start = 0;
    for line in text.split_inclusive('\n') {
        if let Some((parts, at)) = dotted_run(line)
            && parts > 1
            && best.is_none_or(|(most, _)| parts > most)
        {
            best = Some((parts, line_start + at));
        }
        line_start += line.len();
    }
    best.map(|(_, at)| at)
}

/// The longest run of dotted key parts on `line`, skipping comments: its
/// number of parts and where it starts. A quoted string counts as a part.
fn dotted_run(line: &str) -> Option<(usize, usize)> {
    let bytes = line.as_bytes();
    let bare = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'-';
    let mut best: Option<(usize, usize)> = None;
    let mut run: Option<(usize, usize)> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b == b'#' {
            break;
        }
        let start = i;
        if bare(b) {
            while i < bytes.len() && bare(bytes[i]) {
                i += 1;
            }
        } else if b == b'"' || b == b'\'' {
            i += 1;
            while i < bytes.len() && bytes[i] != b {
                i += if bytes[i] == b'\\' && b == b'"' { 2 } else { 1 };
            }
            i += 1;
        } else {
            if b != b'.' && !b.is_ascii_whitespace() {
                run = None;
            }
            i += 1;
            continue;
        }
        // A part: it extends the run if a dot (and blanks) come before it.
        let joined = line[..start].trim_end().ends_with('.');
        run = match run {
            Some((parts, at)) if joined => Some((parts + 1, at)),
            _ => Some((1, start)),
        };
        if run.is_some_and(|(parts, _)| best.is_none_or(|(most, _)| parts > most)) {
            best = run;
        }
    }
    best
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_owned()
    } else {
        format!("{path}.{key}")
    }
}

/// `x` in a message `"{prefix}`x`..."`.
fn quoted_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = message.strip_prefix(prefix)?.strip_prefix('`')?;
    rest.split_once('`').map(|(name, _)| name)
}

/// serde's Rust type names in words an engineer reads.
fn plain_types(message: &str) -> String {
    const WORDS: [(&str, &str); 7] = [
        ("expected f64", "expected a number"),
        ("expected u64", "expected a whole number >= 0"),
        ("expected i64", "expected a whole number"),
        ("expected a sequence", "expected an array"),
        ("invalid type: sequence", "invalid type: array"),
        ("invalid type: map", "invalid type: table"),
        ("expected struct ", "expected a table, not "),
    ];
    let mut message = message.to_owned();
    for (from, to) in WORDS {
        message = message.replace(from, to);
    }
    if let Some(i) = message.find("expected a table, not ") {
        message.truncate(i + "expected a table".len());
    }
    message
}
