//! Reading a packing back from CSV, for `gapack verify` and `gapack plot`:
//! gapack's own `packing.csv` or a table written by another tool.
//!
//! The text is given (the caller reads the file), so this is parsing only.
//! Columns are found by header name, case-insensitively: `x`, `y`, and one
//! of `r`/`radius` or `d`/`diameter`; `material` is optional (a name or a
//! number); any other column is ignored. Lines starting with `#` are comments.

use std::fmt;

use crate::geometry::Disk;

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

/// Read a packing from CSV `text`; `origin` names it in errors.
///
/// # Errors
/// [`ReadError`] at the first fault: no header, a required column missing
/// (reported at line 1), a row with the wrong number of fields, a value that
/// is not a finite number, a radius that is not positive, or no rows.
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
    let mut reader = ::csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(::csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| csv_fault(origin, text, &e))?
        .clone();
    let header_line = header.position().map_or(1, |p| p.line()).max(1);
    let find = |names: &[&str]| {
        header
            .iter()
            .position(|h| names.iter().any(|n| h.eq_ignore_ascii_case(n)))
    };
    let missing = |what: &str| {
        fail(
            header_line,
            1,
            format!(
                "missing column {what}; the header has: {}",
                header.iter().collect::<Vec<_>>().join(", ")
            ),
        )
    };
    let x = find(&["x"]).ok_or_else(|| missing("x"))?;
    let y = find(&["y"]).ok_or_else(|| missing("y"))?;
    let (size, halve) = match (find(&["r", "radius"]), find(&["d", "diameter"])) {
        (Some(r), _) => (r, false),
        (None, Some(d)) => (d, true),
        (None, None) => return Err(missing("r (or radius, d, diameter)")),
    };
    let material = find(&["material", "material_id", "mat"]);

    let mut table = PackingTable {
        disks: Vec::new(),
        materials: Vec::new(),
        material_names: Vec::new(),
    };
    let mut record = ::csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(csv_fault(origin, text, &e)),
        }
        let (line, start) = record
            .position()
            .map_or((0, 0), |p| (p.line(), p.byte() as usize));
        let at = |field: usize| column_of(text, start, field);
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
        let r = if halve { s / 2.0 } else { s };
        if r <= 0.0 {
            return Err(fail(
                line,
                at(size),
                format!(
                    "column {}: a disk's size must be positive, got {s}",
                    header.get(size).unwrap_or("r")
                ),
            ));
        }
        table.disks.push(Disk::new(cx, cy, r));
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
    Ok(table)
}

/// A fault of the CSV reader itself (bad UTF-8, a row of the wrong length), located.
fn csv_fault(origin: &str, text: &str, e: &::csv::Error) -> ReadError {
    let (line, column) = e.position().map_or((1, 1), |p| {
        (p.line(), column_of(text, p.byte() as usize, 0))
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

/// Character column (from 1) of field `field` of the record starting at byte `start`.
fn column_of(text: &str, start: usize, field: usize) -> usize {
    let Some(rest) = text.get(start..) else {
        return 1;
    };
    // Where the record starts on its line (a record may follow a comment on the same read).
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    let lead = text[line_start..start].chars().count();
    let mut commas = 0;
    let mut quoted = false;
    for (i, ch) in rest.chars().enumerate() {
        if commas == field {
            // Skip the blanks that trimming ignored.
            let blanks = rest
                .chars()
                .skip(i)
                .take_while(|c| *c == ' ' || *c == '\t')
                .count();
            return lead + i + blanks + 1;
        }
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => commas += 1,
            '\n' if !quoted => break,
            _ => {}
        }
    }
    lead + 1
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
}
