//! The pack job: the scene packed once (a `[fracture]` config is packed
//! well by well, `wells.rs`).

use super::describe::{Words, pack_line};
use super::error::JobError;
use super::plan::{Plan, Planning};
use super::registry::{Job, Report};
use super::run::Running;
use crate::cancel::Cancel;
use crate::metrics::{Metrics, measure_sharing};
use crate::output::{OutputSettings, RunInfo};

/// The pack job's rules: the search and the layout are other jobs'; a
/// `[fracture]` config packs its wells.
pub(super) fn plan(p: &mut Planning<'_>) -> Job {
    if p.config.optimise.is_some() {
        p.ignore(
            "optimise",
            "the optimise job searches for its target porosity",
        );
    }
    if p.lays_out() {
        p.ignore(
            "layering",
            "the layer and optimise jobs lay the materials out",
        );
    }
    match &p.config.fracture {
        Some(run) => Job::Wells { batch: run.batch },
        None => Job::Pack,
    }
}

/// Pack the scene, measure and write it.
pub(super) fn run(job: &mut Running<'_>, cancel: &Cancel) -> Result<(Report, bool), JobError> {
    let plan = job.plan;
    let scene = &plan.config.scene;
    let output = &plan.config.output;
    let (packing, seconds) = job.pack_scene(scene, "the scene", cancel)?;
    // A cancel while measuring writes nothing, as one while packing.
    let (metrics, ahead) = job.measure_packing("", &packing, output, cancel, |shared, stop| {
        measure_sharing(&packing, scene, Some(shared), stop)
    })?;
    let report = Report::Pack {
        packing,
        metrics,
        seconds,
    };
    job.write_report(&report, output, ahead)?;
    Ok((report, false))
}

/// What the files of a packing record.
pub(super) fn info<'a>(plan: &'a Plan, seconds: f64, output: &'a OutputSettings) -> RunInfo<'a> {
    RunInfo {
        materials: &plan.config.materials,
        ..RunInfo::new(&plan.config.scene, &plan.origin, seconds, output)
    }
}

/// `job: pack`.
pub(super) fn words() -> Words {
    Words::new("job: pack".to_owned())
}

/// The packing in a line.
pub(super) fn lines(at: &str, metrics: &Metrics, seconds: f64) -> Vec<String> {
    vec![pack_line(at, metrics, seconds)]
}
