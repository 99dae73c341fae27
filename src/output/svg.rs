//! `packing.svg`: the packing drawn to scale, for a first look.

use std::fmt::Write;

use super::OutputError;
use super::palette;
use super::plot::{
    Colouring, Fills, boundary_points, bounding_disks, outline_at, packing_png_coloured,
};
use crate::geometry::{Disk, Outline, Point, bounds_of_disks};
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
/// dark from `diameters.0` to `diameters.1` (mm); a scale bar under it.
///
/// `diameters` is the scene's `(d_min, d_max)` when the scene is known, so
/// that packings of one grading share their colours, else
/// [`diameter_range`]; it is all the drawing needs besides the packing.
///
/// The drawing is an `<svg>` 800 px wide whose `viewBox` is in mm with y
/// pointing up (flipped), plus a small margin; under it, in a strip 40 px
/// high, the scale bar (a round 1-2-5 × 10^k mm length of at most a fifth
/// of the width, as in `packing.png`). Numbers are written with 4 decimals
/// (0.1 µm), so the same packing always gives the same text.
///
/// A slender domain (one side over 8 times the other) is cut along its
/// length into panels set side by side (a tall one) or stacked (a wide
/// one), so that the picture is about as wide as high; the title says how.
///
/// A periodic cell is outlined dashed, and a disk crossing its edges is
/// drawn again at each image that reaches into it, every disk clipped to
/// the cell (the title says so).
///
/// Particles that are not disks ([`Packing::grains`]) are drawn as they
/// are: see [`packing_svg_coloured`], which also colours them as asked.
pub fn packing_svg(packing: &Packing, materials: &[Material], diameters: (f64, f64)) -> String {
    packing_svg_coloured(packing, materials, diameters, None)
}

/// [`packing_svg`] with the particles filled as `colour` asks
/// ([`Colouring`]; `None`: by material when the particles carry one and
/// `materials` name them, else by size, as [`packing_svg`] does).
///
/// Each particle that is not a disk is one `<polygon>`: its outline
/// ([`Outline::boundary`], inscribed in it) turned by its angle, with
/// more points the larger it is drawn (8 to 128: within 0.1 px of the
/// outline at four times the drawing's size). Such particles are shaded
/// by their area-equivalent diameters over their own range (the title
/// says so), or by orientation with a colour bar left of the scale bar.
pub fn packing_svg_coloured(
    packing: &Packing,
    materials: &[Material],
    diameters: (f64, f64),
    colour: Option<Colouring>,
) -> String {
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    let (lo, hi) = frame(&outline, packing);
    let panels = Panels::new(lo, hi);
    let (w, h) = panels.size();
    let height_px = (WIDTH_PX * h / w).round();
    let stroke = num(STROKE_PX * w / WIDTH_PX);
    // y up: a point at height y is drawn at lo.y + hi.y − y, inside the same box.
    let flip = |y: f64| lo.y + hi.y - y;

    let mut svg = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(svg, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH_PX}" height="{}">"#,
        height_px + STRIP_PX
    );
    let _ = writeln!(
        svg,
        r#"<svg width="{WIDTH_PX}" height="{height_px}" viewBox="{} {} {} {}">"#,
        num(lo.x),
        num(lo.y),
        num(w),
        num(h)
    );
    let fill_rule = Fills::of(packing, materials, diameters, colour);
    let by_material = matches!(fill_rule, Fills::Materials(_));
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
        "<title>gapack: {}, {} wall disks (mm, y up){}{}{}{}</title>",
        particles_words(packing),
        packing.boundary.len(),
        match panels.note() {
            note if note.is_empty() => note,
            note => format!("; {note}"),
        },
        if periodic {
            "; periodic cell (dashed): a disk crossing an edge is drawn again across the opposite one"
        } else {
            ""
        },
        if legend.is_empty() {
            String::new()
        } else {
            format!("; materials: {}", legend.join(", "))
        },
        fills_words(packing, fill_rule)
    );
    let points: Vec<String> = outline
        .iter()
        .map(|p| format!("{},{}", num(p.x), num(flip(p.y))))
        .collect();
    let points = points.join(" ");
    let mut defs = String::new();
    if periodic {
        let _ = write!(
            defs,
            r#"<clipPath id="cell"><polygon points="{points}"/></clipPath>"#
        );
    }
    if panels.count > 1 {
        for k in 0..panels.count {
            let (a, b) = panels.source(k);
            let _ = write!(
                defs,
                r#"<clipPath id="panel{k}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
                num(a.x),
                num(flip(b.y)),
                num(b.x - a.x),
                num(b.y - a.y)
            );
        }
    }
    if !defs.is_empty() {
        let _ = writeln!(svg, "<defs>{defs}</defs>");
    }
    let walls = panels.sort(&packing.boundary);
    // Particles that are not disks are sorted by their bounding disks.
    let bounding = bounding_disks(packing);
    let grains = !packing.grains.is_empty();
    let disks = panels.sort(if grains { &bounding } else { &packing.disks });
    let fills: Vec<String> = (0..packing.disks.len())
        .map(|i| hex(fill_rule.of_particle(packing, i)))
        .collect();
    let scale = WIDTH_PX / w;
    for k in 0..panels.count {
        if panels.count > 1 {
            let (a, b) = panels.source(k);
            let at = panels.at(k);
            let _ = writeln!(
                svg,
                r#"<g transform="translate({} {})" clip-path="url(#panel{k})">"#,
                num(at.0 + lo.x - a.x),
                num(at.1 + b.y - hi.y)
            );
        }
        if periodic {
            let _ = writeln!(svg, r#"<polygon points="{points}" fill="white"/>"#);
        } else {
            let _ = writeln!(
                svg,
                r#"<polygon points="{points}" fill="white" stroke="black" stroke-width="{stroke}"/>"#
            );
        }
        if !walls[k].is_empty() {
            let _ = writeln!(
                svg,
                r##"<g fill="{}" stroke="{}" stroke-width="{stroke}">"##,
                hex(WALL_FILL),
                hex(WALL_EDGE)
            );
            for &i in &walls[k] {
                let disk = &packing.boundary[i];
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
        for &i in &disks[k] {
            let fill = &fills[i];
            if let (Some(grain), Some(bound)) = (packing.grains.get(i), bounding.get(i)) {
                let n = svg_points(bound.r * scale);
                for at in drawn_images(packing, bound) {
                    svg.push_str(r#"<polygon points=""#);
                    for (j, p) in outline_at(grain, at.c, n).iter().enumerate() {
                        if j > 0 {
                            svg.push(' ');
                        }
                        push_num(&mut svg, p.x);
                        svg.push(',');
                        push_num(&mut svg, flip(p.y));
                    }
                    let _ = writeln!(svg, r#"" fill="{fill}"/>"#);
                }
            } else {
                for at in drawn_images(packing, &packing.disks[i]) {
                    let _ = writeln!(svg, r#"{} fill="{fill}"/>"#, circle(&at, flip(at.c.y)));
                }
            }
        }
        let _ = writeln!(svg, "</g>");
        if periodic {
            // Drawn over the disks, 1 px wide in dashes of 8 px.
            let (wide, dash) = (num(2.0 * STROKE_PX * w / WIDTH_PX), num(8.0 * w / WIDTH_PX));
            let _ = writeln!(
                svg,
                r#"<polygon points="{points}" fill="none" stroke="black" stroke-width="{wide}" stroke-dasharray="{dash}"/>"#
            );
        }
        if panels.count > 1 {
            let _ = writeln!(svg, "</g>");
        }
    }
    let _ = writeln!(svg, "</svg>");
    scale_bar(&mut svg, height_px, WIDTH_PX / w);
    if let Fills::Orientation { period } = fill_rule {
        orientation_bar(&mut svg, height_px, period);
    }
    let _ = writeln!(svg, "</svg>");
    svg
}

/// `12 disks`, or for particles that are not disks `12 particles
/// (superellipses)` (or polygons, or both).
fn particles_words(packing: &Packing) -> String {
    let n = packing.disks.len();
    if packing.grains.is_empty() {
        return format!("{n} disks");
    }
    let superellipses = packing
        .grains
        .iter()
        .filter(|g| matches!(g.outline, Outline::Superellipse { .. }))
        .count();
    let kind = match superellipses {
        0 => "polygons",
        s if s == packing.grains.len() => "superellipses",
        _ => "superellipses and polygons",
    };
    format!("{n} particles ({kind})")
}

/// What the fills of particles that are not disks mean, for the title
/// (nothing for disks: their title is as it always was).
fn fills_words(packing: &Packing, fills: Fills) -> String {
    if packing.grains.is_empty() {
        return String::new();
    }
    match fills {
        Fills::Diameters((lo, hi)) => format!(
            "; shaded light to dark by area-equivalent diameter, {} to {} mm",
            num(lo),
            num(hi)
        ),
        Fills::Materials(_) => String::new(),
        Fills::Orientation { period } => format!(
            "; coloured by orientation, a cyclic scale over 0 to {}°: {}",
            num(period.to_degrees().round()),
            if period < 4.0 {
                "the long axis' angle modulo 180°"
            } else {
                "the angle of each polygon's template modulo 360°"
            }
        ),
    }
}

/// Points of a particle's polygon in `packing.svg`, which a viewer zooms
/// into: as many as `packing.png` would take at four times the size of
/// a particle reaching `px` pixels from its centre.
fn svg_points(px: f64) -> usize {
    boundary_points(4.0 * px)
}

/// Width of the orientation colour bar (px) and its stops.
const ORIENTATION_BAR_PX: f64 = 240.0;
const ORIENTATION_STOPS: usize = 36;

/// The colour bar of orientations in the strip under the drawing (`top` px
/// down), at its left: a label, the cyclic scale over 0 to `period`
/// (radians) in [`ORIENTATION_STOPS`] steps, and ticks at its ends and middle.
fn orientation_bar(svg: &mut String, top: f64, period: f64) {
    let (x0, y) = (20.0, top + 0.5 * STRIP_PX);
    let label_px = 80.0;
    let _ = write!(
        svg,
        r#"<g id="orientation-bar" font-family="sans-serif" font-size="12"><text x="{}" y="{}" dominant-baseline="middle">orientation</text>"#,
        num(x0),
        num(y - 5.0)
    );
    let step = ORIENTATION_BAR_PX / ORIENTATION_STOPS as f64;
    for k in 0..ORIENTATION_STOPS {
        let t = (k as f64 + 0.5) / ORIENTATION_STOPS as f64;
        let _ = write!(
            svg,
            r#"<rect x="{}" y="{}" width="{}" height="10" fill="{}"/>"#,
            num(x0 + label_px + k as f64 * step),
            num(y - 10.0),
            num(step + 0.05),
            hex(palette::cyclic(t))
        );
    }
    let full = period.to_degrees().round();
    for (k, value) in [0.0, 0.5 * full, full].into_iter().enumerate() {
        let _ = write!(
            svg,
            r#"<text x="{}" y="{}" text-anchor="middle" dominant-baseline="middle">{}°</text>"#,
            num(x0 + label_px + 0.5 * ORIENTATION_BAR_PX * k as f64),
            num(y + 9.0),
            num(value)
        );
    }
    let _ = writeln!(svg, "</g>");
}

/// Height of the scale bar's strip under the drawing (px).
const STRIP_PX: f64 = 40.0;

/// The scale bar of a drawing `scale` px per mm, in the strip under it
/// (`top` px down): a line with end ticks at the right, its length
/// ([`scale_bar_mm`]) written on its left (px).
fn scale_bar(svg: &mut String, top: f64, scale: f64) {
    let length = scale_bar_mm(WIDTH_PX, scale);
    let x1 = WIDTH_PX - 20.0;
    let (x0, y, tick) = (x1 - length * scale, top + 0.5 * STRIP_PX, 6.0);
    let _ = writeln!(
        svg,
        r#"<g id="scale-bar" stroke="black" stroke-width="{}"><line x1="{}" y1="{}" x2="{}" y2="{}"/><line x1="{}" y1="{}" x2="{}" y2="{}"/><line x1="{}" y1="{}" x2="{}" y2="{}"/><text x="{}" y="{}" font-family="sans-serif" font-size="{}" text-anchor="end" dominant-baseline="middle" stroke="none">{} mm</text></g>"#,
        2,
        num(x0),
        num(y),
        num(x1),
        num(y),
        num(x0),
        num(y - tick),
        num(x0),
        num(y + tick),
        num(x1),
        num(y - tick),
        num(x1),
        num(y + tick),
        num(x0 - 8.0),
        num(y),
        14,
        num(length)
    );
}

/// Share of the picture's width a scale bar is at most (a round length).
const SCALE_SHARE: f64 = 0.2;

/// The length (mm) of the scale bar of a picture `width` px wide drawn at
/// `scale` px per mm: the largest 1-2-5 × 10^k mm at most a fifth of the
/// width. `packing.png` and `packing.svg` share it.
pub(super) fn scale_bar_mm(width: f64, scale: f64) -> f64 {
    let most = SCALE_SHARE * width / scale;
    let k = most.log10().floor();
    [5, 2, 1]
        .into_iter()
        .filter_map(|m| format!("{m}e{k}").parse::<f64>().ok())
        .find(|&length| length <= most)
        .unwrap_or(most)
}

/// A side over this many times the other makes a domain slender: its
/// drawing is cut into panels.
const SLENDER: f64 = 8.0;
/// Most panels of a drawing (a 25 m slot 2.3 mm wide takes about 80).
const MAX_PANELS: f64 = 200.0;
/// Gap between two panels, as a share of a panel's width.
const PANEL_GAP: f64 = 0.5;

/// How a drawing lays out its framed box (mm): whole, or cut along its
/// longer side into `count` equal panels, set side by side left to right
/// from the bottom (a tall box) or stacked top to bottom from the left (a
/// wide one), `gap` apart, about as wide as high together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Panels {
    /// The framed box (mm).
    lo: Point,
    hi: Point,
    /// Panels (1: the box whole).
    pub(super) count: usize,
    /// Whether the longer side is y (panels side by side).
    tall: bool,
    /// Gap between panels (mm).
    gap: f64,
}

impl Panels {
    /// The layout of the box `lo`–`hi`.
    pub(super) fn new(lo: Point, hi: Point) -> Self {
        let (w, h) = ((hi.x - lo.x).max(1e-12), (hi.y - lo.y).max(1e-12));
        let (long, short) = (w.max(h), w.min(h));
        let gap = PANEL_GAP * short;
        // n panels of long/n by short, gap apart: n·(short + gap) ≈ long/n.
        let count = if long > SLENDER * short {
            (long / (short + gap)).sqrt().round().clamp(1.0, MAX_PANELS) as usize
        } else {
            1
        };
        Panels {
            lo,
            hi,
            count,
            tall: h > w,
            gap,
        }
    }

    /// Length of a panel along the longer side (mm).
    fn length(&self) -> f64 {
        let long = if self.tall {
            self.hi.y - self.lo.y
        } else {
            self.hi.x - self.lo.x
        };
        long / self.count as f64
    }

    /// Width and height of the panels together, gaps included (mm).
    pub(super) fn size(&self) -> (f64, f64) {
        let n = self.count as f64;
        let (w, h) = (self.hi.x - self.lo.x, self.hi.y - self.lo.y);
        if self.count == 1 {
            (w, h)
        } else if self.tall {
            (n * w + (n - 1.0) * self.gap, self.length())
        } else {
            (self.length(), n * h + (n - 1.0) * self.gap)
        }
    }

    /// The part of the box panel `k` shows (mm).
    pub(super) fn source(&self, k: usize) -> (Point, Point) {
        let (a, b) = (k as f64 * self.length(), (k + 1) as f64 * self.length());
        if self.count == 1 {
            (self.lo, self.hi)
        } else if self.tall {
            (
                Point::new(self.lo.x, self.lo.y + a),
                Point::new(self.hi.x, self.lo.y + b),
            )
        } else {
            (
                Point::new(self.lo.x + a, self.lo.y),
                Point::new(self.lo.x + b, self.hi.y),
            )
        }
    }

    /// Where panel `k`'s top-left corner lies, from the top-left corner of
    /// the panels together (mm, x right, y down).
    pub(super) fn at(&self, k: usize) -> (f64, f64) {
        let k = k as f64;
        if self.count == 1 {
            (0.0, 0.0)
        } else if self.tall {
            (k * (self.hi.x - self.lo.x + self.gap), 0.0)
        } else {
            (0.0, k * (self.hi.y - self.lo.y + self.gap))
        }
    }

    /// The panels each of `disks` reaches into: the indices of the disks
    /// per panel.
    pub(super) fn sort(&self, disks: &[Disk]) -> Vec<Vec<usize>> {
        let mut out = vec![Vec::new(); self.count];
        if self.count == 1 {
            out[0] = (0..disks.len()).collect();
            return out;
        }
        let (start, length) = (if self.tall { self.lo.y } else { self.lo.x }, self.length());
        let last = (self.count - 1) as f64;
        let panel = |v: f64| ((v - start) / length).floor().clamp(0.0, last) as usize;
        for (i, d) in disks.iter().enumerate() {
            let along = if self.tall { d.c.y } else { d.c.x };
            for k in panel(along - d.r)..=panel(along + d.r) {
                if let Some(list) = out.get_mut(k) {
                    list.push(i);
                }
            }
        }
        out
    }

    /// `cut into 83 panels of 302 mm along y, left to right from the
    /// bottom` for a slender domain; empty otherwise.
    pub(super) fn note(&self) -> String {
        if self.count == 1 {
            return String::new();
        }
        let length = self.length();
        let decimals = if length >= 100.0 { 0 } else { 1 };
        if self.tall {
            format!(
                "cut into {} panels of {length:.decimals$} mm along y, left to right from the bottom",
                self.count
            )
        } else {
            format!(
                "cut into {} panels of {length:.decimals$} mm along x, top to bottom from the left",
                self.count
            )
        }
    }
}

/// Largest `packing.svg` (bytes, estimated) that draws every disk: a viewer
/// chokes on larger ones (2 million disks made 138 MB).
pub const SVG_MAX_BYTES: usize = 20_000_000;
/// Bytes a packed disk takes in `packing.svg`: a `<circle …/>` line of
/// about 70 with its fill; a wall disk's line (no fill) about 45.
const SVG_BYTES_PER_DISK: usize = 70;
const SVG_BYTES_PER_WALL_DISK: usize = 45;

/// Bytes a point of a particle's `<polygon>` takes (`x,y ` with up to 4
/// decimals each), and the rest of its line.
const SVG_BYTES_PER_POINT: usize = 16;
const SVG_BYTES_PER_POLYGON: usize = 40;

/// What a drawing of every disk of `packing` would weigh (bytes,
/// estimated); of every particle's polygon, for particles that are not disks.
fn svg_bytes(packing: &Packing) -> usize {
    let walls = SVG_BYTES_PER_WALL_DISK.saturating_mul(packing.boundary.len());
    if packing.grains.is_empty() {
        return SVG_BYTES_PER_DISK
            .saturating_mul(packing.disks.len())
            .saturating_add(walls);
    }
    let (lo, hi) = frame(&packing.domain.outline(CIRCLE_SEGMENTS), packing);
    let scale = WIDTH_PX / Panels::new(lo, hi).size().0.max(1e-12);
    bounding_disks(packing)
        .iter()
        .map(|d| SVG_BYTES_PER_POLYGON + SVG_BYTES_PER_POINT * svg_points(d.r * scale))
        .fold(walls, usize::saturating_add)
}

/// Why `packing.svg` holds an image rather than every disk, when a drawing
/// of every disk would exceed `max_bytes`; `None` otherwise.
pub fn packing_svg_note(packing: &Packing, max_bytes: usize) -> Option<String> {
    let bytes = svg_bytes(packing);
    (bytes > max_bytes).then(|| {
        format!(
            "packing.svg holds packing.png as an image: {}{} drawn one by one would make about {:.0} MB, over the {:.0} MB a viewer opens",
            particles_words(packing),
            match packing.boundary.len() {
                0 => String::new(),
                n => format!(" and {n} wall disks"),
            },
            bytes as f64 / 1e6,
            max_bytes as f64 / 1e6
        )
    })
}

/// `packing.svg`: [`packing_svg_coloured`], or when that would exceed `max_bytes`
/// ([`SVG_MAX_BYTES`] in a run) a light SVG holding `packing.png` as an
/// embedded image, scale bar and legend included, the title saying why.
///
/// # Errors
/// [`OutputError::Plot`] if the image cannot be made.
pub fn packing_svg_within(
    packing: &Packing,
    materials: &[Material],
    diameters: (f64, f64),
    colour: Option<Colouring>,
    max_bytes: usize,
) -> Result<String, OutputError> {
    let Some(note) = packing_svg_note(packing, max_bytes) else {
        return Ok(packing_svg_coloured(packing, materials, diameters, colour));
    };
    let png = packing_png_coloured(packing, materials, diameters, colour)?;
    Ok(svg_of_png(&note, &png))
}

/// The light `packing.svg` holding `png` (`packing.png`) as an embedded
/// image, its title saying why (`note`, [`packing_svg_note`]).
pub(crate) fn svg_of_png(note: &str, png: &[u8]) -> String {
    // The PNG header gives the image's size (bytes 16–23: width, height).
    let side = |at: usize| {
        png.get(at..at + 4)
            .and_then(|b| <[u8; 4]>::try_from(b).ok())
            .map_or(0, u32::from_be_bytes)
    };
    let (w, h) = (side(16), side(20));
    let mut svg = String::new();
    let _ = writeln!(svg, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    let _ = writeln!(svg, "<title>gapack: {note}</title>");
    let _ = writeln!(
        svg,
        r#"<image width="{w}" height="{h}" href="data:image/png;base64,{}"/>"#,
        base64(png)
    );
    let _ = writeln!(svg, "</svg>");
    svg
}

/// `bytes` in base64 (RFC 4648, padded), for a data URI.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The copies of `disk` a drawing shows: the disk itself; in a periodic
/// cell, each of its images that reaches into the cell (the disk first
/// when it is one of them).
pub(super) fn drawn_images(packing: &Packing, disk: &Disk) -> impl Iterator<Item = Disk> {
    let domain = &packing.domain;
    let shifts: Vec<_> = if domain.is_periodic() {
        let (lo, hi) = disk.bounds();
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
    for p in outline {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    bounds_of_disks((lo, hi), packing.boundary.iter().chain(&packing.disks))
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

/// [`num`] written at the end of `out`, fast (a drawing of particles
/// writes millions of numbers): `v` rounded to a whole number of 0.1 µm,
/// written as an integer and its four decimals, trailing zeros dropped.
/// It differs from [`num`] only on a value within an ulp of half a step.
fn push_num(out: &mut String, v: f64) {
    let steps = (v * 1e4).round();
    if steps.is_nan() || steps.abs() >= 1e15 {
        out.push_str(&num(v));
        return;
    }
    let steps = steps as i64;
    if steps < 0 {
        out.push('-');
    }
    let (whole, mut fraction) = (steps.unsigned_abs() / 10_000, steps.unsigned_abs() % 10_000);
    let _ = write!(out, "{whole}");
    if fraction > 0 {
        let mut digits = 4;
        while fraction % 10 == 0 {
            fraction /= 10;
            digits -= 1;
        }
        let _ = write!(out, ".{fraction:0digits$}");
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
        // Under it a strip of 40 px for the scale bar.
        assert!(svg.contains(r#"width="800" height="1595">"#), "{svg}");
        assert!(
            svg.contains(r#"<svg width="800" height="1555" viewBox="-0.3 -0.3 10.6 20.6""#),
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

    /// The first `<line>` of the scale bar (its length) and its label.
    fn scale_bar_of(svg: &str) -> (f64, f64, f64, String) {
        let bar = &svg[svg.find(r#"<g id="scale-bar""#).expect("a scale bar")..];
        let attribute = |name: &str| -> f64 {
            let start = bar.find(&format!(" {name}=\"")).expect(name) + name.len() + 3;
            let end = start + bar[start..].find('"').expect("quote");
            bar[start..end].parse().expect("a number")
        };
        let open = bar.find(r#"stroke="none">"#).expect("text") + 14;
        let label = &bar[open..bar.find("</text>").expect("text")];
        (
            attribute("x1"),
            attribute("x2"),
            attribute("y1"),
            label.to_owned(),
        )
    }

    /// `packing.png` had a scale bar, `packing.svg` none: the SVG's is
    /// as long as the same rule gives (a round length of at most a fifth
    /// of the width), labelled in mm, under the drawing.
    #[test]
    fn packing_svg_has_a_scale_bar_under_the_drawing() {
        for (w, h, length) in [(10.0, 20.0, 2.0), (100.0, 20.0, 20.0), (62.5, 8.6, 10.0)] {
            let p = Packing::of_disks(
                Domain::rectangle(w, h).expect("rectangle"),
                vec![Disk::new(1.0, 1.0, 1.0)],
            );
            let svg = packing_svg(&p, &[], (2.0, 2.0));
            let (x1, x2, y, label) = scale_bar_of(&svg);
            // The drawing: the domain and its margins, 800 px wide.
            let (margin_w, margin_h) = (w + 0.06 * w.min(h), h + 0.06 * w.min(h));
            let scale = 800.0 / margin_w;
            assert!(
                (x2 - x1 - length * scale).abs() < 1e-3,
                "{w} × {h}: {x1}–{x2} px"
            );
            assert_eq!(label, format!("{} mm", num(length)));
            assert!(length <= 0.2 * margin_w && length > 0.08 * margin_w);
            // In the strip under the drawing, right of its middle.
            let drawing = (margin_h * scale).round();
            assert!(y > drawing && y < drawing + 40.0, "{y} px");
            assert!(x1 > 400.0 && x2 < 800.0);
        }
    }

    /// A 2.3 mm × 25 m slot was drawn 800 px wide and about 8.7 million px
    /// high (a wedge 3 mm × 150 mm: 800 × 37,781 px): panels side by side
    /// keep it about square, every disk drawn once.
    #[test]
    fn a_slender_domain_is_drawn_in_panels_of_a_bounded_size() {
        for (w, h) in [(2.3f64, 25_000.0f64), (25_000.0, 2.3), (3.0, 150.0)] {
            let tall = h > w;
            let disks: Vec<Disk> = (0..2000)
                .map(|i| {
                    let along = 0.6 + f64::from(i) * (w.max(h) - 1.2) / 1999.0;
                    if tall {
                        Disk::new(w / 2.0, along, 0.5)
                    } else {
                        Disk::new(along, h / 2.0, 0.5)
                    }
                })
                .collect();
            let p = Packing::of_disks(Domain::rectangle(w, h).expect("rectangle"), disks);
            let svg = packing_svg(&p, &[], (1.0, 1.0));
            let start = svg.find("width=").expect("width");
            let size: Vec<f64> = svg[start..]
                .split('"')
                .skip(1)
                .step_by(2)
                .take(2)
                .map(|v| v.parse().expect("a number"))
                .collect();
            assert_eq!(size[0], 800.0);
            assert!((400.0..=1200.0).contains(&size[1]), "{w} × {h}: {size:?}");
            assert!(svg.contains("panels of"), "{w} × {h}");
            // Each disk once (none lies across a panel's end here but a few).
            let circles = svg.matches("<circle").count();
            assert!((2000..2100).contains(&circles), "{circles}");
        }
    }

    #[test]
    fn panels_cut_the_length_and_sort_the_disks_they_show() {
        let panels = Panels::new(Point::new(0.0, 0.0), Point::new(2.0, 200.0));
        // n panels of 200/n × 2 mm, 1 mm apart, about square: n = 8 (√(200/3)).
        assert_eq!(panels.count, 8);
        assert_eq!(
            panels.source(1),
            (Point::new(0.0, 25.0), Point::new(2.0, 50.0))
        );
        assert_eq!(panels.at(2), (6.0, 0.0));
        assert_eq!(panels.size(), (23.0, 25.0));
        // A disk across the end of panel 0 is in panels 0 and 1.
        let sorted = panels.sort(&[Disk::new(1.0, 24.8, 0.5), Disk::new(1.0, 199.0, 0.5)]);
        assert_eq!(sorted[0], [0]);
        assert_eq!(sorted[1], [0]);
        assert_eq!(sorted[7], [1]);
        // Not slender: whole.
        let whole = Panels::new(Point::new(0.0, 0.0), Point::new(62.5, 8.6));
        assert_eq!((whole.count, whole.size()), (1, (62.5, 8.6)));
    }

    /// 2 million disks wrote a 138 MB `packing.svg`: over the limit the
    /// SVG holds the PNG as an image, its title saying why.
    #[test]
    fn a_huge_packing_s_svg_holds_an_image() {
        let p = packing(Vec::new());
        // 2 disks × 70 bytes: over a limit of 100 bytes.
        let note = packing_svg_note(&p, 100).expect("over the limit");
        assert!(
            note.starts_with("packing.svg holds packing.png as an image: 2 disks drawn"),
            "{note}"
        );
        let light = packing_svg_within(&p, &[], (2.0, 4.0), None, 100).expect("svg");
        assert!(light.contains(r#"href="data:image/png;base64,iVBORw0KGgo"#));
        assert!(!light.contains("<circle"));
        assert!(light.contains(&note));
        // Under the limit: every disk drawn.
        assert_eq!(packing_svg_note(&p, SVG_MAX_BYTES), None);
        assert_eq!(
            packing_svg_within(&p, &[], (2.0, 4.0), None, SVG_MAX_BYTES).expect("svg"),
            packing_svg(&p, &[], (2.0, 4.0))
        );
        // 2 million disks are over the real limit.
        const { assert!(SVG_BYTES_PER_DISK * 2_000_000 > SVG_MAX_BYTES) };
    }

    /// Particles that are not disks: one `<polygon>` each (the domain's
    /// outline is the one without a fill colour), no circle; the title
    /// names them and what their colours say.
    #[test]
    fn grains_are_one_polygon_each() {
        use crate::geometry::{Grain, Outline};
        let ellipse = Outline::superellipse(3.0, 1.0, 2.0, 2.0).expect("ellipse");
        let r = ellipse.equivalent_radius();
        let p = Packing {
            grains: vec![
                Grain::new(ellipse.clone(), 0.0),
                Grain::new(ellipse.clone(), 1.0),
                Grain::new(ellipse, 2.0),
            ],
            ..Packing::of_disks(
                Domain::rectangle(20.0, 10.0).expect("rectangle"),
                vec![
                    Disk::new(4.0, 5.0, r),
                    Disk::new(10.0, 5.0, r),
                    Disk::new(16.0, 5.0, r),
                ],
            )
        };
        let svg = packing_svg(&p, &[], (1.0, 2.0));
        assert_eq!(svg.matches(r##"<polygon points=""##).count(), 4, "{svg}");
        assert_eq!(svg.matches(r##"" fill="#"##).count(), 3, "{svg}");
        assert!(!svg.contains("<circle"));
        assert!(
            svg.contains("3 particles (superellipses), 0 wall disks")
                && svg.contains("by area-equivalent diameter"),
            "{svg}"
        );
        // The first ellipse's first point: the end of its long axis, y flipped.
        assert!(svg.contains(r#"<polygon points="7,5 "#), "{svg}");
        let by_angle = packing_svg_coloured(&p, &[], (1.0, 2.0), Some(Colouring::Orientation));
        assert!(by_angle.contains(r#"<g id="orientation-bar""#));
        assert!(by_angle.contains("cyclic scale over 0 to 180°"));
        // Three different colours for three angles.
        let fills: std::collections::BTreeSet<&str> = by_angle
            .split("<polygon points=")
            .filter_map(|element| element.split_once(r##"" fill="#"##))
            .map(|(_, rest)| &rest[..6])
            .collect();
        assert_eq!(fills.len(), 3, "{fills:?}");
        // The estimate of the SVG's size counts the polygons' points.
        assert!(svg_bytes(&p) >= 3 * (SVG_BYTES_PER_POLYGON + 8 * SVG_BYTES_PER_POINT));
        assert!(
            svg_bytes(&p).abs_diff(svg.len()) < svg.len() / 2,
            "{} {}",
            svg_bytes(&p),
            svg.len()
        );
    }

    #[test]
    fn base64_pads_as_rfc_4648() {
        assert_eq!(base64(b"Man"), "TWFu");
        assert_eq!(base64(b"Ma"), "TWE=");
        assert_eq!(base64(b"M"), "TQ==");
        assert_eq!(base64(b""), "");
        assert_eq!(base64(&[0xff, 0xfe, 0xfd, 0xfc]), "//79/A==");
    }

    #[test]
    fn numbers_are_short_and_stable() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.00001), "0");
        assert_eq!(num(2.50), "2.5");
        assert_eq!(num(1.234_567), "1.2346");
        assert_eq!(num(100.0), "100");
        for v in [
            1.0,
            -0.00001,
            2.5,
            1.234_567,
            100.0,
            -3.0,
            0.0,
            -0.25,
            0.0503,
            f64::NAN,
            1e20,
        ] {
            let mut out = "x".to_owned();
            push_num(&mut out, v);
            assert_eq!(out, format!("x{}", num(v)), "{v}");
        }
    }
}
