//! The profile chart of a layering: target fractions as lines, achieved
//! fractions as dots, one colour per material.

use super::chart::{LineChart, Mark, Series};
use crate::layering::{Material, ProfileRow};
use crate::scene::{Axis, Profile};

/// Points per unit of s on the target curves (fine enough to show a step).
const CURVE_POINTS: usize = 400;

/// Each material's target fraction along s (from the profile itself) and
/// its achieved fraction per bin.
pub fn profile_chart(
    rows: &[ProfileRow],
    materials: &[Material],
    profile: &Profile,
    axis: Axis,
) -> LineChart {
    let n = materials.len().max(1);
    let mut series = Vec::with_capacity(2 * n);
    let mut at = vec![0.0; n];
    let curve: Vec<Vec<f64>> = (0..=CURVE_POINTS)
        .map(|k| {
            profile.fractions(k as f64 / CURVE_POINTS as f64, &mut at);
            at.clone()
        })
        .collect();
    for (m, material) in materials.iter().enumerate() {
        series.push(Series {
            name: format!("{} target", material.name),
            points: curve
                .iter()
                .enumerate()
                .map(|(k, f)| (k as f64 / CURVE_POINTS as f64, f[m]))
                .collect(),
            mark: Mark::Line,
            colour: m,
        });
        series.push(Series {
            name: format!("{} achieved", material.name),
            points: rows.iter().map(|r| (r.s, r.achieved[m])).collect(),
            mark: Mark::Dots,
            colour: m,
        });
    }
    let axis = match axis {
        Axis::X => "x",
        Axis::Y => "y",
        Axis::Radial => "distance from the centroid",
    };
    LineChart {
        title: format!(
            "Area fraction of each material, profile \"{}\"",
            profile.name()
        ),
        x_label: format!("s (normalised {axis})"),
        y_label: "area fraction of the solid".to_owned(),
        series,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::Drawable;
    use crate::output::plot::testing::{assert_legend_hides_nothing, legend_labels};

    /// A linear profile's curves end at 0 and 1 at s = 1, in the corners a
    /// legend inside the plot covered.
    #[test]
    fn the_legend_hides_no_curve_end() {
        let materials: Vec<Material> = ["coarse", "fine"]
            .map(|name| Material {
                name: name.to_owned(),
                properties: Vec::new(),
            })
            .to_vec();
        let rows: Vec<ProfileRow> = (0..10)
            .map(|bin| {
                let s = (bin as f64 + 0.5) / 10.0;
                ProfileRow {
                    bin,
                    s,
                    target: vec![1.0 - s, s],
                    achieved: vec![1.0 - s, s],
                }
            })
            .collect();
        let chart = profile_chart(&rows, &materials, &Profile::Linear, Axis::Y);
        let labels = legend_labels(&chart);
        assert_eq!(labels.len(), 4);
        assert_legend_hides_nothing(&chart.to_svg().expect("svg"), &labels);
    }
}
