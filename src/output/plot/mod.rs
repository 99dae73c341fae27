//! Charts: a generic line chart (SVG and PNG, in memory) and the charts built on it.

mod chart;
mod compare;
mod convergence;
mod profile;
mod stability;
mod window;

pub use chart::{Drawable, LineChart, Mark, Series};
pub use compare::{CompareChart, variant_label};
pub use convergence::convergence_chart;
pub use profile::profile_chart;
pub use stability::StabilityChart;
pub use window::window_chart;
