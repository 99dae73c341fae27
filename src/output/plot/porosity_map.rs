//! The porosity map: local porosity of a packing as coloured cells drawn to
//! scale, the domain outline on top, with a colour bar; on a slender domain
//! (a fracture) a profile of porosity along its length.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axis;
use super::chart::{Drawable, FAMILY, tidy};
use crate::geometry::Point;
use crate::geometry::predicates::clip_polygon_box;
use crate::metrics::{PorosityMap, porosity_map};
use crate::output::palette::viridis;
use crate::output::svg::CIRCLE_SEGMENTS;
use crate::packer::Packing;

/// File name of the porosity map.
pub const POROSITY_MAP_SVG: &str = "porosity_map.svg";
/// File name of the porosity map as an image.
pub const POROSITY_MAP_PNG: &str = "porosity_map.png";

/// Pixels on the longer side of the map itself.
const PLOT_LONG: f64 = 900.0;
/// Fewest pixels on the shorter side of the map (a thin domain gets blank
/// room beside it rather than a strip too thin to read).
const PLOT_SHORT: f64 = 300.0;
/// Height of the title strip.
const TITLE_PX: u32 = 44;
/// Space around the chart.
const MARGIN_PX: u32 = 14;
/// Room for the tick labels and names of the axes.
const X_LABELS_PX: u32 = 50;
const Y_LABELS_PX: u32 = 70;
/// Width of the colour-bar strip on the right.
const BAR_STRIP_PX: u32 = 120;
/// Colour of the cells with less than half their area in the domain.
const MASKED: RGBColor = RGBColor(220, 220, 220);
/// Height of the "not mapped" key under the colour bar.
const KEY_PX: i32 = 44;
/// Narrowest colour range drawn: a uniform map is not stretched to full contrast.
const MIN_SPAN: f64 = 0.02;
/// Width of a tick label's digit (px, 14 px font, with room) and the least
/// space between two labels: ticks are spaced so that no two labels meet.
const DIGIT_PX: u32 = 9;
const LABEL_GAP_PX: u32 = 24;
/// Least space between two tick labels of a vertical axis (px).
const ROW_PX: u32 = 30;
/// Room right of a profile for its last x label, centred on the axis' end (px).
const PROFILE_RIGHT_PX: u32 = 40;

/// A [`PorosityMap`] drawn to scale (equal mm per pixel along x and y):
/// each cell's part inside the domain coloured by porosity with viridis
/// over the map's range of values (masked cells light grey, "not mapped"),
/// the domain outline in black on top, axes in mm.
///
/// Built by [`porosity_map_chart`]. Its pixel size follows the domain's
/// shape ([`Drawable::size`]); [`Drawable::SIZE`] is the size for a square.
#[derive(Debug, Clone, PartialEq)]
pub struct PorosityMapChart {
    /// The map.
    map: PorosityMap,
    /// The domain's outline (mm).
    outline: Vec<Point>,
    /// Each cell's part inside the domain (mm), with its porosity (NaN where
    /// masked); clipped once, drawn for every format.
    cells: Vec<(Vec<(f64, f64)>, f64)>,
    /// Range of each axis (mm), widened beyond the grid on a thin domain.
    x: (f64, f64),
    y: (f64, f64),
    /// Size of the map's plotting area (pixels).
    plot: (u32, u32),
    /// Porosity at the two ends of the colour scale.
    scale: (f64, f64),
    /// Whether the domain is a periodic cell (said in the title).
    periodic: bool,
}

/// The porosity map of `packing` ([`porosity_map`]) as a chart: on a
/// slender domain ([`PorosityMap::profile`]) a profile along its length,
/// `PLOT_LONG` × `PLOT_SHORT` px, its axes spanning the domain's length
/// and the porosities'.
pub fn porosity_map_chart(packing: &Packing) -> PorosityMapChart {
    let map = porosity_map(packing);
    let (gw, gh) = (
        map.cols as f64 * map.cell,
        map.rows as f64 * map.cell_height,
    );
    let centre = (map.origin.x + 0.5 * gw, map.origin.y + 0.5 * gh);
    let scale = PLOT_LONG / gw.max(gh);
    let (plot_w, plot_h) = if map.profile {
        (PLOT_LONG, PLOT_SHORT)
    } else {
        (
            (gw * scale).max(PLOT_SHORT).round(),
            (gh * scale).max(PLOT_SHORT).round(),
        )
    };
    let (half_w, half_h) = (0.5 * plot_w / scale, 0.5 * plot_h / scale);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in map.values.iter().filter(|v| v.is_finite()) {
        (lo, hi) = (lo.min(v), hi.max(v));
    }
    if lo > hi {
        (lo, hi) = (0.0, 1.0);
    }
    let widen = 0.5 * (MIN_SPAN - (hi - lo)).max(0.0);
    let (lo, hi) = ((lo - widen).max(0.0), (hi + widen).min(1.0));
    let (lo, hi) = if hi - lo < MIN_SPAN {
        // Against a bound of [0, 1]: take the span from the other side.
        if lo == 0.0 {
            (0.0, MIN_SPAN)
        } else {
            (1.0 - MIN_SPAN, 1.0)
        }
    } else {
        (lo, hi)
    };
    let outline = packing.domain.outline(CIRCLE_SEGMENTS);
    // Each cell clipped to the domain: the map fills it exactly. A profile
    // draws no cells.
    let (cw, ch) = (map.cell, map.cell_height);
    let cells = map
        .values
        .iter()
        .enumerate()
        .filter(|_| !map.profile)
        .filter_map(|(i, &v)| {
            let (col, row) = (i % map.cols, i / map.cols);
            let x0 = map.origin.x + col as f64 * cw;
            let y0 = map.origin.y + row as f64 * ch;
            let part = clip_polygon_box(&outline, x0, x0 + cw, y0, y0 + ch);
            (!part.is_empty()).then(|| (part.iter().map(|p| (p.x, p.y)).collect(), v))
        })
        .collect();
    // A profile's axes: the domain's length, the porosities (padded).
    let (x, y) = if map.profile {
        let (dlo, dhi) = packing.domain.bounds();
        let along = if map.cols == 1 {
            (dlo.y, dhi.y)
        } else {
            (dlo.x, dhi.x)
        };
        let pad = 0.1 * (hi - lo);
        (along, ((lo - pad).max(0.0), (hi + pad).min(1.0)))
    } else {
        (
            (centre.0 - half_w, centre.0 + half_w),
            (centre.1 - half_h, centre.1 + half_h),
        )
    };
    PorosityMapChart {
        outline,
        cells,
        x,
        y,
        plot: (plot_w as u32, plot_h as u32),
        scale: (lo, hi),
        map,
        periodic: packing.domain.is_periodic(),
    }
}

/// The axes a map or a profile draws in.
type Axes<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

impl PorosityMapChart {
    /// The map's colour of porosity `v`.
    fn colour(&self, v: f64) -> RGBColor {
        let (lo, hi) = self.scale;
        let [r, g, b] = viridis((v - lo) / (hi - lo));
        RGBColor(r, g, b)
    }

    /// The title: what is drawn and at which resolution.
    fn title(&self) -> String {
        if self.map.profile {
            let (along, across) = self.along_across();
            return format!(
                "Local porosity along {along}: cells {} mm long, {} mm across (the whole width)",
                tidy(&round4(self.map.cell.max(self.map.cell_height))),
                tidy(&round4(across)),
            );
        }
        format!(
            "Local porosity, cells of {} mm{}",
            tidy(&round4(self.map.cell)),
            if self.periodic {
                ", periodic cell (disks across its edges counted on both sides)"
            } else {
                ""
            }
        )
    }

    /// The profile's axis (`x` or `y`) and the cells' side across it (mm).
    fn along_across(&self) -> (&'static str, f64) {
        if self.map.cols == 1 {
            ("y", self.map.cell)
        } else {
            ("x", self.map.cell_height)
        }
    }

    /// The axes of the map or the profile on `area` (`right` more pixels
    /// of margin on the right), their labels spaced to the plot's pixels.
    fn axes<'a, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
        right: u32,
        (x_desc, y_desc): (&str, &str),
    ) -> Result<Axes<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
        let mut chart = ChartBuilder::on(area)
            .margin(MARGIN_PX)
            .margin_right(MARGIN_PX + right)
            .x_label_area_size(X_LABELS_PX)
            .y_label_area_size(Y_LABELS_PX)
            .build_cartesian_2d(
                Axis::exact(self.x.0, self.x.1),
                Axis::exact(self.y.0, self.y.1),
            )?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(label_count(self.plot.0, self.x))
            .y_labels((self.plot.1 / ROW_PX) as usize)
            .x_desc(x_desc)
            .y_desc(y_desc)
            .x_label_formatter(&tidy)
            .y_label_formatter(&tidy)
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 16))
            .draw()?;
        Ok(chart)
    }

    /// The profile: each cell's porosity as a step over its length, broken
    /// where a cell is not mapped.
    fn draw_profile<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let (along, _) = self.along_across();
        let (start, side) = if self.map.cols == 1 {
            (self.map.origin.y, self.map.cell_height)
        } else {
            (self.map.origin.x, self.map.cell)
        };
        let mut chart = self.axes(
            area,
            PROFILE_RIGHT_PX,
            (&format!("{along} (mm)"), "porosity"),
        )?;
        let (x0, x1) = self.x;
        let mut run: Vec<(f64, f64)> = Vec::new();
        for (i, &v) in self.map.values.iter().enumerate() {
            let (a, b) = (start + i as f64 * side, start + (i + 1) as f64 * side);
            if v.is_finite() {
                run.extend([(a.max(x0), v), (b.min(x1), v)]);
            } else if !run.is_empty() {
                chart.draw_series(LineSeries::new(
                    std::mem::take(&mut run),
                    BLUE.stroke_width(2),
                ))?;
            }
        }
        chart.draw_series(LineSeries::new(run, BLUE.stroke_width(2)))?;
        Ok(())
    }

    /// The colour bar beside the map, level with its plotting area.
    fn draw_bar<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let masked = self.map.values.iter().any(|v| v.is_nan());
        let key = if masked { KEY_PX } else { 0 };
        let (top, height) = (MARGIN_PX as i32, self.plot.1 as i32 - key);
        let (x0, x1) = (12, 36);
        if masked {
            let y = top + height + KEY_PX / 2 + 4;
            area.draw(&Rectangle::new([(x0, y - 9), (x1, y + 9)], MASKED.filled()))?;
            area.draw(&Text::new(
                "not mapped",
                (x1 + 8, y),
                (FAMILY, 14)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        for k in 0..height {
            let v =
                self.scale.1 - (self.scale.1 - self.scale.0) * f64::from(k) / f64::from(height - 1);
            area.draw(&Rectangle::new(
                [(x0, top + k), (x1, top + k + 1)],
                self.colour(v).filled(),
            ))?;
        }
        area.draw(&Rectangle::new(
            [(x0, top), (x1, top + height)],
            BLACK.stroke_width(1),
        ))?;
        let (lo, hi) = self.scale;
        let label = (FAMILY, 14)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let (step, decimals) = tick_step(hi - lo);
        let first = (lo / step).ceil() as i64;
        let last = (hi / step + 1e-9).floor() as i64;
        for k in first..=last {
            let v = k as f64 * step;
            let y = top + ((hi - v) / (hi - lo) * f64::from(height - 1)).round() as i32;
            area.draw(&PathElement::new(
                vec![(x1, y), (x1 + 5, y)],
                BLACK.stroke_width(1),
            ))?;
            area.draw(&Text::new(
                format!("{v:.decimals$}"),
                (x1 + 8, y),
                label.clone(),
            ))?;
        }
        let name = (FAMILY, 16)
            .into_font()
            .transform(FontTransform::Rotate270)
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        // A colour bar not spanning 0–1 says so.
        let title = if self.scale == (0.0, 1.0) {
            "porosity"
        } else {
            "porosity (data range, not 0–1)"
        };
        area.draw(&Text::new(title, (100, top + height / 2), name))
    }
}

/// How many tick labels fit along `pixels` of an axis over `range` without
/// two meeting: each gets the width of its longest label's digits and a gap.
fn label_count(pixels: u32, (lo, hi): (f64, f64)) -> usize {
    let span = (hi - lo).abs().max(1e-12);
    // The longest label: the larger end's digits, a sign, a decimal or two on a short span.
    let digits = lo.abs().max(hi.abs()).max(1.0).log10().floor() as u32 + 1;
    let decimals = if span < 10.0 { 3 } else { 0 };
    let chars = digits + decimals + u32::from(lo < 0.0);
    (pixels / (chars * DIGIT_PX + LABEL_GAP_PX)).clamp(2, 12) as usize
}

/// The finest round tick step (1, 2 or 5 × 10^k) that cuts `span` into at
/// most 6 intervals, and the decimals it needs.
fn tick_step(span: f64) -> (f64, usize) {
    let rough = span.max(1e-12) / 5.0;
    let power = rough.log10().floor();
    let unit = 10f64.powf(power);
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * unit)
        .find(|&s| span / s <= 6.0 + 1e-9)
        .unwrap_or(10.0 * unit);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    (step, decimals)
}

/// 4 significant digits, for a cell side in the title.
fn round4(v: f64) -> f64 {
    if v > 0.0 && v.is_finite() {
        let unit = 10f64.powf(v.log10().floor() - 3.0);
        (v / unit).round() * unit
    } else {
        v
    }
}

impl Drawable for PorosityMapChart {
    const SIZE: (u32, u32) = (
        2 * MARGIN_PX + Y_LABELS_PX + PLOT_LONG as u32 + BAR_STRIP_PX,
        TITLE_PX + 2 * MARGIN_PX + PLOT_LONG as u32 + X_LABELS_PX,
    );

    fn size(&self) -> (u32, u32) {
        // A profile has no colour bar, room for its last x label instead.
        let bar = if self.map.profile {
            PROFILE_RIGHT_PX
        } else {
            BAR_STRIP_PX
        };
        (
            2 * MARGIN_PX + Y_LABELS_PX + self.plot.0 + bar,
            TITLE_PX + 2 * MARGIN_PX + self.plot.1 + X_LABELS_PX,
        )
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (title, body) = root.split_vertically(TITLE_PX);
        let (width, _) = title.dim_in_pixel();
        let mut font = (FAMILY, 22).into_font();
        let mut text = self.title();
        if title.estimate_text_size(&text, &font.color(&BLACK))?.0 + 2 * MARGIN_PX > width {
            (text, font) = ("Local porosity".to_owned(), (FAMILY, 20).into_font());
        }
        title.draw(&Text::new(
            text,
            (width as i32 / 2, TITLE_PX as i32 / 2 + 4),
            font.color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
        if self.map.profile {
            self.draw_profile(&body)?;
            return root.present();
        }
        let (body_w, _) = body.dim_in_pixel();
        let (plot_area, bar_area) = body.split_horizontally(body_w - BAR_STRIP_PX);
        let mut chart = self.axes(&plot_area, 0, ("x (mm)", "y (mm)"))?;
        chart.draw_series(self.cells.iter().map(|(part, v)| {
            let fill = if v.is_finite() {
                self.colour(*v)
            } else {
                MASKED
            };
            Polygon::new(part.clone(), fill.filled())
        }))?;
        let ring: Vec<(f64, f64)> = self
            .outline
            .iter()
            .chain(self.outline.first())
            .map(|p| (p.x, p.y))
            .collect();
        chart.draw_series(LineSeries::new(ring, BLACK.stroke_width(2)))?;
        self.draw_bar(&bar_area)?;
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};
    use crate::output::plot::testing::{SvgText, png_size, svg_size, svg_texts};

    fn packing(domain: Domain) -> Packing {
        // A row of disks along the bottom, of diameter 1.
        let (lo, hi) = domain.bounds();
        let disks = (0..)
            .map(|i| lo.x + 1.0 + f64::from(i))
            .take_while(|&x| x < hi.x - 1.0)
            .map(|x| Disk::new(x, lo.y + 3.0, 0.5))
            .filter(|d| domain.signed_distance(d.c) > d.r)
            .collect();
        Packing::of_disks(domain, disks)
    }

    #[test]
    fn the_map_keeps_the_domain_s_aspect() {
        // 40 × 20 mm: the map 900 × 450 px, equal mm per pixel.
        let chart = porosity_map_chart(&packing(Domain::rectangle(40.0, 20.0).expect("rect")));
        assert_eq!(chart.plot, (900, 450));
        let per_px = |(a, b): (f64, f64), n: u32| (b - a) / f64::from(n);
        assert!((per_px(chart.x, 900) - per_px(chart.y, 450)).abs() < 1e-12);
        assert_eq!(chart.size(), (14 * 2 + 70 + 900 + 120, 44 + 28 + 450 + 50));
        // A thin domain keeps the scale and gets blank room beside it.
        let chart = porosity_map_chart(&packing(Domain::rectangle(40.0, 6.0).expect("rect")));
        assert_eq!(chart.plot, (900, 300));
        assert!((per_px(chart.x, 900) - per_px(chart.y, 300)).abs() < 1e-12);
        // Colour range: the map's own, at least MIN_SPAN wide, inside [0, 1].
        let (lo, hi) = chart.scale;
        assert!(0.0 <= lo && lo < hi && hi <= 1.0 && hi - lo >= MIN_SPAN - 1e-12);
    }

    #[test]
    fn renders_svg_and_png_of_the_chart_s_size() {
        for domain in [
            Domain::rectangle(40.0, 20.0).expect("rect"),
            Domain::circle(Point::new(0.0, 0.0), 12.0).expect("circle"),
            Domain::rectangle(5.0, 60.0).expect("rect"),
        ] {
            let chart = porosity_map_chart(&packing(domain));
            let svg = chart.to_svg().expect("svg");
            assert_eq!(svg_size(&svg), chart.size());
            assert!(svg.contains("<rect") && svg.contains("porosity"), "{svg}");
            assert_eq!(png_size(&chart.to_png().expect("png")), chart.size());
        }
    }

    /// The x tick labels of an SVG chart (the smallest centred texts) in order: none
    /// overlaps the next, all inside the image.
    fn assert_x_labels_apart(svg: &str, width: u32) {
        let texts: Vec<SvgText> = svg_texts(svg)
            .into_iter()
            .filter(|t| t.anchor == "middle")
            .collect();
        // The tick labels are the smallest of the centred texts.
        let least = texts.iter().map(|t| t.size).fold(f64::INFINITY, f64::min);
        let mut labels: Vec<(f64, f64)> = texts
            .iter()
            .filter(|t| t.size == least)
            .map(SvgText::extent)
            .collect();
        labels.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(labels.len() >= 2, "{labels:?}");
        for pair in labels.windows(2) {
            assert!(pair[0].1 < pair[1].0, "labels collide: {labels:?}");
        }
        assert!(
            labels
                .iter()
                .all(|&(a, b)| a >= 0.0 && b <= f64::from(width)),
            "{labels:?}"
        );
    }

    /// The 2.3 mm × 25 m well's map had 125 mm cells, an x axis from −4000
    /// to 4000 mm and overlapping labels: it is a profile along the slot,
    /// its x axis the slot's length, its labels apart.
    #[test]
    fn a_slot_is_drawn_as_a_profile_along_its_length() {
        let slot = Domain::rectangle(2.3, 25_000.0).expect("slot");
        let disks = (0..20_000)
            .map(|i| Disk::new(1.15, 0.7 + 1.25 * f64::from(i), 0.6))
            .collect();
        let chart = porosity_map_chart(&Packing::of_disks(slot, disks));
        assert!(chart.map.profile);
        assert_eq!(chart.x, (0.0, 25_000.0));
        // The porosity axis spans the values, inside [0, 1].
        let values = chart.map.values.iter().copied().filter(|v| v.is_finite());
        let (lo, hi) = values.fold((1.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        assert!(0.0 <= chart.y.0 && chart.y.0 < lo && hi < chart.y.1 && chart.y.1 <= 1.0);
        let svg = chart.to_svg().expect("svg");
        assert!(svg.contains("Local porosity along y"), "{svg}");
        assert_x_labels_apart(&svg, chart.size().0);
        assert_eq!(png_size(&chart.to_png().expect("png")), chart.size());
    }

    /// Maps keep their tick labels apart too, and a colour bar over the
    /// data's range says it is not 0–1.
    #[test]
    fn map_labels_are_apart_and_the_bar_names_its_range() {
        for domain in [
            // 300 px wide over 1333 mm, centred on x = 300 mm.
            Domain::rectangle(600.0, 4000.0).expect("rect"),
            Domain::rectangle(4000.0, 600.0).expect("rect"),
            Domain::rectangle(40.0, 20.0).expect("rect"),
            Domain::circle(Point::new(-3000.0, 0.0), 1000.0).expect("circle"),
        ] {
            let chart = porosity_map_chart(&packing(domain));
            assert!(!chart.map.profile);
            let svg = chart.to_svg().expect("svg");
            assert_x_labels_apart(&svg, chart.size().0);
            assert_ne!(chart.scale, (0.0, 1.0));
            assert!(svg.contains("porosity (data range, not 0–1)"), "{svg}");
        }
    }

    #[test]
    fn colour_bar_ticks_are_round() {
        for (span, step, decimals) in [
            (0.2, 0.05, 2),
            (0.15, 0.05, 2),
            (0.06, 0.01, 2),
            (0.12, 0.02, 2),
            (0.02, 0.005, 3),
            (1.0, 0.2, 1),
        ] {
            let (s, d) = tick_step(span);
            assert!(
                (s - step).abs() < 1e-12 && d == decimals,
                "{span}: {s}, {d}"
            );
        }
    }

    #[test]
    fn cell_sides_are_titled_with_four_digits() {
        assert_eq!(tidy(&round4(7.123456)), "7.123");
        assert_eq!(tidy(&round4(0.012345678)), "0.01235");
        assert_eq!(tidy(&round4(250.0)), "250");
    }
}
