//! Charts: a generic line chart (SVG and PNG, in memory), the charts built
//! on it, and the pictures of a packing (drawing, grading, porosity map).

mod axis;
mod chart;
mod compare;
mod convergence;
mod packing;
mod particles;
mod pile;
mod porosity_map;
mod profile;
mod psd;
mod shape;
mod stability;
mod sweep_chart;
#[cfg(test)]
mod testing;
mod text;
mod window;

pub use chart::{Drawable, LineChart, Mark, Series};
pub use compare::{CompareChart, variant_label};
pub use convergence::convergence_chart;
pub use packing::{PACKING_PNG, packing_png, packing_png_coloured};
pub use particles::Colouring;
pub(crate) use particles::{COLOURINGS, Fills, boundary_points, bounding_disks, outline_at};
pub use porosity_map::{POROSITY_MAP_PNG, POROSITY_MAP_SVG, PorosityMapChart, porosity_map_chart};
pub use profile::profile_chart;
pub use psd::{PSD_PNG, PSD_SVG, PsdChart, psd_chart, psd_chart_of_scene};
pub use shape::{
    Asked, AskedShape, ORIENTATION_PNG, ORIENTATION_SVG, OrientationRose, SHAPE_PNG, SHAPE_SVG,
    ShapeChart, orientation_rose, shape_chart,
};
pub use stability::StabilityChart;
pub use sweep_chart::SweepChart;
pub use window::window_chart;
