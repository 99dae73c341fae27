//! From a config to the job that will run: [`Plan::load`] and
//! [`Plan::new`] resolve the job (the config's own when the request names
//! none), apply the request, and hand the job's own rules about which
//! tables it needs and which it ignores to its file ([`Job`]).

use std::path::{Path, PathBuf};
use std::time::Duration;

use super::error::JobError;
use super::event::{Warning, WarningKind};
use super::registry::{Job, JobKind};
use crate::config::{self, Config, ParseOptions};
use crate::fracture::Extent;
use crate::layering::LayeringMode;
use crate::output::Format;

/// What a front end asks for besides the config.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// Which job; `None`: the config's own ([`JobKind::natural`]),
    /// resolved by [`Plan::new`] from the config's tables.
    pub kind: Option<JobKind>,
    /// Overrides the config's `seed`.
    pub seed: Option<u64>,
    /// Skip the `[limits]` refusals.
    pub force: bool,
    /// `optimise`: go on from the store's checkpoint; `sweep`: keep the
    /// runs the store's `sweep.csv` has finished and run the others.
    pub resume: bool,
    /// `optimise`: save a checkpoint every this many generations (0: never;
    /// one is saved when the job is cancelled all the same).
    pub checkpoint_every: usize,
    /// `stability`: how long one run may take before it counts as not finished.
    pub time_cap: Duration,
}

impl Request {
    /// A request for `kind` with the defaults: the config's seed, limits
    /// enforced, no resume, a checkpoint every 10 generations, a 10 s cap.
    pub fn new(kind: JobKind) -> Self {
        Request {
            kind: Some(kind),
            seed: None,
            force: false,
            resume: false,
            checkpoint_every: 10,
            time_cap: Duration::from_secs(10),
        }
    }

    /// A request for the config's own job ([`JobKind::natural`]), with
    /// the defaults of [`Request::new`].
    pub fn natural() -> Self {
        Request {
            kind: None,
            ..Request::new(JobKind::Pack)
        }
    }

    /// A request for `kind` if given, else for the config's own job.
    pub fn asking(kind: Option<JobKind>) -> Self {
        Request {
            kind,
            ..Request::natural()
        }
    }
}

/// A job ready to run: the validated config (seed applied), what to do with
/// it, and the warnings about tables it ignores.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Which job: the one asked for, or the config's own for a natural request.
    pub kind: JobKind,
    /// What it does.
    pub job: Job,
    /// The config, its seed overridden as asked.
    pub config: Config,
    /// Names the config in messages and in `summary.json` (a path, or
    /// [`config::DEFAULT_ORIGIN`]).
    pub origin: String,
    /// FNV-1a of the config's text and the seed: a checkpoint resumes only the run it came from.
    pub identity: String,
    /// Said before the job runs (each also sent as an event).
    pub warnings: Vec<Warning>,
}

impl Plan {
    /// Parse `text` (named `origin` in messages) and plan the job `request`
    /// asks for: the config's own ([`JobKind::natural`]) when it names none.
    ///
    /// # Errors
    /// [`JobError::Config`] for a bad config, [`JobError::Input`] when the
    /// job needs a table the config lacks or the request is out of range.
    pub fn load(text: &str, origin: &str, request: &Request) -> Result<Plan, JobError> {
        let options = ParseOptions {
            force: request.force,
        };
        let config = config::parse_with(text, origin, options)?;
        Plan::new(config, text, origin, request)
    }

    /// Plan the job `request` asks for on a parsed `config` (of the text
    /// `text`, named `origin`): the config's own when it names none.
    ///
    /// # Errors
    /// [`JobError::Input`] when the job needs a table the config lacks or
    /// the request is out of range; [`JobError::Config`] at its `[shape]`
    /// for a job other than pack on particle shapes (not in this version).
    pub fn new(
        mut config: Config,
        text: &str,
        origin: &str,
        request: &Request,
    ) -> Result<Plan, JobError> {
        if let Some(seed) = request.seed {
            config.scene.seed = seed;
            if let Some(run) = &mut config.fracture {
                run.wells.iter_mut().for_each(|w| w.scene.seed = seed);
            }
        }
        let kind = request.kind.unwrap_or_else(|| JobKind::natural(&config));
        let mut planning = Planning {
            kind,
            config: &config,
            text,
            origin,
            request,
            ignored: Vec::new(),
            more: Vec::new(),
        };
        let job = Job::plan(&mut planning)?;
        let Planning {
            ignored: mut warnings,
            more,
            ..
        } = planning;
        if config.sweep.is_some() && kind != JobKind::Sweep {
            warnings.push(Warning {
                kind: WarningKind::IgnoredTable,
                message: format!(
                    "{origin}: [sweep] is not used by the {} job (the sweep job runs the study)",
                    kind.name()
                ),
            });
        }
        warnings.extend(more);
        // A study's runs are sized (and warned of) one by one when planned.
        if kind != JobKind::Sweep {
            warnings.extend(size_warning(&config, origin));
        }
        if let Some(w) = density_warning(&config, origin)
            && !warnings.contains(&w)
        {
            warnings.push(w);
        }
        let identity = identity(text, config.scene.seed);
        Ok(Plan {
            kind,
            job,
            config,
            origin: origin.to_owned(),
            identity,
            warnings,
        })
    }

    /// The seed the job runs with.
    pub fn seed(&self) -> u64 {
        self.config.scene.seed
    }

    /// Whether the job packs a fracture whole or grows windows.
    pub fn extent(&self) -> Option<Extent> {
        self.config.fracture.as_ref().map(|f| f.extent)
    }
}

/// A job being planned: the job, its config and request, and the
/// warnings its rules give — each job's file reads it and says what it
/// ignores ([`Planning::ignore`]).
pub(super) struct Planning<'a> {
    /// The job planned.
    pub kind: JobKind,
    /// The config, its seed overridden as asked.
    pub config: &'a Config,
    /// The config's text.
    pub text: &'a str,
    /// Names the config in messages.
    pub origin: &'a str,
    /// What the front end asked for.
    pub request: &'a Request,
    /// The tables the job does not use, said first.
    ignored: Vec<Warning>,
    /// The job's other warnings, said after those.
    pub more: Vec<Warning>,
}

impl Planning<'_> {
    /// Say that the job does not use `[table]`, and what it does (`used`).
    pub fn ignore(&mut self, table: &str, used: &str) {
        self.ignored.push(Warning {
            kind: WarningKind::IgnoredTable,
            message: format!(
                "{}: [{table}] is not used by the {} job ({used})",
                self.origin,
                self.kind.name()
            ),
        });
    }

    /// Whether the config lays its materials out (a `[layering]` table
    /// whose mode is not size-graded packing).
    pub fn lays_out(&self) -> bool {
        self.config
            .layering
            .as_ref()
            .is_some_and(|l| l.mode != LayeringMode::Sizes)
    }
}

/// Where a run of the config at `path` writes: `out` if given, else the
/// config's `[output] dir`, else `out/<config file stem>` (`out/default`
/// for the embedded scene).
pub fn output_dir(out: Option<&Path>, config: &Config, path: Option<&Path>) -> PathBuf {
    out.map(Path::to_path_buf)
        .or_else(|| config.output.dir.as_ref().map(PathBuf::from))
        .unwrap_or_else(|| {
            let stem = path
                .and_then(Path::file_stem)
                .map_or_else(|| "default".into(), |s| s.to_string_lossy().into_owned());
            Path::new("out").join(stem)
        })
}

/// FNV-1a (64 bits) of the config's text and the seed, as hex.
fn identity(text: &str, seed: u64) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for byte in text.as_bytes().iter().chain(&seed.to_le_bytes()) {
        h ^= u64::from(*byte);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Disks over which a run is announced before it starts.
const LARGE_RUN_DISKS: f64 = 1e6;
/// Bytes of files over which a run is announced before it starts.
const LARGE_RUN_BYTES: f64 = 100e6;

/// Bytes per disk of each format's file, measured on the default scene's
/// (59 to 128 bytes with shortest round-trip numbers) and rounded up by a
/// third for longer numbers; the pictures at their largest.
fn bytes_per_disk(format: Format) -> f64 {
    match format {
        Format::Csv => 80.0,
        Format::Json => 115.0,
        Format::Vtk => 120.0,
        // Binary, exact for disks: radius, material, id, the point and
        // its vertex cell; x, y, r and material.
        Format::Vtp => 60.0,
        Format::Npz => 28.0,
        Format::Lammps | Format::Mercury | Format::LiggghtsSuperquadric => 100.0,
        Format::Yade | Format::Esys => 95.0,
        Format::Pfc => 170.0,
        // Up to clump_max_disks disks per particle; a disk packing's one.
        Format::LammpsClumps | Format::LiggghtsClumps => 110.0,
        Format::Svg => 85.0,
        Format::Png => 0.0,
    }
}

/// A run estimated at over [`LARGE_RUN_DISKS`] disks or
/// [`LARGE_RUN_BYTES`] of files, said in one line before it starts: most
/// often a length in the wrong unit (`height_m` is metres, every other
/// length millimetres).
fn size_warning(config: &Config, origin: &str) -> Option<Warning> {
    let disks: f64 = match &config.fracture {
        Some(run) => run.wells.iter().map(|w| w.scene.estimated_disks()).sum(),
        None => config.scene.estimated_disks(),
    };
    let per_disk: f64 = config
        .output
        .formats
        .iter()
        .map(|&f| bytes_per_disk(f))
        .sum();
    let bytes = disks * per_disk;
    (disks > LARGE_RUN_DISKS || bytes > LARGE_RUN_BYTES).then(|| Warning {
        kind: WarningKind::LargeRun,
        message: format!(
            "{origin}: this run is estimated at about {} disks and {:.0} MB of files; lengths are millimetres but for keys ending in _m (metres): check the domain's sizes if that is more than meant",
            group_thousands(disks),
            bytes / 1e6
        ),
    })
}

/// Densities under this (kg/m³) read as g/cm³: no solid is lighter.
const LIGHTEST_SOLID: f64 = 100.0;

/// `[output] density` under [`LIGHTEST_SOLID`] kg/m³, said before the run.
fn density_warning(config: &Config, origin: &str) -> Option<Warning> {
    let density = config.output.export.density;
    (density < LIGHTEST_SOLID).then(|| Warning {
        kind: WarningKind::Units,
        message: format!(
            "{origin}: output.density = {density} kg/m³ is lighter than any solid: densities are in kg/m³ (did you mean {} kg/m³, from g/cm³?)",
            density * 1000.0
        ),
    })
}

/// `2150759` as `2,150,759`.
fn group_thousands(v: f64) -> String {
    let digits = format!("{:.0}", v.max(0.0));
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_job_plans_a_scene_of_shapes() {
        let text = "[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 40\n[grading]\nconstant = 1.2\n[shape]\nkind = \"superellipse\"\naspect = 1.5\n[optimise]\ntarget_porosity = 0.3\n[[materials]]\nname = \"a\"\n[[materials]]\nname = \"b\"\n[layering]\nprofile = \"linear\"\n";
        for kind in [
            JobKind::Pack,
            JobKind::Optimise,
            JobKind::Layer,
            JobKind::Compare,
            JobKind::Stability,
        ] {
            let plan = Plan::load(text, "t.toml", &Request::new(kind)).expect("planned");
            assert_eq!(plan.kind, kind);
            assert!(plan.config.scene.shape.is_some());
        }
    }

    const SQUARE: &str =
        "[domain]\nshape = \"rectangle\"\nwidth = 10\nheight = 10\n[grading]\nconstant = 1.0\n";

    #[test]
    fn pack_warns_of_an_optimise_table_and_optimise_needs_one() {
        let with = format!("{SQUARE}[optimise]\ntarget_porosity = 0.2\n");
        let plan = Plan::load(&with, "a.toml", &Request::new(JobKind::Pack)).expect("plans");
        assert_eq!(plan.warnings.len(), 1);
        assert_eq!(plan.warnings[0].kind, WarningKind::IgnoredTable);
        assert!(plan.warnings[0].message.contains("[optimise]"));
        let err = Plan::load(SQUARE, "b.toml", &Request::new(JobKind::Optimise))
            .expect_err("no [optimise]");
        assert!(
            err.to_string()
                .starts_with("b.toml:1:1: optimise: missing table"),
            "{err}"
        );
        assert!(err.is_input());
    }

    const TWO_WELLS: &str = "[fracture]\nextent = \"EXTENT\"\n[[fracture.wells]]\nname = \"a\"\nwidth_mm = 6\nheight_m = 0.05\n[[fracture.wells]]\nname = \"b\"\nwidth_mm = 8\nheight_m = 0.05\n[grading]\nuniform = [1.0, 1.5]\n";

    #[test]
    fn compare_refuses_a_window_and_names_the_wells_it_does_not_pack() {
        let window = TWO_WELLS.replace("EXTENT", "window");
        let err = Plan::load(&window, "w.toml", &Request::new(JobKind::Compare))
            .expect_err("a window is not compared");
        assert!(err.is_input());
        let said = err.to_string();
        for key in [
            "fracture.extent = \"window\"",
            "well \"a\"",
            "fracture.wells",
            "fracture.extent = \"full\"",
        ] {
            assert!(said.contains(key), "{said} does not name {key}");
        }
        // The same batch packed whole is compared on its first well, said so.
        let full = TWO_WELLS.replace("EXTENT", "full");
        let plan = Plan::load(&full, "f.toml", &Request::new(JobKind::Compare)).expect("plans");
        assert_eq!(plan.warnings.len(), 1, "{:?}", plan.warnings);
        assert_eq!(plan.warnings[0].kind, WarningKind::IgnoredWells);
        assert!(plan.warnings[0].message.contains("fracture.wells: the compare job compares the generators on the first well, \"a\", packed whole; the other 1 wells"), "{}", plan.warnings[0].message);
        // The pack job grows its windows, as asked.
        Plan::load(&window, "w.toml", &Request::new(JobKind::Pack)).expect("pack plans a window");
    }

    #[test]
    fn the_seed_override_changes_the_identity() {
        let mut request = Request::new(JobKind::Pack);
        let a = Plan::load(SQUARE, "a.toml", &request).expect("plans");
        request.seed = Some(5);
        let b = Plan::load(SQUARE, "a.toml", &request).expect("plans");
        assert_eq!(b.seed(), 5);
        assert_ne!(a.identity, b.identity);
    }
}
