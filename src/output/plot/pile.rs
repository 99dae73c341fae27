//! Disks rasterised in pixels, and disks piled on one another drawn at a
//! bounded cost.
//!
//! A disk is drawn row by row: a solid span that takes the fill as is,
//! and a rim on either side blended by how much of each pixel it covers
//! ([`DiskPx`]). Drawn one after another, each disk costs its area in
//! pixels: fine for a packing, whose disks share the image, but a pile of
//! them (10⁵ copies of one disk, or centres a nanometre apart) paints the
//! same pixels 10⁵ times — minutes for one picture.
//!
//! [`draw_pile`] draws a pile back to front instead: a pixel a later disk
//! fills is final, and no earlier disk visits it again (per row, a
//! union-find skips the final pixels); a pixel's rim blends are kept for
//! the last [`KEPT_BLENDS`] disks only, then it is final too. Each disk
//! then costs its rows and the pixels still open, and near-copies
//! (centre and radius within 1/1024 px, same clip and colours) beyond the
//! last few are dropped before. A pile is what a packing whose pixel
//! work exceeds [`PILE_BUDGET`] is taken for: a packing's disks, which do
//! not overlap, never are, and are drawn one after another as before.

use std::collections::HashMap;

/// Rim blends kept per pixel when a pile is drawn: the last ones; earlier
/// disks show under at most (1 − cover)⁴ of them.
const KEPT_BLENDS: usize = 4;

/// Pixel work (the disks' clipped boxes of pixels) beyond which the disks
/// are drawn as a pile: this many times the image's pixels, plus
/// [`PER_DISK_BOX`] a disk. Disks that do not overlap cover the image at
/// most once, and their boxes at most 3 times their area (a disk 3 px
/// across or more), so a packing stays well within it.
pub(super) const PILE_BUDGET: usize = 4;

/// The pixels a small disk's box may hold within the budget (a disk under
/// 3 px across has a box of at most 9 × 9 pixels).
const PER_DISK_BOX: usize = 128;

/// Image columns `.0..1` and rows `.2..3` a disk is drawn within.
pub(super) type Clip = (usize, usize, usize, usize);

/// One disk to draw, in pixels: its centre, radius and edge line width,
/// the clip it is drawn within, its fill and edge colours.
#[derive(Debug, Clone, Copy)]
pub(super) struct DiskPx {
    cx: f64,
    cy: f64,
    r: f64,
    line: f64,
    /// The columns (`.0..1`) and rows (`.2..3`) of its box within the clip.
    boxed: Clip,
    /// Its fill colour.
    pub fill: [u8; 3],
    /// Its edge colour.
    pub edge: [u8; 3],
}

/// One row of a disk: its rim pixels `a0..s0` and `s1..a1`, its solid span `s0..s1`.
struct Row {
    a0: usize,
    s0: usize,
    s1: usize,
    a1: usize,
}

impl DiskPx {
    /// The disk of centre `(cx, cy)` and radius `r` (pixels) in an image
    /// `size` pixels wide and high, drawn within `clip` with an edge line
    /// of `line_px` (thinner on small disks); `None` when it draws nothing.
    pub(super) fn new(
        (cx, cy, r): (f64, f64, f64),
        line_px: f64,
        size: (usize, usize),
        clip: Clip,
        fill: [u8; 3],
        edge: [u8; 3],
    ) -> Option<Self> {
        if !(cx.is_finite() && cy.is_finite() && r.is_finite() && r > 0.0) {
            return None;
        }
        // The edge line thins on small disks so that their fill still shows.
        let line = line_px.min(0.25 * r);
        let (i0, i1) = (
            at(cx - r - 1.0, size.0).max(clip.0),
            at(cx + r + 1.0, size.0).min(clip.1),
        );
        let (j0, j1) = (
            at(cy - r - 1.0, size.1).max(clip.2),
            at(cy + r + 1.0, size.1).min(clip.3),
        );
        (i0 < i1).then_some(DiskPx {
            cx,
            cy,
            r,
            line,
            boxed: (i0, i1, j0, j1),
            fill,
            edge,
        })
    }

    /// The pixels of its box.
    fn box_pixels(&self) -> usize {
        let (i0, i1, j0, j1) = self.boxed;
        (i1 - i0).saturating_mul(j1.saturating_sub(j0))
    }

    /// Row `j` of the disk in an image `width` pixels wide, if it has pixels there.
    ///
    /// Pixels well inside the fill radius take the fill as is (cover and
    /// inner share both 1); only the rim is blended. The spans are one
    /// pixel narrower than their exact bound, so the blended pixels are
    /// all those the exact test could put either way.
    fn row(&self, j: usize, width: usize) -> Option<Row> {
        let (i0, i1, _, _) = self.boxed;
        let (cx, r) = (self.cx, self.r);
        let solid = r - self.line - 0.5;
        let outer = r + 0.5;
        let dy = j as f64 + 0.5 - self.cy;
        let reach = (outer * outer - dy * dy).max(0.0).sqrt() + 1.0;
        let (a0, a1) = (
            at(cx - reach, width).max(i0),
            at(cx + reach + 1.0, width).min(i1),
        );
        if a0 >= a1 {
            return None;
        }
        let (s0, s1) = if solid > dy.abs() {
            let half = (solid * solid - dy * dy).sqrt();
            (
                at((cx - half - 0.5).ceil() + 1.0, width).max(a0),
                at((cx + half - 0.5).floor(), width).min(a1),
            )
        } else {
            (a0, a0)
        };
        // A fill clipped away whole (a periodic cell's edge) draws nothing.
        let s0 = s0.min(a1);
        let s1 = s1.max(s0);
        Some(Row { a0, s0, s1, a1 })
    }

    /// The share of pixel (`i`, `j`) the disk covers, and the share inside
    /// its edge line.
    fn cover(&self, i: usize, j: usize) -> (f64, f64) {
        let dx = i as f64 + 0.5 - self.cx;
        let dy = j as f64 + 0.5 - self.cy;
        let dist = (dx * dx + dy * dy).sqrt();
        let cover = (self.r - dist + 0.5).clamp(0.0, 1.0);
        let inner = (self.r - self.line - dist + 0.5).clamp(0.0, 1.0);
        (cover, inner)
    }

    /// Draw the disk over `rgb`, an image `width` pixels wide: the solid
    /// spans filled, the rim blended.
    pub(super) fn draw(&self, rgb: &mut [u8], width: usize) {
        self.draw_rows(rgb, width, 0);
    }

    /// [`DiskPx::draw`] over `band`, the image's rows from `first` on
    /// (the disk's clip must lie within them): each pixel as the whole
    /// image would take it.
    pub(super) fn draw_rows(&self, band: &mut [u8], width: usize, first: usize) {
        let (_, _, j0, j1) = self.boxed;
        for j in j0..j1 {
            let Some(Row { a0, s0, s1, a1 }) = self.row(j, width) else {
                continue;
            };
            let row = (j - first) * width;
            for i in s0..s1 {
                band[3 * (row + i)..3 * (row + i) + 3].copy_from_slice(&self.fill);
            }
            for i in (a0..s0).chain(s1..a1) {
                let (cover, inner) = self.cover(i, j);
                if cover == 0.0 {
                    continue;
                }
                let at = 3 * (row + i);
                blend(&mut band[at..at + 3], cover, inner, self.fill, self.edge);
            }
        }
    }
}

/// A pixel count within `0..=n` from a coordinate in pixels.
fn at(v: f64, n: usize) -> usize {
    v.clamp(0.0, n as f64) as usize
}

/// Blend one pixel's three bytes: a share `cover` of it is the particle,
/// `inner` of it its fill and the rest of the cover its edge.
pub(super) fn blend(pixel: &mut [u8], cover: f64, inner: f64, fill: [u8; 3], edge: [u8; 3]) {
    for (k, byte) in pixel.iter_mut().enumerate() {
        let new = f64::from(*byte) * (1.0 - cover)
            + f64::from(fill[k]) * inner
            + f64::from(edge[k]) * (cover - inner);
        *byte = new.round().clamp(0.0, 255.0) as u8;
    }
}

/// Whether `disks`, drawn one after another on an image of `size`
/// pixels, would do more pixel work than [`PILE_BUDGET`] allows: disks
/// piled on one another.
pub(super) fn is_pile(disks: impl Iterator<Item = DiskPx>, size: (usize, usize)) -> bool {
    pile_of_parts(std::iter::once(pile_part(disks)), size)
}

/// What [`is_pile`] needs of a run of disks drawn one after another:
/// its pixel work beyond [`PER_DISK_BOX`] a disk, in all and at most
/// over its first disks (0 for none).
pub(super) fn pile_part(disks: impl Iterator<Item = DiskPx>) -> (i128, i128) {
    disks.fold((0, 0), |(sum, most), d| {
        let sum = sum + d.box_pixels() as i128 - PER_DISK_BOX as i128;
        (sum, most.max(sum))
    })
}

/// [`is_pile`] of the disks of `parts` ([`pile_part`]s of consecutive
/// runs, in drawing order) one after another: whether the work beyond
/// [`PER_DISK_BOX`] a disk exceeds [`PILE_BUDGET`] images at some disk.
pub(super) fn pile_of_parts(
    parts: impl Iterator<Item = (i128, i128)>,
    size: (usize, usize),
) -> bool {
    let image = PILE_BUDGET.saturating_mul(size.0.saturating_mul(size.1)) as i128;
    let mut before = 0;
    for (sum, most) in parts {
        if before + most > image {
            return true;
        }
        before += sum;
    }
    false
}

/// The serial form [`pile_of_parts`] stands for, kept as the tests'
/// reference.
#[cfg(test)]
pub(super) fn is_pile_serial(disks: impl Iterator<Item = DiskPx>, size: (usize, usize)) -> bool {
    let image = PILE_BUDGET.saturating_mul(size.0.saturating_mul(size.1));
    let (mut work, mut budget) = (0usize, image);
    for d in disks {
        work = work.saturating_add(d.box_pixels());
        budget = budget.saturating_add(PER_DISK_BOX);
        if work > budget {
            return true;
        }
    }
    false
}

/// Draw `disks` in order over `rgb` (an image `size` pixels wide and
/// high), as [`DiskPx::draw`] one after another would, at a cost bounded
/// per pixel: back to front, each pixel visited until a later disk fills
/// it or it has taken the rim blends of [`KEPT_BLENDS`] disks.
///
/// # Behavior
/// Exactly the drawing one after another where no pixel takes more than
/// [`KEPT_BLENDS`] rim blends after the last disk that fills it, and no
/// two disks are near-copies of each other; otherwise the earlier blends
/// (and copies) are left out, each under the later ones' cover.
///
/// # Performance
/// O(disks · rows + pixels · [`KEPT_BLENDS`]) after one hash of the disks,
/// and 9 + 4 · [`KEPT_BLENDS`] bytes of bookkeeping a pixel.
pub(super) fn draw_pile(rgb: &mut [u8], size: (usize, usize), disks: &[DiskPx]) {
    let (width, height) = size;
    let kept = last_copies(disks);
    let pixels = width * height;
    // Per row, the next pixel at or after each column still open to a
    // rim blend, and to a fill (the row's end, `width`, always open):
    // union-finds with path halving. A pixel with its blends kept is
    // still open to the fill under them.
    let stride = width + 1;
    let mut rim: Vec<u32> = (0..height).flat_map(|_| 0..=width as u32).collect();
    let mut fill = rim.clone();
    let find = |next: &mut [u32], base: usize, mut x: usize| {
        while next[base + x] as usize != x {
            let up = next[base + next[base + x] as usize];
            next[base + x] = up;
            x = up as usize;
        }
        x
    };
    let close = |next: &mut [u32], base: usize, x: usize| next[base + x] = x as u32 + 1;
    const NONE: u32 = u32::MAX;
    // The disk that covers each pixel whole last, and the disks whose rims
    // blend it after that one, latest first.
    let mut owner = vec![NONE; pixels];
    let mut count = vec![0u8; pixels];
    let mut blends = vec![0u32; pixels * KEPT_BLENDS];
    for &k in kept.iter().rev() {
        let d = &disks[k];
        let (_, _, j0, j1) = d.boxed;
        for j in j0..j1 {
            let Some(Row { a0, s0, s1, a1 }) = d.row(j, width) else {
                continue;
            };
            let base = j * stride;
            // The covered pixels `c0..c1`, and of them those covered whole
            // `o0..o1` (about the solid span, or in the top and bottom rows
            // within the rim): the cover rises, then falls along a row.
            let cover = |i: usize| d.cover(i, j).0;
            let Some(c0) = (a0..a1).find(|&i| cover(i) > 0.0) else {
                continue;
            };
            let c1 = (c0..a1)
                .rev()
                .find(|&i| cover(i) > 0.0)
                .map_or(c0, |i| i + 1);
            let (o0, o1) = if s0 < s1 {
                let o0 = (c0..s0)
                    .rev()
                    .find(|&i| cover(i) < 1.0)
                    .map_or(c0, |i| i + 1);
                (o0, (s1..c1).find(|&i| cover(i) < 1.0).unwrap_or(c1))
            } else {
                let o0 = (c0..c1).find(|&i| cover(i) >= 1.0).unwrap_or(c1);
                (o0, (o0..c1).find(|&i| cover(i) < 1.0).unwrap_or(c1))
            };
            let (left, right) = (c0, c1);
            for (from, to) in [(left, o0), (o1, right)] {
                let mut x = find(&mut rim, base, from);
                while x < to {
                    let p = j * width + x;
                    let n = usize::from(count[p]);
                    blends[p * KEPT_BLENDS + n] = k as u32;
                    count[p] += 1;
                    if n + 1 == KEPT_BLENDS {
                        close(&mut rim, base, x);
                    }
                    x = find(&mut rim, base, x + 1);
                }
            }
            let mut x = find(&mut fill, base, o0);
            while x < o1 {
                owner[j * width + x] = k as u32;
                close(&mut rim, base, x);
                close(&mut fill, base, x);
                x = find(&mut fill, base, x + 1);
            }
        }
    }
    for p in 0..pixels {
        let (i, j) = (p % width, p / width);
        let pixel = &mut rgb[3 * p..3 * p + 3];
        if owner[p] != NONE {
            // Covered whole: the fill, or the edge line's share of it.
            let d = &disks[owner[p] as usize];
            let (cover, inner) = d.cover(i, j);
            blend(pixel, cover, inner, d.fill, d.edge);
        }
        for &k in blends[p * KEPT_BLENDS..p * KEPT_BLENDS + usize::from(count[p])]
            .iter()
            .rev()
        {
            let d = &disks[k as usize];
            let (cover, inner) = d.cover(i, j);
            blend(pixel, cover, inner, d.fill, d.edge);
        }
    }
}

/// The indices of `disks` to draw, in order: all but the near-copies
/// (centre and radius equal to 1/1024 px, same box and colours) drawn
/// more than [`KEPT_BLENDS`] times after them, which could show only
/// under those.
fn last_copies(disks: &[DiskPx]) -> Vec<usize> {
    let q = |v: f64| (v * 1024.0).round() as i64;
    let mut seen: HashMap<_, usize> = HashMap::new();
    let mut kept: Vec<usize> = (0..disks.len())
        .rev()
        .filter(|&k| {
            let d = &disks[k];
            let key = (q(d.cx), q(d.cy), q(d.r), q(d.line), d.boxed, d.fill, d.edge);
            let n = seen.entry(key).or_insert(0);
            *n += 1;
            *n <= KEPT_BLENDS
        })
        .collect();
    kept.reverse();
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILL: [u8; 3] = [200, 100, 50];
    const EDGE: [u8; 3] = [20, 20, 20];

    fn disk(cx: f64, cy: f64, r: f64, size: (usize, usize)) -> DiskPx {
        let clip = (0, size.0, 0, size.1);
        DiskPx::new((cx, cy, r), 1.0, size, clip, FILL, EDGE).expect("drawn")
    }

    fn one_after_another(disks: &[DiskPx], size: (usize, usize)) -> Vec<u8> {
        let mut rgb = vec![255u8; size.0 * size.1 * 3];
        for d in disks {
            d.draw(&mut rgb, size.0);
        }
        rgb
    }

    fn piled(disks: &[DiskPx], size: (usize, usize)) -> Vec<u8> {
        let mut rgb = vec![255u8; size.0 * size.1 * 3];
        draw_pile(&mut rgb, size, disks);
        rgb
    }

    #[test]
    fn a_pile_of_few_layers_is_drawn_exactly_as_one_after_another() {
        // Overlapping disks of several sizes and colours, each pixel under
        // at most three rims after its last fill.
        let size = (120, 90);
        let mut disks = vec![
            disk(30.3, 40.7, 25.2, size),
            disk(60.1, 45.4, 20.9, size),
            disk(45.8, 30.2, 12.5, size),
            disk(100.0, 80.0, 30.0, size),
            disk(10.0, 10.0, 0.7, size),
        ];
        disks[1].fill = [10, 200, 30];
        disks[3].edge = [90, 0, 0];
        assert_eq!(piled(&disks, size), one_after_another(&disks, size));
    }

    #[test]
    fn copies_of_one_disk_are_a_pile_drawn_as_their_last_few() {
        let size = (200, 200);
        let copies = vec![disk(100.0, 100.0, 99.0, size); 10_000];
        assert!(is_pile(copies.iter().copied(), size));
        assert_eq!(
            last_copies(&copies),
            (10_000 - KEPT_BLENDS..10_000).collect::<Vec<_>>()
        );
        // As the last few drawn one after another.
        assert_eq!(
            piled(&copies, size),
            one_after_another(&copies[..KEPT_BLENDS], size)
        );
    }

    #[test]
    fn concentric_disks_drawn_as_a_pile_are_drawn_as_one_after_another() {
        // Concentric disks, the smaller drawn later: no copies, each
        // disk's solid hidden by none. One after another this paints
        // every disk's area; piled, the output is the same where each
        // pixel took no more than the kept blends.
        let size = (100, 100);
        let disks: Vec<DiskPx> = (0..20)
            .map(|k| disk(50.0, 50.0, 45.0 - 2.0 * f64::from(k), size))
            .collect();
        assert!(is_pile(disks.iter().copied(), size));
        assert_eq!(piled(&disks, size), one_after_another(&disks, size));
    }

    #[test]
    fn a_deep_pile_differs_only_where_more_rims_than_kept_blend_a_pixel() {
        // Concentric disks a tenth of a pixel apart in radius, in two
        // colours, the smaller drawn later: rim pixels under about ten
        // rims after the last disk covering them whole.
        let size = (100, 100);
        let disks: Vec<DiskPx> = (0..200)
            .map(|k| {
                let mut d = disk(50.2, 49.7, 40.0 - 0.1 * f64::from(k), size);
                if k % 2 == 1 {
                    d.fill = [30, 160, 220];
                }
                d
            })
            .collect();
        let (a, b) = (piled(&disks, size), one_after_another(&disks, size));
        let rims = |p: usize| {
            let (i, j) = (p % size.0, p / size.0);
            disks
                .iter()
                .filter(|d| {
                    let (cover, _) = d.cover(i, j);
                    cover > 0.0 && cover < 1.0
                })
                .count()
        };
        let differ: Vec<usize> = (0..size.0 * size.1)
            .filter(|&p| a[3 * p..3 * p + 3] != b[3 * p..3 * p + 3])
            .collect();
        assert!(
            !differ.is_empty(),
            "the pile is deeper than the blends kept"
        );
        for p in differ {
            assert!(rims(p) > KEPT_BLENDS, "pixel {p} under {} rims", rims(p));
        }
    }

    #[test]
    fn disks_side_by_side_are_no_pile() {
        let size = (400, 400);
        let disks: Vec<DiskPx> = (0..400)
            .map(|k| {
                disk(
                    10.0 + 20.0 * f64::from(k % 20),
                    10.0 + 20.0 * f64::from(k / 20),
                    10.0,
                    size,
                )
            })
            .collect();
        assert!(!is_pile(disks.iter().copied(), size));
    }
}
