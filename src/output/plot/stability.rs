//! The stability map: method × case, coloured by pass, each reason of a
//! failure, refused or timed out; a case failing for several reasons is a
//! cell of several colours.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{Drawable, FAMILY};
use super::compare::variant_label;
use crate::compare::{Variant, distinct};
use crate::stability::{CaseShape, RATIOS, Reason, StabilityRun, Status, WIDTHS};

/// Pixel size of the map (one band per shape).
const SIZE: (u32, u32) = (1500, 1500);

/// Height of the legend strip above the bands (px).
const LEGEND: i32 = 64;

const PASS: RGBColor = RGBColor(0, 158, 115);
const REFUSED: RGBColor = RGBColor(200, 200, 200);
const TIMED_OUT: RGBColor = RGBColor(0, 0, 0);

/// Colour of a failure reason (the Okabe–Ito vermilion, blue and purple).
fn reason_colour(reason: Reason) -> RGBColor {
    match reason {
        Reason::Overlap => RGBColor(213, 94, 0),
        Reason::Empty => RGBColor(0, 114, 178),
        Reason::Grading => RGBColor(204, 121, 167),
    }
}

/// The colours of a run's cell, left to right: one for a pass, a refusal or
/// a time-out, one per reason for a failure.
fn cell_colours(run: &StabilityRun) -> Vec<RGBColor> {
    match run.status {
        Status::Refused => vec![REFUSED],
        Status::TimedOut => vec![TIMED_OUT],
        Status::Finished if run.passed() => vec![PASS],
        Status::Finished => run.reasons().into_iter().map(reason_colour).collect(),
    }
}

/// How many seeds `runs` ran with, and the lowest.
fn seeds_of(runs: &[StabilityRun]) -> (usize, Option<u64>) {
    let mut seeds: Vec<u64> = runs.iter().map(|r| r.seed).collect();
    seeds.sort_unstable();
    seeds.dedup();
    (seeds.len(), seeds.first().copied())
}

/// The runs of a stability sweep as a map.
#[derive(Debug, Clone)]
pub struct StabilityChart {
    /// The runs.
    pub runs: Vec<StabilityRun>,
}

/// Where one shape's band draws, in pixels of its area: a caption on top,
/// the variants' names on the left, a row per variant and a column per
/// case (grouped by grading width), the case labels below.
#[derive(Debug, Clone, Copy)]
struct Band {
    /// Size of the band's area.
    width: i32,
    height: i32,
    /// Rows: one per variant.
    rows: usize,
}

impl Band {
    /// Height of the caption above the cells.
    const CAPTION: i32 = 28;
    /// Height of the two label lines below the cells.
    const FOOT: i32 = 42;
    /// Width of the variant names left of the cells.
    const NAMES: i32 = 300;
    /// Space right of the cells.
    const RIGHT: i32 = 16;
    /// Gap between two groups of columns (grading widths).
    const GAP: i32 = 10;

    /// Width of a column.
    fn column_width(&self) -> i32 {
        let groups = RATIOS.len() as i32;
        (self.width - Self::NAMES - Self::RIGHT - (groups - 1) * Self::GAP)
            / (groups * WIDTHS.len() as i32)
    }

    /// Height of a row: the rows fill the band between caption and labels.
    fn row_height(&self) -> i32 {
        (self.height - Self::CAPTION - Self::FOOT) / self.rows.max(1) as i32
    }

    /// Left edge of the column of grading `ratio` (index) and domain `width` (index).
    fn column_left(&self, ratio: usize, width: usize) -> i32 {
        Self::NAMES
            + ratio as i32 * (WIDTHS.len() as i32 * self.column_width() + Self::GAP)
            + width as i32 * self.column_width()
    }

    /// The cell of `row` (from the top) in the column of `ratio` and
    /// `width` (indices), as top-left and bottom-right corners.
    fn cell(&self, row: usize, ratio: usize, width: usize) -> [(i32, i32); 2] {
        let (x, y) = (
            self.column_left(ratio, width),
            Self::CAPTION + row as i32 * self.row_height(),
        );
        [(x, y), (x + self.column_width(), y + self.row_height())]
    }

    /// Bottom of the last row.
    fn cells_bottom(&self) -> i32 {
        Self::CAPTION + self.rows.max(1) as i32 * self.row_height()
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
        let (width, height) = area.dim_in_pixel();
        let band = Band {
            width: width as i32,
            height: height as i32,
            rows: variants.len(),
        };
        let text =
            |size: u32, h: HPos, v: VPos| (FAMILY, size).into_text_style(area).pos(Pos::new(h, v));
        area.draw(&Text::new(
            format!(
                "{}: a column per case, domain width / d_max within each grading d_max/d_min{}",
                shape.name(),
                match seeds_of(&self.runs) {
                    (n, Some(first)) if n > 1 => {
                        format!(
                            "; each cell a line per seed, {first} to {} from the top",
                            first + n as u64 - 1
                        )
                    }
                    _ => String::new(),
                }
            ),
            (Band::NAMES, 6),
            text(16, HPos::Left, VPos::Top),
        ))?;
        for (row, v) in variants.iter().enumerate() {
            let [(_, y0), (_, y1)] = band.cell(row, 0, 0);
            area.draw(&Text::new(
                variant_label(v),
                (Band::NAMES - 8, (y0 + y1) / 2),
                text(13, HPos::Right, VPos::Center),
            ))?;
        }
        let (widths_y, ratios_y) = (band.cells_bottom() + 4, band.cells_bottom() + 22);
        let names_x = Band::NAMES - 8;
        area.draw(&Text::new(
            "width / d_max",
            (names_x, widths_y),
            text(12, HPos::Right, VPos::Top),
        ))?;
        area.draw(&Text::new(
            "d_max / d_min",
            (names_x, ratios_y),
            text(13, HPos::Right, VPos::Top),
        ))?;
        for (ri, ratio) in RATIOS.iter().enumerate() {
            for (wi, width) in WIDTHS.iter().enumerate() {
                let [(x0, _), (x1, _)] = band.cell(0, ri, wi);
                area.draw(&Text::new(
                    format!("{width}"),
                    ((x0 + x1) / 2, widths_y),
                    text(12, HPos::Center, VPos::Top),
                ))?;
            }
            let [(x0, _), _] = band.cell(0, ri, 0);
            let [_, (x1, _)] = band.cell(0, ri, WIDTHS.len() - 1);
            area.draw(&Text::new(
                format!("1:{ratio}"),
                ((x0 + x1) / 2, ratios_y),
                text(13, HPos::Center, VPos::Top),
            ))?;
        }
        // Several seeds: each cell stacks one line per seed, the first on top.
        let mut seeds: Vec<u64> = self.runs.iter().map(|r| r.seed).collect();
        seeds.sort_unstable();
        seeds.dedup();
        for run in self.runs.iter().filter(|r| r.case.shape == shape) {
            let (Some(row), Some(ri), Some(wi), Some(si)) = (
                variants.iter().position(|v| *v == run.variant),
                RATIOS.iter().position(|&r| r == run.case.ratio),
                WIDTHS.iter().position(|&w| w == run.case.width),
                seeds.iter().position(|&s| s == run.seed),
            ) else {
                continue;
            };
            // One vertical strip per colour, a pixel of white around the cell.
            let [(x0, top), (x1, bottom)] = band.cell(row, ri, wi);
            let line = |k: usize| top + ((bottom - top) as usize * k / seeds.len()) as i32;
            let (y0, y1) = if seeds.len() == 1 {
                (top, bottom)
            } else {
                // Seeds' lines touch; the cell keeps its white frame.
                (
                    line(si) - i32::from(si > 0),
                    line(si + 1) + i32::from(si + 1 < seeds.len()),
                )
            };
            let colours = cell_colours(run);
            let strip = (x1 - x0 - 2) / colours.len() as i32;
            for (k, c) in colours.iter().enumerate() {
                let left = x0 + 1 + k as i32 * strip;
                let right = if k + 1 == colours.len() {
                    x1 - 1
                } else {
                    left + strip
                };
                area.draw(&Rectangle::new(
                    [(left, y0 + 1), (right, y1 - 1)],
                    c.filled(),
                ))?;
            }
        }
        Ok(())
    }

    /// The legend: what each colour means, and what a cell of two says.
    fn legend<DB: DrawingBackend>(
        area: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let style = (FAMILY, 15)
            .into_text_style(area)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let items = [
            ("pass", PASS),
            (
                "fail: overlap > 1e-9 of the radii sum",
                reason_colour(Reason::Overlap),
            ),
            ("fail: empty > 2 %", reason_colour(Reason::Empty)),
            (
                "fail: KS beyond sampling noise + 0.05",
                reason_colour(Reason::Grading),
            ),
            ("refused: no disk fits", REFUSED),
            ("timed out", TIMED_OUT),
        ];
        let mut x = 20;
        for (text, c) in items {
            area.draw(&Rectangle::new([(x, 11), (x + 18, 29)], c.filled()))?;
            area.draw(&Text::new(text, (x + 24, 20), style.clone()))?;
            let width = area
                .estimate_text_size(text, &style)
                .map_or(200, |(w, _)| w as i32);
            x += 24 + width + 28;
        }
        // A two-colour swatch: a case failing for two reasons.
        let (a, b) = (reason_colour(Reason::Empty), reason_colour(Reason::Grading));
        area.draw(&Rectangle::new([(20, 38), (29, 56)], a.filled()))?;
        area.draw(&Rectangle::new([(29, 38), (38, 56)], b.filled()))?;
        area.draw(&Text::new(
            "a cell of two (or three) colours: the case fails for each of those reasons (here empty and KS)",
            (44, 47),
            style,
        ))?;
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
        let (legend, body) = root.split_vertically(LEGEND);
        Self::legend(&legend)?;
        let variants = self.variants();
        let bands = body.split_evenly((CaseShape::ALL.len(), 1));
        for (area, shape) in bands.iter().zip(CaseShape::ALL) {
            self.band(area, shape, &variants)?;
        }
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::plot::testing::{png_rgb, svg_texts};
    use crate::packer::Method;
    use crate::stability::Case;

    /// Two variants over every case: the first passes everywhere; the
    /// second, column by column, passes, fails for each reason, for two,
    /// is refused or times out.
    fn chart() -> StabilityChart {
        let variants = Variant::expand(&[Method::Rsa, Method::Relaxation]);
        let kinds = [
            (Status::Finished, 0.0, 0.0, 0.0),
            (Status::Finished, 0.0, 0.1, 0.0),
            (Status::Finished, 0.5, 0.0, 0.0),
            (Status::Finished, 0.0, 0.0, 0.9),
            (Status::Finished, 0.5, 0.0, 0.9),
            (Status::Refused, 1.0, 0.0, 1.0),
            (Status::TimedOut, 1.0, 0.0, 1.0),
        ];
        let runs = Case::all()
            .into_iter()
            .enumerate()
            .flat_map(|(i, case)| {
                let (status, empty, max_overlap, psd_ks) = kinds[i % kinds.len()];
                [
                    (variants[0], kinds[0]),
                    (variants[1], (status, empty, max_overlap, psd_ks)),
                ]
                .map(|(variant, (status, empty, max_overlap, psd_ks))| {
                    StabilityRun {
                        case,
                        variant,
                        seed: 1,
                        status,
                        seconds: 0.1,
                        particles: 100,
                        empty,
                        max_overlap,
                        psd_ks,
                    }
                })
            })
            .collect();
        StabilityChart { runs }
    }

    /// Band `k`'s layout and its top in the image.
    fn band(k: usize, rows: usize) -> (Band, i32) {
        let height = (SIZE.1 as i32 - LEGEND) / CaseShape::ALL.len() as i32;
        let band = Band {
            width: SIZE.0 as i32,
            height,
            rows,
        };
        (band, LEGEND + k as i32 * height)
    }

    /// "201:1.1 | 1.21.5": case labels ran into each other, and a label sat
    /// past the last column. Now each width once per column, each grading
    /// once per group, none overlapping another on its line, all inside.
    #[test]
    fn case_labels_do_not_collide_and_none_lies_past_the_columns() {
        let texts = svg_texts(&chart().to_svg().expect("svg"));
        let count = |label: &str| texts.iter().filter(|t| t.text == label).count();
        for width in WIDTHS {
            assert_eq!(count(&format!("{width}")), 4 * RATIOS.len(), "{width}");
        }
        for ratio in RATIOS {
            assert_eq!(count(&format!("1:{ratio}")), 4, "1:{ratio}");
        }
        let (layout, _) = band(0, 2);
        let right = layout.cell(0, RATIOS.len() - 1, WIDTHS.len() - 1)[1].0 as f64;
        for t in &texts {
            let (left, end) = t.extent();
            assert!(
                left >= 0.0 && end <= f64::from(SIZE.0),
                "{t:?} leaves the image"
            );
            if t.text.parse::<f64>().is_ok() || t.text.starts_with("1:") {
                assert!(end <= right + 20.0, "{t:?} lies past the last column");
            }
        }
        for (i, a) in texts.iter().enumerate() {
            for b in &texts[i + 1..] {
                let (ax, bx) = (a.extent(), b.extent());
                let (ay, by) = (a.vertical(), b.vertical());
                let apart = ax.1 + 2.0 <= bx.0 || bx.1 + 2.0 <= ax.0;
                let other_lines = ay.1 <= by.0 || by.1 <= ay.0;
                assert!(apart || other_lines, "{a:?} collides with {b:?}");
            }
        }
    }

    /// Each band had a row with no variant in it: now the rows fill the
    /// band from caption to labels, every cell of every row drawn.
    #[test]
    fn every_row_holds_a_variant_and_no_row_is_empty() {
        let chart = chart();
        let (rgb, (w, _)) = png_rgb(&chart.to_png().expect("png"));
        let pixel = |x: i32, y: i32| {
            let i = 3 * (y as usize * w as usize + x as usize);
            [rgb[i], rgb[i + 1], rgb[i + 2]]
        };
        for k in 0..CaseShape::ALL.len() {
            let (layout, top) = band(k, 2);
            assert!(layout.height - Band::FOOT - layout.cells_bottom() < 2);
            for row in 0..2 {
                for (ri, wi) in
                    (0..RATIOS.len()).flat_map(|r| (0..WIDTHS.len()).map(move |w| (r, w)))
                {
                    let [(x0, y0), (x1, y1)] = layout.cell(row, ri, wi);
                    let centre = pixel((x0 + x1) / 2, top + (y0 + y1) / 2);
                    assert_ne!(
                        centre, [255; 3],
                        "band {k}, row {row}, column {ri}/{wi} is empty"
                    );
                }
            }
            // Down the first column from caption to labels: cells, save their borders.
            let [(x0, _), (x1, _)] = layout.cell(0, 0, 0);
            let x = (x0 + x1) / 2;
            let white = (Band::CAPTION..layout.height - Band::FOOT)
                .filter(|&y| pixel(x, top + y) == [255; 3])
                .count();
            let span = (layout.height - Band::FOOT - Band::CAPTION) as usize;
            assert!(white * 10 < span, "band {k}: {white} of {span} px white");
        }
    }

    /// All failures shared one colour: now each reason has its own, and a
    /// case failing for two shows both.
    #[test]
    fn each_reason_has_its_own_colour_and_two_reasons_show_both() {
        let chart = chart();
        let (rgb, (w, _)) = png_rgb(&chart.to_png().expect("png"));
        let pixel = |x: i32, y: i32| {
            let i = 3 * (y as usize * w as usize + x as usize);
            RGBColor(rgb[i], rgb[i + 1], rgb[i + 2])
        };
        let (layout, top) = band(0, 2);
        // Row 1, columns 0–6 of the first band: pass, overlap, empty, KS,
        // empty + KS, refused, timed out.
        let at = |column: usize, share: f64| {
            let [(x0, y0), (x1, y1)] = layout.cell(1, column / WIDTHS.len(), column % WIDTHS.len());
            pixel(x0 + ((x1 - x0) as f64 * share) as i32, top + (y0 + y1) / 2)
        };
        let singles: Vec<RGBColor> = [0, 1, 2, 3, 5, 6].map(|c| at(c, 0.5)).to_vec();
        assert_eq!(
            singles,
            [
                PASS,
                reason_colour(Reason::Overlap),
                reason_colour(Reason::Empty),
                reason_colour(Reason::Grading),
                REFUSED,
                TIMED_OUT
            ]
        );
        for (i, a) in singles.iter().enumerate() {
            assert!(singles[i + 1..].iter().all(|b| b != a), "{singles:?}");
        }
        assert_eq!(at(4, 0.25), reason_colour(Reason::Empty));
        assert_eq!(at(4, 0.75), reason_colour(Reason::Grading));
        let svg = chart.to_svg().expect("svg");
        for label in [
            "fail: overlap",
            "fail: empty",
            "fail: KS",
            "two (or three) colours",
        ] {
            assert!(svg.contains(label), "the legend names {label}");
        }
    }

    #[test]
    fn several_seeds_stack_a_line_per_seed_in_each_cell() {
        // The chart's runs again under a second seed, every one failing
        // by overlap: the top half of each cell is seed 1's, the bottom seed 2's.
        let mut chart = chart();
        let again: Vec<StabilityRun> = chart
            .runs
            .iter()
            .map(|r| StabilityRun {
                seed: 2,
                status: Status::Finished,
                max_overlap: 0.5,
                psd_ks: 0.0,
                empty: 0.0,
                ..*r
            })
            .collect();
        chart.runs.extend(again);
        let (rgb, (w, _)) = png_rgb(&chart.to_png().expect("png"));
        let pixel = |x: i32, y: i32| {
            let i = 3 * (y as usize * w as usize + x as usize);
            RGBColor(rgb[i], rgb[i + 1], rgb[i + 2])
        };
        let (layout, top) = band(0, 2);
        let [(x0, y0), (x1, y1)] = layout.cell(1, 0, 0);
        let x = (x0 + x1) / 2;
        assert_eq!(pixel(x, top + y0 + (y1 - y0) / 4), PASS);
        assert_eq!(
            pixel(x, top + y0 + 3 * (y1 - y0) / 4),
            reason_colour(Reason::Overlap)
        );
        assert!(
            chart
                .to_svg()
                .unwrap()
                .contains("each cell a line per seed, 1 to 2 from the top")
        );
    }
}
