//! The stability job: the `[compare]` methods swept over gradings, widths
//! and shapes; `stability.csv` and its map.

use std::time::Duration;

use super::describe::{Words, by_variant, interrupted_runs};
use super::error::JobError;
use super::event::{Event, Stage};
use super::plan::{Plan, Planning};
use super::registry::{Job, Report};
use super::run::Running;
use crate::cancel::Cancel;
use crate::compare::Variant;
use crate::output::{render_stability, variant_label};
use crate::stability::{self, StabilityRun};

/// The stability job's rules: it packs its own cases from the grading,
/// packer settings and seed; each run is capped in time.
pub(super) fn plan(p: &mut Planning<'_>) -> Result<Job, JobError> {
    if p.config.optimise.is_some() {
        p.ignore("optimise", "the sweep packs its own cases");
    }
    if p.lays_out() {
        p.ignore("layering", "the sweep packs its own cases");
    }
    if p.config.fracture.is_some() {
        p.ignore(
            "fracture",
            "the sweep takes the grading, packer settings and seed, and packs its own shapes",
        );
    }
    if p.request.time_cap.is_zero() {
        return Err(JobError::Input(
            "the time cap of a stability run must be a positive number of seconds".to_owned(),
        ));
    }
    Ok(Job::Stability {
        time_cap: p.request.time_cap,
    })
}

/// Run every case × variant × seed, shared out to the farm; write the table and map.
pub(super) fn run(
    job: &mut Running<'_>,
    cap: Duration,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let config = job.config();
    let variants = stability::variants(&config.compare.methods);
    let cases = stability::Case::all();
    // Each case over `compare.repeats` seeds from the config's, as compare does.
    let seeds: Vec<u64> = (0..config.compare.repeats as u64)
        .map(|k| config.scene.seed.wrapping_add(k))
        .collect();
    let total = cases.len() * variants.len() * seeds.len();
    job.event(Event::Stage {
        stage: Stage::Stability,
        total: Some(total as u64),
    });
    let observer = &mut *job.observer;
    let mut index = 0;
    let runs = stability::sweep(
        &config.scene,
        (&cases, &variants, &seeds),
        cap,
        cancel,
        job.farm,
        |r: &StabilityRun| {
            observer.event(&Event::Run {
                stage: Stage::Stability,
                index,
                label: format!(
                    "{} {} seed {}",
                    variant_label(&r.variant),
                    r.case.shape.name(),
                    r.seed
                ),
            });
            index += 1;
        },
    );
    let interrupted = runs.len() < total;
    if runs.is_empty() && interrupted {
        return Err(JobError::Cancelled);
    }
    let files = render_stability(&runs)?;
    job.write("", files);
    Ok((
        Report::Stability {
            runs,
            variants,
            total,
        },
        interrupted,
    ))
}

/// `job: stability: 48 cases × 9 method variants, each capped at 10 s`; its own files.
pub(super) fn words(plan: &Plan, time_cap: Duration) -> Words {
    let config = &plan.config;
    let mut words = Words::new(format!(
        "job: stability: {} cases × {} method variants, each capped at {} s",
        stability::Case::all().len(),
        stability::variants(&config.compare.methods).len(),
        time_cap.as_secs_f64()
    ));
    words.files = Some((
        "stability.csv, .svg, .png",
        "summary.json and manifest.json",
    ));
    words
}

/// A line per variant (its counts, its spread over the seeds), then the files.
pub(super) fn lines(
    at: &str,
    runs: &[StabilityRun],
    variants: &[Variant],
    total: usize,
) -> Vec<String> {
    let mut lines = Vec::new();
    for (variant, mine) in by_variant(runs, variants, |r| &r.variant) {
        let tally = stability::Tally::of(mine.iter().copied());
        lines.push(format!(
            "{:<40} pass {:>3}, fail {:>3} ({}), refused {:>3}, timed out {:>3}",
            variant_label(variant),
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
        interrupted_runs(runs.len(), total)
    ));
    lines
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
