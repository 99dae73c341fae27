//! `packing.png`: the drawing of `packing.svg` as an image, with a legend.
//!
//! The disks are rasterised here, straight into the pixel buffer, with
//! anti-aliased edges: a million disks take a fraction of a second this way,
//! where plotters' circles cost far more and have jagged edges. Plotters then
//! draws the domain outline and the legend (text needs its font) on the
//! same buffer. The legend strip under the drawing carries a scale bar, so
//! it covers no disk.
//!
//! Particles that are not disks are rasterised the same way, as convex
//! polygons ([`super::particles`]): each pixel's coverage is read from
//! its distance to the nearest side, so edges are as smooth as a disk's.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{FAMILY, encode_png, register_font, tidy};
use super::particles::{Colouring, Fills, boundary_points, bounding_disks, outline_at};
use super::pile::{Clip, DiskPx, blend, draw_pile, is_pile, pile_of_parts, pile_part};
use super::text::Glyphs;
use crate::geometry::{Disk, Point};
use crate::layering::Material;
use crate::metrics::{porosity, solid_area};
use crate::output::OutputError;
use crate::output::palette::{colour, cyclic, ramp};
use crate::output::svg::{
    CIRCLE_SEGMENTS, DISK_EDGE, Panels, WALL_EDGE, WALL_FILL, drawn_images, frame, scale_bar_mm,
};
use crate::packer::Packing;
use rayon::prelude::*;

/// File name of the drawing as an image.
pub const PACKING_PNG: &str = "packing.png";

/// Pixels on the longer side of the image.
const LONG_SIDE: u32 = 1600;
/// Height of the legend strip under the drawing.
const LEGEND_PX: u32 = 80;
/// Narrowest image with a legend: a tall domain is centred in a wider image.
const LEGEND_MIN_WIDTH: u32 = 900;
/// Legend text size.
const FONT_PX: u32 = 22;
/// Side of a legend swatch, height of the colour bar.
const SWATCH: i32 = 24;
/// Length of the colour bar.
const BAR: i32 = 320;
/// Space between legend items and at the strip's ends.
const GAP: i32 = 20;
/// Height of the line above the legend saying how a slender domain is cut into panels.
const NOTE_PX: u32 = 36;
/// Offset of the legend's right-hand rows (scale bar above, counts below)
/// from the strip's middle.
const ROW: i32 = 16;
/// Width of the disks' edge line (pixels), thinner on disks under 4 px across.
const EDGE_PX: f64 = 1.0;

/// Where the drawing goes in the image: the framed box whole, or cut into
/// panels ([`Panels`], as in `packing.svg`), drawn `scale` px per mm.
#[derive(Debug, Clone, Copy)]
struct Layout {
    /// Image size (pixels).
    size: (u32, u32),
    /// Pixels per mm.
    scale: f64,
    /// The panels.
    panels: Panels,
    /// Pixels left of the drawing (it is centred in a wider image).
    left: f64,
    /// Whether the legend strip is drawn.
    legend: bool,
    /// Height of the strip under the drawing: the legend, and above it the
    /// line on the panels if any (pixels).
    strip: u32,
}

impl Layout {
    fn new(packing: &Packing, outline: &[Point]) -> Self {
        let (lo, hi) = frame(outline, packing);
        let panels = Panels::new(lo, hi);
        let (w, h) = panels.size();
        let (w, h) = (w.max(1e-12), h.max(1e-12));
        let legend = !packing.disks.is_empty();
        let note = if panels.count > 1 { NOTE_PX } else { 0 };
        let strip = if legend { LEGEND_PX } else { 0 } + note;
        let long = f64::from(LONG_SIDE);
        let by_width = long / w;
        let by_height = f64::from(LONG_SIDE - strip) / h;
        // The longer side of the image is exactly LONG_SIDE pixels.
        let (scale, draw_w, draw_h) = if by_width <= by_height {
            (by_width, LONG_SIDE, px(h * by_width))
        } else {
            (by_height, px(w * by_height), LONG_SIDE - strip)
        };
        let width = if legend {
            draw_w.max(LEGEND_MIN_WIDTH)
        } else {
            draw_w
        };
        Layout {
            size: (width, draw_h + strip),
            scale,
            panels,
            left: 0.5 * f64::from(width - draw_w),
            legend,
            strip,
        }
    }

    /// A point of panel `k` in pixels.
    fn map(&self, k: usize, p: Point) -> (f64, f64) {
        let (lo, hi) = self.panels.source(k);
        let (dx, dy) = self.panels.at(k);
        (
            (p.x - lo.x + dx) * self.scale + self.left,
            (hi.y - p.y + dy) * self.scale,
        )
    }

    /// The pixel columns and rows of the box `lo`–`hi` in panel `k`,
    /// within the image.
    fn pixels(&self, k: usize, lo: Point, hi: Point) -> (usize, usize, usize, usize) {
        let ((x0, y1), (x1, y0)) = (self.map(k, lo), self.map(k, hi));
        let at = |v: f64, n: u32| v.round().clamp(0.0, f64::from(n)) as usize;
        let (w, h) = self.size;
        (at(x0, w), at(x1, w), at(y0, h), at(y1, h))
    }
}

/// A pixel count from a length in pixels: rounded, at least 1.
fn px(v: f64) -> u32 {
    v.round().clamp(1.0, f64::from(u32::MAX)) as u32
}

/// The packing as a PNG image: what [`packing_svg`](crate::output::packing_svg)
/// draws (the domain outline in black, wall disks light grey, packed disks
/// by material or light to dark over `diameters`, in mm), 1600 px on the
/// longer side, with a legend strip below: the diameter colour bar or the
/// materials, a scale bar in mm, the disk count and the porosity.
///
/// # Errors
/// [`OutputError::Plot`] if plotters fails to draw or the PNG cannot be encoded.
///
/// # Performance
/// Each disk is drawn straight into the buffer over its bounding box of
/// pixels: O(disks + pixels). A million disks render in well under a
/// second; most of the time goes to encoding the PNG. Disks piled on one
/// another (their boxes of pixels adding up to more than 4 images' worth)
/// are drawn back to front at a cost of their rows and the pixels still
/// open (`pile` module): 10⁵ copies of a disk filling the image take 0.3 s,
/// not 200.
///
/// Particles that are not disks are drawn as they are: see
/// [`packing_png_coloured`].
pub fn packing_png(
    packing: &Packing,
    materials: &[Material],
    diameters: (f64, f64),
) -> Result<Vec<u8>, OutputError> {
    packing_png_coloured(packing, materials, diameters, None)
}

/// [`packing_png`] with the particles filled as `colour` asks
/// ([`Colouring`]; `None`: by material when the particles carry one and
/// `materials` name them, else by size, as [`packing_png`] does).
///
/// A particle that is not a disk is its outline
/// ([`Outline::boundary`](crate::geometry::Outline::boundary), inscribed
/// in it) turned by its angle, with 8 to 128 points as it is drawn larger
/// (`boundary_points`: within 0.1 px of the outline), filled and edged as
/// a disk is. Such particles are shaded by their area-equivalent diameter
/// over their own range, or coloured by orientation on a cyclic scale
/// (0–180° for superellipses, 0–360° when there are polygons), the legend
/// showing the scale.
///
/// # Errors
/// [`OutputError::Plot`] if plotters fails to draw or the PNG cannot be encoded.
///
/// # Performance
/// O(particles · points + pixels · points on the edges): a particle's
/// inner pixels are filled by spans, only its rim is measured against
/// its sides.
pub fn packing_png_coloured(
    packing: &Packing,
    materials: &[Material],
    diameters: (f64, f64),
    colour: Option<Colouring>,
) -> Result<Vec<u8>, OutputError> {
    register_font();
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    let layout = Layout::new(packing, &outline);
    let (w, h) = layout.size;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    let periodic = packing.domain.is_periodic();
    let panels = layout.panels;
    // Particles that are not disks are sorted by their bounding disks.
    let bounding = bounding_disks(packing);
    let grains = !packing.grains.is_empty();
    let (walls, disks) = (
        panels.sort(&packing.boundary),
        panels.sort(if grains { &bounding } else { &packing.disks }),
    );
    let fills = Fills::of(packing, materials, diameters, colour);
    // Each panel's disks are clipped to it, a periodic cell's to the cell too.
    let clips: Vec<Clip> = (0..panels.count)
        .map(|k| {
            let (lo, hi) = panels.source(k);
            let mut clip = if panels.count > 1 {
                layout.pixels(k, lo, hi)
            } else {
                (0, w as usize, 0, h as usize)
            };
            if periodic {
                let (lo, hi) = packing.domain.bounds();
                let cell = layout.pixels(k, lo, hi);
                clip = (
                    clip.0.max(cell.0),
                    clip.1.min(cell.1),
                    clip.2.max(cell.2),
                    clip.3.min(cell.3),
                );
            }
            clip
        })
        .collect();
    let size = (w as usize, h as usize);
    let pixel_disk = |k: usize, d: &Disk, fill: [u8; 3], edge: [u8; 3]| {
        let (cx, cy) = layout.map(k, d.c);
        DiskPx::new(
            (cx, cy, d.r * layout.scale),
            EDGE_PX,
            size,
            clips[k],
            fill,
            edge,
        )
    };
    if grains {
        for (k, &clip) in clips.iter().enumerate() {
            let mut canvas = Canvas {
                rgb: &mut rgb,
                width: size.0,
                height: size.1,
                clip,
                panel: k,
            };
            for &i in walls.get(k).into_iter().flatten() {
                canvas.disk(&layout, &packing.boundary[i], WALL_FILL, WALL_EDGE);
            }
            for &i in disks.get(k).into_iter().flatten() {
                let fill = fills.of_particle(packing, i);
                if let (Some(grain), Some(bound)) = (packing.grains.get(i), bounding.get(i)) {
                    let n = boundary_points(bound.r * layout.scale);
                    for at in drawn_images(packing, bound) {
                        let outline = outline_at(grain, at.c, n);
                        canvas.polygon(&layout, &outline, fill, DISK_EDGE);
                    }
                }
            }
        }
    } else {
        // The disks in drawing order: each panel's walls, then its disks
        // at each of their images.
        let (walls, disks, fills, pixel_disk) = (&walls, &disks, &fills, &pixel_disk);
        let drawn = || {
            (0..panels.count).flat_map(move |k| {
                let walls = walls.get(k).into_iter().flatten().filter_map(move |&i| {
                    pixel_disk(k, &packing.boundary[i], WALL_FILL, WALL_EDGE)
                });
                let packed = disks.get(k).into_iter().flatten().flat_map(move |&i| {
                    let fill = fills.of_particle(packing, i);
                    drawn_images(packing, &packing.disks[i])
                        .filter_map(move |at| pixel_disk(k, &at, fill, DISK_EDGE))
                });
                walls.chain(packed)
            })
        };
        // Outside a periodic cell each disk is drawn once, as itself: the
        // pile test runs over chunks of the disks on all cores, and the
        // drawing in bands of rows (below).
        let pile = if periodic {
            is_pile(drawn(), size)
        } else {
            let parts: Vec<(i128, i128)> = (0..panels.count)
                .flat_map(|k| {
                    [
                        (k, walls.get(k), &packing.boundary),
                        (k, disks.get(k), &packing.disks),
                    ]
                })
                .flat_map(|(k, list, from)| {
                    list.map_or(&[][..], Vec::as_slice)
                        .par_chunks(1 << 16)
                        .map(|chunk| {
                            pile_part(
                                chunk
                                    .iter()
                                    .filter_map(|&i| pixel_disk(k, &from[i], WALL_FILL, WALL_EDGE)),
                            )
                        })
                        .collect::<Vec<_>>()
                })
                .collect();
            pile_of_parts(parts.into_iter(), size)
        };
        if pile {
            let piled: Vec<DiskPx> = drawn().collect();
            draw_pile(&mut rgb, size, &piled);
        } else if periodic {
            for d in drawn() {
                d.draw(&mut rgb, size.0);
            }
        } else {
            draw_in_bands(
                &mut rgb,
                size,
                &layout,
                &clips,
                walls,
                disks,
                |i| fills.of_particle(packing, i),
                packing,
            );
        }
    }
    {
        let root = Glyphs(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
        let plot = |e: DrawingAreaErrorKind<_>| OutputError::Plot(e.to_string());
        for line in outline_lines(&layout, &outline) {
            if periodic {
                // Dashed: the cell's edges are not walls.
                for dash in dashes(&line, DASH_PX) {
                    root.draw(&PathElement::new(dash, BLACK.stroke_width(2)))
                        .map_err(plot)?;
                }
            } else {
                root.draw(&PathElement::new(line, BLACK.stroke_width(2)))
                    .map_err(plot)?;
            }
        }
        if panels.count > 1 {
            let font = (FAMILY, FONT_PX).into_font();
            let y = (h - layout.strip) as i32 + NOTE_PX as i32 / 2;
            root.draw(&Text::new(
                panels.note(),
                (GAP, y),
                font.color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center)),
            ))
            .map_err(plot)?;
        }
        if layout.legend {
            let strip = root.margin(h - LEGEND_PX, 0, 0, 0);
            let legend = match fills {
                Fills::Materials(_) => Legend::Materials(materials),
                Fills::Diameters(range) => Legend::Diameters(range),
                Fills::Orientation { period } => Legend::Orientation { period },
            };
            draw_legend(&strip, packing, &legend, layout.scale).map_err(plot)?;
        }
        root.present().map_err(plot)?;
    }
    encode_png(&rgb, (w, h))
}

/// Draw each panel's wall disks then its packed disks (`walls[k]`,
/// `disks[k]`: indices into `packing.boundary` and `packing.disks`), one
/// after another as [`DiskPx::draw`] would, over `rgb` (`size` pixels)
/// cut into bands of rows drawn in parallel: each band draws, in the same
/// order, the disks whose rows reach it, within its rows only, so every
/// pixel takes the same steps in the same order whatever the bands and
/// threads, and the image is the same to the byte.
#[allow(clippy::too_many_arguments)]
fn draw_in_bands(
    rgb: &mut [u8],
    size: (usize, usize),
    layout: &Layout,
    clips: &[Clip],
    walls: &[Vec<usize>],
    disks: &[Vec<usize>],
    fill: impl Fn(usize) -> [u8; 3] + Sync,
    packing: &Packing,
) {
    let threads = rayon::current_num_threads();
    let bands = if threads <= 1 { 1 } else { 4 * threads };
    let rows = size.1.div_ceil(bands).max(1);
    let (width, scale) = (size.0, layout.scale);
    rgb.par_chunks_mut(rows * width * 3)
        .enumerate()
        .for_each(|(b, band)| {
            let (first, end) = (b * rows, ((b + 1) * rows).min(size.1));
            for (k, &clip) in clips.iter().enumerate() {
                let clip = (clip.0, clip.1, clip.2.max(first), clip.3.min(end));
                if clip.2 >= clip.3 {
                    continue;
                }
                let runs = [
                    (walls.get(k), &packing.boundary, true),
                    (disks.get(k), &packing.disks, false),
                ];
                for (list, from, wall) in runs {
                    for &i in list.into_iter().flatten() {
                        let d = &from[i];
                        let (cx, cy) = layout.map(k, d.c);
                        let r = d.r * scale;
                        // Rows the disk's box spans (DiskPx::new): none here.
                        if cy + r + 1.0 < first as f64 || cy - r - 1.0 >= end as f64 {
                            continue;
                        }
                        let (f, e) = if wall {
                            (WALL_FILL, WALL_EDGE)
                        } else {
                            (fill(i), DISK_EDGE)
                        };
                        if let Some(px) = DiskPx::new((cx, cy, r), EDGE_PX, size, clip, f, e) {
                            px.draw_rows(band, width, first);
                        }
                    }
                }
            }
        });
}

/// The domain's outline in pixels: the closed ring, or cut into panels its
/// parts in each panel.
fn outline_lines(layout: &Layout, outline: &[Point]) -> Vec<Vec<(i32, i32)>> {
    let pixel = |k: usize, p: Point| {
        let (x, y) = layout.map(k, p);
        (x.round() as i32, y.round() as i32)
    };
    let ring = outline.iter().chain(outline.first());
    let panels = layout.panels;
    if panels.count == 1 {
        return vec![ring.map(|&p| pixel(0, p)).collect()];
    }
    let ring: Vec<Point> = ring.copied().collect();
    let mut lines = Vec::new();
    for k in 0..panels.count {
        let (lo, hi) = panels.source(k);
        for pair in ring.windows(2) {
            if let Some((a, b)) = clip_segment(pair[0], pair[1], lo, hi) {
                lines.push(vec![pixel(k, a), pixel(k, b)]);
            }
        }
    }
    lines
}

/// The part of the segment `p`–`q` inside the box `lo`–`hi` (Liang–Barsky).
fn clip_segment(p: Point, q: Point, lo: Point, hi: Point) -> Option<(Point, Point)> {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, room) in [
        (-d.x, p.x - lo.x),
        (d.x, hi.x - p.x),
        (-d.y, p.y - lo.y),
        (d.y, hi.y - p.y),
    ] {
        if den == 0.0 {
            if room < 0.0 {
                return None;
            }
        } else if den < 0.0 {
            t0 = t0.max(room / den);
        } else {
            t1 = t1.min(room / den);
        }
    }
    (t0 < t1).then(|| (p + t0 * d, p + t1 * d))
}

/// Length of the dashes (and of the gaps between them) of a periodic cell's outline (pixels).
const DASH_PX: f64 = 10.0;

/// The dashes of the polyline `ring`, each `dash` pixels long with gaps as
/// long, the pattern running on across its corners.
fn dashes(ring: &[(i32, i32)], dash: f64) -> Vec<Vec<(i32, i32)>> {
    let mut out: Vec<Vec<(i32, i32)>> = Vec::new();
    // Distance along the polyline, and whether the pen is down there.
    let mut along = 0.0f64;
    let mut current: Vec<(i32, i32)> = Vec::new();
    let point = |a: (i32, i32), b: (i32, i32), t: f64| {
        (
            (f64::from(a.0) + t * f64::from(b.0 - a.0)).round() as i32,
            (f64::from(a.1) + t * f64::from(b.1 - a.1)).round() as i32,
        )
    };
    for pair in ring.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let len = f64::from(b.0 - a.0).hypot(f64::from(b.1 - a.1));
        if len == 0.0 {
            continue;
        }
        let mut t = 0.0;
        while t < len {
            let phase = along % (2.0 * dash);
            let down = phase < dash;
            let step = (if down {
                dash - phase
            } else {
                2.0 * dash - phase
            })
            .min(len - t);
            if down {
                if current.is_empty() {
                    current.push(point(a, b, t / len));
                }
                current.push(point(a, b, (t + step) / len));
            } else if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
            t += step;
            along += step;
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}

/// An RGB buffer, row by row from the top.
struct Canvas<'a> {
    rgb: &'a mut [u8],
    width: usize,
    height: usize,
    /// Pixel columns `.0..1` and rows `.2..3` drawn into (the whole image,
    /// a panel, a periodic cell).
    clip: (usize, usize, usize, usize),
    /// The panel drawn.
    panel: usize,
}

impl Canvas<'_> {
    /// Draw `disk` filled with `fill`, with an edge line of `edge`,
    /// anti-aliased by the distance of each pixel's centre to the rim
    /// ([`DiskPx`]).
    fn disk(&mut self, layout: &Layout, disk: &Disk, fill: [u8; 3], edge: [u8; 3]) {
        let (cx, cy) = layout.map(self.panel, disk.c);
        let size = (self.width, self.height);
        let at = (cx, cy, disk.r * layout.scale);
        if let Some(d) = DiskPx::new(at, EDGE_PX, size, self.clip, fill, edge) {
            d.draw(self.rgb, self.width);
        }
    }

    /// Draw the convex polygon `outline` (mm, counter-clockwise) filled
    /// with `fill`, with an edge line of `edge`, anti-aliased as
    /// [`Canvas::disk`] is, by the distance of each pixel's centre to the
    /// outline: the largest of its signed distances to the sides' lines
    /// (exact inside and along the sides; near a corner a little less).
    fn polygon(&mut self, layout: &Layout, outline: &[Point], fill: [u8; 3], edge: [u8; 3]) {
        let points: Vec<(f64, f64)> = outline.iter().map(|&p| layout.map(self.panel, p)).collect();
        if points.len() < 3
            || points
                .iter()
                .any(|(x, y)| !(x.is_finite() && y.is_finite()))
        {
            return;
        }
        // Each side as n·p ≤ c inside, n its outward unit normal (pixels,
        // y down: the outline turns clockwise there, unless reflected).
        let n_points = points.len();
        let twice_area: f64 = (0..n_points)
            .map(|i| {
                let ((x0, y0), (x1, y1)) = (points[i], points[(i + 1) % n_points]);
                x0 * y1 - x1 * y0
            })
            .sum();
        let turn = if twice_area < 0.0 { -1.0 } else { 1.0 };
        let sides: Vec<(f64, f64, f64)> = (0..n_points)
            .filter_map(|i| {
                let ((x0, y0), (x1, y1)) = (points[i], points[(i + 1) % n_points]);
                let (ex, ey) = (x1 - x0, y1 - y0);
                let len = ex.hypot(ey);
                (len > 0.0).then(|| {
                    let (nx, ny) = (turn * ey / len, -turn * ex / len);
                    (nx, ny, nx * x0 + ny * y0)
                })
            })
            .collect();
        if sides.len() < 3 {
            return;
        }
        let distance = |x: f64, y: f64| {
            sides
                .iter()
                .map(|&(nx, ny, c)| nx * x + ny * y - c)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        // The edge line thins on small particles so that their fill shows,
        // as on disks: a quarter of the distance from the centre to the nearest side.
        let (cx, cy) = points.iter().fold((0.0, 0.0), |(sx, sy), (x, y)| {
            (sx + x / n_points as f64, sy + y / n_points as f64)
        });
        let line = EDGE_PX.min(0.25 * (-distance(cx, cy)).max(0.0));
        // Pixel centres x with n·(x, y) − c < `reach` for every side: a
        // span of the row at height y (empty: start ≥ end).
        let span = |y: f64, reach: f64| {
            let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
            for &(nx, ny, c) in &sides {
                let room = c + reach - ny * y;
                if nx > 1e-12 {
                    hi = hi.min(room / nx);
                } else if nx < -1e-12 {
                    lo = lo.max(room / nx);
                } else if room < 0.0 {
                    return (0.0, 0.0);
                }
            }
            (lo, hi)
        };
        let clip = |v: f64, n: usize| v.clamp(0.0, n as f64) as usize;
        let (y_min, y_max) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(_, y)| {
                (lo.min(y), hi.max(y))
            });
        let (j0, j1) = (
            clip(y_min - 1.0, self.height).max(self.clip.2),
            clip(y_max + 2.0, self.height).min(self.clip.3),
        );
        // Pixels (i + ½ in the span) of a row, within the clip.
        let columns = |(lo, hi): (f64, f64)| {
            if lo >= hi {
                return (0, 0);
            }
            let first = clip((lo - 0.5).ceil(), self.width).max(self.clip.0);
            let end = clip((hi - 0.5).floor() + 1.0, self.width).min(self.clip.1);
            (first, end.max(first))
        };
        for j in j0..j1 {
            let y = j as f64 + 0.5;
            let row = j * self.width;
            // Touched pixels: d < ½; filled whole: d ≤ −(line + ½).
            let (a0, a1) = columns(span(y, 0.5));
            if a0 >= a1 {
                continue;
            }
            let (s0, s1) = columns(span(y, -(line + 0.5)));
            let (s0, s1) = if s0 < s1 {
                (s0.clamp(a0, a1), s1.clamp(a0, a1))
            } else {
                (a0, a0)
            };
            for i in s0..s1 {
                self.rgb[3 * (row + i)..3 * (row + i) + 3].copy_from_slice(&fill);
            }
            for i in (a0..s0).chain(s1..a1) {
                let d = distance(i as f64 + 0.5, y);
                let cover = (0.5 - d).clamp(0.0, 1.0);
                if cover == 0.0 {
                    continue;
                }
                let inner = (0.5 - line - d).clamp(0.0, 1.0);
                let at = 3 * (row + i);
                blend(&mut self.rgb[at..at + 3], cover, inner, fill, edge);
            }
        }
    }
}

/// What the legend strip shows besides the counts.
enum Legend<'a> {
    /// The colour bar of the diameters (mm).
    Diameters((f64, f64)),
    /// One swatch per material.
    Materials(&'a [Material]),
    /// The cyclic colour bar of the orientations over 0 to `period` (radians).
    Orientation {
        /// The angle the scale spans (radians).
        period: f64,
    },
}

/// The legend strip: a colour bar or material swatches on the left, wall
/// disks if any; on the right a scale bar (`scale` px per mm) above the
/// disk count and porosity. An item that would run into the right-hand
/// ones is left out.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    packing: &Packing,
    legend: &Legend<'_>,
    scale: f64,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, height) = area.dim_in_pixel();
    let (width, mid) = (width as i32, height as i32 / 2);
    let font = (FAMILY, FONT_PX).into_font();
    let text = font.color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    let text_width = |s: &str| -> Result<i32, DrawingAreaErrorKind<DB::ErrorType>> {
        Ok(area.estimate_text_size(s, &text)?.0 as i32)
    };
    let counts = legend_counts(packing);
    let end = font.color(&BLACK).pos(Pos::new(HPos::Right, VPos::Center));
    let bar_mm = scale_bar_mm(f64::from(width), scale);
    let bar_px = (bar_mm * scale).round() as i32;
    let bar_label = format!("{} mm", tidy(&bar_mm));
    let bar_width = text_width(&bar_label)? + 8 + bar_px;
    let right = width - GAP - text_width(&counts)?.max(bar_width);
    area.draw(&Text::new(counts, (width - GAP, mid + ROW), end.clone()))?;
    // The scale bar: a line with end ticks, its length on its left.
    let (x0, x1, y) = (width - GAP - bar_px, width - GAP, mid - ROW);
    for line in [
        vec![(x0, y), (x1, y)],
        vec![(x0, y - 6), (x0, y + 6)],
        vec![(x1, y - 6), (x1, y + 6)],
    ] {
        area.draw(&PathElement::new(line, BLACK.stroke_width(2)))?;
    }
    area.draw(&Text::new(bar_label, (x0 - 8, y), end))?;
    let room = right - GAP;
    let half = SWATCH / 2;
    let swatch = |x: i32, [r, g, b]: [u8; 3]| {
        Rectangle::new(
            [(x, mid - half), (x + SWATCH, mid + half)],
            RGBColor(r, g, b).filled(),
        )
    };
    // Width of a swatch and its text, up to the next item.
    let item = |s: &str| -> Result<i32, DrawingAreaErrorKind<DB::ErrorType>> {
        Ok(SWATCH + 8 + text_width(s)? + GAP)
    };
    let mut x = GAP;
    // A colour bar: its label, `shade` over 0–1, and its tick labels below.
    let bar = |x: &mut i32,
               label: &str,
               ticks: &[String],
               shade: &dyn Fn(f64) -> [u8; 3]|
     -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let overhang = text_width(ticks.last().map_or("", String::as_str))? / 2;
        let label_width = text_width(label)? + 12;
        if *x + label_width + BAR + overhang <= room {
            let (top, bottom) = (mid - SWATCH, mid);
            area.draw(&Text::new(label, (*x, mid - half), text.clone()))?;
            *x += label_width;
            for k in 0..BAR {
                let [r, g, b] = shade(f64::from(k) / f64::from(BAR - 1));
                area.draw(&Rectangle::new(
                    [(*x + k, top), (*x + k + 1, bottom)],
                    RGBColor(r, g, b).filled(),
                ))?;
            }
            area.draw(&Rectangle::new(
                [(*x, top), (*x + BAR, bottom)],
                BLACK.stroke_width(1),
            ))?;
            let below = font.color(&BLACK).pos(Pos::new(HPos::Center, VPos::Top));
            let last = ticks.len().saturating_sub(1).max(1) as i32;
            for (k, tick) in ticks.iter().enumerate() {
                let at = *x + (BAR - 1) * k as i32 / last;
                area.draw(&PathElement::new(
                    vec![(at, bottom), (at, bottom + 4)],
                    BLACK.stroke_width(1),
                ))?;
                area.draw(&Text::new(tick.clone(), (at, bottom + 6), below.clone()))?;
            }
            *x += BAR + overhang + GAP;
        }
        Ok(())
    };
    let diameter = if packing.grains.is_empty() {
        "diameter"
    } else {
        "equivalent diameter"
    };
    match legend {
        Legend::Diameters((d_min, d_max)) if d_max > d_min => {
            let label = format!("{diameter} (mm)");
            bar(&mut x, &label, &ticks(*d_min, *d_max), &ramp)?;
        }
        Legend::Orientation { period } => {
            let full = period.to_degrees().round();
            let ticks: Vec<String> = [0.0, 0.25, 0.5, 0.75, 1.0]
                .iter()
                .map(|t| format!("{}°", tidy(&(t * full))))
                .collect();
            bar(&mut x, "orientation", &ticks, &cyclic)?;
        }
        Legend::Diameters((d, _)) => {
            let label = format!("{diameter} {} mm", tidy(d));
            if x + item(&label)? <= room {
                area.draw(&swatch(x, ramp(0.5)))?;
                area.draw(&Text::new(
                    label.clone(),
                    (x + SWATCH + 8, mid),
                    text.clone(),
                ))?;
                x += item(&label)?;
            }
        }
        Legend::Materials(materials) => {
            for (i, m) in materials.iter().enumerate() {
                if x + item(&m.name)? > room {
                    break;
                }
                area.draw(&swatch(x, colour(i)))?;
                area.draw(&Text::new(
                    m.name.clone(),
                    (x + SWATCH + 8, mid),
                    text.clone(),
                ))?;
                x += item(&m.name)?;
            }
        }
    }
    let walls = "wall disks";
    if !packing.boundary.is_empty() && x + item(walls)? <= room {
        area.draw(&swatch(x, WALL_FILL))?;
        area.draw(&Text::new(walls, (x + SWATCH + 8, mid), text.clone()))?;
    }
    let periodic = "periodic cell";
    if packing.domain.is_periodic() && x + item(periodic)? <= room {
        // The outline's dashes, as the swatch.
        for k in 0..3 {
            let at = x + k * SWATCH / 3;
            area.draw(&PathElement::new(
                vec![(at, mid), (at + SWATCH / 5, mid)],
                BLACK.stroke_width(2),
            ))?;
        }
        area.draw(&Text::new(periodic, (x + SWATCH + 8, mid), text))?;
    }
    Ok(())
}

/// The legend's count and porosity. Disks summing to more than the frame
/// overlap (a table drawn without its config, piled up): a negative
/// porosity would be no measure, so the legend says they overlap.
fn legend_counts(packing: &Packing) -> String {
    let phi = porosity(solid_area(&packing.disks), packing.domain.area());
    format!(
        "{} {}, {}",
        packing.disks.len(),
        if packing.grains.is_empty() {
            "disks"
        } else {
            "particles"
        },
        if phi >= 0.0 {
            format!("porosity {phi:.3}")
        } else {
            "overlapping".to_owned()
        }
    )
}

/// Three tick labels from `lo` to `hi`, all with the decimals needed to
/// show either end to 4 significant digits and to tell the ticks apart.
fn ticks(lo: f64, hi: f64) -> Vec<String> {
    // Decimals of `v` written with 4 significant digits, trailing zeros dropped.
    let decimals_of = |v: f64| {
        let places = (3.0 - v.abs().max(1e-12).log10().floor()).clamp(0.0, 6.0) as usize;
        let s = format!("{v:.places$}");
        let s = s.trim_end_matches('0');
        s.find('.').map_or(0, |dot| s.len() - dot - 1)
    };
    let half = 0.5 * (hi - lo);
    let apart = ((-half.log10()).ceil() + 1.0).clamp(0.0, 6.0) as usize;
    let decimals = decimals_of(lo).max(decimals_of(hi)).max(apart);
    [lo, lo + half, hi]
        .iter()
        .map(|v| format!("{v:.decimals$}"))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Domain;
    use crate::output::diameter_range;
    use crate::output::plot::testing::{png_rgb, png_size};

    /// Random non-overlapping-or-not disks over a `w` × `h` rectangle,
    /// with wall disks along its foot and materials.
    fn scattered(w: f64, h: f64, n: usize, seed: u64) -> Packing {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let size = 0.002 * w.min(h);
        let disks = (0..n)
            .map(|_| {
                Disk::new(
                    rng.gen_range(0.0..w),
                    rng.gen_range(0.0..h),
                    rng.gen_range(0.2..3.0) * size,
                )
            })
            .collect();
        let mut p = Packing::of_disks(Domain::rectangle(w, h).expect("rectangle"), disks);
        p.boundary = (0..50)
            .map(|i| Disk::new(f64::from(i) * w / 50.0, 0.0, size))
            .collect();
        p.materials = (0..n).map(|_| rng.gen_range(0..3)).collect();
        p
    }

    #[test]
    fn the_bands_draw_the_same_bytes_whatever_the_threads() {
        let materials: Vec<Material> = ["a", "b", "c"]
            .iter()
            .map(|&name| Material {
                name: name.to_owned(),
                properties: Vec::new(),
            })
            .collect();
        for (w, h, n) in [
            (100.0, 100.0, 40_000),
            (3.0, 150.0, 3_000),
            (50.0, 20.0, 2_000),
        ] {
            let p = scattered(w, h, n, n as u64);
            let range = diameter_range(&p);
            let images: Vec<Vec<u8>> = [1, 2, 3]
                .into_iter()
                .flat_map(|threads| {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .expect("pool");
                    [
                        pool.install(|| packing_png_coloured(&p, &[], range, None))
                            .expect("png"),
                        pool.install(|| packing_png_coloured(&p, &materials, range, None))
                            .expect("png"),
                    ]
                })
                .collect();
            assert_ne!(images[0], images[1], "materials change the colours");
            for (k, image) in images.iter().enumerate() {
                assert!(*image == images[k % 2], "{w} × {h}: image {k}");
            }
        }
    }

    #[test]
    fn the_pile_test_in_parts_is_the_serial_one() {
        use super::super::pile::is_pile_serial;
        let size = (300, 200);
        for (n, r) in [(1_000, 2.0), (5_000, 8.0), (20_000, 3.0), (300, 60.0)] {
            let disks: Vec<DiskPx> = (0..n)
                .filter_map(|i| {
                    let t = f64::from(i);
                    DiskPx::new(
                        ((t * 7.3) % 300.0, (t * 3.1) % 200.0, r * (1.0 + (t % 3.0))),
                        1.0,
                        size,
                        (0, size.0, 0, size.1),
                        [0; 3],
                        [0; 3],
                    )
                })
                .collect();
            let serial = is_pile_serial(disks.iter().copied(), size);
            for chunk in [1, 7, 1000, n as usize] {
                let parts = disks.chunks(chunk).map(|c| pile_part(c.iter().copied()));
                assert_eq!(
                    pile_of_parts(parts, size),
                    serial,
                    "{n} disks of {r}, chunks of {chunk}"
                );
            }
            assert_eq!(is_pile(disks.iter().copied(), size), serial);
        }
    }

    #[test]
    fn piled_disks_are_said_to_overlap_not_given_a_negative_porosity() {
        let square = || Domain::rectangle(10.0, 10.0).expect("rectangle");
        let apart = Packing::of_disks(
            square(),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(6.0, 6.0, 1.0)],
        );
        let phi = 1.0 - 2.0 * std::f64::consts::PI / 100.0;
        assert_eq!(legend_counts(&apart), format!("2 disks, porosity {phi:.3}"));
        let piled = Packing::of_disks(square(), vec![Disk::new(5.0, 5.0, 4.0); 10]);
        assert_eq!(legend_counts(&piled), "10 disks, overlapping");
    }

    #[test]
    fn a_tall_domain_is_1600_px_high_and_centred_in_a_legend_wide_image() {
        // 15 × 20 mm plus 0.45 mm margins: 15.9 × 20.9 mm in 1520 px of
        // height (the legend strip is 80 px), so 1156 px wide.
        let p = Packing::of_disks(
            Domain::rectangle(15.0, 20.0).expect("rectangle"),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(5.0, 15.0, 2.0)],
        );
        let png = packing_png(&p, &[], diameter_range(&p)).expect("renders");
        assert_eq!(png_size(&png), (1156, 1600));
        // 5.3 × 20.3 mm would be 397 px wide, narrower than the legend: 900 px.
        let p = Packing::of_disks(
            Domain::rectangle(5.0, 20.0).expect("rectangle"),
            vec![Disk::new(2.0, 2.0, 1.0)],
        );
        let png = packing_png(&p, &[], (2.0, 2.0)).expect("renders");
        assert_eq!(png_size(&png), (900, 1600));
    }

    #[test]
    fn a_wide_domain_is_1600_px_wide() {
        // 40.6 × 10.6 mm at 1600 / 40.6 px/mm: 418 px + 80 px of legend.
        let p = Packing::of_disks(
            Domain::rectangle(40.0, 10.0).expect("rectangle"),
            vec![Disk::new(2.0, 2.0, 1.0)],
        );
        assert_eq!(
            png_size(&packing_png(&p, &[], (1.0, 3.0)).expect("png")),
            (1600, 498)
        );
        // Without disks there is no legend.
        let empty = Packing::of_disks(
            Domain::rectangle(40.0, 10.0).expect("rectangle"),
            Vec::new(),
        );
        assert_eq!(
            png_size(&packing_png(&empty, &[], (0.0, 0.0)).expect("png")),
            (1600, 418)
        );
    }

    #[test]
    fn disks_are_filled_with_their_colour() {
        let p = Packing::of_disks(
            Domain::circle(Point::new(0.0, 0.0), 10.0).expect("circle"),
            vec![Disk::new(-4.0, 0.0, 3.0), Disk::new(4.0, 0.0, 2.0)],
        );
        let layout = Layout::new(&p, &p.domain.outline(CIRCLE_SEGMENTS));
        let mut rgb = vec![255u8; layout.size.0 as usize * layout.size.1 as usize * 3];
        let mut canvas = Canvas {
            rgb: &mut rgb,
            width: layout.size.0 as usize,
            height: layout.size.1 as usize,
            clip: (0, layout.size.0 as usize, 0, layout.size.1 as usize),
            panel: 0,
        };
        for (i, d) in p.disks.iter().enumerate() {
            canvas.disk(
                &layout,
                d,
                Fills::Diameters((4.0, 6.0)).of_particle(&p, i),
                DISK_EDGE,
            );
        }
        let pixel = |q: Point| {
            let (x, y) = layout.map(0, q);
            let at = 3 * (y as usize * layout.size.0 as usize + x as usize);
            [rgb[at], rgb[at + 1], rgb[at + 2]]
        };
        // Centres: the larger disk darkest, the smaller lightest; between them white.
        assert_eq!(pixel(Point::new(-4.0, 0.0)), ramp(1.0));
        assert_eq!(pixel(Point::new(4.0, 0.0)), ramp(0.0));
        assert_eq!(pixel(Point::new(0.5, 0.0)), [255, 255, 255]);
        // The light disk has a dark rim: along its radius, some pixel is at
        // least half edge colour (26) and the rest fill (198) or white.
        let (x, y) = layout.map(0, Point::new(4.0, 0.0));
        let row = y as usize * layout.size.0 as usize;
        let darkest = (x as usize..(x + 2.0 * layout.scale + 2.0) as usize)
            .map(|i| rgb[3 * (row + i)])
            .min();
        assert!(darkest < Some(150), "{darkest:?}");
    }

    /// `packing.png` of a 2.3 mm × 25 m well was a line one pixel wide: cut
    /// into panels, each is several pixels across and most of the image
    /// high, the panels apart, the image within 1600 px a side.
    #[test]
    fn a_slender_domain_is_drawn_in_readable_panels() {
        for (w, h) in [(2.3f64, 25_000.0f64), (25_000.0, 2.3), (3.0, 150.0)] {
            let tall = h > w;
            let disks = (0..500)
                .map(|i| {
                    let along = 1.0 + f64::from(i) * (w.max(h) - 2.0) / 499.0;
                    if tall {
                        Disk::new(w / 2.0, along, 0.6)
                    } else {
                        Disk::new(along, h / 2.0, 0.6)
                    }
                })
                .collect();
            let p = Packing::of_disks(Domain::rectangle(w, h).expect("rectangle"), disks);
            let layout = Layout::new(&p, &p.domain.outline(CIRCLE_SEGMENTS));
            let panels = layout.panels;
            assert!(panels.count > 1, "{w} × {h}");
            let (width, height) = layout.size;
            assert!(
                (900..=1600).contains(&width) && (900..=1600).contains(&height),
                "{w} × {h}: {width} × {height}"
            );
            let mut previous: Option<(usize, usize, usize, usize)> = None;
            for k in 0..panels.count {
                let (lo, hi) = panels.source(k);
                let (x0, x1, y0, y1) = layout.pixels(k, lo, hi);
                let (across, along) = if tall {
                    (x1 - x0, y1 - y0)
                } else {
                    (y1 - y0, x1 - x0)
                };
                assert!(
                    across >= 8 && along >= 700,
                    "{w} × {h}, panel {k}: {across} × {along}"
                );
                if let Some(p) = previous {
                    assert!(if tall { x0 > p.1 } else { y0 > p.3 }, "panel {k} apart");
                }
                previous = Some((x0, x1, y0, y1));
            }
            let png = packing_png(&p, &[], (1.2, 1.2)).expect("png");
            assert_eq!(png_size(&png), layout.size);
        }
    }

    /// Four ellipses 12 × 4 mm, at 0°, 90°, 45° and 0°: each particle's
    /// centre and along its long axis.
    fn ellipses() -> Packing {
        use crate::geometry::{Grain, Outline};
        let ellipse = Outline::superellipse(6.0, 2.0, 2.0, 2.0).expect("ellipse");
        let r = ellipse.equivalent_radius();
        let placed = [
            (10.0, 10.0, 0.0),
            (28.0, 10.0, 90.0f64),
            (10.0, 22.0, 45.0),
            (28.0, 22.0, 0.0),
        ];
        Packing {
            grains: placed
                .iter()
                .map(|&(_, _, deg)| Grain::new(ellipse.clone(), deg.to_radians()))
                .collect(),
            ..Packing::of_disks(
                Domain::rectangle(40.0, 32.0).expect("rectangle"),
                placed.iter().map(|&(x, y, _)| Disk::new(x, y, r)).collect(),
            )
        }
    }

    /// The pixel of `rgb` (an image laid out as `layout`) at `q` (mm).
    fn pixel_at(rgb: &[u8], layout: &Layout, q: Point) -> [u8; 3] {
        let (x, y) = layout.map(0, q);
        let at = 3 * (y as usize * layout.size.0 as usize + x as usize);
        [rgb[at], rgb[at + 1], rgb[at + 2]]
    }

    /// Particles that are not disks are drawn as they are, not as their
    /// disks: inside each outline its fill, just outside it (well inside
    /// its bounding circle, and its area-equivalent disk) the background.
    #[test]
    fn ellipses_are_drawn_as_ellipses() {
        let p = ellipses();
        let layout = Layout::new(&p, &p.domain.outline(CIRCLE_SEGMENTS));
        let png = packing_png_coloured(&p, &[], (0.0, 0.0), None).expect("png");
        let (rgb, size) = png_rgb(&png);
        assert_eq!(size, layout.size);
        let fill = Fills::of(&p, &[], (0.0, 0.0), None).of_particle(&p, 0);
        let white = [255, 255, 255];
        // 0.15 mm is over 5 px at this scale.
        assert!(0.15 * layout.scale > 5.0, "{}", layout.scale);
        for (g, d) in p.grains.iter().zip(&p.disks) {
            let (s, c) = g.angle.sin_cos();
            let (long, short) = (Point::new(c, s).coords, Point::new(-s, c).coords);
            for inside in [d.c, d.c + 5.7 * long, d.c - 5.7 * long, d.c + 1.8 * short] {
                assert_eq!(pixel_at(&rgb, &layout, inside), fill, "{inside:?}");
            }
            // Outside the ellipse, inside its disk of the same area (r ≈ 3.46 mm).
            for outside in [
                d.c + 2.15 * short,
                d.c - 2.15 * short,
                d.c + 3.0 * short,
                d.c + 6.15 * long,
                // On the diagonal of its box, 0.15 mm beyond the outline.
                d.c + (4.5 * long + 1.323 * short) * 1.0
                    + 0.15 * (0.5 * long + 1.5 * short).normalize(),
            ] {
                assert_eq!(pixel_at(&rgb, &layout, outside), white, "{outside:?}");
            }
        }
    }

    /// Coloured by orientation, particles at 0° and 90° differ, two at 0°
    /// are alike; the legend strip carries the cyclic colour bar.
    #[test]
    fn ellipses_are_coloured_by_orientation() {
        let p = ellipses();
        let layout = Layout::new(&p, &p.domain.outline(CIRCLE_SEGMENTS));
        let png =
            packing_png_coloured(&p, &[], (0.0, 0.0), Some(Colouring::Orientation)).expect("png");
        let (rgb, _) = png_rgb(&png);
        let centre = |i: usize| pixel_at(&rgb, &layout, p.disks[i].c);
        assert_eq!(centre(0), cyclic(0.0));
        assert_eq!(centre(1), cyclic(0.5));
        assert_eq!(centre(2), cyclic(0.25));
        assert_eq!(centre(3), centre(0));
        assert_ne!(centre(0), centre(1));
        // The strip shows the scale's colour a quarter along: 45°.
        let quarter = cyclic(0.25);
        let (w, h) = layout.size;
        let strip = (h - LEGEND_PX..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let at = 3 * (y * w + x) as usize;
                rgb[at..at + 3] == quarter
            })
            .count();
        assert!(strip >= 10, "{strip}");
    }

    /// Disks are drawn as they always were, whatever the colouring asked
    /// for (orientation is refused for disks by the config; here it falls
    /// back), byte for byte.
    #[test]
    fn disks_stay_as_they_were() {
        let p = Packing::of_disks(
            Domain::rectangle(15.0, 20.0).expect("rectangle"),
            vec![Disk::new(2.0, 2.0, 1.0), Disk::new(5.0, 15.0, 2.0)],
        );
        let png = packing_png(&p, &[], (2.0, 4.0)).expect("png");
        for colour in [Some(Colouring::Size), Some(Colouring::Orientation), None] {
            assert_eq!(
                packing_png_coloured(&p, &[], (2.0, 4.0), colour).expect("png"),
                png
            );
        }
    }

    #[test]
    fn segments_are_clipped_to_a_box() {
        let (lo, hi) = (Point::new(0.0, 0.0), Point::new(1.0, 2.0));
        let clip = |a: (f64, f64), b: (f64, f64)| {
            clip_segment(Point::new(a.0, a.1), Point::new(b.0, b.1), lo, hi)
        };
        assert_eq!(
            clip((0.5, -1.0), (0.5, 3.0)),
            Some((Point::new(0.5, 0.0), Point::new(0.5, 2.0)))
        );
        assert_eq!(clip((2.0, 0.0), (2.0, 1.0)), None);
        assert_eq!(
            clip((-1.0, 1.0), (0.5, 1.0)),
            Some((Point::new(0.0, 1.0), Point::new(0.5, 1.0)))
        );
    }

    #[test]
    fn tick_labels_tell_the_sizes_apart() {
        assert_eq!(ticks(1.2, 6.0), ["1.2", "3.6", "6.0"]);
        assert_eq!(ticks(1.0, 1.1), ["1.000", "1.050", "1.100"]);
        assert_eq!(ticks(1.275, 3.525), ["1.275", "2.400", "3.525"]);
        assert_eq!(ticks(100.0, 300.0), ["100", "200", "300"]);
    }

    #[test]
    fn scale_bars_are_round_lengths_of_at_most_a_fifth_of_the_width() {
        assert_eq!(scale_bar_mm(1600.0, 25.0), 10.0); // 12.8 mm at most
        assert_eq!(scale_bar_mm(900.0, 2.0), 50.0); // 90 mm
        assert_eq!(scale_bar_mm(1600.0, 1600.0 / 25_000.0), 5000.0); // a 25 m well
        assert_eq!(scale_bar_mm(1600.0, 1600.0), 0.2); // a 1 mm cell
        assert_eq!(scale_bar_mm(1000.0, 100.0), 2.0); // exactly a fifth
    }

    /// `packing.png` had no scale: a bar of a round length in mm lies in
    /// the legend strip under the drawing (so over no disk), as long as
    /// that length at the drawing's scale, ending GAP px from the right.
    #[test]
    fn packing_png_has_a_scale_bar_under_the_drawing() {
        for (w, h) in [(40.0, 10.0), (15.0, 20.0), (62.5, 8.6)] {
            let p = Packing::of_disks(
                Domain::rectangle(w, h).expect("rectangle"),
                vec![Disk::new(2.0, 2.0, 1.0), Disk::new(6.0, 5.0, 1.5)],
            );
            let layout = Layout::new(&p, &p.domain.outline(CIRCLE_SEGMENTS));
            let (rgb, (width, height)) = png_rgb(&packing_png(&p, &[], (2.0, 3.0)).expect("png"));
            let black = |x: u32, y: u32| rgb[3 * (y * width + x) as usize] < 80;
            // The longest black run ending at the bar's right end, per row of the strip.
            let end = width - GAP as u32 - 1;
            let (row, run) = (height - LEGEND_PX..height)
                .map(|y| {
                    let run = (0..=end).rev().take_while(|&x| black(x, y)).count();
                    (y, run)
                })
                .max_by_key(|&(_, run)| run)
                .expect("a strip");
            let bar_mm = scale_bar_mm(f64::from(width), layout.scale);
            let expected = bar_mm * layout.scale;
            assert!(
                (run as f64 - expected).abs() <= 2.0,
                "{w} × {h} mm: a run of {run} px in row {row}, {bar_mm} mm is {expected} px"
            );
            assert!(expected >= 0.08 * f64::from(width) && expected <= 0.2 * f64::from(width));
        }
    }
}
