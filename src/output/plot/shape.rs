//! The pictures of particle shapes: the shape chart (the aspect ratios and
//! sphericities found in a packing, each beside what was asked) and the
//! orientation rose (a polar histogram of the particles' long axes, with
//! the fabric tensor's principal direction).
//!
//! Both are built from plain numbers, so any caller (a pack job, a packing
//! read back) can draw them; drawn with [`Drawable::to_svg`] and
//! [`Drawable::to_png`].

use std::f64::consts::{PI, TAU};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{Axis, Pad};
use super::chart::{Drawable, FAMILY, plot_area, tidy};
use crate::output::palette::colour;

/// File name of the shape chart.
pub const SHAPE_SVG: &str = "shape.svg";
/// File name of the shape chart as an image.
pub const SHAPE_PNG: &str = "shape.png";
/// File name of the orientation rose.
pub const ORIENTATION_SVG: &str = "orientation.svg";
/// File name of the orientation rose as an image.
pub const ORIENTATION_PNG: &str = "orientation.png";

/// Most points of a cumulative curve: with more values it is taken at
/// this many ranks, which moves it by less than a pixel.
const MAX_CURVE_POINTS: usize = 2000;

/// What was asked of one shape measure: nothing, one value, a uniform
/// range, or values with their shares (summing to 1).
#[derive(Debug, Clone, PartialEq)]
pub enum Asked {
    /// Nothing asked (the measure follows from the others).
    Nothing,
    /// Every particle this value.
    Fixed(f64),
    /// Spread between the two values (low first).
    Range(f64, f64),
    /// Each value with its share of the particles.
    Shares(Vec<(f64, f64)>),
}

/// What was asked of the particles' shapes, for the shape chart.
#[derive(Debug, Clone, PartialEq)]
pub struct AskedShape {
    /// Aspect ratio (greatest over least width, ≥ 1).
    pub aspect: Asked,
    /// Sphericity (0–1).
    pub sphericity: Asked,
}

/// One panel of the shape chart: the cumulative curve of the values found,
/// and what was asked.
#[derive(Debug, Clone, PartialEq)]
struct Panel {
    /// The measure's name.
    name: &'static str,
    /// The found values' cumulative curve: (value, % of particles at most it).
    found: Vec<(f64, f64)>,
    /// Number of finite values found.
    count: usize,
    /// Their median, when there are values.
    median: Option<f64>,
    /// What was asked.
    asked: Asked,
    /// The value axis.
    x: Axis,
}

/// The shape chart: two panels side by side, aspect ratio and sphericity,
/// each the cumulative distribution (% of particles at most a value) of the
/// values found, beside what was asked: a fixed value as a dashed vertical
/// line, a range as a shaded band (with the uniform distribution over it
/// dashed), shares as the dashed steps of their cumulative sum.
///
/// Built by [`shape_chart`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeChart {
    panels: [Panel; 2],
}

/// The shape chart of the particles' `aspects` and `sphericities` (values
/// that are not finite left out) against `asked`.
pub fn shape_chart(aspects: &[f64], sphericities: &[f64], asked: &AskedShape) -> ShapeChart {
    ShapeChart {
        panels: [
            panel("aspect ratio", aspects, &asked.aspect),
            panel("sphericity", sphericities, &asked.sphericity),
        ],
    }
}

/// A panel of `values` against `asked`.
fn panel(name: &'static str, values: &[f64], asked: &Asked) -> Panel {
    let mut sorted: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    sorted.sort_unstable_by(f64::total_cmp);
    let asked_values: Vec<f64> = match asked {
        Asked::Nothing => Vec::new(),
        Asked::Fixed(v) => vec![*v],
        Asked::Range(lo, hi) => vec![*lo, *hi],
        Asked::Shares(t) => t.iter().map(|p| p.0).collect(),
    };
    let x = Axis::linear(
        sorted
            .first()
            .into_iter()
            .chain(sorted.last())
            .chain(&asked_values)
            .copied(),
        Pad {
            share: 0.08,
            least: 0.02,
        },
    );
    Panel {
        name,
        found: cumulative(&sorted),
        count: sorted.len(),
        median: sorted.get(sorted.len() / 2).copied(),
        asked: asked.clone(),
        x,
    }
}

/// The step curve (value, % at most it) of `sorted` values, at most
/// [`MAX_CURVE_POINTS`] steps.
fn cumulative(sorted: &[f64]) -> Vec<(f64, f64)> {
    let n = sorted.len();
    if n == 0 {
        return Vec::new();
    }
    let steps = n.min(MAX_CURVE_POINTS);
    let mut points = Vec::with_capacity(2 * steps);
    let mut before = 0.0;
    for k in 1..=steps {
        // The rank ending this step, and its value.
        let rank = k * n / steps;
        let v = sorted[rank - 1];
        let through = 100.0 * rank as f64 / n as f64;
        points.push((v, before));
        points.push((v, through));
        before = through;
    }
    points
}

/// The uniform or share-weighted cumulative curve asked, as (value, %), if
/// it is one (a fixed value is a line instead).
fn asked_curve(asked: &Asked, (x0, x1): (f64, f64)) -> Vec<(f64, f64)> {
    match asked {
        Asked::Range(lo, hi) => vec![(x0, 0.0), (*lo, 0.0), (*hi, 100.0), (x1, 100.0)],
        Asked::Shares(table) => {
            let mut sorted = table.clone();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            let total: f64 = sorted.iter().map(|p| p.1).sum();
            let mut points = vec![(x0, 0.0)];
            let mut through = 0.0;
            for (v, share) in sorted {
                points.push((v, 100.0 * through));
                through += if total > 0.0 { share / total } else { 0.0 };
                points.push((v, 100.0 * through));
            }
            points.push((x1, 100.0 * through));
            points
        }
        Asked::Nothing | Asked::Fixed(_) => Vec::new(),
    }
}

impl Panel {
    /// The panel's caption: the measure, count and median.
    fn title(&self) -> String {
        match self.median {
            Some(m) => format!(
                "{}: {} particle{}, median {:.3}",
                capitalised(self.name),
                self.count,
                if self.count == 1 { "" } else { "s" },
                m
            ),
            None => format!("{}: no particle", capitalised(self.name)),
        }
    }

    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let mut chart = plot_area(
            area,
            (&self.title(), 18),
            (self.x, Axis::exact(0.0, 100.0)),
            [self.name, "% of particles at most"],
            &tidy,
        )?;
        let grey = RGBColor(200, 200, 200);
        let asked_colour = BLACK.stroke_width(2);
        match &self.asked {
            Asked::Range(lo, hi) => {
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(*lo, 0.0), (*hi, 100.0)],
                    grey.mix(0.5).filled(),
                )))?;
            }
            Asked::Fixed(v) => {
                chart.draw_series(DashedLineSeries::new(
                    [(*v, 0.0), (*v, 100.0)],
                    8,
                    5,
                    asked_colour,
                ))?;
            }
            Asked::Nothing | Asked::Shares(_) => {}
        }
        let curve = asked_curve(&self.asked, self.x.ends());
        if !curve.is_empty() {
            chart.draw_series(DashedLineSeries::new(curve, 8, 5, asked_colour))?;
        }
        let [r, g, b] = colour(0);
        chart.draw_series(LineSeries::new(
            self.found.iter().copied(),
            RGBColor(r, g, b).stroke_width(2),
        ))?;
        // A key in the plot's lower right: the found curve and the asked mark.
        let key = match self.asked {
            Asked::Nothing => None,
            Asked::Fixed(_) => Some("dashed: asked value"),
            Asked::Range(..) => Some("band: asked range"),
            Asked::Shares(_) => Some("dashed: asked shares"),
        };
        if let Some(key) = key {
            let (w, h) = area.dim_in_pixel();
            area.draw(&Text::new(
                key,
                (w as i32 - 24, h as i32 - 70),
                (FAMILY, 13)
                    .into_font()
                    .color(&BLACK)
                    .pos(Pos::new(HPos::Right, VPos::Bottom)),
            ))?;
        }
        Ok(())
    }
}

/// `name` with its first letter upper-case.
fn capitalised(name: &str) -> String {
    let mut chars = name.chars();
    chars.next().map_or_else(String::new, |c| {
        c.to_uppercase().chain(chars).collect::<String>()
    })
}

impl Drawable for ShapeChart {
    const SIZE: (u32, u32) = (1000, 480);

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let width = root.dim_in_pixel().0 as i32;
        let (left, right) = root.split_horizontally(width / 2);
        self.panels[0].draw(&left)?;
        self.panels[1].draw(&right)?;
        root.present()
    }
}

/// Bins of the rose over a full turn (10° each).
const ROSE_BINS: usize = 36;

/// The orientation rose: a polar histogram of the particles' long-axis
/// angles in 10° bins, each bin a wedge whose radius is its count over the
/// largest bin's, with the fabric tensor's principal direction drawn
/// across it and the anisotropy in the title.
///
/// For shapes that look the same after a half turn (superellipses) the
/// angles are taken modulo 180° into 18 bins, each drawn twice, at θ and
/// θ + 180°: the rose is symmetric. Otherwise 36 bins over 360°.
///
/// Built by [`orientation_rose`].
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationRose {
    /// Count per bin, from 0° counter-clockwise.
    bins: Vec<usize>,
    /// Whether the bins span a half turn (drawn twice).
    half_turn: bool,
    /// The principal direction (degrees, counter-clockwise from x).
    principal_deg: f64,
    /// The anisotropy (0 isotropic, 1 all aligned).
    anisotropy: f64,
}

/// The rose of the long-axis `angles` (radians, counter-clockwise from the
/// x axis; those not finite left out), modulo a half turn when
/// `half_turn`, with the fabric tensor's principal direction
/// `principal_deg` (degrees) and its `anisotropy`.
pub fn orientation_rose(
    angles: &[f64],
    half_turn: bool,
    principal_deg: f64,
    anisotropy: f64,
) -> OrientationRose {
    let (period, n) = if half_turn {
        (PI, ROSE_BINS / 2)
    } else {
        (TAU, ROSE_BINS)
    };
    let mut bins = vec![0usize; n];
    for a in angles.iter().filter(|a| a.is_finite()) {
        let k = ((a.rem_euclid(period) / period) * n as f64).floor() as usize;
        bins[k.min(n - 1)] += 1;
    }
    OrientationRose {
        bins,
        half_turn,
        principal_deg,
        anisotropy,
    }
}

impl OrientationRose {
    /// The count of particles binned.
    fn count(&self) -> usize {
        self.bins.iter().sum()
    }

    fn title(&self) -> String {
        let n = self.count();
        format!(
            "Orientations of {n} particle{}: anisotropy {}, principal direction {}°",
            if n == 1 { "" } else { "s" },
            if self.anisotropy.is_finite() {
                format!("{:.3}", self.anisotropy)
            } else {
                "–".to_owned()
            },
            if self.principal_deg.is_finite() {
                format!("{:.1}", self.principal_deg)
            } else {
                "–".to_owned()
            }
        )
    }

    /// Each wedge drawn: its start and end angles (radians) and radius (0–1).
    fn wedges(&self) -> Vec<(f64, f64, f64)> {
        let most = self.bins.iter().copied().max().unwrap_or(0).max(1) as f64;
        let width = TAU / ROSE_BINS as f64;
        let copies = if self.half_turn { 2 } else { 1 };
        (0..copies)
            .flat_map(|c| {
                self.bins.iter().enumerate().map(move |(k, &count)| {
                    let start = (k + c * self.bins.len()) as f64 * width;
                    (start, start + width, count as f64 / most)
                })
            })
            .filter(|w| w.2 > 0.0)
            .collect()
    }
}

impl Drawable for OrientationRose {
    const SIZE: (u32, u32) = (720, 750);

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title(), (FAMILY, 18))
            .margin(20)
            .build_cartesian_2d(-1.25f64..1.25f64, -1.25f64..1.25f64)?;
        let on_circle = |t: f64, r: f64| (r * t.cos(), r * t.sin());
        // Rings at a quarter, half, three quarters and all of the largest bin.
        let ring = RGBColor(190, 190, 190);
        for r in [0.25, 0.5, 0.75, 1.0] {
            chart.draw_series(std::iter::once(PathElement::new(
                (0..=120)
                    .map(|k| on_circle(TAU * f64::from(k) / 120.0, r))
                    .collect::<Vec<_>>(),
                ring.stroke_width(1),
            )))?;
        }
        for k in 0..8 {
            let t = f64::from(k) * PI / 4.0;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), on_circle(t, 1.0)],
                ring.stroke_width(1),
            )))?;
        }
        let [r, g, b] = colour(0);
        let fill = RGBColor(r, g, b);
        for (start, end, radius) in self.wedges() {
            let arc: Vec<(f64, f64)> = std::iter::once((0.0, 0.0))
                .chain(
                    (0..=6).map(|j| on_circle(start + (end - start) * f64::from(j) / 6.0, radius)),
                )
                .collect();
            chart.draw_series(std::iter::once(Polygon::new(
                arc.clone(),
                fill.mix(0.75).filled(),
            )))?;
            chart.draw_series(std::iter::once(PathElement::new(
                arc.into_iter()
                    .chain(std::iter::once((0.0, 0.0)))
                    .collect::<Vec<_>>(),
                WHITE.stroke_width(1),
            )))?;
        }
        // The principal direction, across the whole rose (a direction, not a vector).
        if self.principal_deg.is_finite() {
            let t = self.principal_deg.to_radians();
            let [r, g, b] = colour(1);
            chart.draw_series(std::iter::once(PathElement::new(
                vec![on_circle(t, 1.12), on_circle(t + PI, 1.12)],
                RGBColor(r, g, b).stroke_width(3),
            )))?;
        }
        let label = (FAMILY, 14)
            .into_font()
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Center));
        for k in 0..4 {
            let t = f64::from(k) * PI / 2.0;
            chart.draw_series(std::iter::once(Text::new(
                format!("{}°", 90 * k),
                on_circle(t, 1.19),
                label.clone(),
            )))?;
        }
        let [r, g, b] = colour(1);
        let key = (FAMILY, 13).into_font().color(&RGBColor(r, g, b));
        let (w, h) = root.dim_in_pixel();
        root.draw(&Text::new(
            "line: principal direction of the fabric tensor",
            (20, h as i32 - 30),
            key,
        ))?;
        root.draw(&Text::new(
            if self.half_turn {
                "10° bins, symmetric (angles modulo 180°)"
            } else {
                "10° bins over 360°"
            },
            (w as i32 - 20, h as i32 - 30),
            (FAMILY, 13)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Right, VPos::Top)),
        ))?;
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::testing::{png_size, svg_size};

    fn asked() -> AskedShape {
        AskedShape {
            aspect: Asked::Range(1.5, 2.5),
            sphericity: Asked::Shares(vec![(0.7, 0.4), (0.85, 0.6)]),
        }
    }

    /// Empty, single and 10⁵ values all render, at the chart's size.
    #[test]
    fn charts_render_for_any_number_of_values() {
        let many: Vec<f64> = (0..100_000).map(|k| 1.0 + f64::from(k) * 1e-5).collect();
        let angles: Vec<f64> = (0..100_000).map(|k| f64::from(k) * 0.001).collect();
        for (values, asked) in [
            (&[][..], asked()),
            (&[1.7][..], asked()),
            (
                &many[..],
                AskedShape {
                    aspect: Asked::Fixed(2.0),
                    sphericity: Asked::Nothing,
                },
            ),
        ] {
            let chart = shape_chart(values, values, &asked);
            assert_eq!(svg_size(&chart.to_svg().expect("svg")), ShapeChart::SIZE);
            assert_eq!(png_size(&chart.to_png().expect("png")), ShapeChart::SIZE);
            assert!(chart.panels[0].found.len() <= 2 * MAX_CURVE_POINTS);
            for half_turn in [true, false] {
                let rose = orientation_rose(&angles[..values.len()], half_turn, 30.0, 0.4);
                assert_eq!(
                    svg_size(&rose.to_svg().expect("svg")),
                    OrientationRose::SIZE
                );
                assert_eq!(
                    png_size(&rose.to_png().expect("png")),
                    OrientationRose::SIZE
                );
            }
        }
        let svg = shape_chart(&[1.2, 1.9], &[0.8], &asked())
            .to_svg()
            .expect("svg");
        assert!(svg.contains("Aspect ratio: 2 particles") && svg.contains("band: asked range"));
    }

    #[test]
    fn the_cumulative_curve_climbs_to_100_percent() {
        let curve = cumulative(&[1.0, 2.0, 2.0, 3.0]);
        assert_eq!(curve.first(), Some(&(1.0, 0.0)));
        assert_eq!(curve.last(), Some(&(3.0, 100.0)));
        assert!(
            curve
                .windows(2)
                .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1)
        );
        let many: Vec<f64> = (0..10_000).map(f64::from).collect();
        let curve = cumulative(&many);
        assert_eq!(curve.len(), 2 * MAX_CURVE_POINTS);
        assert_eq!(curve.last(), Some(&(9999.0, 100.0)));
        // The asked shares step to 100 %.
        let steps = asked_curve(&Asked::Shares(vec![(0.85, 0.6), (0.7, 0.4)]), (0.5, 1.0));
        assert_eq!(steps[1..3], [(0.7, 0.0), (0.7, 40.0)]);
        assert_eq!(steps.last(), Some(&(1.0, 100.0)));
    }

    /// The bins hold every finite angle once; a half-turn rose folds θ and
    /// θ + 180° together and draws each bin twice, opposite.
    #[test]
    fn the_rose_s_bins_sum_to_the_count() {
        let angles: Vec<f64> = (0..1000).map(|k| f64::from(k) * 0.0137 - 3.0).collect();
        for half_turn in [true, false] {
            let rose = orientation_rose(&angles, half_turn, 0.0, 0.0);
            assert_eq!(rose.count(), 1000);
            assert_eq!(rose.bins.len(), if half_turn { 18 } else { 36 });
        }
        let rose = orientation_rose(&[0.1, 0.1 + PI, f64::NAN, -0.1], true, 0.0, 1.0);
        assert_eq!(rose.count(), 3);
        assert_eq!(rose.bins[0], 2);
        assert_eq!(rose.bins[17], 1);
        let wedges = rose.wedges();
        assert_eq!(wedges.len(), 4);
        assert_eq!(wedges[0], (0.0, TAU / 36.0, 1.0));
        assert!((wedges[2].0 - PI).abs() < 1e-12);
        let full = orientation_rose(&[0.1, 0.1 + PI], false, 0.0, 0.0);
        assert_eq!((full.bins[0], full.bins[18]), (1, 1));
        assert!(
            full.title()
                .starts_with("Orientations of 2 particles: anisotropy 0.000")
        );
    }
}
