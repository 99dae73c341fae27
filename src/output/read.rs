//! Reading a packing back from CSV, for `gapack verify` and `gapack plot`:
//! gapack's own `packing.csv` or a table written by another tool.
//!
//! The text is given (the caller reads the file), so this is parsing only.
//! Columns are found by header name, case-insensitively: `x`, `y`, and one
//! of `r`/`radius` or `d`/`diameter`; `material` is optional (a name or a
//! number); any other column is ignored. Lines starting with `#` are comments.
//! A table with an `angle` column holds particles that are not disks, as
//! gapack's `packing.csv` writes them: `a`, `b`, `alpha`, `beta` for a
//! superellipse, `template`, `rounding`, `vertices` for a rounded polygon
//! (`x1 y1;x2 y2;…`, in the particle's own axes), `r` the area-equivalent
//! radius.
//! Two columns for one part (`r` and `d`, or `x` twice) are refused, not
//! guessed between.
//!
//! Every value is checked as it is read, so that nothing downstream (the
//! check, the charts, the pictures) meets a degenerate packing: positions
//! within `MAX_COORDINATE` of the origin, sizes between `MIN_DIAMETER`
//! and `MAX_DIAMETER`, and at most `MAX_SIZE_RATIO` between the largest
//! and the smallest disk.

use std::fmt;

use crate::geometry::{Disk, Grain, Outline, Point};

/// A packing as read from a table: the disks in file order, and their
/// materials when the table has a `material` column.
#[derive(Debug, Clone, PartialEq)]
pub struct PackingTable {
    /// The disks, one per row (mm).
    pub disks: Vec<Disk>,
    /// Per disk, an index into `material_names`; empty without a `material` column.
    pub materials: Vec<u16>,
    /// Material names in order of first appearance.
    pub material_names: Vec<String>,
    /// Per disk, the file line of its row (from 1).
    pub lines: Vec<u64>,
    /// Per disk, its `id` column; empty when the table has none, or one
    /// that is not a whole number on every row.
    pub ids: Vec<u64>,
    /// Per disk, the particle's outline and angle when the table has an
    /// `angle` column (particles that are not disks); empty otherwise. Each
    /// disk is then the particle's centre and area-equivalent radius.
    pub grains: Vec<Grain>,
}

impl PackingTable {
    /// Disk `i` (in file order) as a person finds it in the file: `disk id
    /// 2494 (line 2496)`, or `the disk on line 2496` without ids.
    pub fn disk_name(&self, i: usize) -> String {
        let line = self.lines.get(i).copied().unwrap_or(0);
        match self.ids.get(i) {
            Some(id) => format!("disk id {id} (line {line})"),
            None => format!("the disk on line {line}"),
        }
    }
}

/// How a table separates its fields: one character, or runs of blanks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Separator {
    Char(u8),
    Blanks,
}

impl Separator {
    /// The separator of a table whose header line is `header`: a comma if
    /// it has one, else a semicolon, else a tab, else runs of spaces.
    fn of(header: &str) -> Self {
        [b',', b';', b'\t']
            .into_iter()
            .find(|&c| header.as_bytes().contains(&c))
            .map_or(Separator::Blanks, Separator::Char)
    }
}

/// Why a table cannot be read as a packing: where (origin, line, column) and what.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{origin}:{line}:{column}: {message}")]
pub struct ReadError {
    /// The file the text came from, as given.
    pub origin: String,
    /// Line, from 1.
    pub line: u64,
    /// Column in characters, from 1.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// Most distinct materials a table may name (they are stored as `u16`).
const MAX_MATERIALS: usize = u16::MAX as usize;
/// Smallest disk diameter a table may hold (mm): a nanometre.
const MIN_DIAMETER: f64 = 1e-6;
/// Largest disk diameter a table may hold (mm): a kilometre.
const MAX_DIAMETER: f64 = 1e6;
/// Largest ratio of the largest to the smallest disk of one table
/// (gradings span three to four decades; a wider table is a unit mix-up or
/// a stray row, and would squeeze every chart of it).
const MAX_SIZE_RATIO: f64 = 1e6;
/// Largest distance of a disk centre from the origin (mm): a thousand kilometres.
const MAX_COORDINATE: f64 = 1e9;

/// Read a packing from CSV `text`; `origin` names it in errors.
///
/// # Errors
/// [`ReadError`] at the first fault: no header, a required column missing
/// (reported at the header), two columns for one part (reported at the second),
/// a row with the wrong number of fields, a value that is not a finite
/// number, a position or size out of range, a radius that is not positive,
/// no rows, or sizes more than `MAX_SIZE_RATIO` apart (reported at the
/// smallest).
///
/// # Example
/// ```
/// let t = gapack::output::read_packing_csv("id,x,y,r\n0,1.5,2,0.5\n", "p.csv").unwrap();
/// assert_eq!(t.disks.len(), 1);
/// assert_eq!(t.disks[0].r, 0.5);
/// let e = gapack::output::read_packing_csv("id,x,y,r\n0,1.5,abc,0.5\n", "p.csv").unwrap_err();
/// assert_eq!(e.to_string(), "p.csv:2:7: column y: expected a number, got \"abc\"");
/// ```
pub fn read_packing_csv(text: &str, origin: &str) -> Result<PackingTable, ReadError> {
    let fail = |line: u64, column: usize, message: String| ReadError {
        origin: origin.to_owned(),
        line,
        column,
        message,
    };
    // Lines ended by a carriage return alone (old Mac files) ended by a
    // line feed instead: one byte for one, so positions stay, and every
    // line count below sees them. CRLF stays as it is.
    let lf: String;
    let text = if has_bare_cr(text) {
        lf = bare_cr_to_lf(text);
        &lf
    } else {
        text
    };
    // Where each line starts, to locate a field from its line.
    let starts: Vec<usize> = std::iter::once(0)
        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
        .collect();
    // The header is the first line that is neither blank nor a comment.
    let header_line = text
        .lines()
        .position(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map_or(1, |i| i as u64 + 1);
    let header_text = text.lines().nth(header_line as usize - 1).unwrap_or("");
    let sep = Separator::of(header_text);
    // Fields separated by runs of blanks are read as one comma each, line
    // for line (the lines, and so the positions reported, stay the same).
    let commas: String;
    let read = match sep {
        Separator::Char(_) => text,
        Separator::Blanks => {
            commas = text
                .split_inclusive('\n')
                .map(|l| {
                    if l.starts_with('#') {
                        return l.to_owned();
                    }
                    let end = if l.ends_with('\n') { "\n" } else { "" };
                    let mut joined = l.split_whitespace().collect::<Vec<_>>().join(",");
                    joined.push_str(end);
                    joined
                })
                .collect();
            &commas
        }
    };
    let column_of = |line: u64, field: usize| column_at(text, &starts, line, field, sep);
    // The line (from 1) of a record of the text read, the same line in
    // `text`: the reader's own line count does not count blank lines, and
    // its position may be that of the blank or comment lines before it.
    let read_starts: Vec<usize> = std::iter::once(0)
        .chain(read.match_indices('\n').map(|(i, _)| i + 1))
        .collect();
    let line_of = |p: &::csv::Position| {
        // After a CRLF the reader's record starts at the LF: the line is
        // the one after it.
        let at = usize::try_from(p.byte()).unwrap_or(usize::MAX);
        let at = read.get(at..).map_or(at, |rest| {
            at + rest.len() - rest.trim_start_matches(['\r', '\n']).len()
        });
        let mut line = read_starts.partition_point(|&s| s <= at);
        while let Some(&next) = read_starts.get(line) {
            let this = &read[read_starts[line - 1]..next];
            if !(this.trim().is_empty() || this.starts_with('#')) {
                break;
            }
            line += 1;
        }
        line as u64
    };
    let mut reader = ::csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(::csv::Trim::All)
        .delimiter(match sep {
            Separator::Char(c) => c,
            Separator::Blanks => b',',
        })
        .from_reader(read.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| csv_fault(origin, &line_of, &column_of, &e))?
        .clone();
    let name_of = |field: usize| header.get(field).unwrap_or("?").to_owned();
    // The one column playing a part (`what`), found under any of `names`:
    // two of them leave the part ambiguous, and the table is refused.
    let find = |names: &[&str], what: &str| -> Result<Option<usize>, ReadError> {
        let mut found = header
            .iter()
            .enumerate()
            .filter(|(_, h)| names.iter().any(|n| h.eq_ignore_ascii_case(n)))
            .map(|(i, _)| i);
        let Some(first) = found.next() else {
            return Ok(None);
        };
        match found.next() {
            None => Ok(Some(first)),
            Some(second) => {
                let (a, b) = (name_of(first), name_of(second));
                let message = if a.eq_ignore_ascii_case(&b) {
                    format!(
                        "column {b:?} appears twice (fields {} and {}); keep one",
                        first + 1,
                        second + 1
                    )
                } else {
                    format!(
                        "columns {a:?} and {b:?} both give {what} (fields {} and {}); keep one",
                        first + 1,
                        second + 1
                    )
                };
                Err(fail(header_line, column_of(header_line, second), message))
            }
        }
    };
    let missing = |what: &str| {
        fail(
            header_line,
            1,
            format!(
                "missing column {what}; the header has: {}{}",
                header.iter().collect::<Vec<_>>().join(", "),
                if header.len() == 1 {
                    " (one field: fields are separated by commas, semicolons, tabs or spaces)"
                } else {
                    ""
                }
            ),
        )
    };
    let x = find(&["x"], "x")?.ok_or_else(|| missing("x"))?;
    let y = find(&["y"], "y")?.ok_or_else(|| missing("y"))?;
    let size = find(&["r", "radius", "d", "diameter"], "the disk size")?
        .ok_or_else(|| missing("r (or radius, d, diameter)"))?;
    let halve = ["d", "diameter"]
        .iter()
        .any(|n| header.get(size).is_some_and(|h| h.eq_ignore_ascii_case(n)));
    let material = find(&["material", "material_id", "mat"], "the material")?;
    let id = find(&["id"], "the id")?;
    let mut ids_whole = id.is_some();
    let shape = match find(&["angle"], "the angle")? {
        None => None,
        Some(angle) => Some(ShapeColumns::find(angle, &find, &missing)?),
    };
    // Halving is exact: the bounds on the diameter are bounds on twice the radius.
    let (size_min, size_max, size_word) = if halve {
        (MIN_DIAMETER, MAX_DIAMETER, "diameter")
    } else {
        (MIN_DIAMETER / 2.0, MAX_DIAMETER / 2.0, "radius")
    };
    // The smallest and largest size so far: (size, line).
    let mut smallest = (f64::INFINITY, 0);
    let mut largest = (0.0f64, 0);

    let mut table = PackingTable {
        disks: Vec::new(),
        materials: Vec::new(),
        material_names: Vec::new(),
        lines: Vec::new(),
        ids: Vec::new(),
        grains: Vec::new(),
    };
    let mut record = ::csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(csv_fault(origin, &line_of, &column_of, &e)),
        }
        let line = record.position().map_or(0, line_of);
        let at = |field: usize| column_of(line, field);
        let number = |field: usize| -> Result<f64, ReadError> {
            let raw = record.get(field).unwrap_or("");
            let name = header.get(field).unwrap_or("?");
            match raw.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                Ok(_) => Err(fail(
                    line,
                    at(field),
                    format!("column {name}: must be a finite number, got {raw:?}"),
                )),
                Err(_) => Err(fail(
                    line,
                    at(field),
                    format!("column {name}: expected a number, got {raw:?}"),
                )),
            }
        };
        let (cx, cy, s) = (number(x)?, number(y)?, number(size)?);
        for (field, v) in [(x, cx), (y, cy)] {
            if v.abs() > MAX_COORDINATE {
                return Err(fail(
                    line,
                    at(field),
                    format!(
                        "column {}: a coordinate must lie in [-{MAX_COORDINATE:e}, {MAX_COORDINATE:e}] mm, got {v:e}",
                        name_of(field)
                    ),
                ));
            }
        }
        if s <= 0.0 {
            return Err(fail(
                line,
                at(size),
                format!(
                    "column {}: a disk's size must be positive, got {s}",
                    name_of(size)
                ),
            ));
        }
        if !(size_min..=size_max).contains(&s) {
            return Err(fail(
                line,
                at(size),
                format!(
                    "column {}: a {size_word} must lie in [{size_min:e}, {size_max:e}] mm, got {s:e}",
                    name_of(size)
                ),
            ));
        }
        if s < smallest.0 {
            smallest = (s, line);
        }
        if s > largest.0 {
            largest = (s, line);
        }
        let r = if halve { s / 2.0 } else { s };
        if let Some(cols) = &shape {
            let grain = cols.grain(&record, &number, &|field, message| {
                fail(line, at(field), message)
            })?;
            let equivalent = grain.outline.equivalent_radius();
            if (equivalent - r).abs() > EQUIVALENT_REL * equivalent {
                return Err(fail(
                    line,
                    at(size),
                    format!(
                        "column {}: a particle's r must be its area-equivalent radius sqrt(area/pi) = {equivalent}, got {r}",
                        name_of(size)
                    ),
                ));
            }
            table.grains.push(grain);
        }
        table.disks.push(Disk::new(cx, cy, r));
        table.lines.push(line);
        if let Some(field) = id.filter(|_| ids_whole) {
            match record.get(field).and_then(|v| v.parse::<u64>().ok()) {
                Some(v) => table.ids.push(v),
                None => ids_whole = false,
            }
        }
        if let Some(m) = material {
            let name = record.get(m).unwrap_or("");
            let index = match table.material_names.iter().position(|n| n == name) {
                Some(i) => i,
                None if table.material_names.len() < MAX_MATERIALS => {
                    table.material_names.push(name.to_owned());
                    table.material_names.len() - 1
                }
                None => {
                    return Err(fail(
                        line,
                        at(m),
                        format!("column material: more than {MAX_MATERIALS} distinct materials"),
                    ));
                }
            };
            table.materials.push(index as u16);
        }
    }
    if table.disks.is_empty() {
        return Err(fail(
            header_line + 1,
            1,
            "no disks: the table has no rows".to_owned(),
        ));
    }
    if !ids_whole {
        table.ids = Vec::new();
    }
    if largest.0 > MAX_SIZE_RATIO * smallest.0 {
        let (s, line) = smallest;
        return Err(fail(
            line,
            column_of(line, size),
            format!(
                "column {}: {s:e} is more than {MAX_SIZE_RATIO:e} times smaller than the largest {size_word}, {:e} (line {}); the sizes of one packing may differ by that factor at most",
                name_of(size),
                largest.0,
                largest.1
            ),
        ));
    }
    Ok(table)
}

/// Largest relative difference between a particle's `r` and the
/// area-equivalent radius of its outline (a table made elsewhere computes
/// the area its own way, to a few ulps).
const EQUIVALENT_REL: f64 = 1e-6;

/// Most vertices of one polygon in a table.
const MAX_VERTICES: usize = 10_000;

/// The fields of the particle columns of a table with an `angle` column.
struct ShapeColumns {
    /// `angle`.
    angle: usize,
    /// `a`, `b`, `alpha`, `beta`, when the table has them.
    superellipse: Option<[usize; 4]>,
    /// `template`, `rounding`, `vertices`, when the table has them.
    polygon: Option<[usize; 3]>,
}

/// A column finder: the one field under any of the names, if any.
type Find<'a> = dyn Fn(&[&str], &str) -> Result<Option<usize>, ReadError> + 'a;

impl ShapeColumns {
    /// The particle columns next to `angle`: every column of a family, or
    /// none of it; at least one family.
    fn find(
        angle: usize,
        find: &Find<'_>,
        missing: &dyn Fn(&str) -> ReadError,
    ) -> Result<Self, ReadError> {
        let mut se = [None; 4];
        for (slot, name) in se.iter_mut().zip(["a", "b", "alpha", "beta"]) {
            *slot = find(&[name], name)?;
        }
        let mut poly = [None; 3];
        for (slot, name) in poly.iter_mut().zip(["template", "rounding", "vertices"]) {
            *slot = find(&[name], name)?;
        }
        let whole = |cols: &[Option<usize>], names: &str| -> Result<bool, ReadError> {
            match cols.iter().filter(|c| c.is_some()).count() {
                0 => Ok(false),
                k if k == cols.len() => Ok(true),
                _ => Err(missing(names)),
            }
        };
        let has_se = whole(&se, "a, b, alpha and beta (a superellipse needs all four)")?;
        let has_poly = whole(
            &poly,
            "template, rounding and vertices (a rounded polygon needs all three)",
        )?;
        if !has_se && !has_poly {
            return Err(missing(
                "a, b, alpha, beta (superellipses) or template, rounding, vertices (rounded polygons) next to angle",
            ));
        }
        let all = |cols: &[Option<usize>]| cols.iter().copied().collect::<Option<Vec<_>>>();
        Ok(ShapeColumns {
            angle,
            superellipse: if has_se {
                all(&se).and_then(|v| v.try_into().ok())
            } else {
                None
            },
            polygon: if has_poly {
                all(&poly).and_then(|v| v.try_into().ok())
            } else {
                None
            },
        })
    }

    /// The particle of one row: a superellipse if its `a` cell is filled,
    /// else a rounded polygon if its `vertices` cell is.
    fn grain(
        &self,
        record: &::csv::StringRecord,
        number: &dyn Fn(usize) -> Result<f64, ReadError>,
        fail: &dyn Fn(usize, String) -> ReadError,
    ) -> Result<Grain, ReadError> {
        let filled = |field: usize| record.get(field).is_some_and(|v| !v.is_empty());
        let angle = number(self.angle)?;
        if let Some([a, b, alpha, beta]) = self.superellipse.filter(|f| filled(f[0])) {
            let outline =
                Outline::superellipse(number(a)?, number(b)?, number(alpha)?, number(beta)?)
                    .map_err(|e| fail(a, format!("superellipse: {e}")))?;
            return Ok(Grain::new(outline, angle));
        }
        let Some([template, rounding, vertices]) = self.polygon.filter(|f| filled(f[2])) else {
            return Err(fail(
                self.angle,
                "the row gives no particle: fill a, b, alpha, beta (a superellipse) or template, rounding, vertices (a rounded polygon)".to_owned(),
            ));
        };
        let raw = record.get(template).unwrap_or("");
        let template_index = raw.parse::<u16>().map_err(|_| {
            fail(
                template,
                format!("column template: expected a whole number from 0 to 65535, got {raw:?}"),
            )
        })?;
        let rounding_value = number(rounding)?;
        let points = parse_vertices(record.get(vertices).unwrap_or(""))
            .map_err(|message| fail(vertices, format!("column vertices: {message}")))?;
        let checked = Outline::polygon(template_index, &points, rounding_value)
            .map_err(|e| fail(vertices, format!("column vertices: {e}")))?;
        // The particle's centre is (x, y): its vertices must be about their
        // centroid (the check moved it to the origin).
        let scale = points.iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        let (c, signed) = centroid_of(&points);
        if c.coords.norm() > 1e-9 * scale {
            return Err(fail(
                vertices,
                format!(
                    "column vertices: the vertices must be given about the particle's centre, their centroid at (0, 0); it is at ({}, {})",
                    c.x, c.y
                ),
            ));
        }
        if signed < 0.0 {
            // Clockwise: the check's counter-clockwise order.
            return Ok(Grain::new(checked, angle));
        }
        // As written (exactly): the file's own numbers.
        Ok(Grain::new(
            Outline::Polygon {
                template: template_index,
                vertices: points.into(),
                rounding: rounding_value,
            },
            angle,
        ))
    }
}

/// The vertices of a `vertices` cell, `x1 y1;x2 y2;…`.
fn parse_vertices(cell: &str) -> Result<Vec<Point>, String> {
    let mut points = Vec::new();
    for (k, vertex) in cell.split(';').enumerate() {
        if k >= MAX_VERTICES {
            return Err(format!("more than {MAX_VERTICES} vertices"));
        }
        let coords: Vec<&str> = vertex.split_whitespace().collect();
        let [x, y] = coords.as_slice() else {
            return Err(format!(
                "vertex {}: expected two numbers \"x y\", got {vertex:?} (vertices are written x1 y1;x2 y2;...)",
                k + 1
            ));
        };
        let parse = |v: &str| match v.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!(
                "vertex {}: expected a finite number, got {v:?}",
                k + 1
            )),
        };
        points.push(Point::new(parse(x)?, parse(y)?));
    }
    Ok(points)
}

/// Area centroid of a simple polygon and its signed area times 2
/// (positive counter-clockwise); the mean of its vertices if it has no area.
fn centroid_of(points: &[Point]) -> (Point, f64) {
    let n = points.len();
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        let cross = p.x * q.y - q.x * p.y;
        a += cross;
        cx += (p.x + q.x) * cross;
        cy += (p.y + q.y) * cross;
    }
    if a == 0.0 {
        let k = n.max(1) as f64;
        let mean = Point::new(
            points.iter().map(|p| p.x).sum::<f64>() / k,
            points.iter().map(|p| p.y).sum::<f64>() / k,
        );
        return (mean, 0.0);
    }
    (Point::new(cx / (3.0 * a), cy / (3.0 * a)), a)
}

/// A fault of the CSV reader itself (bad UTF-8, a row of the wrong
/// length), located with `line_of` (position → line) and `column_of`
/// (line, field → column).
fn csv_fault(
    origin: &str,
    line_of: &dyn Fn(&::csv::Position) -> u64,
    column_of: &dyn Fn(u64, usize) -> usize,
    e: &::csv::Error,
) -> ReadError {
    let (line, column) = e.position().map_or((1, 1), |p| {
        let line = line_of(p);
        (line, column_of(line, 0))
    });
    let message = match e.kind() {
        ::csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("expected {expected_len} fields like the header, got {len}"),
        _ => e.to_string(),
    };
    ReadError {
        origin: origin.to_owned(),
        line: line.max(1),
        column,
        message,
    }
}

/// Character column (from 1) of field `field` on line `line` (from 1) of
/// Whether `text` has a carriage return not followed by a line feed.
fn has_bare_cr(text: &str) -> bool {
    let bytes = text.as_bytes();
    bytes
        .iter()
        .enumerate()
        .any(|(i, &b)| b == b'\r' && bytes.get(i + 1) != Some(&b'\n'))
}

/// `text` with each carriage return not followed by a line feed made a line feed.
fn bare_cr_to_lf(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        out.push(if c == '\r' && chars.peek() != Some(&'\n') {
            '\n'
        } else {
            c
        });
    }
    out
}

/// `text`, whose lines start at `starts`, its fields separated by `sep`.
fn column_at(text: &str, starts: &[usize], line: u64, field: usize, sep: Separator) -> usize {
    let start = usize::try_from(line.max(1) - 1)
        .ok()
        .and_then(|i| starts.get(i))
        .copied()
        .unwrap_or(0);
    let Some(rest) = text.get(start..) else {
        return 1;
    };
    let blank = |c: char| c == ' ' || c == '\t';
    let mut seen = 0;
    let mut quoted = false;
    let mut chars = rest.chars().enumerate().peekable();
    if sep == Separator::Blanks {
        // Leading blanks are no field.
        while chars.next_if(|&(_, c)| blank(c)).is_some() {}
    }
    while let Some((i, ch)) = chars.next() {
        if seen == field {
            // Skip the blanks that trimming ignored.
            let blanks = rest.chars().skip(i).take_while(|&c| blank(c)).count();
            return i + blanks + 1;
        }
        match (ch, sep) {
            ('"', Separator::Char(_)) => quoted = !quoted,
            ('\n', _) if !quoted => break,
            (c, Separator::Char(d)) if !quoted && c == char::from(d) => seen += 1,
            (c, Separator::Blanks) if blank(c) => {
                while chars.next_if(|&(_, c)| blank(c)).is_some() {}
                seen += 1;
            }
            _ => {}
        }
    }
    1
}

impl fmt::Display for PackingTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} disks", self.disks.len())?;
        if !self.material_names.is_empty() {
            write!(f, " of {} materials", self.material_names.len())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fault(text: &str) -> String {
        read_packing_csv(text, "p.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_gapack_s_own_table_with_materials() {
        let t = read_packing_csv(
            "id,x,y,r,material\n0,1,2,0.5,sand\n1,3,2,0.25,clay\n2,5,2,0.5,sand\n",
            "p.csv",
        )
        .unwrap();
        assert_eq!(t.disks.len(), 3);
        assert_eq!(t.disks[1], Disk::new(3.0, 2.0, 0.25));
        assert_eq!(t.materials, [0, 1, 0]);
        assert_eq!(t.material_names, ["sand", "clay"]);
        assert_eq!(t.to_string(), "3 disks of 2 materials");
    }

    #[test]
    fn reads_other_tools_tables_by_column_name() {
        let t = read_packing_csv("# from elsewhere\nDiameter, X, Y\n1.0, 4, 5\n", "p.csv").unwrap();
        assert_eq!(t.disks, [Disk::new(4.0, 5.0, 0.5)]);
        assert!(t.materials.is_empty());
    }

    #[test]
    fn round_trips_every_bit() {
        let x = 0.1 + 0.2;
        let t =
            read_packing_csv(&format!("x,y,r\n{x},{},{}\n", 1e-7, 2.0f64.sqrt()), "p.csv").unwrap();
        assert_eq!(t.disks[0], Disk::new(x, 1e-7, 2.0f64.sqrt()));
    }

    #[test]
    fn faults_name_line_and_column() {
        assert_eq!(
            fault("id,x,y\n0,1,2\n"),
            "p.csv:1:1: missing column r (or radius, d, diameter); the header has: id, x, y"
        );
        assert_eq!(
            fault("id,x,y,r\n0,1,2,0.5\n1,3,nan,0.5\n"),
            "p.csv:3:5: column y: must be a finite number, got \"nan\""
        );
        assert_eq!(
            fault("id,x,y,r\n0,1,2,0.5\n1, 3 ,2,x\n"),
            "p.csv:3:9: column r: expected a number, got \"x\""
        );
        assert_eq!(
            fault("id,x,y,r\n0,1,2,-0.5\n"),
            "p.csv:2:7: column r: a disk's size must be positive, got -0.5"
        );
        assert_eq!(
            fault("id,x,y,r\n0,1,2\n"),
            "p.csv:2:1: expected 4 fields like the header, got 3"
        );
        assert_eq!(
            fault("id,x,y,r\n"),
            "p.csv:2:1: no disks: the table has no rows"
        );
        assert_eq!(fault(""), "p.csv:1:1: missing column x; the header has: ");
    }

    #[test]
    fn semicolons_tabs_and_spaces_separate_fields_too() {
        let comma = read_packing_csv("id,x,y,r\n0,1.5,2,0.5\n7,3,4,0.25\n", "p.csv").unwrap();
        for text in [
            "id;x;y;r\n0;1.5;2;0.5\n7;3;4;0.25\n",
            "id\tx\ty\tr\n0\t1.5\t2\t0.5\n7\t3\t4\t0.25\n",
            "id x y r\n0 1.5 2 0.5\n  7   3 4   0.25  \n",
            "# a comment, with a comma\nid x y r\n0 1.5 2 0.5\n7 3 4 0.25",
        ] {
            let t = read_packing_csv(text, "p.csv").unwrap();
            assert_eq!(t.disks, comma.disks, "{text:?}");
            assert_eq!(t.ids, [0, 7], "{text:?}");
        }
        // Faults name the column of the original text.
        assert_eq!(
            fault("id x  y r\n0 1  2 0.5\n1 3  z 0.5\n"),
            "p.csv:3:6: column y: expected a number, got \"z\""
        );
        assert_eq!(
            fault("id;x;y;r\n0;1;2;0.5\n1;3;2;-1\n"),
            "p.csv:3:7: column r: a disk's size must be positive, got -1"
        );
        // One field: the header names what separates fields.
        assert_eq!(
            fault("id|x|y|r\n0|1|2|0.5\n"),
            "p.csv:1:1: missing column x; the header has: id|x|y|r (one field: fields are separated by commas, semicolons, tabs or spaces)"
        );
    }

    #[test]
    fn disks_are_named_by_id_and_file_line() {
        let t = read_packing_csv(
            "# made by hand\nid,x,y,r\n2494,1,2,0.5\n\n17,3,4,0.5\n",
            "p.csv",
        )
        .unwrap();
        assert_eq!(t.lines, [3, 5]);
        assert_eq!(t.disk_name(1), "disk id 17 (line 5)");
        // Without whole-number ids, by line alone.
        let t = read_packing_csv("x,y,r\n1,2,0.5\n3,4,0.5\n", "p.csv").unwrap();
        assert!(t.ids.is_empty());
        assert_eq!(t.disk_name(0), "the disk on line 2");
        let t = read_packing_csv("id,x,y,r\na,1,2,0.5\n3,3,4,0.5\n", "p.csv").unwrap();
        assert!(t.ids.is_empty());
    }

    #[test]
    fn crlf_and_cr_line_ends_keep_the_file_lines() {
        // The same table with LF, CRLF and CR line ends, comma, semicolon,
        // tab or blank separated: each disk on the line it is written on.
        for sep in [",", ";", "\t", " "] {
            let lf = format!(
                "# by hand\nid{sep}x{sep}y{sep}r\n3{sep}1{sep}1{sep}0.5\n\n12{sep}5{sep}5{sep}0.5\n"
            );
            for end in ["\n", "\r\n", "\r"] {
                let text = lf.replace('\n', end);
                let t = read_packing_csv(&text, "p.csv").unwrap();
                assert_eq!(t.lines, [3, 5], "{text:?}");
                assert_eq!(t.disk_name(1), "disk id 12 (line 5)", "{text:?}");
                let bad = text.replace("12", "x12").replace("0.5", "0.5e");
                let e = read_packing_csv(&bad, "p.csv").unwrap_err();
                assert_eq!((e.line, e.column), (3, 7), "{bad:?}: {e}");
            }
        }
    }

    #[test]
    fn two_columns_for_one_part_are_refused_at_the_second() {
        assert_eq!(
            fault("x,y,r,d\n0,0,1,2\n"),
            "p.csv:1:7: columns \"r\" and \"d\" both give the disk size (fields 3 and 4); keep one"
        );
        assert_eq!(
            fault("# two x\nx, y, x, r\n0,0,1,2\n"),
            "p.csv:2:7: column \"x\" appears twice (fields 1 and 3); keep one"
        );
        assert_eq!(
            fault("x,y,Radius,diameter\n0,0,1,2\n"),
            "p.csv:1:12: columns \"Radius\" and \"diameter\" both give the disk size (fields 3 and 4); keep one"
        );
        assert_eq!(
            fault("x,y,r,mat,material\n0,0,1,a,b\n"),
            "p.csv:1:11: columns \"mat\" and \"material\" both give the material (fields 4 and 5); keep one"
        );
    }

    #[test]
    fn sizes_and_positions_out_of_range_are_refused() {
        assert_eq!(
            fault("x,y,r\n0,0,5e-324\n"),
            "p.csv:2:5: column r: a radius must lie in [5e-7, 5e5] mm, got 5e-324"
        );
        assert_eq!(
            fault("x,y,d\n0,0,1e300\n"),
            "p.csv:2:5: column d: a diameter must lie in [1e-6, 1e6] mm, got 1e300"
        );
        assert_eq!(
            fault("x,y,r\n1,2,1\n1e12,2,1\n"),
            "p.csv:3:1: column x: a coordinate must lie in [-1e9, 1e9] mm, got 1e12"
        );
        assert_eq!(
            fault("x,y,r\n0,0,1e-6\n5,0,2\n"),
            "p.csv:2:5: column r: 1e-6 is more than 1e6 times smaller than the largest radius, 2e0 (line 3); the sizes of one packing may differ by that factor at most"
        );
        // At the limits: read.
        let t = read_packing_csv("x,y,d\n-1e9,1e9,1e-6\n0,0,1\n", "p.csv").unwrap();
        assert_eq!(t.disks[0], Disk::new(-1e9, 1e9, 5e-7));
    }

    #[test]
    fn particle_columns_round_trip_every_bit() {
        use crate::geometry::{Domain, Grain, Outline};
        use crate::output::csv::write_packing_csv;
        use crate::packer::Packing;
        let se = Outline::superellipse(0.1 + 0.2, 1.0 / 3.0, 2.5, 7.0).expect("valid");
        let square = [
            Point::new(-0.5, -0.5),
            Point::new(0.5, -0.5),
            Point::new(0.5, 0.5),
            Point::new(-0.5, 0.5),
        ];
        let poly = Outline::polygon(3, &square, 0.125).expect("valid");
        let grains = vec![Grain::new(se, 0.7), Grain::new(poly, -1.0 / 7.0)];
        let disks = grains
            .iter()
            .zip([1.0, 4.0])
            .map(|(g, x)| Disk::new(x, 2.0, g.outline.equivalent_radius()))
            .collect();
        let packing = Packing {
            grains: grains.clone(),
            ..Packing::of_disks(Domain::rectangle(10.0, 10.0).expect("valid"), disks)
        };
        let mut bytes = Vec::new();
        write_packing_csv(&packing, &[], &[], &mut bytes).expect("csv");
        let text = String::from_utf8(bytes).expect("utf-8");
        assert!(text.starts_with("id,x,y,r,angle,a,b,alpha,beta,template,rounding,vertices\n"));
        assert!(
            text.contains(",,,,3,0.125,-0.5 -0.5;0.5 -0.5;0.5 0.5;-0.5 0.5\n"),
            "{text}"
        );
        let t = read_packing_csv(&text, "p.csv").expect("reads");
        assert_eq!(t.grains, grains);
        assert_eq!(t.disks, packing.disks);
        // Bad vertices, a wrong r, or vertices off the centre, are refused.
        let bad = text.replacen("0.5 0.5;", "0.5;", 1);
        assert!(
            fault(&bad).contains("vertex 3: expected two numbers"),
            "{}",
            fault(&bad)
        );
        let off = "x,y,r,angle,template,rounding,vertices\n0,0,1,0,0,0,1 1;2 1;2 2;1 2\n";
        assert!(
            fault(off).contains("centroid at (0, 0); it is at (1.5, 1.5)"),
            "{}",
            fault(off)
        );
        let wrong_r = "x,y,r,angle,a,b,alpha,beta\n0,0,1,0,2,2,2,2\n";
        assert!(
            fault(wrong_r).contains("area-equivalent radius"),
            "{}",
            fault(wrong_r)
        );
    }
}
