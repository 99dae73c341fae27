//! The layer job: the scene packed once, then the `[[materials]]` laid
//! out along the `[layering]` profile (the optimise job lays out its best
//! packing the same way, [`lay_out`]).

use super::describe::{TIME_LIMIT_NOTE, Words, duration, grading_note};
use super::error::JobError;
use super::event::{Event, Stage};
use super::plan::{Plan, Planning};
use super::registry::{Job, Report};
use super::run::{Running, generation};
use super::wells::whole_fracture;
use crate::cancel::Cancel;
use crate::ga::{Layered, StopReason};
use crate::layering::LayeringSettings;
use crate::metrics::{Metrics, measure_sharing};
use crate::names::ConfigName;
use crate::output::{LayeringDetails, LayeringReport, LayeringSummary, OutputSettings, RunInfo};
use crate::packer::Packing;

/// The layer job's rules: it needs a `[layering]` table; the search is the
/// optimise job's.
pub(super) fn plan(p: &mut Planning<'_>) -> Result<Job, JobError> {
    let Some(settings) = p.config.layering.clone() else {
        return Err(JobError::Input(format!(
            "{}:1:1: layering: missing table [layering]; the layer job needs one with at least profile, and [[materials]]",
            p.origin
        )));
    };
    if p.config.optimise.is_some() {
        p.ignore(
            "optimise",
            "the layer job packs the scene once; the optimise job searches and then lays out",
        );
    }
    Ok(Job::Layer { settings })
}

/// Pack the scene, lay the materials out, write.
pub(super) fn run(
    job: &mut Running<'_>,
    settings: &LayeringSettings,
    cancel: &Cancel,
) -> Result<(Report, bool), JobError> {
    let plan = job.plan;
    let config = &plan.config;
    let scene = &config.scene;
    let (mut packing, seconds) = job.pack_scene(scene, "the scene", cancel)?;
    let layered = lay_out(job, &packing, settings, cancel);
    packing.materials = layered.assignment.clone();
    // The layout is done: a cancel now no longer stops the run.
    let (metrics, ahead) = job.measure_packing(
        "",
        &packing,
        &config.output,
        &Cancel::new(),
        |shared, stop| measure_sharing(&packing, scene, Some(shared), stop),
    )?;
    let interrupted = layered.stop == Some(StopReason::Interrupted);
    let report = Report::Layer {
        packing,
        metrics,
        layered,
        seconds,
    };
    job.write_report(&report, &config.output, ahead)?;
    Ok((report, interrupted))
}

/// Lay the config's materials out on `packing`, with generation events.
pub(super) fn lay_out(
    job: &mut Running<'_>,
    packing: &Packing,
    settings: &LayeringSettings,
    stop: &Cancel,
) -> Layered {
    job.event(Event::Stage {
        stage: Stage::Layering,
        total: Some(settings.stop.generations as u64),
    });
    let plan = job.plan;
    let observer = &mut *job.observer;
    crate::ga::lay_out(
        packing,
        settings,
        plan.config.materials.len(),
        plan.seed(),
        stop,
        job.farm,
        |g| observer.event(&generation(Stage::Layering, g)),
    )
}

/// What the files of a layering record.
pub(super) fn info<'a>(
    plan: &'a Plan,
    layered: &'a Layered,
    seconds: f64,
    output: &'a OutputSettings,
) -> RunInfo<'a> {
    let config = &plan.config;
    RunInfo {
        materials: &config.materials,
        layering: config
            .layering
            .as_ref()
            .map(|settings| layering_report(settings, layered)),
        fracture: whole_fracture(config),
        ..RunInfo::new(&config.scene, &plan.origin, seconds, output)
    }
}

/// What the files of a layering record: its summary block, the shares,
/// the bins and the profile aimed at.
pub(super) fn layering_report<'a>(
    settings: &'a LayeringSettings,
    l: &'a Layered,
) -> LayeringReport<'a> {
    LayeringReport {
        summary: LayeringSummary {
            profile_rms_error: l.rms,
            baseline_rms_error: l.baseline_rms,
            baseline_seconds: l.baseline_seconds,
            layering: LayeringDetails {
                mode: settings.mode.config_name(),
                axis: settings.axis.config_name(),
                bins: settings.bins,
                profile: settings.profile.name(),
                ga_seconds: l.seconds,
                evaluations: l.evaluations,
                generations: l.generations,
                stop: l.stop.map(StopReason::describe),
                reproducible: l.stop.is_none_or(StopReason::reproducible),
            },
        },
        fractions: &l.fractions,
        rows: &l.rows,
        profile: &settings.profile,
        axis: settings.axis,
    }
}

/// `job: layer: pack once, then lay the materials out`.
pub(super) fn words() -> Words {
    Words::new("job: layer: pack once, then lay the materials out".to_owned())
}

/// The packing and its layout in a line.
pub(super) fn lines(at: &str, metrics: &Metrics, layered: &Layered) -> Vec<String> {
    let mut lines = vec![format!(
        "{at}: {} {}, porosity {:.4}, {}{}",
        metrics.particles,
        if metrics.shapes.is_some() {
            "particles"
        } else {
            "disks"
        },
        metrics.porosity,
        layering_line(layered),
        grading_note(metrics)
    )];
    if layered.stop == Some(StopReason::TimeLimit) {
        lines.push(TIME_LIMIT_NOTE.to_owned());
    }
    lines
}

/// `profile RMS 0.0123 (baseline 0.0187), GA 1.20 s, baseline 2.1 ms`.
pub(super) fn layering_line(l: &Layered) -> String {
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
