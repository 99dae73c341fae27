//! The stability map: method × case, coloured by pass, fail, refused or timed out.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::chart::{Drawable, FAMILY};
use super::compare::variant_label;
use crate::compare::{Variant, distinct};
use crate::stability::{CaseShape, RATIOS, StabilityRun, Status, WIDTHS};

/// Pixel size of the map (one band per shape).
const SIZE: (u32, u32) = (1500, 1500);

/// The runs of a stability sweep as a map.
#[derive(Debug, Clone)]
pub struct StabilityChart {
    /// The runs.
    pub runs: Vec<StabilityRun>,
}

/// Colour of a run: green pass, red fail, grey refused, black timed out.
fn cell_colour(run: &StabilityRun) -> RGBColor {
    match run.status {
        Status::Refused => RGBColor(200, 200, 200),
        Status::TimedOut => RGBColor(0, 0, 0),
        Status::Finished if run.passed() => RGBColor(0, 158, 115),
        Status::Finished => RGBColor(213, 94, 0),
    }
}

impl StabilityChart {
    fn variants(&self) -> Vec<Variant> {
        distinct(self.runs.iter().map(|r| r.variant))
    }

    fn band<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        shape: CaseShape,
        variants: &[Variant],
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let columns = RATIOS.len() * WIDTHS.len();
        let rows = variants.len().max(1);
        let labels: Vec<String> = variants.iter().map(variant_label).collect();
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: columns d_max/d_min 1:1, 1:1.1, 1:2, 1:4, 1:8, 1:16, each over width/d_max 1.2, 1.5, 2, 3, 5, 20",
                    shape.name()
                ),
                (FAMILY, 17),
            )
            .margin(8)
            .x_label_area_size(28)
            .y_label_area_size(300)
            .build_cartesian_2d(
                (0..columns as i32).into_segmented(),
                (0..rows as i32).into_segmented(),
            )?;
        let centre = |v: &SegmentValue<i32>| match v {
            SegmentValue::CenterOf(i) => Some(*i as usize),
            _ => None,
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(columns)
            .x_label_formatter(&|v| {
                centre(v).map_or(String::new(), |i| {
                    let (r, w) = (
                        RATIOS[i / WIDTHS.len() % RATIOS.len()],
                        WIDTHS[i % WIDTHS.len()],
                    );
                    if i % WIDTHS.len() == 0 {
                        format!("1:{r} | {w}")
                    } else {
                        format!("{w}")
                    }
                })
            })
            .y_labels(rows)
            .y_label_formatter(&|v| {
                centre(v)
                    .and_then(|i| labels.get(i).cloned())
                    .unwrap_or_default()
            })
            .label_style((FAMILY, 11))
            .draw()?;
        for run in self.runs.iter().filter(|r| r.case.shape == shape) {
            let Some(row) = variants.iter().position(|v| *v == run.variant) else {
                continue;
            };
            let ri = RATIOS
                .iter()
                .position(|&r| r == run.case.ratio)
                .unwrap_or(0);
            let wi = WIDTHS
                .iter()
                .position(|&w| w == run.case.width)
                .unwrap_or(0);
            let x = (ri * WIDTHS.len() + wi) as i32;
            let y = row as i32;
            let corners = [
                (SegmentValue::Exact(x), SegmentValue::Exact(y)),
                (SegmentValue::Exact(x + 1), SegmentValue::Exact(y + 1)),
            ];
            chart.draw_series([
                Rectangle::new(corners.clone(), cell_colour(run).filled()),
                Rectangle::new(corners, WHITE.stroke_width(2)),
            ])?;
        }
        Ok(())
    }
}

impl Drawable for StabilityChart {
    const SIZE: (u32, u32) = SIZE;

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (legend, body) = root.split_vertically(40);
        let items = [
            ("pass", RGBColor(0, 158, 115)),
            (
                "fail (overlap, empty > 2 %, or KS beyond sampling noise + 0.05)",
                RGBColor(213, 94, 0),
            ),
            ("refused: no disk fits", RGBColor(200, 200, 200)),
            ("timed out", RGBColor(0, 0, 0)),
        ];
        let mut x = 20;
        for (text, c) in items {
            legend.draw(&Rectangle::new([(x, 12), (x + 18, 30)], c.filled()))?;
            legend.draw(&Text::new(text, (x + 24, 14), (FAMILY, 15)))?;
            x += 60 + 8 * text.len() as i32;
        }
        let variants = self.variants();
        let bands = body.split_evenly((CaseShape::ALL.len(), 1));
        for (area, shape) in bands.iter().zip(CaseShape::ALL) {
            self.band(area, shape, &variants)?;
        }
        root.present()
    }
}
