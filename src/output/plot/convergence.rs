//! The convergence chart of a target-porosity run.

use super::chart::{LineChart, Mark, Series};
use crate::ga::Generation;

/// Best and mean porosity against generation, with the target as a dashed line.
pub fn convergence_chart(history: &[Generation], target: f64) -> LineChart {
    let last = history.last().map_or(1.0, |g| g.index.max(1) as f64);
    let line = |name: &str, value: fn(&Generation) -> f64, colour| Series {
        name: name.to_owned(),
        points: history.iter().map(|g| (g.index as f64, value(g))).collect(),
        mark: Mark::Line,
        colour,
    };
    LineChart {
        title: format!("Convergence towards porosity {target}"),
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
