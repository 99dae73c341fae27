//! A parameter study's chart: its measure, the mean over the seeds with
//! the smallest–largest spread as a bar, against the first swept key (a
//! numeric axis when its values are numbers, else one place per value),
//! one series per value of the other keys, the legend beside the plot.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{Axis, Pad};
use super::chart::{Drawable, Entry, LEGEND_TOP, Mark, beside, draw_legend, plot_area, tidy};
use crate::output::palette::colour;
use crate::study::{Measure, Row, Spread, SweepSettings, spreads};

/// Pixel size of the chart.
const SIZE: (u32, u32) = (1000, 600);

/// Half-width of a spread bar's caps, as a share of the x axis.
const CAP: f64 = 0.008;

/// Spacing of the series at one x, as a share of the x axis, so that
/// their spread bars do not hide one another.
const DODGE: f64 = 0.012;

/// The places along x: the first key's values as numbers, or one place per value.
#[derive(Debug, Clone, PartialEq)]
enum Xs {
    Numbers(Vec<f64>),
    Categories(Vec<String>),
}

/// A study's chart, built from its settings and rows by [`SweepChart::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct SweepChart {
    /// The caption.
    title: String,
    /// The x axis' title.
    x_title: String,
    /// The measure charted.
    measure: Measure,
    /// The first key's values as places.
    xs: Xs,
    /// Each series' name (one series without a second key).
    series: Vec<String>,
    /// Each point's spread, in product order: point `i · series + s` is
    /// value `i` of the first key in series `s`.
    points: Vec<Option<Spread>>,
}

/// The unit of a config key, where its name tells it.
fn unit(path: &str) -> Option<&'static str> {
    let last = path.rsplit('.').next().unwrap_or(path);
    if last.ends_with("_mm") {
        return Some("mm");
    }
    if last.ends_with("_m") {
        return Some("m");
    }
    if last.ends_with("_s") {
        return Some("s");
    }
    let millimetres = [
        "domain.width",
        "domain.height",
        "domain.radius",
        "domain.bottom",
        "domain.top",
        "domain.wall_disk",
        "fracture.wall_disk",
        "fracture.mean_diameter",
        "grading.constant",
    ];
    millimetres.contains(&path).then_some("mm")
}

impl SweepChart {
    /// The chart of `rows` (a study's, in product order) as `settings` describe them.
    pub fn new(settings: &SweepSettings, rows: &[Row]) -> Self {
        let (x_path, xs) = match settings.keys.first() {
            Some(key) => (
                key.path.clone(),
                key.numbers()
                    .map_or_else(|| Xs::Categories(key.texts()), Xs::Numbers),
            ),
            None => (String::new(), Xs::Categories(vec![String::new()])),
        };
        let rest = settings.keys.get(1..).unwrap_or_default();
        let series: Vec<String> = if rest.is_empty() {
            vec![format!(
                "mean over {} seed{}",
                settings.seeds,
                plural(settings.seeds)
            )]
        } else {
            let labels: Vec<Vec<String>> = rest
                .iter()
                .map(|k| {
                    let last = k.path.rsplit('.').next().unwrap_or(&k.path).to_owned();
                    k.texts()
                        .into_iter()
                        .map(|v| format!("{last} {v}"))
                        .collect()
                })
                .collect();
            crate::study::points(rest)
                .iter()
                .map(|combo| {
                    combo
                        .iter()
                        .enumerate()
                        .map(|(k, &i)| labels[k][i].clone())
                        .collect::<Vec<_>>()
                        .join(", ")
                })
                .collect()
        };
        let x_title = match unit(&x_path) {
            Some(u) => format!("{x_path} ({u})"),
            None => x_path.clone(),
        };
        SweepChart {
            title: format!(
                "{} against {x_path}: mean over {} seed{}, bars from least to most",
                measure_name(settings.measure),
                settings.seeds,
                plural(settings.seeds)
            ),
            x_title,
            measure: settings.measure,
            xs,
            series,
            points: spreads(rows, settings.seeds, settings.measure),
        }
    }

    /// How many places along x.
    fn places(&self) -> usize {
        match &self.xs {
            Xs::Numbers(v) => v.len(),
            Xs::Categories(v) => v.len(),
        }
    }

    /// The x of place `i`.
    fn x(&self, i: usize) -> f64 {
        match &self.xs {
            Xs::Numbers(v) => v[i],
            Xs::Categories(_) => i as f64,
        }
    }

    /// Series `s` as (x, spread) in the order of the first key's values.
    fn series_points(&self, s: usize) -> Vec<(f64, Spread)> {
        let n = self.series.len();
        (0..self.places())
            .filter_map(|i| {
                self.points
                    .get(i * n + s)
                    .copied()
                    .flatten()
                    .map(|p| (self.x(i), p))
            })
            .collect()
    }

    fn axes(&self) -> (Axis, Axis) {
        let x = match &self.xs {
            Xs::Numbers(v) => Axis::linear(
                v.iter().copied(),
                Pad {
                    share: 0.08,
                    least: 0.02,
                },
            ),
            Xs::Categories(v) => Axis::exact(-0.5, v.len() as f64 - 0.5).whole(),
        };
        let ys = self
            .points
            .iter()
            .flatten()
            .flat_map(|p| [p.min, p.max, p.mean]);
        let y = Axis::linear(
            ys,
            Pad {
                share: 0.08,
                least: 0.002,
            },
        );
        let y = if self.measure == Measure::Particles {
            y.whole()
        } else {
            y
        };
        (x, y)
    }

    fn legend(&self) -> Vec<Entry> {
        self.series
            .iter()
            .enumerate()
            .map(|(s, name)| {
                let [r, g, b] = colour(s);
                Entry {
                    text: name.clone(),
                    colour: RGBColor(r, g, b),
                    mark: Mark::Line,
                }
            })
            .collect()
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// The measure as a caption names it.
fn measure_name(measure: Measure) -> &'static str {
    match measure {
        Measure::Porosity => "porosity",
        Measure::Particles => "disks",
        Measure::PsdKs => "psd_ks",
        Measure::Coordination => "coordination",
        Measure::Error => "target error",
        Measure::Seconds => "seconds",
    }
}

impl Drawable for SweepChart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (xs, ys) = self.axes();
        let entries = self.legend();
        let (plot, legend) = beside(&root, &entries);
        let categories = match &self.xs {
            Xs::Categories(names) => Some(names.clone()),
            Xs::Numbers(_) => None,
        };
        let x_label = |v: &f64| match &categories {
            Some(names) => {
                let i = v.round();
                if (v - i).abs() < 1e-9 && i >= 0.0 {
                    names.get(i as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            }
            None => tidy(v),
        };
        let mut chart = plot_area(
            &plot,
            (&self.title, 18),
            (xs, ys),
            [&self.x_title, self.measure.title()],
            &x_label,
        )?;
        let (lo, hi) = xs.ends();
        let span = hi - lo;
        let n = self.series.len();
        for s in 0..n {
            let [r, g, b] = colour(s);
            let c = RGBColor(r, g, b);
            let shift = (s as f64 - 0.5 * (n as f64 - 1.0)) * DODGE * span;
            let points: Vec<(f64, Spread)> = self
                .series_points(s)
                .into_iter()
                .map(|(x, p)| (x + shift, p))
                .collect();
            let means: Vec<(f64, f64)> = points.iter().map(|(x, p)| (*x, p.mean)).collect();
            if means.len() > 1 {
                chart.draw_series(LineSeries::new(means.iter().copied(), c.stroke_width(2)))?;
            }
            chart.draw_series(means.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
            let cap = CAP * span;
            for (x, p) in &points {
                if p.max > p.min {
                    let bar = c.stroke_width(1);
                    chart.draw_series([
                        PathElement::new(vec![(*x, p.min), (*x, p.max)], bar),
                        PathElement::new(vec![(x - cap, p.min), (x + cap, p.min)], bar),
                        PathElement::new(vec![(x - cap, p.max), (x + cap, p.max)], bar),
                    ])?;
                }
            }
        }
        draw_legend(&legend, &entries, 1, LEGEND_TOP)?;
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::testing::{assert_legend_hides_nothing, svg_texts};
    use crate::study::{Keep, Measures, Status, SweptKey};

    fn key(path: &str, values: Vec<toml::Value>) -> SweptKey {
        let n = values.len();
        SweptKey {
            path: path.to_owned(),
            values,
            span: 0..0,
            value_spans: vec![0..0; n],
        }
    }

    fn settings(keys: Vec<SweptKey>, seeds: usize) -> SweepSettings {
        SweepSettings {
            keys,
            seeds,
            keep: Keep::None,
            measure: Measure::Porosity,
            job: None,
        }
    }

    /// Rows of a study whose porosity rises with the width, the second
    /// key's values apart, the seeds spread by 0.01.
    fn rows(widths: usize, meshes: usize, seeds: usize) -> Vec<Row> {
        let mut rows = Vec::new();
        for w in 0..widths {
            for m in 0..meshes {
                for k in 0..seeds {
                    rows.push(Row {
                        run: format!("{w}-{m}-{k}"),
                        values: Vec::new(),
                        seed: k as u64,
                        status: Status::Finished(Measures {
                            particles: 100,
                            porosity: 0.2 + 0.05 * w as f64 + 0.03 * m as f64 + 0.01 * k as f64,
                            psd_ks: 0.05,
                            coordination: 3.5,
                            target_error: None,
                            seconds: 0.01,
                        }),
                    });
                }
            }
        }
        rows
    }

    fn floats(v: &[f64]) -> Vec<toml::Value> {
        v.iter().map(|&f| toml::Value::Float(f)).collect()
    }

    fn strings(v: &[&str]) -> Vec<toml::Value> {
        v.iter()
            .map(|s| toml::Value::String((*s).to_owned()))
            .collect()
    }

    #[test]
    fn one_series_per_value_of_the_second_key() {
        let s = settings(
            vec![
                key("fracture.width_mm", floats(&[1.5, 2.0, 3.0])),
                key("grading.preset", strings(&["20/40", "30/50"])),
            ],
            3,
        );
        let chart = SweepChart::new(&s, &rows(3, 2, 3));
        assert_eq!(chart.series, ["preset 20/40", "preset 30/50"]);
        // Series 1 is the second mesh at every width, in the widths' order.
        let second = chart.series_points(1);
        let xs: Vec<f64> = second.iter().map(|p| p.0).collect();
        assert_eq!(xs, [1.5, 2.0, 3.0]);
        let p = second[2].1;
        assert!((p.mean - (0.2 + 0.1 + 0.03 + 0.01)).abs() < 1e-12, "{p:?}");
        assert!((p.max - p.min - 0.02).abs() < 1e-12 && p.runs == 3);
        let svg = chart.to_svg().expect("svg");
        assert!(
            svg.contains("fracture.width_mm (mm)"),
            "the x axis names the key and its unit"
        );
        assert_legend_hides_nothing(&svg, &chart.series);
        assert_eq!(&chart.to_png().expect("png")[..4], b"\x89PNG");
    }

    #[test]
    fn text_values_are_places_and_one_key_is_one_series() {
        let s = settings(
            vec![key("grading.preset", strings(&["20/40", "30/50", "40/70"]))],
            2,
        );
        let chart = SweepChart::new(&s, &rows(3, 1, 2));
        assert_eq!(chart.series, ["mean over 2 seeds"]);
        let svg = chart.to_svg().expect("svg");
        let texts: Vec<String> = svg_texts(&svg).into_iter().map(|t| t.text).collect();
        for preset in ["20/40", "30/50", "40/70"] {
            assert!(
                texts.iter().any(|t| t == preset),
                "{preset} labels its place: {texts:?}"
            );
        }
    }

    #[test]
    fn a_point_without_a_finished_run_is_left_out() {
        let s = settings(vec![key("fracture.width_mm", floats(&[0.2, 2.0]))], 1);
        let mut rows = rows(2, 1, 1);
        rows[0].status = Status::Failed("too narrow".to_owned());
        let chart = SweepChart::new(&s, &rows);
        let xs: Vec<f64> = chart.series_points(0).iter().map(|p| p.0).collect();
        assert_eq!(xs, [2.0]);
        assert!(chart.to_svg().expect("svg").starts_with("<svg"));
    }
}
