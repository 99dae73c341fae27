//! `packing.json`: the domain, every packed disk and the run summary in one
//! JSON document, for scripts.

use serde::Serialize;

use super::common::{Export, Lines, Writer, bytes};
use crate::geometry::{Domain, Grain, Outline, Point, Shape};
use crate::metrics::Metrics;
use crate::names::ConfigName;
use crate::output::digits::write_rows;
use crate::output::json::summary;
use crate::output::svg::CIRCLE_SEGMENTS;
use crate::output::{OutputError, RunInfo};
use crate::packer::Packing;

/// File name of the packing as JSON.
pub const PACKING_JSON: &str = "packing.json";

/// The domain's axis-aligned bounds (mm).
#[derive(Serialize)]
struct BoundsJson {
    min: [f64; 2],
    max: [f64; 2],
}

/// One packed disk.
#[derive(Serialize)]
struct DiskJson<'a> {
    id: usize,
    x: f64,
    y: f64,
    r: f64,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    shape: Option<ShapeJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    material: Option<&'a str>,
}

/// A particle's outline and angle, after its area-equivalent radius `r`.
#[derive(Serialize)]
#[serde(untagged)]
enum ShapeJson {
    /// |x'/a|^alpha + |y'/b|^beta <= 1 in the particle's own axes.
    Superellipse {
        angle: f64,
        a: f64,
        b: f64,
        alpha: f64,
        beta: f64,
    },
    /// A convex polygon (own axes, counter-clockwise about its centroid)
    /// with corners rounded by `rounding`.
    Polygon {
        angle: f64,
        template: u16,
        rounding: f64,
        vertices: Vec<[f64; 2]>,
    },
}

impl ShapeJson {
    /// The JSON of `grain`.
    fn of(grain: &Grain) -> Self {
        let angle = grain.angle;
        match &grain.outline {
            Outline::Superellipse { a, b, alpha, beta } => ShapeJson::Superellipse {
                angle,
                a: *a,
                b: *b,
                alpha: *alpha,
                beta: *beta,
            },
            Outline::Polygon {
                template,
                vertices,
                rounding,
            } => ShapeJson::Polygon {
                angle,
                template: *template,
                rounding: *rounding,
                vertices: vertices.iter().map(|&p| xy(p)).collect(),
            },
        }
    }
}

/// A point as a JSON pair `[x, y]`.
fn xy(p: Point) -> [f64; 2] {
    [p.x, p.y]
}

/// `value` as compact JSON.
fn compact(value: &impl Serialize) -> Result<String, OutputError> {
    Ok(serde_json::to_string(value)?)
}

/// One member `"key": value,` of the domain object, the value compact.
fn member(t: &mut Lines<'_>, key: &str, value: &impl Serialize) -> Result<(), OutputError> {
    t.line(format_args!("    \"{key}\": {},", compact(value)?));
    Ok(())
}

/// A member holding a list of points, one `[x, y]` per line; `last` leaves
/// out the comma after it.
fn points(t: &mut Lines<'_>, key: &str, points: &[Point], last: bool) -> Result<(), OutputError> {
    t.line(format_args!("    \"{key}\": ["));
    for (i, &p) in points.iter().enumerate() {
        let comma = if i + 1 < points.len() { "," } else { "" };
        t.line(format_args!("      {}{comma}", compact(&xy(p))?));
    }
    t.line(format_args!("    ]{}", if last { "" } else { "," }));
    Ok(())
}

/// The `domain` member: the shape and its config parameters, the bounds,
/// the area and the outline.
fn domain(t: &mut Lines<'_>, domain: &Domain) -> Result<(), OutputError> {
    t.line(format_args!("  \"domain\": {{"));
    member(t, "shape", &domain.shape().config_name())?;
    match domain.shape() {
        Shape::Rectangle { width, height } => {
            member(t, "width", width)?;
            member(t, "height", height)?;
        }
        Shape::Polygon { vertices } => points(t, "vertices", vertices, false)?,
        Shape::Circle { center, radius } => {
            member(t, "center", &xy(*center))?;
            member(t, "radius", radius)?;
        }
        Shape::Trapezoid {
            bottom,
            top,
            height,
        } => {
            member(t, "bottom", bottom)?;
            member(t, "top", top)?;
            member(t, "height", height)?;
        }
    }
    let (lo, hi) = domain.bounds();
    member(
        t,
        "bounds",
        &BoundsJson {
            min: xy(lo),
            max: xy(hi),
        },
    )?;
    member(t, "area", &domain.area())?;
    member(t, "periodic", &domain.is_periodic())?;
    if let Some(period) = domain.period() {
        member(t, "period", &[period.x, period.y])?;
    }
    points(t, "outline", &domain.outline(CIRCLE_SEGMENTS), true)?;
    t.line(format_args!("  }},"));
    Ok(())
}

/// `value` as pretty JSON with every line after the first indented by two
/// spaces, to sit as a member of the top-level object.
fn nested(value: &impl Serialize) -> Result<String, OutputError> {
    // JSON strings escape their newlines, so every raw newline is a line break.
    Ok(serde_json::to_string_pretty(value)?.replace('\n', "\n  "))
}

/// The packing as one JSON document, lengths in mm:
///
/// ```text
/// {
///   "units": "mm",
///   "domain": {
///     "shape": "rectangle",
///     "width": 20.0,
///     "height": 20.0,
///     "bounds": {"min":[0.0,0.0],"max":[20.0,20.0]},
///     "area": 400.0,
///     "periodic": false,
///     "outline": [
///       [0.0,0.0],
///       …
///     ]
///   },
///   "disks": [
///     {"id":0,"x":0.6,"y":0.6,"r":0.6,"material":"metal"},
///     …
///   ],
///   "summary": { …the object summary.json holds… }
/// }
/// ```
///
/// `domain` gives the shape with its config parameters (`width`/`height`,
/// `vertices`, `center`/`radius`, `bottom`/`top`/`height`), the bounds, the
/// area (mm²), whether it is a periodic cell (`walls = "periodic"`; then
/// also `period`: `[width, height]`, the shifts of a disk's images, the
/// bounds being the cell) and the outline (a circle as 256 points,
/// counter-clockwise).
/// `disks` lists the packed disks (not the wall disks) one per line, `id`
/// from 0 in placement order as in `packing.csv`, with the material's name
/// when `run.materials` is not empty. Particles that are not disks
/// (non-empty `packing.grains`) add, after `r` (the area-equivalent
/// radius), `angle` (radians, counter-clockwise) and either `a`, `b`,
/// `alpha`, `beta` (a superellipse |x'/a|^alpha + |y'/b|^beta <= 1 in its
/// own axes) or `template`, `rounding` and `vertices` (a rounded polygon:
/// `[[x, y], …]` in its own axes, counter-clockwise about the centroid).
/// `summary` is exactly what
/// [`crate::output::summary_json`] writes. Numbers read back exactly; the
/// same run always gives the same bytes.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `run.materials`; [`OutputError::Json`] if serialisation fails
/// (it does not for these types).
pub fn packing_json(
    packing: &Packing,
    metrics: &Metrics,
    run: &RunInfo<'_>,
) -> Result<Vec<u8>, OutputError> {
    Ok(bytes(packing_json_writer(packing, metrics, run)?))
}

/// [`packing_json`] checked (materials, the domain and the summary made),
/// its disks left to be written where the file goes, in parallel blocks.
///
/// # Errors
/// As [`packing_json`].
pub(crate) fn packing_json_writer<'a>(
    packing: &'a Packing,
    metrics: &Metrics,
    run: &'a RunInfo<'a>,
) -> Result<Writer<'a>, OutputError> {
    // Lengths in mm: rows unscaled.
    let e = Export::new(packing, run.materials, 1.0)?;
    let n = e.len();
    let mut head = Vec::new();
    let mut t = Lines::new(&mut head);
    t.line(format_args!("{{"));
    t.line(format_args!("  \"units\": \"mm\","));
    domain(&mut t, &packing.domain)?;
    if n == 0 {
        t.line(format_args!("  \"disks\": [],"));
    } else {
        t.line(format_args!("  \"disks\": ["));
    }
    // Writing to a Vec cannot fail.
    let _ = t.finish();
    let mut tail = Vec::new();
    let mut t = Lines::new(&mut tail);
    if n > 0 {
        t.line(format_args!("  ],"));
    }
    t.line(format_args!(
        "  \"summary\": {}",
        nested(&summary(packing, metrics, run))?
    ));
    t.line(format_args!("}}"));
    let _ = t.finish();
    let materials = run.materials;
    Ok(Box::new(move |out| {
        out.write_all(&head)?;
        write_rows(out, n, |id, b| {
            let d = e.row(id);
            let disk = DiskJson {
                id,
                x: d.x.0,
                y: d.y.0,
                r: d.r.0,
                shape: packing.grains.get(id).map(ShapeJson::of),
                material: d
                    .material
                    .and_then(|m| materials.get(m))
                    .map(|m| m.name.as_str()),
            };
            b.extend_from_slice(b"    ");
            // Serialising these plain records to a Vec cannot fail.
            let _ = serde_json::to_writer(&mut *b, &disk);
            if id + 1 < n {
                b.push(b',');
            }
            b.push(b'\n');
        })?;
        out.write_all(&tail)
    }))
}
