//! The web page and what it draws: the page and its assets (`/`,
//! `/app.js`, `/app.css`, open to anyone: they hold no data), a finished
//! job's packing as columns (`GET /jobs/{id}/packing`) and the shipped
//! example configs (`GET /examples`).

use std::collections::HashMap;
use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::sync::Arc;

use axum::Extension;
use axum::body::{Body, Bytes};
use axum::extract::State;
use axum::http::{StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use gapack::jobs::{JobKind, Plan, Request as JobRequest};
use gapack::output::{PackingTable, ReadError};
use gapack::{Domain, Grain, Outline};
use serde::ser::{Error as _, SerializeSeq};
use serde::{Serialize, Serializer};
use tokio::sync::mpsc;
use utoipa::ToSchema;

use super::error::{ApiError, ErrorBody};
use super::files::manifest;
use super::jobs::JobId;
use super::{AppState, blocking};
use crate::Shared;
use crate::store::Caller;
use crate::web;
use crate::worker::{ORIGIN, job_dir};

/// The API routes of the page's data (under `/api/v1`, guarded).
pub fn data() -> Router<Arc<Shared>> {
    Router::new()
        .route("/jobs/{id}/packing", get(packing))
        .route("/examples", get(examples))
}

/// The page and its assets (open).
pub fn web() -> Router<Arc<Shared>> {
    Router::new()
        .route("/", get(web::index))
        .route("/app.js", get(web::script))
        .route("/app.css", get(web::style))
}

/// A finished job's packing, for drawing: the domain's outline and the
/// disks as columns; for particles that are not disks, their outlines too.
// Its columns are written as the body is sent, each from its own pass over
// `packing.csv` (see `Rows`), so that a packing of any size costs the
// server a batch of rows rather than the whole view.
#[derive(Serialize, ToSchema)]
pub struct PackingView {
    /// The domain's boundary, a closed polyline (mm; circles as 256 segments).
    outline: Vec<[f64; 2]>,
    /// Lower-left and upper-right corners of the domain's bounding box (mm).
    bounds: [[f64; 2]; 2],
    /// Centres and radii (mm), in `packing.csv`'s order (`id` is the index).
    #[schema(value_type = Vec<f64>)]
    x: Column<f64>,
    #[schema(value_type = Vec<f64>)]
    y: Column<f64>,
    #[schema(value_type = Vec<f64>)]
    r: Column<f64>,
    /// Per disk, an index into `materials`; empty without materials.
    #[schema(value_type = Vec<u16>)]
    material: Column<u16>,
    /// Material names.
    #[schema(value_type = Vec<String>)]
    materials: Names,
    /// Particles that are not disks (`packing.csv` with an `angle` column):
    /// each one's outline, as columns in the same order; absent for disks
    /// (`r` is then each particle's area-equivalent radius).
    #[serde(skip_serializing_if = "Option::is_none")]
    shapes: Option<ShapesView>,
}

/// The outlines of a packing's particles that are not disks, as columns of
/// one value per particle (in `packing.csv`'s order), as `packing.csv`
/// gives them: a superellipse |x'/a|^alpha + |y'/b|^beta <= 1 or a convex
/// polygon rounded by a disk of radius `rounding`, in the particle's own
/// axes (x', y') about its centre, turned by `angle`. A family's columns are
/// absent when no particle is of it, and null for a particle of the other.
#[derive(Serialize, ToSchema)]
#[schema(as = PackingShapes)]
pub struct ShapesView {
    /// Radians, counter-clockwise from the x axis to the particle's own x' axis.
    #[schema(value_type = Vec<f64>)]
    angle: Column<f64>,
    /// Superellipses: semi-axis along x' (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<f64>>>)]
    a: Option<Column<Option<f64>>>,
    /// Superellipses: semi-axis along y' (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<f64>>>)]
    b: Option<Column<Option<f64>>>,
    /// Superellipses: exponent of x' (>= 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<f64>>>)]
    alpha: Option<Column<Option<f64>>>,
    /// Superellipses: exponent of y' (>= 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<f64>>>)]
    beta: Option<Column<Option<f64>>>,
    /// Rounded polygons: the index of the config's template.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<u16>>>)]
    template: Option<Column<Option<u16>>>,
    /// Rounded polygons: the corner radius (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<f64>>>)]
    rounding: Option<Column<Option<f64>>>,
    /// Rounded polygons: the vertices (mm) in the particle's own axes,
    /// counter-clockwise about its centroid (the particle's centre).
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schema(value_type = Option<Vec<Option<Vec<[f64; 2]>>>>)]
    vertices: Option<Column<Option<Vec<[f64; 2]>>>>,
}

/// A superellipse's `a`, `b`, `alpha`, `beta`; `None` for a polygon.
fn superellipse(g: &Grain) -> Option<[f64; 4]> {
    match g.outline {
        Outline::Superellipse { a, b, alpha, beta } => Some([a, b, alpha, beta]),
        Outline::Polygon { .. } => None,
    }
}

/// A rounded polygon's template, rounding and vertices; `None` for a superellipse.
fn polygon(g: &Grain) -> Option<(u16, f64, Vec<[f64; 2]>)> {
    match &g.outline {
        Outline::Superellipse { .. } => None,
        Outline::Polygon {
            template,
            vertices,
            rounding,
        } => Some((
            *template,
            *rounding,
            vertices.iter().map(|v| [v.x, v.y]).collect(),
        )),
    }
}

impl ShapesView {
    /// The columns of the particles of `rows`; `None` for disks.
    fn of(rows: &Arc<Rows>) -> Option<Self> {
        /// A family's column, when some particle is of it.
        fn column<T>(present: bool, rows: &Arc<Rows>, cells: Cells<T>) -> Option<Column<T>> {
            present.then(|| Column::of(rows, cells))
        }
        if !rows.grains {
            return None;
        }
        let (se, poly) = (rows.superellipses, rows.polygons);
        Some(ShapesView {
            angle: Column::of(rows, |t| t.grains.iter().map(|g| g.angle).collect()),
            a: column(se, rows, |t| {
                t.grains
                    .iter()
                    .map(|g| superellipse(g).map(|s| s[0]))
                    .collect()
            }),
            b: column(se, rows, |t| {
                t.grains
                    .iter()
                    .map(|g| superellipse(g).map(|s| s[1]))
                    .collect()
            }),
            alpha: column(se, rows, |t| {
                t.grains
                    .iter()
                    .map(|g| superellipse(g).map(|s| s[2]))
                    .collect()
            }),
            beta: column(se, rows, |t| {
                t.grains
                    .iter()
                    .map(|g| superellipse(g).map(|s| s[3]))
                    .collect()
            }),
            template: column(poly, rows, |t| {
                t.grains.iter().map(|g| polygon(g).map(|p| p.0)).collect()
            }),
            rounding: column(poly, rows, |t| {
                t.grains.iter().map(|g| polygon(g).map(|p| p.1)).collect()
            }),
            vertices: column(poly, rows, |t| {
                t.grains.iter().map(|g| polygon(g).map(|p| p.2)).collect()
            }),
        })
    }
}

/// The cells of one column for a batch of rows (its materials already
/// numbered as in the whole file).
type Cells<T> = fn(&PackingTable) -> Vec<T>;

/// One column of the view, written as it is serialized: a pass over
/// `packing.csv`, a batch of rows at a time.
struct Column<T> {
    /// The file.
    rows: Arc<Rows>,
    /// The column's cells of a batch; `None` for an empty column.
    cells: Option<Cells<T>>,
}

impl<T> Column<T> {
    /// The column `cells` picks from each batch of `rows`.
    fn of(rows: &Arc<Rows>, cells: Cells<T>) -> Self {
        Column {
            rows: Arc::clone(rows),
            cells: Some(cells),
        }
    }
}

impl<T: Serialize> Serialize for Column<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        // The same bytes as a `Vec`'s: `[`, the cells between commas, `]`.
        let mut seq = serializer.serialize_seq(None)?;
        if let Some(cells) = self.cells {
            self.rows.for_each_batch(S::Error::custom, |table| {
                cells(table)
                    .iter()
                    .try_for_each(|cell| seq.serialize_element(cell))
            })?;
        }
        seq.end()
    }
}

/// The material names of a packing, in order of first appearance.
struct Names(Arc<Rows>);

impl Serialize for Names {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.materials.serialize(serializer)
    }
}

/// Bytes of `packing.csv` parsed at a time, about (whole rows): what one
/// request for the view holds of it, whatever the packing's size (with
/// its parsed table, about three times as much).
const BATCH_BYTES: usize = 256 << 10;

/// Bytes of the view handed to the connection at a time.
const CHUNK_BYTES: usize = 64 << 10;

/// Chunks of the view written ahead of the connection: with the batch
/// being parsed, what a slow client can make the server hold.
const CHUNKS_AHEAD: usize = 4;

/// Why `packing.csv` could not be read as the view's rows.
#[derive(Debug, thiserror::Error)]
enum RowsError {
    /// The file could not be read.
    #[error("packing.csv: {0}")]
    Io(#[from] std::io::Error),
    /// A row is not a packing's (as the library's reader says, at the file's line).
    #[error(transparent)]
    Read(#[from] ReadError),
    /// The file is not the one first read (a material appeared).
    #[error("packing.csv changed while it was being sent")]
    Changed,
    /// More material names than a `u16` numbers.
    #[error("packing.csv: more than {} distinct materials", u16::MAX)]
    Materials,
}

/// A job's `packing.csv` as the view reads it: read once whole to check it
/// (as [`gapack::output::read_packing_csv`] checks a table) and to learn
/// its materials and particle families, then once per column of the view.
/// Each pass parses about `batch_bytes` of whole rows at a time, under the
/// file's header, with the library's own reader: the values, and so the
/// view, are those of reading the file whole.
struct Rows {
    /// The file.
    path: PathBuf,
    /// About how many bytes of rows a batch holds.
    batch_bytes: usize,
    /// The header line (the first line neither blank nor a comment), with its end.
    header: Vec<u8>,
    /// Its line in the file, from 1.
    header_line: u64,
    /// The material names, in order of first appearance in the file.
    materials: Vec<String>,
    /// The index of each of `materials`.
    numbers: HashMap<String, u16>,
    /// Whether the rows are particles that are not disks (an `angle` column).
    grains: bool,
    /// Whether some particle is a superellipse.
    superellipses: bool,
    /// Whether some particle is a rounded polygon.
    polygons: bool,
}

impl Rows {
    /// `path` read through once and checked.
    ///
    /// # Errors
    /// The file cannot be read, or it is not a packing (at its first fault).
    fn scan(path: PathBuf, batch_bytes: usize) -> Result<Self, RowsError> {
        let mut rows = Rows {
            path,
            batch_bytes,
            header: Vec::new(),
            header_line: 0,
            materials: Vec::new(),
            numbers: HashMap::new(),
            grains: false,
            superellipses: false,
            polygons: false,
        };
        let mut materials = Vec::new();
        let mut numbers = HashMap::new();
        let (mut grains, mut superellipses, mut polygons) = (false, false, false);
        let (header, header_line) = rows.batches(|table| {
            for name in &table.material_names {
                if !numbers.contains_key(name) {
                    let number =
                        u16::try_from(materials.len()).map_err(|_| RowsError::Materials)?;
                    numbers.insert(name.clone(), number);
                    materials.push(name.clone());
                }
            }
            grains |= !table.grains.is_empty();
            superellipses |= table.grains.iter().any(|g| superellipse(g).is_some());
            polygons |= table.grains.iter().any(|g| superellipse(g).is_none());
            Ok(())
        })?;
        rows.header = header;
        rows.header_line = header_line;
        rows.materials = materials;
        rows.numbers = numbers;
        (rows.grains, rows.superellipses, rows.polygons) = (grains, superellipses, polygons);
        Ok(rows)
    }

    /// Each batch of rows in file order, its materials numbered as in the
    /// whole file; `fault` turns why the file could not be read into `E`.
    fn for_each_batch<E>(
        &self,
        fault: impl Fn(RowsError) -> E,
        mut each: impl FnMut(&PackingTable) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut failed = None;
        let read = self.batches(|mut table| {
            for m in &mut table.materials {
                let name = &table.material_names[usize::from(*m)];
                *m = *self.numbers.get(name).ok_or(RowsError::Changed)?;
            }
            each(&table).map_err(|e| {
                failed = Some(e);
                // Stops the pass; `each`'s own error is the one returned.
                RowsError::Changed
            })
        });
        match (failed, read) {
            (Some(e), _) => Err(e),
            (None, Err(e)) => Err(fault(e)),
            (None, Ok(_)) => Ok(()),
        }
    }

    /// Read the file through, handing `each` its rows parsed a batch at a
    /// time; the header line and its line number (the first pass finds
    /// them: the first line neither blank nor a comment).
    fn batches(
        &self,
        mut each: impl FnMut(PackingTable) -> Result<(), RowsError>,
    ) -> Result<(Vec<u8>, u64), RowsError> {
        let file = std::fs::File::open(&self.path)?;
        let mut reader = std::io::BufReader::with_capacity(CHUNK_BYTES, file);
        let mut line = Vec::new();
        let mut number = 0u64;
        // Every turn reads a line, or stops at the end of the file.
        while reader.read_until(b'\n', &mut line)? > 0 {
            number += 1;
            if !blank_or_comment(&line) {
                break;
            }
            line.clear();
        }
        let header = std::mem::take(&mut line);
        let header_line = number.max(1);
        if !self.header.is_empty() && (header != self.header || header_line != self.header_line) {
            return Err(RowsError::Changed);
        }
        let mut text = header.clone();
        if !text.ends_with(b"\n") {
            text.push(b'\n');
        }
        let head = text.len();
        // The batch's first line in the file; whether it holds a row; whether
        // one has been parsed; whether the text ends inside a quoted field
        // (its row goes on to the next line).
        let mut first = number + 1;
        let mut any_row = false;
        let mut parsed_one = false;
        let mut quoted = false;
        loop {
            line.clear();
            // Every turn reads a line, or stops at the end of the file.
            if reader.read_until(b'\n', &mut line)? == 0 {
                break;
            }
            number += 1;
            if quoted || !blank_or_comment(&line) {
                any_row = true;
                let quotes = line.iter().filter(|&&b| b == b'"').count();
                quoted ^= quotes % 2 == 1;
            }
            text.extend_from_slice(&line);
            // Cut after whole rows (blank lines go with the next batch, so
            // that a file of no rows is refused where the reader says).
            if any_row && !quoted && text.len() - head >= self.batch_bytes {
                each(self.parse(&text, first, header_line)?)?;
                parsed_one = true;
                text.truncate(head);
                first = number + 1;
                any_row = false;
            }
        }
        if any_row || !parsed_one {
            // The last rows; or none in the whole file, which the reader refuses.
            each(self.parse(&text, first, header_line)?)?;
        }
        Ok((header, header_line))
    }

    /// The rows of `text` (the header, then rows from line `first` of the
    /// file on), faults placed at the file's own lines (the header's is
    /// `header_line`).
    fn parse(&self, text: &[u8], first: u64, header_line: u64) -> Result<PackingTable, RowsError> {
        let text = std::str::from_utf8(text)
            .map_err(|e| RowsError::Io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))?;
        gapack::output::read_packing_csv(text, "packing.csv").map_err(|mut e| {
            e.line = if e.line >= 2 {
                e.line - 2 + first
            } else {
                header_line
            };
            RowsError::Read(e)
        })
    }
}

/// Whether `line` is blank or a comment (`#`), which the reader skips.
fn blank_or_comment(line: &[u8]) -> bool {
    line.first() == Some(&b'#') || line.iter().all(u8::is_ascii_whitespace)
}

/// The view's body, written to `out` as it is serialized.
fn write_view(view: &PackingView, mut out: impl Write) -> std::io::Result<()> {
    serde_json::to_writer(&mut out, view)?;
    out.flush()
}

/// A writer that hands what it is given on to the response body in
/// chunks of [`CHUNK_BYTES`], waiting while [`CHUNKS_AHEAD`] are unsent.
struct Chunks {
    /// The body's end.
    tx: mpsc::Sender<std::io::Result<Bytes>>,
    /// What is not yet sent.
    buf: Vec<u8>,
}

impl Write for Chunks {
    fn write(&mut self, data: &[u8]) -> std::io::Result<usize> {
        self.buf.extend_from_slice(data);
        if self.buf.len() >= CHUNK_BYTES {
            self.flush()?;
        }
        Ok(data.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.buf.is_empty() {
            return Ok(());
        }
        let chunk = std::mem::replace(&mut self.buf, Vec::with_capacity(CHUNK_BYTES));
        self.tx
            .blocking_send(Ok(Bytes::from(chunk)))
            .map_err(|_| std::io::Error::new(std::io::ErrorKind::BrokenPipe, "the client left"))
    }
}

/// Segments per circle in a drawn outline.
const OUTLINE_SEGMENTS: usize = 256;

impl PackingView {
    /// The view of `rows`, a packing of `domain`.
    fn of(domain: &Domain, rows: &Arc<Rows>) -> Self {
        let (lo, hi) = domain.bounds();
        let material = if rows.materials.is_empty() {
            Column {
                rows: Arc::clone(rows),
                cells: None,
            }
        } else {
            Column::of(rows, |t| t.materials.clone())
        };
        PackingView {
            outline: domain
                .outline(OUTLINE_SEGMENTS)
                .iter()
                .map(|p| [p.x, p.y])
                .collect(),
            bounds: [[lo.x, lo.y], [hi.x, hi.y]],
            x: Column::of(rows, |t| t.disks.iter().map(|d| d.c.x).collect()),
            y: Column::of(rows, |t| t.disks.iter().map(|d| d.c.y).collect()),
            r: Column::of(rows, |t| t.disks.iter().map(|d| d.r).collect()),
            material,
            materials: Names(Arc::clone(rows)),
            shapes: ShapesView::of(rows),
        }
    }
}

/// The packing of a finished job that wrote `packing.csv`, as columns.
// Written as it is sent: a packing of any size holds a batch of its rows
// in memory, not the whole view.
#[utoipa::path(get, path = "/api/v1/jobs/{id}/packing", params(super::jobs::IdParam),
    responses(
        (status = 200, description = "The packing as columns", body = PackingView),
        (status = 400, description = "An id that is not UTF-8", body = ErrorBody),
        (status = 404, description = "No such job", body = ErrorBody),
        (status = 409, description = "Not finished, or it wrote no packing.csv", body = ErrorBody),
    ))]
async fn packing(
    State(shared): AppState,
    Extension(who): Extension<Caller>,
    JobId(id): JobId,
) -> Result<Response, ApiError> {
    let view = blocking(move || {
        let manifest = manifest(&shared, &who, &id)?;
        if !manifest.files.iter().any(|f| f == "packing.csv") {
            return Err(ApiError::new(
                StatusCode::CONFLICT,
                format!("job {id} wrote no packing.csv (a comparison or a study has none to draw)"),
            ));
        }
        let row = shared
            .store
            .get(&who, &id)?
            .ok_or_else(|| ApiError::unknown_job(&id))?;
        let path = job_dir(&shared, &id).join("packing.csv");
        let rows = Arc::new(Rows::scan(path, BATCH_BYTES).map_err(ApiError::internal)?);
        // Planned only for its domain: the job ran, so the ceilings and
        // [limits] it was forced past are not asked again.
        let request = JobRequest {
            seed: row.seed,
            force: true,
            ..JobRequest::new(JobKind::Pack)
        };
        let plan = Plan::load(&row.config, ORIGIN, &request)?;
        Ok(PackingView::of(&plan.config.scene.domain, &rows))
    })
    .await?;
    // Written on a blocking thread as the client reads it: the file is
    // read again for each column, a batch at a time.
    let (tx, mut rx) = mpsc::channel(CHUNKS_AHEAD);
    tokio::task::spawn_blocking(move || {
        let out = Chunks {
            tx: tx.clone(),
            buf: Vec::with_capacity(CHUNK_BYTES),
        };
        if let Err(e) = write_view(&view, out) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                tracing::debug!("the client left before the packing view's end");
                return;
            }
            tracing::warn!(error = %e, "the packing view was cut short");
            // Ends the body with an error: the client sees it cut, not whole.
            let _ = tx.blocking_send(Err(e));
        }
    });
    let body = Body::from_stream(futures_util::stream::poll_fn(move |cx| rx.poll_recv(cx)));
    Ok(([(header::CONTENT_TYPE, "application/json")], body).into_response())
}

/// A shipped example config.
#[derive(Debug, Serialize, ToSchema)]
pub struct Example {
    /// Its name (the file stem under `configs/`).
    name: &'static str,
    /// Its text.
    config: &'static str,
}

/// The shipped example configs, the default scene first.
#[utoipa::path(get, path = "/api/v1/examples",
    responses((status = 200, description = "The examples, the default scene first", body = Vec<Example>)))]
async fn examples() -> Json<Vec<Example>> {
    Json(
        web::EXAMPLES
            .iter()
            .map(|&(name, config)| Example { name, config })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use axum::http::StatusCode;

    use super::{BATCH_BYTES, PackingView, Rows, write_view};
    use crate::api::testing::{SQUARE, TestServer};
    use crate::web::EXAMPLES;

    #[tokio::test]
    async fn the_packing_of_a_job_forced_past_a_limit_is_shown() {
        let server = TestServer::with(|o| o.force = true, None);
        // Refused before the run (the square could hold about 510), packed
        // whole (about 170).
        let config = format!("{SQUARE}[limits]\nmax_particles = 300\n");
        let id = server.submit("?kind=pack&force=true", &config).await;
        server.run_queued().await;
        let r = server.get(&format!("/api/v1/jobs/{id}/packing")).await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        assert!(r.json()["x"].as_array().is_some_and(|x| x.len() > 10));
    }

    #[tokio::test]
    async fn the_page_and_its_assets_are_served_revalidated() {
        let server = TestServer::new();
        for (path, kind, text) in [
            (
                "/",
                "text/html; charset=utf-8",
                include_str!("../web/index.html"),
            ),
            (
                "/app.js",
                "text/javascript; charset=utf-8",
                include_str!("../web/app.js"),
            ),
            (
                "/app.css",
                "text/css; charset=utf-8",
                include_str!("../web/app.css"),
            ),
        ] {
            let r = server.get(path).await;
            assert_eq!(r.status, StatusCode::OK, "{path}");
            assert_eq!(r.header("content-type"), Some(kind), "{path}");
            assert_eq!(r.header("cache-control"), Some("no-cache"), "{path}");
            assert_eq!(r.text(), text, "{path}");
        }
    }

    /// The view as it was built before it was streamed: the whole file
    /// read, then the columns serialized at once (the reference the
    /// streamed body must equal byte for byte).
    mod whole {
        use gapack::output::read_packing_csv;
        use gapack::{Domain, Outline};
        use serde::Serialize;

        #[derive(Serialize)]
        struct View {
            outline: Vec<[f64; 2]>,
            bounds: [[f64; 2]; 2],
            x: Vec<f64>,
            y: Vec<f64>,
            r: Vec<f64>,
            material: Vec<u16>,
            materials: Vec<String>,
            #[serde(skip_serializing_if = "Option::is_none")]
            shapes: Option<Shapes>,
        }

        #[derive(Serialize)]
        struct Shapes {
            angle: Vec<f64>,
            #[serde(skip_serializing_if = "Option::is_none")]
            a: Option<Vec<Option<f64>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            b: Option<Vec<Option<f64>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            alpha: Option<Vec<Option<f64>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            beta: Option<Vec<Option<f64>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            template: Option<Vec<Option<u16>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            rounding: Option<Vec<Option<f64>>>,
            #[serde(skip_serializing_if = "Option::is_none")]
            vertices: Option<Vec<Option<Vec<[f64; 2]>>>>,
        }

        /// The view of `text` over `domain`, built whole; or the reader's fault.
        pub fn view(text: &str, domain: &Domain) -> Result<Vec<u8>, String> {
            let t = read_packing_csv(text, "packing.csv").map_err(|e| e.to_string())?;
            let se = |g: &gapack::Grain| match g.outline {
                Outline::Superellipse { a, b, alpha, beta } => Some([a, b, alpha, beta]),
                Outline::Polygon { .. } => None,
            };
            let poly = |g: &gapack::Grain| match &g.outline {
                Outline::Polygon {
                    template,
                    vertices,
                    rounding,
                } => Some((
                    *template,
                    *rounding,
                    vertices.iter().map(|v| [v.x, v.y]).collect::<Vec<_>>(),
                )),
                Outline::Superellipse { .. } => None,
            };
            let any_se = t.grains.iter().any(|g| se(g).is_some());
            let any_poly = t.grains.iter().any(|g| poly(g).is_some());
            let col = |present: bool, f: &dyn Fn(&gapack::Grain) -> Option<f64>| {
                present.then(|| t.grains.iter().map(f).collect::<Vec<_>>())
            };
            let shapes = (!t.grains.is_empty()).then(|| Shapes {
                angle: t.grains.iter().map(|g| g.angle).collect(),
                a: col(any_se, &|g| se(g).map(|s| s[0])),
                b: col(any_se, &|g| se(g).map(|s| s[1])),
                alpha: col(any_se, &|g| se(g).map(|s| s[2])),
                beta: col(any_se, &|g| se(g).map(|s| s[3])),
                template: any_poly.then(|| t.grains.iter().map(|g| poly(g).map(|p| p.0)).collect()),
                rounding: col(any_poly, &|g| poly(g).map(|p| p.1)),
                vertices: any_poly.then(|| t.grains.iter().map(|g| poly(g).map(|p| p.2)).collect()),
            });
            let (lo, hi) = domain.bounds();
            let view = View {
                outline: domain.outline(256).iter().map(|p| [p.x, p.y]).collect(),
                bounds: [[lo.x, lo.y], [hi.x, hi.y]],
                x: t.disks.iter().map(|d| d.c.x).collect(),
                y: t.disks.iter().map(|d| d.c.y).collect(),
                r: t.disks.iter().map(|d| d.r).collect(),
                material: t.materials,
                materials: t.material_names,
                shapes,
            };
            serde_json::to_vec(&view).map_err(|e| e.to_string())
        }
    }

    /// A `packing.csv` of `n` rows: disks, or with `materials` a material
    /// column cycling through them, or with `shapes` particles of both
    /// families (odd rows rounded polygons, one of them clockwise).
    fn table(n: usize, materials: &[&str], shapes: bool) -> String {
        use gapack::{Outline, Point};
        let mut text = String::from("id,x,y,r");
        if !materials.is_empty() {
            text.push_str(",material");
        }
        if shapes {
            text.push_str(",angle,a,b,alpha,beta,template,rounding,vertices");
        }
        text.push('\n');
        for i in 0..n {
            let f = i as f64;
            let (x, y) = (0.1 + 0.2 * f, 20.0 / 3.0 - f / 7.0);
            let mut r = 0.5 + (f * 0.618_033_988_7).fract();
            let mut cells = String::new();
            if shapes {
                let angle = f * 0.3 - 1.0;
                if i % 2 == 0 {
                    let (a, b) = (r * 1.25, r / 1.5);
                    let o = Outline::superellipse(a, b, 2.5, 3.0).expect("a superellipse");
                    r = o.equivalent_radius();
                    cells = format!(",{angle},{a},{b},2.5,3,,,");
                } else {
                    let s = r / 2.0;
                    let mut square = vec![
                        Point::new(-s, -s),
                        Point::new(s, -s),
                        Point::new(s, s),
                        Point::new(-s, s),
                    ];
                    if i % 4 == 1 {
                        square.reverse();
                    }
                    let o = Outline::polygon(7, &square, s / 4.0).expect("a polygon");
                    r = o.equivalent_radius();
                    let v: Vec<String> =
                        square.iter().map(|p| format!("{} {}", p.x, p.y)).collect();
                    cells = format!(",{angle},,,,,7,{},{}", s / 4.0, v.join(";"));
                }
            }
            text.push_str(&format!("{i},{x},{y},{r}"));
            if !materials.is_empty() {
                let m = materials[i % materials.len()];
                text.push(',');
                if m.contains([',', '"', '\n']) {
                    text.push_str(&format!("\"{}\"", m.replace('"', "\"\"")));
                } else {
                    text.push_str(m);
                }
            }
            text.push_str(&cells);
            text.push('\n');
        }
        text
    }

    /// The streamed view of `text` over `domain`, `packing.csv` parsed
    /// `batch` bytes at a time; or why not.
    fn streamed(text: &str, domain: &gapack::Domain, batch: usize) -> Result<Vec<u8>, String> {
        let dir = tempfile::tempdir().expect("a folder");
        let path = dir.path().join("packing.csv");
        std::fs::write(&path, text).expect("written");
        let rows = Arc::new(Rows::scan(path, batch).map_err(|e| e.to_string())?);
        let mut out = Vec::new();
        write_view(&PackingView::of(domain, &rows), &mut out).map_err(|e| e.to_string())?;
        Ok(out)
    }

    #[test]
    fn the_view_streamed_is_byte_for_byte_the_view_built_whole() {
        let square = gapack::Domain::rectangle(20.0, 20.0).expect("a square");
        let circle = gapack::Domain::circle(gapack::Point::new(1.0, 2.0), 5.0).expect("a circle");
        let odd = ["sand", "clay, \"wet\"", "two\nlines", "#not a comment", ""];
        let mut tables = vec![
            table(1, &[], false),
            table(300, &[], false),
            table(300, &["a", "b"], false),
            table(300, &odd, false),
            table(120, &[], true),
            table(120, &odd, true),
            // Comments and blank lines before the header, among the rows, at the end.
            format!(
                "# made by hand\n\n{}\n\n# the end\n\n",
                table(50, &["a"], false)
            ),
            // A table from elsewhere: semicolons, diameters, no id, no final newline.
            "D;X;Y\n1;2;3\n0.5;4;5\n2;6;7".to_owned(),
        ];
        let both = table(60, &[], true);
        // One family only: the other's columns are left out.
        let ellipses: String = both
            .lines()
            .enumerate()
            .filter(|(i, _)| *i == 0 || i % 2 == 1)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        let polygons: String = both
            .lines()
            .enumerate()
            .filter(|(i, _)| i % 2 == 0)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        tables.extend([ellipses, polygons]);
        for (k, text) in tables.iter().enumerate() {
            for domain in [&square, &circle] {
                let whole = whole::view(text, domain).expect("a packing");
                for batch in [1, 64, 1000, BATCH_BYTES] {
                    let got = streamed(text, domain, batch).expect("a packing");
                    assert!(
                        got == whole,
                        "table {k}, batch {batch}:\n{}\nagainst\n{}",
                        String::from_utf8_lossy(&got),
                        String::from_utf8_lossy(&whole)
                    );
                }
            }
        }
        // The families' columns are there: the reference is not empty of them.
        let view: serde_json::Value =
            serde_json::from_slice(&streamed(&tables[5], &square, 64).expect("a packing"))
                .expect("JSON");
        let shapes = view["shapes"].as_object().expect("shapes");
        assert_eq!(shapes.len(), 8, "{shapes:?}");
        assert_eq!(shapes["template"][0], serde_json::Value::Null);
        assert_eq!(shapes["template"][1], 7);
        assert_eq!(view["materials"].as_array().map(Vec::len), Some(odd.len()));
        assert_eq!(view["x"].as_array().map(Vec::len), Some(120));
    }

    #[test]
    fn a_fault_is_placed_where_the_whole_file_places_it() {
        let square = gapack::Domain::rectangle(20.0, 20.0).expect("a square");
        let good = table(200, &["a", "b"], false);
        let mut lines: Vec<String> = good.lines().map(str::to_owned).collect();
        lines[150] = lines[150].replacen(",0.", ",x0.", 1);
        let bad = lines.join("\n") + "\n";
        let header_only = "# none\nid,x,y,r\n\n".to_owned();
        let no_r = "x,y\n1,2\n".to_owned();
        for text in [bad, header_only, no_r] {
            let whole = whole::view(&text, &square).expect_err("a fault");
            for batch in [1, 64, BATCH_BYTES] {
                let got = streamed(&text, &square, batch).expect_err("a fault");
                assert_eq!(got, whole, "batch {batch}");
            }
        }
    }

    #[tokio::test]
    async fn a_job_s_packing_is_sent_as_built_whole() {
        let server = TestServer::new();
        let id = server.submit("?kind=pack", SQUARE).await;
        server.run_queued().await;
        let r = server.get(&format!("/api/v1/jobs/{id}/packing")).await;
        assert_eq!(r.status, StatusCode::OK, "{}", r.text());
        assert_eq!(r.header("content-type"), Some("application/json"));
        let csv = std::fs::read_to_string(server.data().join("jobs").join(&id).join("packing.csv"))
            .expect("the csv");
        let square = gapack::Domain::rectangle(20.0, 20.0).expect("a square");
        assert!(r.body == whole::view(&csv, &square).expect("a packing"));
        assert!(r.json()["x"].as_array().is_some_and(|x| x.len() > 100));
    }

    #[tokio::test]
    async fn the_examples_are_the_shipped_configs_default_first() {
        let server = TestServer::new();
        let r = server.get("/api/v1/examples").await;
        assert_eq!(r.status, StatusCode::OK);
        let examples = r.json();
        let examples = examples.as_array().expect("a list");
        assert_eq!(examples.len(), EXAMPLES.len());
        assert_eq!(examples[0]["name"], "default");
        for (got, (name, config)) in examples.iter().zip(EXAMPLES) {
            assert_eq!(
                (&got["name"], &got["config"]),
                (&(*name).into(), &(*config).into())
            );
        }
    }
}
