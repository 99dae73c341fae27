//! The grading chart: cumulative percent passing against diameter, the
//! target curve and the packed disks' own, with the KS distance between them.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{Axis, Pad};
use super::chart::{Drawable, Entry, FAMILY, LEGEND_TOP, Mark, beside, draw_legend, tidy};
use crate::Scene;
use crate::grading::{Basis, Grading};
use crate::layering::Material;
use crate::metrics::{Blend, curve_diameters, psd_ks_blend, psd_ks_by_curve};
use crate::output::palette::colour;
use crate::packer::Packing;

/// File name of the grading chart.
pub const PSD_SVG: &str = "psd.svg";
/// File name of the grading chart as an image.
pub const PSD_PNG: &str = "psd.png";

/// Points on which the target curve is evaluated (a step shows as a
/// vertical line: one interval is under a pixel wide).
const CURVE_POINTS: usize = 1000;
/// Most steps drawn of the packed curve; with more distinct diameters it is
/// evaluated on this many points instead.
const MAX_STEPS: usize = 2000;
/// Diameter ratio above which the diameter axis is logarithmic.
const LOG_RATIO: f64 = 3.0;

/// The grading chart of a packing: cumulative % passing (0–100) against
/// diameter (mm; logarithmic when d_max/d_min > 3), in the grading's basis.
///
/// Built by [`psd_chart`]; drawn with [`Drawable::to_svg`] and [`Drawable::to_png`].
#[derive(Debug, Clone, PartialEq)]
pub struct PsdChart {
    /// The target curve as (diameter, % passing); empty without a grading.
    target: Vec<(f64, f64)>,
    /// The packed disks' step curve as (diameter, % passing).
    packed: Vec<(f64, f64)>,
    /// Number of packed disks.
    disks: usize,
    /// KS distance of the packed diameters to the target, when both exist.
    ks: Option<f64>,
    /// What percent passing counts.
    basis: Basis,
    /// The diameter axis (mm), logarithmic when the sizes span more than
    /// [`LOG_RATIO`] and not too many decades.
    x: Axis,
    /// Size-graded: each material against its own curve (then `target` is
    /// the blend of the curves and `ks` the distance to it).
    parts: Vec<Part>,
}

/// One material of a size-graded packing: its own curve and its own disks.
#[derive(Debug, Clone, PartialEq)]
struct Part {
    /// The material's name.
    name: String,
    /// Its grading curve as (diameter, % passing).
    target: Vec<(f64, f64)>,
    /// Its disks' step curve as (diameter, % passing).
    packed: Vec<(f64, f64)>,
    /// Its disks.
    disks: usize,
    /// KS distance of its disks to its curve ([`psd_ks_by_curve`]).
    ks: f64,
}

/// The grading chart of `packing` against `grading`, or of the packing
/// alone without one (a packing read back from a CSV).
///
/// # Behavior
/// The target is `grading`'s CDF evaluated on 1000 points; the packed curve
/// steps at each distinct packed diameter, each disk weighted as the
/// grading's basis says (number: 1, area: d², mass: d³; by number without a
/// grading), exactly as [`Grading::ks_distance`] counts, and that distance
/// is shown in the title. Above 2000 distinct diameters the packed curve is
/// evaluated on 2000 points spread over its range instead, which moves a
/// step by less than a pixel. A size-graded packing is drawn against its
/// own curves by `psd_chart_of_scene`.
pub fn psd_chart(packing: &Packing, grading: Option<&Grading>) -> PsdChart {
    let diameters = sorted_diameters(packing.disks.iter().map(|d| 2.0 * d.r));
    let basis = grading.map_or(Basis::Number, Grading::basis);
    let limits: Vec<f64> = grading
        .iter()
        .flat_map(|g| [g.d_min(), g.d_max()])
        .collect();
    let x = diameter_axis(&diameters, &limits);
    PsdChart {
        target: grading.map_or_else(Vec::new, |g| curve(|d| g.cdf(d), &[g], &x)),
        packed: staircase(&diameters, basis.exponent(), x.ends(), x.is_log()),
        disks: packing.disks.len(),
        ks: grading
            .filter(|_| !diameters.is_empty())
            .map(|g| g.ks_distance(&diameters)),
        basis,
        x,
        parts: Vec::new(),
    }
}

/// The grading chart of a packing of `scene`: as [`psd_chart`] against the
/// scene's grading, except for a size-graded scene, where each material
/// (named by `materials`) is drawn against its own curve and the whole
/// packing against their [`Blend`]; the KS distances shown are those
/// `summary.json` records ([`psd_ks_by_curve`], [`psd_ks_blend`]).
pub fn psd_chart_of_scene(packing: &Packing, scene: &Scene, materials: &[Material]) -> PsdChart {
    if scene.gradient.is_none() {
        return psd_chart(packing, Some(&scene.grading));
    }
    let diameters = sorted_diameters(packing.disks.iter().map(|d| 2.0 * d.r));
    let basis = scene.grading.basis();
    let limits: Vec<f64> = scene
        .curves()
        .flat_map(|g| [g.d_min(), g.d_max()])
        .collect();
    let x = diameter_axis(&diameters, &limits);
    let blend = Blend::of(packing, scene);
    let parts = scene
        .curves()
        .zip(psd_ks_by_curve(packing, scene))
        .enumerate()
        .map(|(m, (g, ks))| {
            let own = sorted_diameters(curve_diameters(packing, scene, m));
            Part {
                name: materials
                    .get(m)
                    .map_or_else(|| format!("material {}", m + 1), |x| x.name.clone()),
                target: curve(|d| g.cdf(d), &[g], &x),
                packed: staircase(&own, g.basis().exponent(), x.ends(), x.is_log()),
                disks: own.len(),
                ks,
            }
        })
        .collect();
    PsdChart {
        target: blend.as_ref().map_or_else(Vec::new, |b| {
            curve(|d| b.cdf(d), &scene.curves().collect::<Vec<_>>(), &x)
        }),
        packed: staircase(&diameters, basis.exponent(), x.ends(), x.is_log()),
        disks: packing.disks.len(),
        ks: psd_ks_blend(packing, scene),
        basis,
        x,
        parts,
    }
}

/// The finite positive diameters of `diameters`, sorted.
fn sorted_diameters(diameters: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut sorted: Vec<f64> = diameters
        .into_iter()
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    sorted.sort_unstable_by(f64::total_cmp);
    sorted
}

/// The diameter axis (mm) over the packed `sorted` diameters and the
/// curves' `limits`: logarithmic when they span more than [`LOG_RATIO`]
/// (or are none; [`Axis::log`] itself falls back to linear when they span
/// too many decades).
fn diameter_axis(sorted: &[f64], limits: &[f64]) -> Axis {
    let sizes = || {
        sorted
            .first()
            .into_iter()
            .chain(sorted.last())
            .chain(limits)
            .copied()
    };
    let (lo, hi) = sizes().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    if lo > hi || hi > LOG_RATIO * lo {
        Axis::log(
            sizes(),
            Pad {
                share: 0.04,
                least: 0.0,
            },
        )
    } else {
        Axis::linear(
            sizes(),
            Pad {
                share: 0.05,
                least: 0.02,
            },
        )
    }
}

/// A target curve (diameter, % passing) of `cdf` over axis `x`, with
/// the smallest and largest diameters of the `limits` curves as exact points.
fn curve(cdf: impl Fn(f64) -> f64, limits: &[&Grading], x: &Axis) -> Vec<(f64, f64)> {
    let (a, b) = x.ends();
    let mut xs = spaced(a, b, CURVE_POINTS, x.is_log());
    xs.extend(limits.iter().flat_map(|g| [g.d_min(), g.d_max()]));
    xs.sort_unstable_by(f64::total_cmp);
    xs.into_iter().map(|d| (d, 100.0 * cdf(d))).collect()
}

/// `n + 1` points from `a` to `b` (both exact), evenly in ln d or in d.
fn spaced(a: f64, b: f64, n: usize, log: bool) -> Vec<f64> {
    let mut points: Vec<f64> = (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            if log {
                a * (b / a).powf(t)
            } else {
                a + t * (b - a)
            }
        })
        .collect();
    if let Some(last) = points.last_mut() {
        *last = b;
    }
    points
}

/// The step curve (diameter, % passing) of `sorted` diameters, each weighing
/// d^k, from the axis' left end at 0 % to its right end at 100 %.
fn staircase(sorted: &[f64], k: i32, (x0, x1): (f64, f64), log_x: bool) -> Vec<(f64, f64)> {
    let Some(&largest) = sorted.last() else {
        return Vec::new();
    };
    // Relative to the largest diameter: no overflow, the largest weighs 1.
    let weight = |d: f64| if k == 0 { 1.0 } else { (d / largest).powi(k) };
    let total: f64 = sorted.iter().map(|&d| weight(d)).sum();
    let mut knots = Vec::new();
    let mut through = 0.0;
    for group in sorted.chunk_by(|a, b| a == b) {
        through += group.iter().map(|&d| weight(d)).sum::<f64>();
        knots.push((group[0], through / total));
    }
    if let Some(last) = knots.last_mut() {
        last.1 = 1.0;
    }
    if knots.len() > MAX_STEPS {
        let (first, last) = (sorted[0], largest);
        let mut j = 0;
        knots = spaced(first, last, MAX_STEPS, log_x)
            .into_iter()
            .map(|d| {
                while j < knots.len() && knots[j].0 <= d {
                    j += 1;
                }
                (d, j.checked_sub(1).map_or(0.0, |i| knots[i].1))
            })
            .collect();
    }
    let mut points = Vec::with_capacity(2 * knots.len() + 2);
    points.push((x0, 0.0));
    let mut before = 0.0;
    for (d, fraction) in knots {
        points.push((d, 100.0 * before));
        points.push((d, 100.0 * fraction));
        before = fraction;
    }
    points.push((x1, 100.0 * before));
    points
}

impl PsdChart {
    fn title(&self) -> String {
        let by = match self.basis {
            Basis::Number => "number",
            Basis::Mass => "area",
            Basis::Mass3d => "mass",
        };
        if !self.parts.is_empty() {
            let worst = self.parts.iter().map(|p| p.ks).fold(0.0, f64::max);
            return format!("Grading by {by}, per material: KS = {worst:.4}");
        }
        match (self.target.is_empty(), self.ks) {
            (false, Some(ks)) => format!("Grading by {by}: target and packed, KS = {ks:.4}"),
            (false, None) => format!("Grading by {by}: target (no disk packed)"),
            (true, _) => format!("Grading of the packing by {by}"),
        }
    }

    fn y_label(&self) -> &'static str {
        match self.basis {
            Basis::Number => "% passing by number",
            Basis::Mass => "% passing by area (d²)",
            Basis::Mass3d => "% passing by mass (d³)",
        }
    }
}

impl PsdChart {
    /// Every curve drawn, legend text first: the target (or the blend) in
    /// black, the packing, then each material's curve (dashed) and disks.
    fn curves(&self) -> Vec<(Entry, &[(f64, f64)])> {
        let entry = |text: String, colour: RGBColor, mark: Mark| Entry { text, colour, mark };
        let disks = |n: usize| format!("{n} disk{}", if n == 1 { "" } else { "s" });
        let graded = !self.parts.is_empty();
        let mut curves = Vec::new();
        if !self.target.is_empty() {
            let text = if graded {
                "blend of the curves"
            } else {
                "target grading"
            };
            curves.push((entry(text.to_owned(), BLACK, Mark::Line), &self.target[..]));
        }
        if !self.packed.is_empty() {
            let (text, colour) = match (graded, self.ks) {
                (true, Some(ks)) => (
                    format!("packed, {}, KS {ks:.4}", disks(self.disks)),
                    RGBColor(120, 120, 120),
                ),
                (true, None) => (
                    format!("packed, {}", disks(self.disks)),
                    RGBColor(120, 120, 120),
                ),
                (false, _) => {
                    let [r, g, b] = colour(0);
                    (format!("packed, {}", disks(self.disks)), RGBColor(r, g, b))
                }
            };
            curves.push((entry(text, colour, Mark::Line), &self.packed[..]));
        }
        for (m, part) in self.parts.iter().enumerate() {
            let [r, g, b] = colour(m);
            let c = RGBColor(r, g, b);
            curves.push((
                entry(format!("{} curve", part.name), c, Mark::Dashed),
                &part.target[..],
            ));
            if !part.packed.is_empty() {
                let text = format!(
                    "{} packed, {}, KS {:.4}",
                    part.name,
                    disks(part.disks),
                    part.ks
                );
                curves.push((entry(text, c, Mark::Line), &part.packed[..]));
            }
        }
        curves
    }
}

impl Drawable for PsdChart {
    const SIZE: (u32, u32) = (900, 560);

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let curves = self.curves();
        let entries: Vec<Entry> = curves.iter().map(|(e, _)| e.clone()).collect();
        // The legend in a strip beside the plot: it covers no curve.
        let (plot, legend) = beside(&root, &entries);
        let mut builder = ChartBuilder::on(&plot);
        builder
            .caption(self.title(), (FAMILY, 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(70);
        let mut chart = builder.build_cartesian_2d(self.x, Axis::exact(0.0, 100.0))?;
        chart
            .configure_mesh()
            .x_desc(if self.x.is_log() {
                "diameter (mm, log scale)"
            } else {
                "diameter (mm)"
            })
            .y_desc(self.y_label())
            .x_label_formatter(&tidy)
            .y_label_formatter(&tidy)
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 16))
            .draw()?;
        for (e, points) in &curves {
            let style = e.colour.stroke_width(2);
            let points = points.iter().copied();
            match e.mark {
                Mark::Dashed => chart.draw_series(DashedLineSeries::new(points, 8, 5, style))?,
                _ => chart.draw_series(LineSeries::new(points, style))?,
            };
        }
        draw_legend(&legend, &entries, 1, LEGEND_TOP)?;
        root.present()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};
    use crate::grading::Interpolation;
    use crate::output::plot::testing::{png_size, svg_size, svg_texts};

    fn packing(diameters: &[f64]) -> Packing {
        Packing::of_disks(
            Domain::rectangle(100.0, 100.0).expect("rectangle"),
            diameters
                .iter()
                .enumerate()
                .map(|(i, &d)| Disk::new(10.0 * i as f64 + 5.0, 5.0, d / 2.0))
                .collect(),
        )
    }

    #[test]
    fn steps_weigh_disks_in_the_grading_s_basis() {
        let p = packing(&[1.0, 2.0, 2.0]);
        // By number: a third at 1, all at 2.
        let g = Grading::uniform(1.0, 2.0, Basis::Number).expect("grading");
        let chart = psd_chart(&p, Some(&g));
        assert!(!chart.x.is_log());
        let (x0, x1) = chart.x.ends();
        assert!(x0 < 1.0 && x1 > 2.0);
        let third = 100.0 * (1.0 / 3.0);
        assert_eq!(
            chart.packed,
            [
                (x0, 0.0),
                (1.0, 0.0),
                (1.0, third),
                (2.0, third),
                (2.0, 100.0),
                (x1, 100.0)
            ]
        );
        assert_eq!(chart.ks, Some(g.ks_distance(&[1.0, 2.0, 2.0])));
        // By area: weights 1, 4, 4.
        let g = Grading::uniform(1.0, 2.0, Basis::Mass).expect("grading");
        let chart = psd_chart(&p, Some(&g));
        assert!(
            (chart.packed[2].1 - 100.0 / 9.0).abs() < 1e-12,
            "{:?}",
            chart.packed
        );
        assert!(chart.title().contains("by area") && chart.title().contains("KS = "));
        // The target runs 0 → 100 % over the axis.
        assert_eq!(chart.target.first().map(|p| p.1), Some(0.0));
        assert_eq!(chart.target.last().map(|p| p.1), Some(100.0));
    }

    #[test]
    fn many_sizes_are_binned_and_wide_gradings_are_log() {
        let diameters: Vec<f64> = (0..5000).map(|i| 1.0 + f64::from(i) * 1e-3).collect();
        let chart = psd_chart(&packing(&diameters), None);
        assert!(chart.x.is_log(), "1 to 6 mm is a ratio above 3");
        assert!(chart.target.is_empty() && chart.ks.is_none());
        assert_eq!(chart.packed.len(), 2 * (MAX_STEPS + 1) + 2);
        // Non-decreasing, ending at 100 %.
        assert!(
            chart
                .packed
                .windows(2)
                .all(|w| w[0].1 <= w[1].1 && w[0].0 <= w[1].0)
        );
        assert_eq!(chart.packed.last().map(|p| p.1), Some(100.0));
        assert!(chart.title().starts_with("Grading of the packing"));
    }

    /// Sizes 300 decades apart (or one subnormal size) made plotters' log
    /// axis allocate without end; now the axis is linear and the chart renders.
    #[test]
    fn sizes_too_many_decades_apart_get_a_linear_axis_and_render() {
        let g = Grading::uniform(1.0, 2.0, Basis::Number).expect("grading");
        for (diameters, grading) in [
            (vec![1e-323], Some(&g)),
            (vec![1e-300, 2.0], None),
            (vec![2e300], Some(&g)),
        ] {
            let chart = psd_chart(&packing(&diameters), grading);
            assert!(!chart.x.is_log(), "{diameters:?}");
            assert!(chart.to_svg().expect("svg").contains("diameter (mm)"));
            assert_eq!(png_size(&chart.to_png().expect("png")), PsdChart::SIZE);
        }
    }

    #[test]
    fn renders_svg_and_png_of_the_chart_s_size() {
        let g = Grading::from_table(
            &[(1.2, 0.0), (2.4, 10.0), (2.4, 90.0), (6.0, 100.0)],
            Interpolation::Log,
            Basis::Number,
        )
        .expect("grading");
        let p = packing(&[1.5, 2.4, 2.4, 2.4, 2.4, 5.0]);
        for chart in [
            psd_chart(&p, Some(&g)),
            psd_chart(&p, None),
            psd_chart(&packing(&[]), Some(&g)),
        ] {
            let svg = chart.to_svg().expect("svg");
            assert_eq!(svg_size(&svg), PsdChart::SIZE);
            assert!(svg.contains("diameter (mm"), "{svg}");
            assert_eq!(png_size(&chart.to_png().expect("png")), PsdChart::SIZE);
        }
        let svg = psd_chart(&p, Some(&g)).to_svg().expect("svg");
        assert!(
            svg.contains("target grading")
                && svg.contains("packed, 6 disks")
                && svg.contains("KS = ")
        );
    }

    /// The diameter axis' tick labels of `chart`'s SVG, left to right, with
    /// their extents (px).
    fn x_tick_labels(chart: &PsdChart) -> Vec<(f64, (f64, f64))> {
        let mut labels: Vec<_> = svg_texts(&chart.to_svg().expect("svg"))
            .into_iter()
            .filter(|t| t.anchor == "middle")
            .filter_map(|t| Some((t.text.parse::<f64>().ok()?, t.extent())))
            .collect();
        labels.sort_by(|a, b| a.1.0.total_cmp(&b.1.0));
        labels
    }

    /// A log diameter axis had no number at all over 1.2–4.8 mm and only
    /// "1" and "2" over 0.5–2 mm: now at least three 1-2-5 (or finer round)
    /// labels, none overlapping the next.
    #[test]
    fn log_diameter_axis_labels_are_present_and_do_not_collide() {
        for (lo, hi, expected) in [
            (1.2, 4.8, &[1.5, 2.0, 3.0, 4.0, 5.0][..]),
            (0.5, 2.0, &[0.5, 1.0, 2.0]),
            (0.1, 10.0, &[0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0]),
            (0.075, 38.0, &[0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0]),
            (0.01, 100.0, &[0.01, 0.1, 1.0, 10.0, 100.0]),
        ] {
            let g = Grading::uniform(lo, hi, Basis::Number).expect("grading");
            let chart = psd_chart(&packing(&[lo, hi]), Some(&g));
            assert!(chart.x.is_log());
            let labels = x_tick_labels(&chart);
            let values: Vec<f64> = labels.iter().map(|l| l.0).collect();
            assert_eq!(values, expected, "{lo}–{hi} mm");
            for pair in labels.windows(2) {
                let ((a, (_, a_end)), (b, (b_start, _))) = (pair[0], pair[1]);
                assert!(a_end + 4.0 <= b_start, "{lo}–{hi} mm: {a} and {b} collide");
            }
        }
    }
}
