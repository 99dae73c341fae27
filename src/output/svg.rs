//! `packing.svg`: the packing drawn to scale, for a first look.

use std::fmt::Write;

use super::palette;
use crate::geometry::{Disk, Point};
use crate::layering::Material;
use crate::packer::Packing;

/// File name of the drawing.
pub const PACKING_SVG: &str = "packing.svg";

/// Width of the drawing in pixels; the height follows the domain's aspect.
const WIDTH_PX: f64 = 800.0;
/// Segments of a circular domain's outline, in the drawings and the exports.
pub(super) const CIRCLE_SEGMENTS: usize = 256;
/// Margin around the drawing, as a fraction of its shorter side.
const MARGIN: f64 = 0.03;
/// Stroke width in pixels.
const STROKE_PX: f64 = 0.5;

/// The smallest and largest diameter of the packed disks (mm), the colour
/// range of [`packing_svg`] when no grading is known (a packing read back
/// from a CSV); `(0, 0)` without disks.
pub fn diameter_range(packing: &Packing) -> (f64, f64) {
    if packing.disks.is_empty() {
        return (0.0, 0.0);
    }
    packing
        .disks
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(2.0 * d.r), hi.max(2.0 * d.r))
        })
}

/// The packing as an SVG document: the domain outline, wall disks in light
/// grey, packed disks filled by material (one palette colour each, named in
/// the title) when they carry one and `materials` are given, else light to
/// dark from `diameters.0` to `diameters.1` (mm).
///
/// `diameters` is the scene's `(d_min, d_max)` when the scene is known, so
/// that packings of one grading share their colours, else
/// [`diameter_range`]; it is all the drawing needs besides the packing.
///
/// The `viewBox` is in mm with y pointing up (flipped), plus a small margin;
/// the drawing is 800 px wide. Numbers are written with 4 decimals (0.1 µm),
/// so the same packing always gives the same text.
///
/// A periodic cell is outlined dashed, and a disk crossing its edges is
/// drawn again at each image that reaches into it, every disk clipped to
/// the cell (the title says so).
pub fn packing_svg(packing: &Packing, materials: &[Material], diameters: (f64, f64)) -> String {
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    let (lo, hi) = frame(&outline, packing);
    let (x0, y0) = (lo.x, lo.y);
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    let height_px = (WIDTH_PX * h / w).round();
    let stroke = num(STROKE_PX * w / WIDTH_PX);
    // y up: a point at height y is drawn at lo.y + hi.y − y, inside the same box.
    let flip = |y: f64| lo.y + hi.y - y;

    let mut svg = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(svg, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="{} {} {} {}">"#,
        WIDTH_PX,
        height_px,
        num(x0),
        num(y0),
        num(w),
        num(h)
    );
    let by_material = by_material(packing, materials);
    let legend: Vec<String> = if by_material {
        materials
            .iter()
            .enumerate()
            .map(|(i, m)| format!("{} {}", m.name, hex(palette::colour(i))))
            .collect()
    } else {
        Vec::new()
    };
    let periodic = packing.domain.is_periodic();
    let _ = writeln!(
        svg,
        "<title>gapack: {} disks, {} wall disks (mm, y up){}{}</title>",
        packing.disks.len(),
        packing.boundary.len(),
        if periodic {
            "; periodic cell (dashed): a disk crossing an edge is drawn again across the opposite one"
        } else {
            ""
        },
        if legend.is_empty() {
            String::new()
        } else {
            format!("; materials: {}", legend.join(", "))
        }
    );
    let points: Vec<String> = outline
        .iter()
        .map(|p| format!("{},{}", num(p.x), num(flip(p.y))))
        .collect();
    if periodic {
        let _ = writeln!(
            svg,
            r#"<defs><clipPath id="cell"><polygon points="{}"/></clipPath></defs>"#,
            points.join(" ")
        );
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="white"/>"#,
            points.join(" ")
        );
    } else {
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="white" stroke="black" stroke-width="{stroke}"/>"#,
            points.join(" ")
        );
    }
    if !packing.boundary.is_empty() {
        let _ = writeln!(
            svg,
            r##"<g fill="{}" stroke="{}" stroke-width="{stroke}">"##,
            hex(WALL_FILL),
            hex(WALL_EDGE)
        );
        for disk in &packing.boundary {
            let _ = writeln!(svg, "{}/>", circle(disk, flip(disk.c.y)));
        }
        let _ = writeln!(svg, "</g>");
    }
    let clip = if periodic {
        r#" clip-path="url(#cell)""#
    } else {
        ""
    };
    let _ = writeln!(
        svg,
        r##"<g stroke="{}" stroke-width="{stroke}"{clip}>"##,
        hex(DISK_EDGE)
    );
    for (i, disk) in packing.disks.iter().enumerate() {
        let fill = hex(disk_fill(packing, i, by_material, diameters));
        for at in drawn_images(packing, disk) {
            let _ = writeln!(svg, r#"{} fill="{fill}"/>"#, circle(&at, flip(at.c.y)));
        }
    }
    let _ = writeln!(svg, "</g>");
    if periodic {
        // Drawn over the disks, 1 px wide in dashes of 8 px.
        let (wide, dash) = (num(2.0 * STROKE_PX * w / WIDTH_PX), num(8.0 * w / WIDTH_PX));
        let _ = writeln!(
            svg,
            r#"<polygon points="{}" fill="none" stroke="black" stroke-width="{wide}" stroke-dasharray="{dash}"/>"#,
            points.join(" ")
        );
    }
    let _ = writeln!(svg, "</svg>");
    svg
}

/// The copies of `disk` a drawing shows: the disk itself; in a periodic
/// cell, each of its images that reaches into the cell (the disk first
/// when it is one of them).
pub(super) fn drawn_images(packing: &Packing, disk: &Disk) -> impl Iterator<Item = Disk> {
    let domain = &packing.domain;
    let shifts: Vec<_> = if domain.is_periodic() {
        let (lo, hi) = (
            Point::new(disk.c.x - disk.r, disk.c.y - disk.r),
            Point::new(disk.c.x + disk.r, disk.c.y + disk.r),
        );
        let mut shifts: Vec<_> = domain.image_shifts(lo, hi).collect();
        shifts.sort_by_key(|v| *v != nalgebra::Vector2::zeros());
        shifts
    } else {
        vec![nalgebra::Vector2::zeros()]
    };
    let disk = *disk;
    shifts.into_iter().map(move |v| Disk {
        c: if v == nalgebra::Vector2::zeros() {
            disk.c
        } else {
            disk.c - v
        },
        r: disk.r,
    })
}

/// Fill of the wall disks (light grey).
pub(super) const WALL_FILL: [u8; 3] = [0xd9, 0xd9, 0xd9];
/// Edge of the wall disks.
pub(super) const WALL_EDGE: [u8; 3] = [0xa6, 0xa6, 0xa6];
/// Edge of the packed disks (near black).
pub(super) const DISK_EDGE: [u8; 3] = [0x1a, 0x1a, 0x1a];

/// Whether disks are coloured by material: they carry one and materials are named.
pub(super) fn by_material(packing: &Packing, materials: &[Material]) -> bool {
    !materials.is_empty() && !packing.materials.is_empty()
}

/// Fill of packed disk `i`: its material's palette colour, else its diameter's shade.
pub(super) fn disk_fill(
    packing: &Packing,
    i: usize,
    by_material: bool,
    diameters: (f64, f64),
) -> [u8; 3] {
    match packing.materials.get(i) {
        Some(&m) if by_material => palette::colour(usize::from(m)),
        _ => packing.disks.get(i).map_or(palette::ramp(0.5), |d| {
            palette::diameter_colour(2.0 * d.r, diameters)
        }),
    }
}

/// The box drawn (mm): the outline and every disk (a periodic cell: the
/// outline, the disks being clipped to it), plus a margin of [`MARGIN`] of
/// the shorter side all round.
pub(super) fn frame(outline: &[Point], packing: &Packing) -> (Point, Point) {
    let (lo, hi) = if packing.domain.is_periodic() {
        packing.domain.bounds()
    } else {
        extent(outline, packing)
    };
    let margin = MARGIN * (hi.x - lo.x).min(hi.y - lo.y);
    (
        Point::new(lo.x - margin, lo.y - margin),
        Point::new(hi.x + margin, hi.y + margin),
    )
}

/// Bounding box of the outline and of every disk.
fn extent(outline: &[Point], packing: &Packing) -> (Point, Point) {
    let (mut lo, mut hi) = packing.domain.bounds();
    let boxes =
        outline
            .iter()
            .map(|p| (*p, *p))
            .chain(packing.boundary.iter().chain(&packing.disks).map(|d| {
                (
                    Point::new(d.c.x - d.r, d.c.y - d.r),
                    Point::new(d.c.x + d.r, d.c.y + d.r),
                )
            }));
    for (a, b) in boxes {
        lo = Point::new(lo.x.min(a.x), lo.y.min(a.y));
        hi = Point::new(hi.x.max(b.x), hi.y.max(b.y));
    }
    (lo, hi)
}

/// `<circle cx=".." cy=".." r=".."` (unclosed, for attributes to follow).
fn circle(disk: &Disk, y: f64) -> String {
    format!(
        r#"<circle cx="{}" cy="{}" r="{}""#,
        num(disk.c.x),
        num(y),
        num(disk.r)
    )
}

/// `#rrggbb`.
fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// A number with at most 4 decimals, trailing zeros and `-0` dropped.
fn num(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_owned()
    } else {
        s.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;

    fn packing(boundary: Vec<Disk>) -> Packing {
        Packing {
            boundary,
            ..Packing::of_disks(
                Domain::rectangle(10.0, 20.0).expect("valid rectangle"),
                vec![Disk::new(1.0, 1.0, 1.0), Disk::new(5.0, 18.0, 2.0)],
            )
        }
    }

    #[test]
    fn draws_to_scale_with_y_up() {
        // The colour range of a 2–4 mm grading.
        let svg = packing_svg(&packing(Vec::new()), &[], (2.0, 4.0));
        // Margin 3 % of the shorter side (10 mm): 0.3 mm.
        assert!(
            svg.contains(r#"width="800" height="1555" viewBox="-0.3 -0.3 10.6 20.6""#),
            "{svg}"
        );
        // y = 1 is drawn at 20 − 1 = 19, the smallest disk lightest, the largest darkest.
        assert!(
            svg.contains(r##"<circle cx="1" cy="19" r="1" fill="#c6dbef"/>"##),
            "{svg}"
        );
        assert!(
            svg.contains(r##"<circle cx="5" cy="2" r="2" fill="#08306b"/>"##),
            "{svg}"
        );
        assert!(
            !svg.contains("#d9d9d9"),
            "no wall-disk group without wall disks"
        );
        assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(svg, packing_svg(&packing(Vec::new()), &[], (2.0, 4.0)));
    }

    #[test]
    fn draws_materials_in_palette_colours() {
        let mut p = packing(Vec::new());
        p.materials = vec![1, 0];
        let named = |name: &str| Material {
            name: name.to_owned(),
            properties: Vec::new(),
        };
        let svg = packing_svg(&p, &[named("ceramic"), named("metal")], (2.0, 2.0));
        assert!(
            svg.contains("materials: ceramic #0072b2, metal #d55e00"),
            "{svg}"
        );
        assert!(svg.contains(r##"r="1" fill="#d55e00"/>"##), "{svg}");
        assert!(svg.contains(r##"r="2" fill="#0072b2"/>"##), "{svg}");
    }

    #[test]
    fn draws_wall_disks_in_grey() {
        let svg = packing_svg(&packing(vec![Disk::new(0.0, 0.0, 0.5)]), &[], (2.0, 2.0));
        assert!(svg.contains(r##"<g fill="#d9d9d9""##), "{svg}");
        // The wall disk widens the box to y = −0.5, so y = 0 is drawn at 19.5.
        assert!(
            svg.contains(r#"<circle cx="0" cy="19.5" r="0.5"/>"#),
            "{svg}"
        );
    }

    #[test]
    fn the_diameter_range_is_the_packed_disks_own() {
        assert_eq!(
            diameter_range(&packing(vec![Disk::new(0.0, 0.0, 9.0)])),
            (2.0, 4.0)
        );
        let mut empty = packing(Vec::new());
        empty.disks.clear();
        assert_eq!(diameter_range(&empty), (0.0, 0.0));
    }

    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.00001), "0");
        assert_eq!(num(2.50), "2.5");
        assert_eq!(num(1.234_567), "1.2346");
        assert_eq!(num(100.0), "100");
    }
}
