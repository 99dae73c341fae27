//! Plans and outcomes in words, the same for every front end: what
//! `gapack validate` prints, the CLI's result lines, the service's log.
//! The words of each job are in its own file ([`Words`] for its plan, its
//! report's lines); here what they share.

use super::plan::Plan;
use super::run::{Outcome, Step};
use crate::check::{grading_kept, ks_limit};
use crate::compare::Variant;
use crate::config::ConfigName;
use crate::fracture::MM_PER_M;
use crate::metrics::Metrics;
use crate::packer::{estimated_peak_bytes, peak_bytes_per_particle};
use crate::{Scene, Shape};

/// What `gapack validate` says of a job besides its scene: its lines
/// (the job line first), its memory, and its files when not the
/// config's `[output]` formats.
pub(super) struct Words {
    /// The job line, and any under it (a study's points).
    pub head: Vec<String>,
    /// The job's memory, after the scene's.
    pub memory: Option<String>,
    /// The files it writes, and those it always writes; `None`: the
    /// config's formats, and `summary.json` and `manifest.json`.
    pub files: Option<(&'static str, &'static str)>,
}

impl Words {
    /// The job line alone.
    pub fn new(line: String) -> Words {
        Words {
            head: vec![line],
            memory: None,
            files: None,
        }
    }
}

impl Plan {
    /// What the job will do, a line each: the job, the grading, the packer,
    /// each scene (each well with its own fill), memory, the outputs going
    /// to `location`.
    pub fn describe(&self, location: &str) -> Vec<String> {
        let config = &self.config;
        let scene = &config.scene;
        let words = self.job.words(self);
        let mut lines = words.head;
        if let Some(l) = &config.layering {
            lines.push(format!(
                "layering: {} material(s), {} along {}, {} bins",
                config.materials.len(),
                l.mode.config_name(),
                l.axis.config_name(),
                l.bins
            ));
        }
        let g = &scene.grading;
        lines.push(format!(
            "grading: d {} to {} mm ({} basis, {} interpolation){}, seed {}",
            tidy(scene.d_min()),
            tidy(scene.d_max()),
            g.basis().config_name(),
            g.interpolation().config_name(),
            if scene.gradient.is_some() {
                ", size-graded"
            } else {
                ""
            },
            scene.seed
        ));
        lines.push(format!(
            "packer: {}, {} index, {} rules, fill {}",
            scene.packer.method.config_name(),
            scene.packer.index.config_name(),
            scene.packer.rules.config_name(),
            scene.packer.fill.config_name()
        ));
        match &config.fracture {
            Some(run) => {
                for well in &run.wells {
                    let f = well.fracture;
                    let taper = f
                        .tip_width
                        .map_or(String::new(), |t| format!(" tapering to {} mm", tidy(t)));
                    lines.push(format!(
                        "well {}: {} mm wide{taper}, {} m high, fill {}; {}",
                        well.name,
                        tidy(f.width),
                        tidy(f.length / MM_PER_M),
                        well.scene.packer.fill.config_name(),
                        scene_line(&well.scene)
                    ));
                }
            }
            None => lines.push(format!("domain: {}", scene_line(scene))),
        }
        lines.extend(words.memory);
        let (formats, always) = match words.files {
            Some((files, always)) => (vec![files], always),
            None => (
                config
                    .output
                    .formats
                    .iter()
                    .map(|f| f.config_name())
                    .collect(),
                "summary.json and manifest.json",
            ),
        };
        lines.push(format!(
            "output: {location} ({}; {always} always)",
            if formats.is_empty() {
                "no format".to_owned()
            } else {
                formats.join(", ")
            }
        ));
        for w in &self.warnings {
            lines.push(format!("warning: {}", w.message));
        }
        lines
    }
}

impl Outcome {
    /// The result in a line or a few: what was made, where, how well, how fast.
    pub fn lines(&self) -> Vec<String> {
        let at = &self.location;
        let mut lines = self.report.lines(at);
        for note in &self.notes {
            lines.push(format!("  {at}/{note}"));
        }
        lines
    }

    /// Wall-clock time of the job's main work (s): the packing, or the whole search.
    pub fn seconds(&self) -> f64 {
        self.report.seconds()
    }

    /// `timings: pack 3.31 s, measure 1.20 s, write 2.04 s; after packing
    /// 0.98 × the packing`: where the run's time went, step by step
    /// ([`Outcome::steps`]); `None` for a job that times no step.
    pub fn timings_line(&self) -> Option<String> {
        if self.steps.is_empty() {
            return None;
        }
        let each: Vec<String> = self
            .steps
            .iter()
            .map(|s| format!("{} {:.2} s", s.step.name(), s.seconds))
            .collect();
        let of = |step| {
            self.steps
                .iter()
                .filter(|s| s.step == step)
                .map(|s| s.seconds)
                .sum::<f64>()
        };
        let pack = of(Step::Pack);
        let after = of(Step::Measure) + of(Step::Write);
        let ratio = if pack > 0.0 {
            format!("; after packing {:.2} × the packing", after / pack)
        } else {
            String::new()
        };
        Some(format!("timings: {}{ratio}", each.join(", ")))
    }
}

/// ` (interrupted: 12 of 144 runs)` when cut short.
pub(super) fn interrupted_runs(done: usize, total: usize) -> String {
    if done < total {
        format!(" (interrupted: {done} of {total} runs)")
    } else {
        String::new()
    }
}

/// `out/x: 345 disks, porosity 0.2139, psd_ks 0.061, max overlap 0, coordination 3.69, packed in 0.3 ms`.
pub(super) fn pack_line(at: &str, metrics: &Metrics, seconds: f64) -> String {
    format!(
        "{at}: {} {}, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, packed in {}{}",
        metrics.particles,
        if metrics.shapes.is_some() {
            "particles"
        } else {
            "disks"
        },
        metrics.porosity,
        metrics.psd_ks,
        overlap(metrics.max_overlap),
        metrics.coordination,
        duration(seconds),
        grading_note(metrics),
    )
}

/// ` (grading bent: psd_ks 0.278 > 0.217)` when the packing's sizes lie
/// beyond the sampling noise `gapack verify` allows ([`grading_kept`]); empty otherwise.
pub(super) fn grading_note(metrics: &Metrics) -> String {
    if grading_kept(metrics.particles, metrics.psd_ks) {
        String::new()
    } else {
        format!(
            " (grading bent: psd_ks {:.3} > {:.3}, gapack verify rejects it)",
            metrics.psd_ks,
            ks_limit(metrics.particles)
        )
    }
}

/// The line under a result that a time limit stopped.
pub(super) const TIME_LIMIT_NOTE: &str = "  stopped by the time limit: another machine or load stops elsewhere, so this result is not reproducible; max_evaluations stops at the same place everywhere";

/// `rectangle 8.6 × 62.5 mm, area 537.5 mm², walls exact: about 340 disks (at most 430), peak memory about 41 kB`.
fn scene_line(scene: &Scene) -> String {
    let domain = &scene.domain;
    let shape = match domain.shape() {
        Shape::Rectangle { width, height } => {
            format!("rectangle {} × {} mm", tidy(*width), tidy(*height))
        }
        Shape::Polygon { vertices } => format!("polygon of {} vertices", vertices.len()),
        Shape::Circle { radius, .. } => format!("circle of radius {} mm", tidy(*radius)),
        Shape::Trapezoid {
            bottom,
            top,
            height,
        } => format!(
            "trapezoid {} / {} × {} mm",
            tidy(*bottom),
            tidy(*top),
            tidy(*height)
        ),
    };
    let bytes = estimated_peak_bytes(scene);
    let noun = if scene.shape.is_some() {
        "particles"
    } else {
        "disks"
    };
    format!(
        "{shape}, area {} mm², walls {}: about {:.0} {noun} (at most {:.0}), peak memory about {}",
        tidy(domain.area()),
        scene.walls.config_name(),
        scene.estimated_disks(),
        bytes / peak_bytes_per_particle(scene),
        memory(bytes)
    )
}

/// `12 kB`, `1.6 MB`, `2.3 GB` (powers of 1024).
pub(super) fn memory(bytes: f64) -> String {
    let kb = bytes / 1024.0;
    if kb < 1024.0 {
        format!("{kb:.0} kB")
    } else if kb < 1024.0 * 1024.0 {
        format!("{:.1} MB", kb / 1024.0)
    } else {
        format!("{:.1} GB", kb / (1024.0 * 1024.0))
    }
}

/// Four significant digits, no trailing zeros.
fn tidy(v: f64) -> String {
    let s = format!("{}", (v * 1e4).round() / 1e4);
    if v.abs() >= 1e4 || s.len() <= 8 {
        s
    } else {
        format!("{v:.4}")
    }
}

/// `0` for no overlap, else 2 significant digits.
pub(super) fn overlap(v: f64) -> String {
    if v == 0.0 {
        "0".to_owned()
    } else {
        format!("{v:.1e}")
    }
}

/// `0.4 ms`, `812.3 ms`, `3.21 s`.
pub fn duration(seconds: f64) -> String {
    if seconds < 1.0 {
        format!("{:.1} ms", seconds * 1e3)
    } else {
        format!("{seconds:.2} s")
    }
}

/// The runs of each variant, in the variants' order; variants without a
/// run (an interrupted comparison or sweep) are left out.
pub(super) fn by_variant<'r, R>(
    runs: &'r [R],
    variants: &'r [Variant],
    variant_of: impl Fn(&R) -> &Variant,
) -> impl Iterator<Item = (&'r Variant, Vec<&'r R>)> {
    variants.iter().filter_map(move |variant| {
        let mine: Vec<&R> = runs.iter().filter(|r| variant_of(r) == variant).collect();
        (!mine.is_empty()).then_some((variant, mine))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};
    use crate::jobs::{JobKind, Report};
    use crate::packer::Packing;

    /// A run whose `packing.svg` holds an image says so under its line.
    #[test]
    fn a_run_s_notes_follow_its_line() {
        let packing = Packing::of_disks(
            Domain::rectangle(10.0, 10.0).expect("square"),
            vec![Disk::new(2.0, 2.0, 1.0)],
        );
        let config = crate::config::parse(
            "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 2.0\n",
            "t.toml",
        )
        .expect("config");
        let metrics = crate::metrics::measure(&packing, &config.scene);
        let outcome = Outcome {
            kind: JobKind::Pack,
            location: "out/x".to_owned(),
            interrupted: false,
            files: Vec::new(),
            notes: vec!["packing.svg holds packing.png as an image: why".to_owned()],
            report: Report::Pack {
                packing,
                metrics,
                seconds: 0.1,
            },
            steps: Vec::new(),
        };
        let lines = outcome.lines();
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(lines[0].starts_with("out/x: 1 disks"), "{lines:?}");
        assert_eq!(
            lines[1],
            "  out/x/packing.svg holds packing.png as an image: why"
        );
    }
}
