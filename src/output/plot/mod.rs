//! Charts: a generic line chart (SVG and PNG, in memory) and the charts built on it.

mod chart;
mod convergence;

pub use chart::{LineChart, Mark, Series};
pub use convergence::convergence_chart;
