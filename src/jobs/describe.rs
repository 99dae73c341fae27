//! Plans and outcomes in words, the same for every front end: what
//! `gapack validate` prints, the CLI's result lines, the service's log.

use super::plan::{Job, Plan};
use super::run::{Outcome, Report};
use super::sweep::Study;
use crate::check::{grading_kept, ks_limit};
use crate::compare::Variant;
use crate::config::ConfigName;
use crate::fracture::{Extent, MM_PER_M};
use crate::ga::{Layered, StopReason, Verdict};
use crate::metrics::Metrics;
use crate::packer::{PEAK_BYTES_PER_DISK, estimated_peak_bytes};
use crate::stability;
use crate::study::{Keep, Measure, Row, Status};
use crate::{Scene, Shape};

impl Plan {
    /// What the job will do, a line each: the job, the grading, the packer,
    /// each scene (each well with its own fill), memory, the outputs going
    /// to `location`.
    pub fn describe(&self, location: &str) -> Vec<String> {
        let config = &self.config;
        let scene = &config.scene;
        let mut lines = Vec::new();
        let job = match &self.job {
            Job::Pack => "job: pack".to_owned(),
            Job::Wells { batch } => {
                let n = config.fracture.as_ref().map_or(0, |f| f.wells.len());
                format!(
                    "job: pack: {n} fracture{}{}, {}",
                    if n == 1 { "" } else { "s" },
                    if *batch {
                        " (a folder each, and wells.csv)"
                    } else {
                        ""
                    },
                    match self.extent() {
                        Some(Extent::Window { tolerance }) =>
                            format!("representative windows (porosity tolerance {tolerance})"),
                        _ => "packed whole".to_owned(),
                    }
                )
            }
            Job::Optimise {
                settings: o,
                resume,
                ..
            } => format!(
                "job: optimise{}: target porosity {} ± {}, population {}, at most {} generations{}, {} s",
                if *resume {
                    " (resumed from the checkpoint)"
                } else {
                    ""
                },
                o.target_porosity,
                o.tolerance,
                o.population,
                o.generations,
                o.max_evaluations
                    .map(|n| format!(" or {n} evaluations"))
                    .unwrap_or_default(),
                o.time_limit_s
            ),
            Job::Layer { .. } => "job: layer: pack once, then lay the materials out".to_owned(),
            Job::Compare { .. } => format!(
                "job: compare: {} method variants × {} seeds",
                crate::compare::Variant::expand(&config.compare.methods).len(),
                config.compare.repeats
            ),
            Job::Stability { time_cap } => format!(
                "job: stability: {} cases × {} method variants, each capped at {} s",
                stability::Case::all().len(),
                stability::variants(&config.compare.methods).len(),
                time_cap.as_secs_f64()
            ),
            Job::Sweep { study } => study_line(study),
        };
        lines.push(job);
        if let Job::Sweep { study } = &self.job {
            lines.extend(point_lines(study));
        }
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
        if let (Job::Wells { batch: true }, Some(run)) = (&self.job, &config.fracture) {
            // The wells of a batch are packed a few at a time, one per thread.
            let at_once = rayon::current_num_threads().min(run.wells.len());
            let mut peaks: Vec<f64> = run
                .wells
                .iter()
                .map(|w| estimated_peak_bytes(&w.scene))
                .collect();
            peaks.sort_by(|a, b| b.total_cmp(a));
            lines.push(format!(
                "batch memory: about {} ({at_once} wells at once, one per thread)",
                memory(peaks.iter().take(at_once).sum())
            ));
        }
        if let Job::Optimise { settings: o, .. } = &self.job {
            lines.push(format!(
                "search memory: about {} ({} genomes)",
                memory(o.peak_bytes(scene)),
                o.population
            ));
        }
        let formats: Vec<&str> = match &self.job {
            Job::Compare { .. } => vec!["compare.csv, .svg, .png"],
            Job::Stability { .. } => vec!["stability.csv, .svg, .png"],
            Job::Sweep { study } => vec![match study.settings.keep {
                Keep::None => "sweep.csv, .svg, .png",
                Keep::Summary => "sweep.csv, .svg, .png, and runs/<run>/summary.json",
                Keep::All => "sweep.csv, .svg, .png, and every file of each run in runs/<run>/",
            }],
            _ => config
                .output
                .formats
                .iter()
                .map(|f| f.config_name())
                .collect(),
        };
        let always = match self.job {
            Job::Sweep { .. } => "manifest.json",
            _ => "summary.json and manifest.json",
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
        let mut lines = Vec::new();
        match &self.report {
            Report::Pack {
                metrics, seconds, ..
            } => lines.push(pack_line(at, metrics, *seconds)),
            Report::Wells {
                wells,
                batch,
                total,
            } => {
                for w in wells {
                    let dir = format!("{at}/{}", w.folder.trim_end_matches('/'));
                    let dir = dir.trim_end_matches('/');
                    lines.push(match &w.window {
                        Some((steps, settled)) if !steps.is_empty() => {
                            let last = &steps[steps.len() - 1];
                            format!(
                                "{dir}: window {:.1} mm of {:.0} mm ({:.1}%), porosity {:.4} ± {:.4}, coordination {:.2}, {} disks, {} windows in {}{}{}",
                                last.length,
                                w.length,
                                100.0 * last.length / w.length,
                                last.porosity,
                                last.spread,
                                last.coordination,
                                last.particles,
                                steps.len(),
                                duration(w.row.seconds),
                                if *settled {
                                    ""
                                } else {
                                    " (not settled: the whole fracture was packed)"
                                },
                                grading_note(&w.metrics)
                            )
                        }
                        _ => pack_line(dir, &w.metrics, w.row.seconds),
                    });
                }
                if *batch {
                    lines.push(format!(
                        "{at}/wells.csv: {} wells in {}{}",
                        wells.len(),
                        duration(wells.iter().map(|w| w.row.seconds).sum()),
                        if wells.len() < *total {
                            format!(" (interrupted: {} of {total} wells)", wells.len())
                        } else {
                            String::new()
                        }
                    ));
                }
            }
            Report::Optimise {
                metrics,
                summary,
                layered,
                ..
            } => {
                let layering = layered
                    .as_ref()
                    .map_or(String::new(), |l| format!("; {}", layering_line(l)));
                // The stop says `target reached` or `interrupted`; otherwise the verdict.
                let said = [Verdict::Reached, Verdict::Interrupted].map(Verdict::describe);
                let verdict = if said.contains(&summary.verdict) {
                    String::new()
                } else if summary.achievable_range.is_none() {
                    format!(
                        "; target {}, no packing honoured the grading (max_psd_ks {})",
                        summary.verdict, summary.max_psd_ks
                    )
                } else {
                    format!("; target {}", summary.verdict)
                };
                let window = summary.window.as_ref().map_or(String::new(), |w| {
                    format!(
                        "; searched on a {:.0} × {:.0} mm window ({:.1}% of the domain{}), the whole packed {}",
                        w.size[0],
                        w.size[1],
                        100.0 * w.share,
                        if w.settled { "" } else { ", not settled" },
                        match w.whole_packs {
                            1 => "once".to_owned(),
                            n => format!("{n} times"),
                        }
                    )
                });
                lines.push(format!(
                    "{at}: porosity {:.4} (target {}, error {:.4}), psd_ks {:.3}, {} disks, {} evaluations in {} generations, {} ({}{verdict}{window}){layering}{}",
                    metrics.porosity,
                    summary.target_porosity,
                    summary.error,
                    metrics.psd_ks,
                    metrics.particles,
                    summary.evaluations,
                    summary.generations,
                    duration(self.seconds()),
                    summary.stop,
                    grading_note(metrics),
                ));
                if !summary.reproducible && !summary.interrupted {
                    lines.push(TIME_LIMIT_NOTE.to_owned());
                }
            }
            Report::Layer {
                metrics, layered, ..
            } => {
                lines.push(format!(
                    "{at}: {} disks, porosity {:.4}, {}{}",
                    metrics.particles,
                    metrics.porosity,
                    layering_line(layered),
                    grading_note(metrics)
                ));
                if layered.stop == Some(StopReason::TimeLimit) {
                    lines.push(TIME_LIMIT_NOTE.to_owned());
                }
            }
            Report::Compare {
                runs,
                variants,
                total,
            } => {
                for (variant, mine) in by_variant(runs, variants, |r| &r.variant) {
                    let n = mine.len() as f64;
                    let mean = |f: &dyn Fn(&crate::compare::CompareRun) -> f64| {
                        mine.iter().map(|r| f(r)).sum::<f64>() / n
                    };
                    let worst_overlap = mine.iter().map(|r| r.max_overlap).fold(0.0, f64::max);
                    lines.push(format!(
                        "{:<40} {} runs: {} disks, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, {} each",
                        crate::output::variant_label(variant),
                        mine.len(),
                        mean(&|r| r.particles as f64).round(),
                        mean(&|r| r.porosity),
                        mean(&|r| r.psd_ks),
                        overlap(worst_overlap),
                        mean(&|r| r.coordination),
                        duration(mean(&|r| r.seconds)),
                    ));
                }
                lines.push(format!(
                    "{at}: compare.csv, compare.svg, compare.png{}",
                    interrupted_runs(runs.len(), *total)
                ));
            }
            Report::Stability {
                runs,
                variants,
                total,
            } => {
                for (variant, mine) in by_variant(runs, variants, |r| &r.variant) {
                    let tally = stability::Tally::of(mine.iter().copied());
                    lines.push(format!(
                        "{:<40} pass {:>3}, fail {:>3} ({}), refused {:>3}, timed out {:>3}",
                        crate::output::variant_label(variant),
                        tally.pass,
                        tally.fail,
                        fail_reasons(&tally),
                        tally.refused,
                        tally.timed_out,
                    ));
                    lines.extend(seed_spread(&mine));
                }
                lines.push(format!(
                    "{at}: stability.csv, stability.svg, stability.png{}",
                    interrupted_runs(runs.len(), *total)
                ));
            }
            Report::Sweep {
                rows,
                seeds,
                resumed,
                ..
            } => {
                lines.extend(study_result(rows, *seeds));
                let count = |f: fn(&Status) -> bool| rows.iter().filter(|r| f(&r.status)).count();
                let finished = count(|s| matches!(s, Status::Finished(_)));
                let failed = count(|s| matches!(s, Status::Failed(_)));
                let done = finished + failed;
                lines.push(format!(
                    "{at}: sweep.csv, sweep.svg, sweep.png: {} runs, {finished} finished, {failed} failed{}{}",
                    rows.len(),
                    if *resumed > 0 {
                        format!(" ({resumed} kept from the earlier sweep.csv)")
                    } else {
                        String::new()
                    },
                    interrupted_runs(done, rows.len())
                ));
            }
        }
        for note in &self.notes {
            lines.push(format!("  {at}/{note}"));
        }
        lines
    }

    /// Wall-clock time of the job's main work (s): the packing, or the whole search.
    pub fn seconds(&self) -> f64 {
        match &self.report {
            Report::Pack { seconds, .. } | Report::Layer { seconds, .. } => *seconds,
            Report::Optimise { seconds, .. } => *seconds,
            Report::Wells { wells, .. } => wells.iter().map(|w| w.row.seconds).sum(),
            Report::Compare { runs, .. } => runs.iter().map(|r| r.seconds).sum(),
            Report::Stability { runs, .. } => runs.iter().map(|r| r.seconds).sum(),
            Report::Sweep { rows, .. } => rows
                .iter()
                .map(|r| match &r.status {
                    Status::Finished(m) => m.seconds,
                    _ => 0.0,
                })
                .sum(),
        }
    }
}

/// Points of a study listed by `gapack validate`, before `and N more`.
const LISTED_POINTS: usize = 40;

/// `job: sweep: 3 values of fracture.width_mm × 2 of grading.preset × 5 seeds = 30 pack runs, porosity charted`.
fn study_line(study: &Study) -> String {
    let s = &study.settings;
    let keys: Vec<String> = s
        .keys
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let n = k.values.len();
            if i == 0 {
                format!("{n} value{} of {}", plural(n), k.path)
            } else {
                format!("{n} of {}", k.path)
            }
        })
        .collect();
    format!(
        "job: sweep{}: {} × {} seed{} = {} {} runs, {} charted against {}",
        if study.resume {
            " (resumed: the finished rows of sweep.csv are kept)"
        } else {
            ""
        },
        keys.join(" × "),
        s.seeds,
        plural(s.seeds),
        study.runs.len(),
        study.kind.name(),
        s.measure.config_name(),
        s.keys.first().map_or("", |k| k.path.as_str()),
    )
}

/// One line per point of a study: its disks (estimated, per run), or why it cannot run.
fn point_lines(study: &Study) -> Vec<String> {
    let mut lines: Vec<String> = study
        .points
        .iter()
        .take(LISTED_POINTS)
        .map(|point| {
            let name = &point.name;
            match &point.config {
                Ok(config) => {
                    let (disks, window) = match &config.fracture {
                        Some(f) => (
                            f.wells
                                .iter()
                                .map(|w| w.scene.estimated_disks())
                                .sum::<f64>(),
                            matches!(f.extent, Extent::Window { .. }),
                        ),
                        None => (config.scene.estimated_disks(), false),
                    };
                    format!(
                        "point {name}: about {disks:.0} disks a run{}",
                        if window {
                            " if packed whole (a window packs fewer)"
                        } else {
                            ""
                        }
                    )
                }
                Err(why) => format!("point {name}: its runs fail: {why}"),
            }
        })
        .collect();
    let points = study.points.len();
    if points > LISTED_POINTS {
        lines.push(format!("… and {} more points", points - LISTED_POINTS));
    }
    lines
}

/// One line per point of a study's rows: its measures over the seeds
/// that finished (porosity with its range), or why its runs failed.
fn study_result(rows: &[Row], seeds: usize) -> Vec<String> {
    let spreads = crate::study::spreads(rows, seeds, Measure::Porosity);
    rows.chunks(seeds.max(1))
        .zip(spreads)
        .filter_map(|(point, porosity)| {
            let first = point.first()?;
            let name = first
                .run
                .rsplit_once(",seed=")
                .map_or(first.run.as_str(), |(p, _)| p);
            let done: Vec<&crate::study::Measures> = point
                .iter()
                .filter_map(|r| match &r.status {
                    Status::Finished(m) => Some(m),
                    _ => None,
                })
                .collect();
            let Some(p) = porosity else {
                let failed = point.iter().find_map(|r| match &r.status {
                    Status::Failed(why) => Some(why.as_str()),
                    _ => None,
                });
                return failed.map(|why| format!("{name:<40} failed: {why}"));
            };
            let n = done.len() as f64;
            let mean = |f: fn(&crate::study::Measures) -> f64| done.iter().map(|m| f(m)).sum::<f64>() / n;
            let errors: Vec<f64> = done.iter().filter_map(|m| m.target_error).collect();
            Some(format!(
                "{name:<40} porosity {:.4} ({:.4}–{:.4}), {:.0} disks, psd_ks {:.3}, coordination {:.2}{}, {} of {} runs, {} each",
                p.mean,
                p.min,
                p.max,
                mean(|m| m.particles as f64),
                mean(|m| m.psd_ks),
                mean(|m| m.coordination),
                if errors.is_empty() {
                    String::new()
                } else {
                    format!(
                        ", target error {:.4}",
                        errors.iter().sum::<f64>() / errors.len() as f64
                    )
                },
                done.len(),
                point.len(),
                duration(mean(|m| m.seconds)),
            ))
        })
        .collect()
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// The failing runs of `tally`, each counted once: `overlap 0, empty 2, KS 43, empty + KS 1`
/// (every single reason, then each pair or triple that occurs).
fn fail_reasons(tally: &stability::Tally) -> String {
    let single = stability::Reason::ALL.map(|reason| {
        let n = tally
            .by_reasons
            .iter()
            .find(|(r, _)| r[..] == [reason])
            .map_or(0, |(_, n)| *n);
        format!("{} {n}", reason.name())
    });
    let several = tally
        .by_reasons
        .iter()
        .filter(|(r, _)| r.len() > 1)
        .map(|(r, n)| {
            let names: Vec<&str> = r.iter().map(|x| x.name()).collect();
            format!("{} {n}", names.join(" + "))
        });
    single
        .into_iter()
        .chain(several)
        .collect::<Vec<_>>()
        .join(", ")
}

/// ` (interrupted: 12 of 144 runs)` when cut short.
fn interrupted_runs(done: usize, total: usize) -> String {
    if done < total {
        format!(" (interrupted: {done} of {total} runs)")
    } else {
        String::new()
    }
}

/// `out/x: 345 disks, porosity 0.2139, psd_ks 0.061, max overlap 0, coordination 3.69, packed in 0.3 ms`.
fn pack_line(at: &str, metrics: &Metrics, seconds: f64) -> String {
    format!(
        "{at}: {} disks, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, packed in {}{}",
        metrics.particles,
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
fn grading_note(metrics: &Metrics) -> String {
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
const TIME_LIMIT_NOTE: &str = "  stopped by the time limit: another machine or load stops elsewhere, so this result is not reproducible; max_evaluations stops at the same place everywhere";

/// `profile RMS 0.0123 (baseline 0.0187), GA 1.20 s, baseline 2.1 ms`.
fn layering_line(l: &Layered) -> String {
    if l.stop.is_none() {
        format!("profile RMS {:.4} (size-graded)", l.rms)
    } else {
        format!(
            "profile RMS {:.4} (baseline {:.4}), GA {} ({} evaluations), baseline {}",
            l.rms,
            l.baseline_rms,
            duration(l.seconds),
            l.evaluations,
            duration(l.baseline_seconds)
        )
    }
}

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
    format!(
        "{shape}, area {} mm², walls {}: about {:.0} disks (at most {:.0}), peak memory about {}",
        tidy(domain.area()),
        scene.walls.config_name(),
        scene.estimated_disks(),
        bytes / PEAK_BYTES_PER_DISK,
        memory(bytes)
    )
}

/// `12 kB`, `1.6 MB`, `2.3 GB` (powers of 1024).
fn memory(bytes: f64) -> String {
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
fn overlap(v: f64) -> String {
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
fn by_variant<'r, R>(
    runs: &'r [R],
    variants: &'r [Variant],
    variant_of: impl Fn(&R) -> &Variant,
) -> impl Iterator<Item = (&'r Variant, Vec<&'r R>)> {
    variants.iter().filter_map(move |variant| {
        let mine: Vec<&R> = runs.iter().filter(|r| variant_of(r) == variant).collect();
        (!mine.is_empty()).then_some((variant, mine))
    })
}

/// The pass rates of one method's stability runs over their seeds: per
/// seed (lowest–highest), and by domain width, each with its spread over
/// the seeds — the lines under the method's counts.
fn seed_spread(runs: &[&stability::StabilityRun]) -> Vec<String> {
    let mut seeds: Vec<u64> = runs.iter().map(|r| r.seed).collect();
    seeds.sort_unstable();
    seeds.dedup();
    // Passes and runs among `runs` that `keep` selects, per seed.
    let rates = |keep: &dyn Fn(&stability::StabilityRun) -> bool| -> Vec<(usize, usize)> {
        seeds
            .iter()
            .map(|&seed| {
                let mine = runs.iter().filter(|r| r.seed == seed && keep(r));
                mine.fold((0, 0), |(p, n), r| (p + usize::from(r.passed()), n + 1))
            })
            .collect()
    };
    let spread = |per_seed: &[(usize, usize)]| {
        let share = |(p, n): (usize, usize)| if n == 0 { 0.0 } else { p as f64 / n as f64 };
        let (lo, hi) = per_seed
            .iter()
            .map(|&c| share(c))
            .fold((1.0f64, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let (p, n) = per_seed
            .iter()
            .fold((0, 0), |(p, n), &(a, b)| (p + a, n + b));
        format!(
            "{:.0}% ({:.0}–{:.0}%)",
            100.0 * share((p, n)),
            100.0 * lo,
            100.0 * hi
        )
    };
    let all = rates(&|_| true);
    let per_seed = all.iter().map(|(p, _)| *p);
    let (lo, hi) = per_seed.fold((usize::MAX, 0), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let cases = all.first().map_or(0, |c| c.1);
    let mut widths: Vec<f64> = runs.iter().map(|r| r.case.width).collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup();
    let by_width: Vec<String> = widths
        .iter()
        .map(|&w| format!("{w} {}", spread(&rates(&|r| r.case.width == w))))
        .collect();
    vec![
        format!(
            "    {} seeds: pass {} of all runs, per seed {lo}–{hi} of {cases}",
            seeds.len(),
            spread(&all)
        ),
        format!("    by width (d_max): {}", by_width.join(", ")),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Disk, Domain};
    use crate::jobs::JobKind;
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
