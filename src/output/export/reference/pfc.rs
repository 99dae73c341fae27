//! `packing.p2dat`: a PFC2D command file (PFC 6 / 7 syntax).

use super::clumps::clumps;
use super::common::{Export, Num, Text, VERSION, density, labels};
use nalgebra::Vector2;

use crate::geometry::{Point, Shape};
use crate::layering::Material;
use crate::names::ConfigName;
use crate::output::OutputError;
use crate::output::format::ExportOptions;
use crate::packer::Packing;

/// File name of the PFC2D command file.
pub const PFC_COMMANDS: &str = "packing.p2dat";

/// Margin of the model domain around the packing, as a share of its span
/// along each axis (at least twice the largest radius).
const MARGIN: f64 = 0.05;

/// Precision of the mass properties PFC computes for each clump from its
/// pebbles (`clump create … calculate`): its volume within 0.5 %.
const CLUMP_PRECISION: f64 = 0.005;

/// Group of the balls when there are no materials.
const DEFAULT_GROUP: &str = "gapack";

/// The packed disks (not the wall disks) as a PFC2D command file (PFC 6 and
/// 7 command syntax), lengths in `opts.units`.
///
/// # Layout
/// `;` comment lines (version, count, units); `model new`; `model domain
/// extent xmin xmax ymin ymax` around the domain and the disks with a margin
/// of 5 % of the span on each axis, at least twice the largest radius (PFC
/// refuses a ball whose radius reaches a quarter of the smallest extent);
/// one `ball create id i position-x x position-y y radius r group 'name'`
/// per disk (`i` from 1 in placement order, `packing.csv`'s id + 1; the
/// group is the material's name made a single word of letters, digits and
/// `_`, or `gapack` without materials); one `ball attribute density ρ range
/// group 'name'` per group, ρ in kg per cubic length unit (kg/m³ in metres,
/// kg/mm³ in millimetres): the material's `density`, else `opts.density`.
/// A PFC2D ball is a disk of unit thickness, so its mass is ρ·π·r²·1.
/// Last, one wall named `domain` on the domain outline: `wall generate
/// circle` for a circle, else `wall create vertices` with the first edge and
/// one `wall addfacet` per further edge (PFC walls are active on both sides).
/// With `walls = "disks"` the wall disks are not exported; the wall is the
/// outline moved inwards to where the packed balls touch the wall disks
/// (by the smallest clearance of a ball from the outline, each edge moved
/// parallel to itself, so the nearest ball touches it and none crosses it),
/// said in a comment line.
///
/// With non-disk particles (a `[shape]`), each particle is one clump
/// instead of a ball: `clump create id i group 'name' calculate 0.005
/// pebbles k r (x,y) … r (x,y)`, its `k` pebbles (every one inside the
/// particle; see the clumps of `opts.clumps`) one per `...`-continued
/// line, PFC computing its centroid, area and inertia from them within
/// 0.5 %; one `clump attribute density ρ range group 'name'` per group;
/// a comment line under the header saying what the clumps achieved (the
/// coverage target and cap, the least and mean coverage reached, and how
/// many particles fall short of the target).
///
/// A periodic cell is PFC's periodic domain instead: `model domain extent
/// xmin xmax ymin ymax condition periodic periodic` on the cell itself (no
/// margin: the balls crossing its edges are PFC's ghosts) and no wall (PFC
/// refuses walls across a periodic domain).
///
/// # In PFC2D
/// `program call 'packing.p2dat'` (PFC 6 / 7), then set contact models and
/// properties (`contact cmat default …`) before cycling.
///
/// # Errors
/// [`OutputError::UnknownMaterial`] if a disk's material is not in a
/// non-empty `materials`.
pub fn pfc_commands(
    packing: &Packing,
    materials: &[Material],
    opts: &ExportOptions,
) -> Result<Vec<u8>, OutputError> {
    let e = Export::dem(packing, materials, opts)?;
    let (s, n) = (e.s, e.len());
    let rho = opts.units.density_per_kg_m3();
    let groups = if materials.is_empty() {
        vec![DEFAULT_GROUP.to_owned()]
    } else {
        labels(materials)
    };
    let (lo, hi) = e.extent();
    let r = e.r_max();
    let periodic = packing.domain.is_periodic();
    let (mx, my) = if periodic {
        (0.0, 0.0)
    } else {
        (
            (MARGIN * (hi.x - lo.x)).max(2.0 * r),
            (MARGIN * (hi.y - lo.y)).max(2.0 * r),
        )
    };

    let grains = !packing.grains.is_empty();
    let clumped = grains.then(|| clumps(packing, &opts.clumps));
    let mut t = Text::with_lines(n + groups.len() + 16);
    match &clumped {
        None => t.line(format_args!(
            "; gapack {VERSION}: {n} disks for PFC2D, lengths in {u}, density in kg/{u}^3",
            u = opts.units.config_name()
        )),
        Some(all) => {
            t.line(format_args!(
                "; gapack {VERSION}: {n} particles as clumps of {} pebbles for PFC2D, lengths in {u}, density in kg/{u}^3",
                all.disks(),
                u = opts.units.config_name()
            ));
            t.line(format_args!("; clumps: {}", all.summary(&opts.clumps)));
        }
    }
    t.line(format_args!("; run with: program call 'packing.p2dat'"));
    t.line(format_args!("model new"));
    t.line(format_args!(
        "model domain extent {} {} {} {}{}",
        Num((lo.x - mx) * s),
        Num((hi.x + mx) * s),
        Num((lo.y - my) * s),
        Num((hi.y + my) * s),
        if periodic {
            " condition periodic periodic"
        } else {
            ""
        }
    ));
    let point = |x: f64, y: f64| format!("({},{})", Num(x * s), Num(y * s));
    let group_of = |d: &super::common::Row| {
        groups
            .get(d.material.unwrap_or(0))
            .map_or(DEFAULT_GROUP, String::as_str)
    };
    match &clumped {
        None => {
            for d in e.rows() {
                t.line(format_args!(
                    "ball create id {} position-x {} position-y {} radius {} group '{}'",
                    d.id + 1,
                    d.x,
                    d.y,
                    d.r,
                    group_of(&d)
                ));
            }
        }
        Some(all) => {
            for (d, clump) in e.rows().zip(&all.clumps) {
                t.line(format_args!(
                    "clump create id {} group '{}' calculate {CLUMP_PRECISION} pebbles {} ...",
                    d.id + 1,
                    group_of(&d),
                    clump.disks.len()
                ));
                let last = clump.disks.len().saturating_sub(1);
                for (k, &(c, r)) in clump.disks.iter().enumerate() {
                    t.line(format_args!(
                        "  {} {}{}",
                        Num(r * s),
                        point(c.x, c.y),
                        if k < last { " ..." } else { "" }
                    ));
                }
            }
        }
    }
    let body = if grains { "clump" } else { "ball" };
    for (i, group) in groups.iter().enumerate() {
        let m = (!materials.is_empty()).then_some(i);
        t.line(format_args!(
            "{body} attribute density {} range group '{group}'",
            Num(density(materials, m, opts) * rho)
        ));
    }
    if periodic {
        t.line(format_args!(
            "; periodic cell: no wall, the balls crossing its edges meet their neighbours across them"
        ));
        return Ok(t.into_bytes());
    }
    let inset = if packing.boundary.is_empty() {
        0.0
    } else {
        let inset = wall_inset(packing);
        t.line(format_args!(
            "; walls = \"disks\": the wall disks are not exported; the wall is the domain outline moved in by {} {u}, where the balls touch the wall disks",
            Num(inset * s),
            u = opts.units.config_name()
        ));
        inset
    };
    match *packing.domain.shape() {
        Shape::Circle { center, radius } => t.line(format_args!(
            "wall generate name 'domain' circle position {} radius {}",
            point(center.x, center.y),
            Num((radius - inset) * s)
        )),
        _ => {
            let outline = inset_outline(&packing.domain.outline(0), inset);
            let next = outline.iter().cycle().skip(1);
            for (i, (a, b)) in outline.iter().zip(next).enumerate() {
                let (a, b) = (point(a.x, a.y), point(b.x, b.y));
                if i == 0 {
                    t.line(format_args!("wall create name 'domain' vertices {a} {b}"));
                } else {
                    t.line(format_args!(
                        "wall addfacet name 'domain' vertex {a} vertex {b}"
                    ));
                }
            }
        }
    }
    Ok(t.into_bytes())
}

/// The smallest clearance of a packed disk from the domain's outline (mm,
/// at least 0): how far in the packed disks stop, against the wall disks.
fn wall_inset(packing: &Packing) -> f64 {
    packing
        .disks
        .iter()
        .map(|d| packing.domain.signed_distance(d.c) - d.r)
        .fold(f64::INFINITY, f64::min)
        .clamp(0.0, f64::MAX)
}

/// The counter-clockwise polygon `outline` with each edge moved `by` inwards
/// (to its left) parallel to itself, each vertex where its two moved edges
/// meet (the vertex moved along its edge's normal where they are parallel).
fn inset_outline(outline: &[Point], by: f64) -> Vec<Point> {
    if by == 0.0 {
        return outline.to_vec();
    }
    let n = outline.len();
    let normal = |i: usize| {
        let d = outline[(i + 1) % n] - outline[i];
        Vector2::new(-d.y, d.x) / d.norm()
    };
    (0..n)
        .map(|i| {
            let (prev, next) = (normal((i + n - 1) % n), normal(i));
            // The point at distance `by` from both edges' lines: along the
            // bisector of the normals, 1 / cos(half the turn) longer.
            let sum = prev + next;
            let cos = sum.norm() / 2.0;
            if cos < 1e-9 {
                outline[i] + next * by
            } else {
                outline[i] + sum.normalize() * (by / cos)
            }
        })
        .collect()
}
