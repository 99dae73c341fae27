//! A line chart rendered to SVG text or PNG bytes, in memory (the caller
//! writes them atomically with the other outputs).

use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

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

    /// Where the legend hides the fewest data: the upper or the lower right
    /// corner, whichever holds fewer points.
    fn legend_corner(&self, xs: &Axis, ys: &Axis) -> SeriesLabelPosition {
        let ((x0, x1), (y0, y1)) = (xs.ends(), ys.ends());
        let right = x0 + 0.6 * (x1 - x0);
        let (low, high) = (y0 + 0.35 * (y1 - y0), y0 + 0.65 * (y1 - y0));
        let points = self.series.iter().flat_map(|s| &s.points);
        let (mut upper, mut lower) = (0, 0);
        for &(_, y) in points.filter(|(x, _)| *x >= right) {
            upper += usize::from(y >= high);
            lower += usize::from(y <= low);
        }
        if lower < upper {
            SeriesLabelPosition::LowerRight
        } else {
            SeriesLabelPosition::UpperRight
        }
    }

    fn draw_on<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (xs, ys) = self.axes();
        let corner = self.legend_corner(&xs, &ys);
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, (FAMILY, 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(xs, ys)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&tidy)
            .y_label_formatter(&tidy)
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 16))
            .draw()?;
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
            let drawn = match s.mark {
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
            // A series without a name (the second line of a band) stays out of the legend.
            if !s.name.is_empty() {
                drawn.label(s.name.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(3))
                });
            }
        }
        chart
            .configure_series_labels()
            .label_font((FAMILY, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(corner)
            .draw()?;
        root.present()
    }
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
