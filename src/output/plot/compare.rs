//! The comparison chart: time (log) against accuracy, one panel per measure,
//! one marker per run coloured by method variant, the Pareto front drawn.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{Axis, Pad};
use super::chart::{Drawable, Entry, FAMILY, Mark, below, draw_legend, sci, tidy};
use crate::compare::{CompareRun, Variant, distinct, pareto};
use crate::output::palette::colour;

/// Pixel size of the comparison chart (three panels side by side).
const SIZE: (u32, u32) = (1500, 620);

/// Smallest value drawn on a log axis: zeros (no overlap) sit on it.
const LOG_FLOOR: f64 = 1e-16;

/// Time against porosity error (or porosity without a target), KS and
/// residual overlap, for every run of a comparison.
#[derive(Debug, Clone)]
pub struct CompareChart {
    /// The runs.
    pub runs: Vec<CompareRun>,
    /// Whether the runs have a target-porosity error to plot.
    pub has_target: bool,
}

/// A variant's label, free of commas for CSV: `advancing-front (mx-quadtree; 2 contacts)`, `rsa`.
pub fn variant_label(v: &Variant) -> String {
    use crate::names::ConfigName;
    match v.method {
        crate::packer::Method::AdvancingFront => format!(
            "{} ({}; {} contact{})",
            v.method.config_name(),
            v.index.config_name(),
            if v.one_contact_share > 0.0 { 1 } else { 2 },
            if v.one_contact_share > 0.0 { "" } else { "s" }
        ),
        _ => v.method.config_name().to_owned(),
    }
}

/// One panel: its title, the value of a run, whether y is logarithmic, and
/// whether the value is an error (lower is better: a Pareto front is drawn).
struct Panel {
    title: &'static str,
    value: fn(&CompareRun) -> f64,
    log_y: bool,
    error: bool,
}

impl CompareChart {
    fn panels(&self) -> [Panel; 3] {
        let first = if self.has_target {
            Panel {
                title: "porosity error |φ − target|",
                value: |r| r.target_error.unwrap_or(f64::NAN),
                log_y: false,
                error: true,
            }
        } else {
            Panel {
                title: "porosity",
                value: |r| r.porosity,
                log_y: false,
                error: false,
            }
        };
        [
            first,
            Panel {
                title: "KS distance to the grading",
                value: |r| r.psd_ks,
                log_y: false,
                error: true,
            },
            Panel {
                title: "largest overlap / sum of radii",
                value: |r| r.max_overlap.max(LOG_FLOOR),
                log_y: true,
                error: true,
            },
        ]
    }

    fn variants(&self) -> Vec<Variant> {
        distinct(self.runs.iter().map(|r| r.variant))
    }

    fn draw_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        panel: &Panel,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let points = || {
            self.runs
                .iter()
                .map(|r| (r.seconds.max(1e-7), (panel.value)(r)))
                .filter(|(t, y)| t.is_finite() && y.is_finite())
        };
        let t_axis = Axis::log(
            points().map(|p| p.0),
            Pad {
                share: 0.0,
                least: 1.5f64.log10(),
            },
        );
        let y_axis = if panel.log_y {
            Axis::log(
                points().map(|p| p.1.max(LOG_FLOOR)),
                Pad {
                    share: 0.0,
                    least: 3f64.log10(),
                },
            )
        } else {
            Axis::linear(
                points().map(|p| p.1),
                Pad {
                    share: 0.08,
                    least: 0.005,
                },
            )
        };
        let variants = self.variants();
        let front = if panel.error {
            pareto(&self.runs, |r| {
                let v = (panel.value)(r);
                if v.is_finite() { v } else { f64::INFINITY }
            })
        } else {
            Vec::new()
        };
        let mut builder = ChartBuilder::on(area);
        builder
            .caption(panel.title, (FAMILY, 20))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(70);
        let mut chart = builder.build_cartesian_2d(t_axis, y_axis)?;
        chart
            .configure_mesh()
            .x_desc(if t_axis.is_log() {
                "seconds (log)"
            } else {
                "seconds"
            })
            .x_label_formatter(&sci)
            .y_label_formatter(&|v: &f64| {
                if y_axis.is_log() { sci(v) } else { tidy(v) }
            })
            .label_style((FAMILY, 13))
            .axis_desc_style((FAMILY, 15))
            .draw()?;
        for (i, v) in variants.iter().enumerate() {
            let [r, g, b] = colour(i);
            let c = RGBColor(r, g, b);
            let pts: Vec<(f64, f64)> = self
                .runs
                .iter()
                .filter(|run| run.variant == *v)
                .map(|run| (run.seconds.max(1e-7), (panel.value)(run)))
                .filter(|&(_, y)| y.is_finite())
                .collect();
            chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 5, c.filled())))?;
        }
        let line: Vec<(f64, f64)> = front
            .iter()
            .map(|run| (run.seconds.max(1e-7), (panel.value)(run)))
            .filter(|&(_, y)| y.is_finite())
            .collect();
        chart.draw_series(LineSeries::new(line, BLACK.stroke_width(1)))?;
        Ok(())
    }

    /// The legend: a dot per variant, then the Pareto front.
    fn legend(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self
            .variants()
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let [r, g, b] = colour(i);
                Entry {
                    text: variant_label(v),
                    colour: RGBColor(r, g, b),
                    mark: Mark::Dots,
                }
            })
            .collect();
        entries.push(Entry {
            text: "Pareto front (error panels)".to_owned(),
            colour: BLACK,
            mark: Mark::Line,
        });
        entries
    }
}

impl Drawable for CompareChart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let panels = self.panels();
        // The legend in a strip below the panels: it covers no run.
        let entries = self.legend();
        let (plots, legend, columns) = below(&root, &entries);
        let areas = plots.split_evenly((1, panels.len()));
        for (area, panel) in areas.iter().zip(&panels) {
            self.draw_panel(area, panel)?;
        }
        draw_legend(&legend, &entries, columns, 8)?;
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::testing::assert_legend_hides_nothing;
    use crate::packer::Method;

    /// Five runs of each variant as `compare configs/compare_fracture.toml`
    /// spreads them: the rsa runs slow and loose, in the panels' upper
    /// right corner, where the legend used to hide four of them.
    fn runs() -> Vec<CompareRun> {
        let variants = Variant::expand(&[Method::AdvancingFront, Method::Rsa, Method::Relaxation]);
        let mut runs = Vec::new();
        for (i, &variant) in variants.iter().enumerate() {
            for seed in 0..5 {
                let f = i as f64 + 0.1 * seed as f64;
                let rsa = variant.method == Method::Rsa;
                runs.push(CompareRun {
                    variant,
                    seed,
                    seconds: if rsa {
                        2e-3 + 2e-3 * seed as f64
                    } else {
                        1e-4 * (1.0 + f)
                    },
                    particles: 300,
                    porosity: if rsa {
                        0.48 + 0.006 * seed as f64
                    } else {
                        0.2 + 0.01 * f
                    },
                    target_error: None,
                    psd_ks: 0.04 + 0.008 * f,
                    max_overlap: if variant.method == Method::Relaxation {
                        1e-2
                    } else {
                        0.0
                    },
                    coordination: 3.0,
                    local_porosity_std: 0.01,
                });
            }
        }
        runs
    }

    #[test]
    fn the_legend_hides_no_run() {
        let chart = CompareChart {
            runs: runs(),
            has_target: false,
        };
        let labels: Vec<String> = chart.legend().into_iter().map(|e| e.text).collect();
        assert_eq!(
            labels.len(),
            7,
            "six variants and the Pareto front: {labels:?}"
        );
        assert_legend_hides_nothing(&chart.to_svg().expect("svg"), &labels);
    }
}
