//! The convergence chart of a target-porosity run.

use super::chart::{LineChart, Mark, Series};
use crate::ga::Generation;

/// Best and mean porosity against generation (0: the initial population,
/// a dot each when it is the only one), with the target as a dashed line
/// over generations 0 to the last (at least 1); whole generations on the axis.
/// The title names the particle shape found, when the search moved it.
pub fn convergence_chart(history: &[Generation], target: f64, shape: Option<String>) -> LineChart {
    let last = history.last().map_or(1.0, |g| g.index.max(1) as f64);
    let line = |name: &str, value: fn(&Generation) -> f64, colour| Series {
        name: name.to_owned(),
        points: history.iter().map(|g| (g.index as f64, value(g))).collect(),
        mark: Mark::Line,
        colour,
    };
    LineChart {
        title: match shape {
            None => format!("Convergence towards porosity {target}"),
            Some(shape) => format!("Convergence towards porosity {target} ({shape})"),
        },
        x_label: "generation".to_owned(),
        y_label: "porosity".to_owned(),
        series: vec![
            line("best", |g| g.best.value, 0),
            line("population mean", |g| g.mean_value, 1),
            Series {
                name: "target".to_owned(),
                points: vec![(0.0, target), (last, target)],
                mark: Mark::Dashed,
                colour: 2,
            },
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ga::Score;
    use crate::output::plot::Drawable;
    use crate::output::plot::testing::svg_texts;

    fn generation(index: usize, best: f64, mean: f64) -> Generation {
        Generation {
            index,
            best: Score {
                violation: 0.0,
                error: (best - 0.21).powi(2),
                value: best,
            },
            mean_value: mean,
            worst_value: 0.52,
            evaluations: 8,
            seconds: 0.003,
        }
    }

    /// The tick labels of the generation axis (numbers centred under it).
    fn generation_ticks(svg: &str) -> Vec<String> {
        svg_texts(svg)
            .into_iter()
            .filter(|t| t.anchor == "middle" && t.text.parse::<f64>().is_ok())
            .map(|t| t.text)
            .collect()
    }

    /// A target reached by the initial population drew only the target
    /// line, over ticks of 0.1 generation: now the population's best and
    /// mean are a dot each at generation 0, and the ticks are whole.
    #[test]
    fn the_initial_population_alone_shows_at_generation_0() {
        let chart = convergence_chart(&[generation(0, 0.232, 0.41)], 0.21, None);
        let svg = chart.to_svg().expect("svg");
        // Two filled dots (plotters writes a circle per dot), at one x.
        let dots: Vec<&str> = svg.split("<circle").skip(1).collect();
        assert_eq!(dots.len(), 2, "{svg}");
        let cx = |d: &str| {
            d.split("cx=\"")
                .nth(1)
                .and_then(|r| r.split('"').next())
                .map(str::to_owned)
        };
        assert_eq!(cx(dots[0]), cx(dots[1]));
        assert_eq!(generation_ticks(&svg), ["0", "1"]);
        // Many generations: lines, whole ticks only.
        let history: Vec<_> = (0..=7)
            .map(|i| generation(i, 0.3 - 0.01 * i as f64, 0.4))
            .collect();
        let svg = convergence_chart(&history, 0.21, None)
            .to_svg()
            .expect("svg");
        assert!(!svg.contains("<circle"));
        let ticks = generation_ticks(&svg);
        assert!(ticks.len() >= 3, "{ticks:?}");
        assert!(ticks.iter().all(|t| !t.contains('.')), "{ticks:?}");
    }
}
