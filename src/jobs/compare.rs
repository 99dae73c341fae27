//! The compare job: every generator of `[compare]` on the scene, each
//! variant over `compare.repeats` seeds; `compare.csv` and its chart.

use super::describe::{Words, by_variant, duration, interrupted_runs, overlap};
use super::error::JobError;
use super::event::{Event, Stage, Warning, WarningKind};
use super::plan::Planning;
use super::registry::{Job, Report};
use super::run::Running;
use crate::cancel::Cancel;
use crate::compare::{CompareRun, Variant, compare};
use crate::config::{ConfigError, Location, key_location};
use crate::fracture::{Extent, FIRST_DIAMETERS, FractureRun, MM_PER_M};
use crate::output::{render_compare, variant_label};

/// The compare job's rules: every generator packs the scene alone (no
/// layout); on a `[fracture]` config, the first well packed whole.
pub(super) fn plan(p: &mut Planning<'_>) -> Result<Job, JobError> {
    if p.lays_out() {
        p.ignore("layering", "every generator packs the scene alone");
    }
    if let Some(run) = &p.config.fracture {
        compare_fracture(run, p.text, p.origin, &mut p.more)?;
    }
    Ok(Job::Compare {
        target: p.config.optimise.map(|o| o.target_porosity),
    })
}

/// The compare job on a `[fracture]` config runs every generator on the
/// first well's scene, packed whole. A window (`fracture.extent =
/// "window"`) is refused at that key of the config's `text`, as a config
/// error: the user asked not to pack the whole fracture, and a comparison
/// of generators on it would pack it whole every run. A batch of full
/// wells is compared on its first well, with a warning naming
/// `fracture.wells`.
fn compare_fracture(
    run: &FractureRun,
    text: &str,
    origin: &str,
    warnings: &mut Vec<Warning>,
) -> Result<(), JobError> {
    let Some(first) = run.wells.first() else {
        return Ok(());
    };
    let others = run.wells.len() - 1;
    if let Extent::Window { .. } = run.extent {
        return Err(ConfigError::NotApplicable {
            at: key_location(text, origin, "fracture.extent")
                .unwrap_or_else(|| Location::at(origin, text, 0)),
            key: "fracture.extent".to_owned(),
            reason: format!(
                "the compare job packs one scene whole with every generator and grows no windows, so with fracture.extent = \"window\" it would pack all {} m of well \"{}\"{} instead of a window; set fracture.extent = \"full\" to compare on the whole fracture, or give a [domain] the size of a window (its first is {FIRST_DIAMETERS}·d_max = {} mm long) to compare on one",
                first.fracture.length / MM_PER_M,
                first.name,
                if others > 0 {
                    format!(" (and none of the other {others} of fracture.wells)")
                } else {
                    String::new()
                },
                FIRST_DIAMETERS * first.scene.d_max(),
            ),
        }
        .into());
    }
    if others > 0 {
        warnings.push(Warning {
            kind: WarningKind::IgnoredWells,
            message: format!(
                "{origin}: fracture.wells: the compare job compares the generators on the first well, \"{}\", packed whole; the other {others} wells are not packed",
                first.name
            ),
        });
    }
    Ok(())
}

/// Run every variant over its seeds, shared out to the farm; write the table and chart.
pub(super) fn run(
    job: &mut Running<'_>,
    target: Option<f64>,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let config = job.config();
    let settings = &config.compare;
    let variants = Variant::expand(&settings.methods);
    let total = variants.len() * settings.repeats;
    job.event(Event::Stage {
        stage: Stage::Compare,
        total: Some(total as u64),
    });
    let observer = &mut *job.observer;
    let mut index = 0;
    let runs = compare(&config.scene, settings, target, cancel, job.farm, |r| {
        observer.event(&Event::Run {
            stage: Stage::Compare,
            index,
            label: variant_label(&r.variant),
        });
        index += 1;
    })
    .map_err(|source| JobError::Pack {
        what: "the scene".to_owned(),
        source,
    })?;
    let interrupted = runs.len() < total;
    if runs.is_empty() && interrupted {
        return Err(JobError::Cancelled);
    }
    let files = render_compare(&runs, target.is_some())?;
    job.write("", files);
    Ok((
        Report::Compare {
            runs,
            variants,
            total,
        },
        interrupted,
    ))
}

/// `job: compare: 9 method variants × 3 seeds`; its own files.
pub(super) fn words(plan: &super::Plan) -> Words {
    let config = &plan.config;
    let mut words = Words::new(format!(
        "job: compare: {} method variants × {} seeds",
        Variant::expand(&config.compare.methods).len(),
        config.compare.repeats
    ));
    words.files = Some(("compare.csv, .svg, .png", "summary.json and manifest.json"));
    words
}

/// A line per variant (means over its seeds), then the files.
pub(super) fn lines(
    at: &str,
    runs: &[CompareRun],
    variants: &[Variant],
    total: usize,
) -> Vec<String> {
    let mut lines = Vec::new();
    for (variant, mine) in by_variant(runs, variants, |r| &r.variant) {
        let n = mine.len() as f64;
        let mean = |f: &dyn Fn(&CompareRun) -> f64| mine.iter().map(|r| f(r)).sum::<f64>() / n;
        let worst_overlap = mine.iter().map(|r| r.max_overlap).fold(0.0, f64::max);
        lines.push(format!(
            "{:<40} {} runs: {} particles, porosity {:.4}, psd_ks {:.3}, max overlap {}, coordination {:.2}, {} each",
            variant_label(variant),
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
        interrupted_runs(runs.len(), total)
    ));
    lines
}
