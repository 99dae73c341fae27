//! A line chart rendered to SVG text or PNG bytes, in memory (the caller
//! writes them atomically with the other outputs).

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{Axis, Pad};
use super::text::Glyphs;
use crate::output::OutputError;
use crate::output::palette::colour;

/// The font every chart uses, bundled (DejaVu Sans, `assets/`): the system's
/// fonts are not needed, so charts render the same on a bare machine.
pub(super) static FONT: &[u8] = include_bytes!("../../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

/// Family name the bundled font is registered under.
pub(super) const FAMILY: &str = "sans-serif";

/// Pixel size of the charts.
const SIZE: (u32, u32) = (900, 560);

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A solid line through the points.
    Line,
    /// A dashed line through the points (targets, references).
    Dashed,
    /// A dot at each point (measured values).
    Dots,
}

/// One named series of (x, y) points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// The points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// How the series is drawn.
    pub mark: Mark,
    /// Its colour, as an index into the palette (a material's target and
    /// achieved series share one).
    pub colour: usize,
}

/// A chart: a title, axis labels and series drawn in a palette order.
#[derive(Debug, Clone, PartialEq)]
pub struct LineChart {
    /// Caption above the plot.
    pub title: String,
    /// Horizontal axis label.
    pub x_label: String,
    /// Vertical axis label.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
}

/// A chart that draws itself on any plotters backend; [`Drawable::to_svg`]
/// and [`Drawable::to_png`] render it in memory.
pub trait Drawable {
    /// Pixel size of the chart (for a chart whose size depends on its
    /// content, its usual size; [`Drawable::size`] gives the actual one).
    const SIZE: (u32, u32);

    /// Pixel size of this chart: [`Drawable::SIZE`] unless the chart's
    /// content decides it (a map drawn to scale).
    fn size(&self) -> (u32, u32) {
        Self::SIZE
    }

    /// Draw the chart on `root`.
    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>;

    /// The chart as an SVG document.
    ///
    /// # Errors
    /// [`OutputError::Plot`] if plotters fails to draw.
    fn to_svg(&self) -> Result<String, OutputError> {
        register_font();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, self.size()).into_drawing_area();
            self.draw(root)
                .map_err(|e| OutputError::Plot(e.to_string()))?;
        }
        Ok(svg)
    }

    /// The chart as a PNG image.
    ///
    /// # Errors
    /// [`OutputError::Plot`] if plotters fails to draw or the PNG cannot be encoded.
    fn to_png(&self) -> Result<Vec<u8>, OutputError> {
        register_font();
        let (w, h) = self.size();
        let mut rgb = vec![0u8; w as usize * h as usize * 3];
        {
            let root = Glyphs(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
            self.draw(root)
                .map_err(|e| OutputError::Plot(e.to_string()))?;
        }
        encode_png(&rgb, (w, h))
    }
}

impl Drawable for LineChart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        self.draw_on(root)
    }
}

impl LineChart {
    /// The axes: the data's ranges (points with a coordinate that is not
    /// finite left out), padded by 5 %, never empty; the x axis ticks whole
    /// numbers only when every x is one (generations).
    fn axes(&self) -> (Axis, Axis) {
        let pad = Pad {
            share: 0.05,
            least: 1e-3,
        };
        let points = || {
            self.series
                .iter()
                .flat_map(|s| &s.points)
                .filter(|(x, y)| x.is_finite() && y.is_finite())
        };
        let x = Axis::linear(points().map(|p| p.0), pad);
        (
            if points().all(|p| p.0.fract() == 0.0) {
                x.whole()
            } else {
                x
            },
            Axis::linear(points().map(|p| p.1), pad),
        )
    }

    /// The legend: each named series, in order (a band's unnamed second line left out).
    fn legend(&self) -> Vec<Entry> {
        self.series
            .iter()
            .filter(|s| !s.name.is_empty())
            .map(|s| {
                let [r, g, b] = colour(s.colour);
                Entry {
                    text: s.name.clone(),
                    colour: RGBColor(r, g, b),
                    mark: s.mark,
                }
            })
            .collect()
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let entries = self.legend();
        let (plot, legend) = beside(&root, &entries);
        let mut chart = plot_area(
            &plot,
            (&self.title, 22),
            self.axes(),
            [&self.x_label, &self.y_label],
            &tidy,
        )?;
        for s in &self.series {
            let [r, g, b] = colour(s.colour);
            let colour = RGBColor(r, g, b);
            let style = colour.stroke_width(2);
            let points = s.points.iter().copied();
            let single = s
                .points
                .iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .count()
                == 1;
            match s.mark {
                // A line through a single point draws nothing: a dot shows it.
                Mark::Line if single => {
                    chart.draw_series(points.map(|p| Circle::new(p, 4, colour.filled())))?
                }
                Mark::Line => chart.draw_series(LineSeries::new(points, style))?,
                Mark::Dashed => chart.draw_series(DashedLineSeries::new(points, 10, 6, style))?,
                Mark::Dots => {
                    chart.draw_series(points.map(|p| Circle::new(p, 4, colour.filled())))?
                }
            };
        }
        draw_legend(&legend, &entries, 1, LEGEND_TOP)?;
        root.present()
    }
}

/// A chart's plot area, drawn on with its axes' values.
pub(super) type Plot<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// The plot area of a chart on `plot`: its caption (`title` at `size` px),
/// the axes and their mesh, labelled `descs` (x, y), the x values written
/// by `x_label` and the y values tidied.
pub(super) fn plot_area<'a, DB: DrawingBackend>(
    plot: &'a DrawingArea<DB, Shift>,
    (title, size): (&str, u32),
    (xs, ys): (Axis, Axis),
    [x_desc, y_desc]: [&str; 2],
    x_label: &dyn Fn(&f64) -> String,
) -> Result<Plot<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let mut chart = ChartBuilder::on(plot)
        .caption(title, (FAMILY, size))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d(xs, ys)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(x_label)
        .y_label_formatter(&tidy)
        .label_style((FAMILY, 14))
        .axis_desc_style((FAMILY, 16))
        .draw()?;
    Ok(chart)
}

/// One line of a legend: a swatch in the series' colour and its text.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Entry {
    /// The text.
    pub text: String,
    /// The series' colour.
    pub colour: RGBColor,
    /// How the series is drawn, which the swatch echoes.
    pub mark: Mark,
}

/// Legend text size.
const LEGEND_FONT: u32 = 14;
/// Height of a legend line (px).
const LEGEND_LINE: i32 = 22;
/// Swatch width plus the gap before the text (px).
const SWATCH: i32 = 32;
/// Space around a legend (px).
const LEGEND_PAD: i32 = 10;
/// Where a legend beside a plot starts: level with the plot's top.
pub(super) const LEGEND_TOP: i32 = 44;

/// Width (px) of the widest legend entry, swatch and padding included.
fn entry_width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> i32 {
    entries
        .iter()
        .map(|e| {
            area.estimate_text_size(&e.text, &(FAMILY, LEGEND_FONT).into_text_style(area))
                .map_or(0, |(w, _)| w as i32)
        })
        .max()
        .map_or(0, |w| w + SWATCH + 2 * LEGEND_PAD)
}

/// `root` cut into the plot's area and a strip at its right for the legend
/// of `entries` (empty without entries): the legend then covers no data.
pub(super) fn beside<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>) {
    let width = root.dim_in_pixel().0 as i32;
    let strip = entry_width(root, entries).min(width / 2);
    root.split_horizontally(width - strip)
}

/// `root` cut into the plot's area and a strip below it for the legend of
/// `entries`, laid out in as many columns as fit, and that number of columns.
pub(super) fn below<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>, usize) {
    let (width, height) = root.dim_in_pixel();
    let columns = (width as i32 / entry_width(root, entries).max(1)).max(1) as usize;
    let rows = entries.len().div_ceil(columns) as i32;
    let strip = if rows == 0 {
        0
    } else {
        rows * LEGEND_LINE + 2 * LEGEND_PAD
    };
    let (plot, legend) = root.split_vertically(height as i32 - strip.min(height as i32 / 2));
    (plot, legend, columns)
}

/// Draw `entries` on `area` in `columns` columns from `top` down, each a
/// swatch and its text. Swatches are rectangles (a square for dots, a bar
/// for a line, two bars for a dashed line), so none reads as a data point.
pub(super) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    columns: usize,
    top: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let column = entry_width(area, entries);
    let style = (FAMILY, LEGEND_FONT)
        .into_text_style(area)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (i, e) in entries.iter().enumerate() {
        let (c, r) = ((i % columns.max(1)) as i32, (i / columns.max(1)) as i32);
        let (x, y) = (
            LEGEND_PAD + c * column,
            top + r * LEGEND_LINE + LEGEND_LINE / 2,
        );
        let fill = e.colour.filled();
        match e.mark {
            Mark::Dots => area.draw(&Rectangle::new([(x + 6, y - 5), (x + 16, y + 5)], fill))?,
            Mark::Line => area.draw(&Rectangle::new([(x, y - 1), (x + 24, y + 1)], fill))?,
            Mark::Dashed => {
                area.draw(&Rectangle::new([(x, y - 1), (x + 9, y + 1)], fill))?;
                area.draw(&Rectangle::new([(x + 15, y - 1), (x + 24, y + 1)], fill))?;
            }
        }
        area.draw(&Text::new(e.text.as_str(), (x + SWATCH, y), style.clone()))?;
    }
    Ok(())
}

/// An RGB buffer of `size` pixels, row by row from the top, as PNG bytes.
///
/// # Errors
/// [`OutputError::Plot`] if the encoder fails (a buffer of the wrong length).
pub(super) fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, OutputError> {
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
    let plot = |e: png::EncodingError| OutputError::Plot(e.to_string());
    let mut writer = encoder.write_header().map_err(plot)?;
    writer.write_image_data(rgb).map_err(plot)?;
    writer.finish().map_err(plot)?;
    Ok(png)
}

/// A tick label: at most six decimals, trailing zeros dropped (`2`, `0.36`).
pub(super) fn tidy(v: &f64) -> String {
    let rounded = (v * 1e6).round() / 1e6;
    format!("{}", rounded + 0.0)
}

/// A tick label of a logarithmic axis: three significant digits in
/// scientific notation, trailing zeros dropped (`1e-3`, `1.5e-2`).
pub(super) fn sci(v: &f64) -> String {
    let s = format!("{v:.2e}");
    match s.split_once('e') {
        Some((mantissa, exponent)) => format!(
            "{}e{exponent}",
            mantissa.trim_end_matches('0').trim_end_matches('.')
        ),
        None => s,
    }
}

/// Register the bundled font once per process.
pub(super) fn register_font() {
    REGISTER.call_once(|| {
        // The bundled bytes are a valid font (checked by the tests below).
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

#[cfg(test)]
mod tests {
    use super::super::testing;
    use super::*;

    fn chart() -> LineChart {
        LineChart {
            title: "test".to_owned(),
            x_label: "x".to_owned(),
            y_label: "y".to_owned(),
            series: vec![
                Series {
                    name: "line".to_owned(),
                    points: vec![(0.0, 0.1), (1.0, 0.3), (2.0, 0.2)],
                    mark: Mark::Line,
                    colour: 0,
                },
                Series {
                    name: "target".to_owned(),
                    points: vec![(0.0, 0.25), (2.0, 0.25)],
                    mark: Mark::Dashed,
                    colour: 1,
                },
                Series {
                    name: "dots".to_owned(),
                    points: vec![(1.0, f64::NAN), (1.5, 0.15)],
                    mark: Mark::Dots,
                    colour: 1,
                },
            ],
        }
    }

    /// Ranges plotters' own axes never finish with: the chart still renders.
    #[test]
    fn degenerate_ranges_render() {
        for points in [
            vec![(5e-324, 5e-324)],
            vec![(1e300, -1e300), (-f64::MAX, f64::MAX)],
            vec![(1.0, 1e300), (1.0, 1e300 * (1.0 + f64::EPSILON))],
            vec![(f64::NAN, f64::INFINITY)],
        ] {
            let mut c = chart();
            c.series[0].points = points;
            assert!(c.to_svg().unwrap().starts_with("<svg"));
            assert_eq!(&c.to_png().unwrap()[..4], b"\x89PNG");
        }
    }

    #[test]
    fn tick_labels_are_tidy() {
        assert_eq!(tidy(&2.0), "2");
        assert_eq!(tidy(&0.30000000000000004), "0.3");
        assert_eq!(tidy(&-0.0), "0");
        assert_eq!(sci(&0.015), "1.5e-2");
        assert_eq!(sci(&1e-7), "1e-7");
        assert_eq!(sci(&200.0), "2e2");
    }

    /// The legend of a line chart lies beside the plot: no point or line
    /// under it, wherever the data lie (here in every corner).
    #[test]
    fn the_legend_hides_no_data() {
        let mut c = chart();
        c.series.push(Series {
            name: "corners".to_owned(),
            points: vec![(0.0, 0.1), (2.0, 0.1), (2.0, 0.3), (0.0, 0.3)],
            mark: Mark::Dots,
            colour: 2,
        });
        let labels: Vec<String> = c.legend().into_iter().map(|e| e.text).collect();
        assert_eq!(labels, ["line", "target", "dots", "corners"]);
        testing::assert_legend_hides_nothing(&c.to_svg().unwrap(), &labels);
    }

    #[test]
    fn the_bundled_font_loads() {
        assert!(plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    }

    #[test]
    fn renders_svg_with_text_and_png_with_the_png_signature() {
        let svg = chart().to_svg().unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("target") && svg.contains("<text"));
        let png = chart().to_png().unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert!(png.len() > 2000);
    }
}
