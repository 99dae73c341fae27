//! The most a job asks of a machine: the largest scene and the most memory
//! over every run it makes ([`Plan::largest`]) — every well of a
//! `[fracture]` (a window packs no more than its well whole), every case of
//! the stability sweep, every point of a study, and the memory of the
//! optimise and layering searches besides the packings'. A front end holds
//! it against its own ceilings: a config's `[limits]` do not lift them.

use super::plan::Plan;
use super::registry::{Job, JobKind};
use crate::Scene;
use crate::config::{Config, layering_peak_bytes};
use crate::layering::LayeringMode;
use crate::packer::estimated_peak_bytes;
use crate::stability::Case;

/// The largest scene and the most memory over every run of a plan, each
/// with the run (and the part of it) it comes from.
///
/// # Behavior
/// Upper bounds, per run: runs that go on at once (a batch's wells, a
/// study's runs, one per thread) each need their own.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Largest {
    /// The most disks the scene of any run could hold ([`Scene::max_disks`]).
    pub max_disks: f64,
    /// Which scene that is: `the scene`, `well "a"`, `point width=600: the scene`.
    pub max_disks_in: String,
    /// The most memory any run is estimated to need (bytes, an upper
    /// bound): its packing's, or its optimise or layering search's.
    pub peak_bytes: f64,
    /// What needs it: `the scene`, `the layering search on the scene`, …
    pub peak_bytes_in: String,
}

impl Largest {
    /// Nothing yet: a study none of whose points can run.
    pub(super) fn none() -> Largest {
        Largest {
            max_disks: 0.0,
            max_disks_in: "no run".to_owned(),
            peak_bytes: 0.0,
            peak_bytes_in: "no run".to_owned(),
        }
    }

    /// Keep `disks` of `what` if over the largest so far.
    fn disks(&mut self, disks: f64, what: impl FnOnce() -> String) {
        if disks > self.max_disks || self.max_disks_in == "no run" {
            self.max_disks = disks;
            self.max_disks_in = what();
        }
    }

    /// Keep `bytes` of `what` if over the most so far.
    fn bytes(&mut self, bytes: f64, what: impl FnOnce() -> String) {
        if bytes > self.peak_bytes || self.peak_bytes_in == "no run" {
            self.peak_bytes = bytes;
            self.peak_bytes_in = what();
        }
    }

    /// Keep the larger of each of `other`'s, said to be of `point`
    /// (`point width=600: the scene`).
    pub(super) fn merge(&mut self, other: &Largest, point: &str) {
        self.disks(other.max_disks, || {
            format!("point {point}: {}", other.max_disks_in)
        });
        self.bytes(other.peak_bytes, || {
            format!("point {point}: {}", other.peak_bytes_in)
        });
    }
}

impl Plan {
    /// The largest scene and the most memory over every run the job makes
    /// ([`Largest`]): what a server's ceilings are held against.
    ///
    /// # Performance
    /// A study's is found when it is planned, a point at a time; this reads it.
    pub fn largest(&self) -> Largest {
        match &self.job {
            Job::Sweep { study } => study.largest.clone(),
            job => of_run(self.kind, job, &self.config),
        }
    }
}

/// [`Plan::largest`] of one run, `job` (a `kind`) on `config`.
fn of_run(kind: JobKind, job: &Job, config: &Config) -> Largest {
    let scenes: Vec<(Scene, String)> = match (kind, &config.fracture) {
        (JobKind::Stability, _) => Case::all()
            .into_iter()
            .filter_map(|case| {
                let scene = case.scene(&config.scene).ok()?;
                Some((
                    scene,
                    format!(
                        "the stability case {} of d_max/d_min {} and width {} d_max",
                        case.shape.name(),
                        case.ratio,
                        case.width
                    ),
                ))
            })
            .collect(),
        (_, Some(run)) => run
            .wells
            .iter()
            .map(|w| (w.scene.clone(), format!("well {:?}", w.name)))
            .collect(),
        (_, None) => vec![(config.scene.clone(), "the scene".to_owned())],
    };
    let optimise = match job {
        Job::Optimise { settings, .. } => Some(settings),
        _ => None,
    };
    // The layer job lays out; the optimise job too, after its search.
    let layering = match job {
        Job::Layer { settings } => Some(settings),
        Job::Optimise { .. } => config.layering.as_ref(),
        _ => None,
    }
    .filter(|l| l.mode != LayeringMode::Sizes);
    let mut largest = Largest::none();
    for (scene, what) in &scenes {
        largest.disks(scene.max_disks(), || what.clone());
        largest.bytes(estimated_peak_bytes(scene), || what.clone());
        if let Some(o) = optimise {
            largest.bytes(o.peak_bytes(scene), || {
                format!("the optimisation search on {what}")
            });
        }
        if let Some(l) = layering {
            largest.bytes(layering_peak_bytes(scene, l), || {
                format!("the layering search on {what}")
            });
        }
    }
    largest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::Request;

    const SQUARE: &str =
        "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1.0\n";

    fn plan(text: &str, kind: Option<JobKind>) -> Plan {
        Plan::load(text, "t.toml", &Request::asking(kind)).expect("plans")
    }

    /// A study's largest scene is its largest point's, whichever point it is.
    #[test]
    fn a_study_is_as_large_as_its_largest_point() {
        let study = format!("{SQUARE}[sweep]\n\"domain.width\" = [10, 600, 20]\n");
        let largest = plan(&study, None).largest();
        let alone = plan(&SQUARE.replace("width = 10", "width = 600"), None).largest();
        let first = plan(SQUARE, None).largest();
        assert!(alone.max_disks > 50.0 * first.max_disks);
        assert_eq!(largest.max_disks, alone.max_disks);
        assert_eq!(largest.peak_bytes, alone.peak_bytes);
        assert_eq!(largest.max_disks_in, "point width=600: the scene");
        assert_eq!(first.max_disks_in, "the scene");
    }

    /// The layering search's memory counts, and grows with its population.
    #[test]
    fn a_layering_search_counts_its_memory() {
        let layered = format!(
            "{SQUARE}[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\nprofile = \"linear\"\npopulation = POP\n"
        );
        let small = plan(&layered.replace("POP", "10"), Some(JobKind::Layer)).largest();
        let big = plan(&layered.replace("POP", "20000"), Some(JobKind::Layer)).largest();
        let packing = plan(SQUARE, Some(JobKind::Pack)).largest();
        assert_eq!(big.peak_bytes_in, "the layering search on the scene");
        assert!(small.peak_bytes > packing.peak_bytes);
        assert!(
            big.peak_bytes > 100.0 * small.peak_bytes,
            "{big:?} {small:?}"
        );
        // The pack job lays nothing out: the packing alone.
        let packed = plan(&layered.replace("POP", "20000"), Some(JobKind::Pack)).largest();
        assert_eq!(packed.peak_bytes, packing.peak_bytes);
        // A study of layering runs counts each point's search.
        let study = format!(
            "{}[sweep]\n\"layering.population\" = [10, 20000]\n",
            layered.replace("POP", "10")
        );
        let swept = plan(&study, None).largest();
        assert_eq!(swept.peak_bytes, big.peak_bytes);
        assert_eq!(
            swept.peak_bytes_in,
            "point population=20000: the layering search on the scene"
        );
    }

    /// Every well counts, not only the first.
    #[test]
    fn every_well_counts() {
        let wells = "[fracture]\nextent = \"window\"\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 6\nheight_m = 0.05\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 60\nheight_m = 0.05\n[grading]\nuniform = [1.0, 1.5]\n";
        let p = plan(wells, Some(JobKind::Pack));
        let largest = p.largest();
        let run = p.config.fracture.as_ref().expect("wells");
        assert_eq!(largest.max_disks, run.wells[1].scene.max_disks());
        assert!(largest.max_disks > run.wells[0].scene.max_disks());
        assert_eq!(largest.max_disks_in, "well \"b\"");
    }
}
