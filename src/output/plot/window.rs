//! The window chart of a fracture run: porosity against window length.

use super::chart::{LineChart, Mark, Series};
use crate::fracture::WindowStep;

/// Each window's core porosity against its length, with the settling band
/// (the last estimate ± `tolerance`) dashed.
pub fn window_chart(steps: &[WindowStep], tolerance: f64, name: &str) -> LineChart {
    let points: Vec<(f64, f64)> = steps.iter().map(|s| (s.length, s.porosity)).collect();
    let (first, last) = (
        steps.first().map_or(0.0, |s| s.length),
        steps.last().map_or(1.0, |s| s.length),
    );
    let estimate = steps.last().map_or(f64::NAN, |s| s.porosity);
    let band = |sign: f64, label: &str| Series {
        name: label.to_owned(),
        points: vec![
            (first, estimate + sign * tolerance),
            (last, estimate + sign * tolerance),
        ],
        mark: Mark::Dashed,
        colour: 1,
    };
    LineChart {
        title: format!("Porosity of {name} against window length"),
        x_label: "window length along the fracture (mm)".to_owned(),
        y_label: "porosity of the window's core".to_owned(),
        series: vec![
            Series {
                name: "window core".to_owned(),
                points: points.clone(),
                mark: Mark::Line,
                colour: 0,
            },
            Series {
                name: String::new(),
                points,
                mark: Mark::Dots,
                colour: 0,
            },
            band(1.0, &format!("estimate ± {tolerance}")),
            band(-1.0, ""),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::Drawable;
    use crate::output::plot::testing::{assert_legend_hides_nothing, legend_labels};

    /// The band's upper line runs the chart's whole width near its top,
    /// where a legend inside the plot covered it.
    #[test]
    fn the_legend_hides_neither_the_curve_nor_the_band() {
        let steps: Vec<WindowStep> = [(40.0, 0.262), (80.0, 0.251), (160.0, 0.2495)]
            .into_iter()
            .map(|(length, porosity)| WindowStep {
                length,
                particles: 100,
                porosity,
                coordination: 3.0,
                spread: 0.002,
                seconds: 0.01,
            })
            .collect();
        let chart = window_chart(&steps, 0.005, "well");
        let labels = legend_labels(&chart);
        assert_eq!(labels, ["window core", "estimate ± 0.005"]);
        assert_legend_hides_nothing(&chart.to_svg().expect("svg"), &labels);
    }
}
