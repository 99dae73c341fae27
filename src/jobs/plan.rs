//! From a config to the job that will run: one function, [`Plan::new`],
//! holds every rule about which tables a job needs and which it ignores.

use std::path::{Path, PathBuf};
use std::time::Duration;

use serde::Serialize;

use super::error::JobError;
use super::event::{Warning, WarningKind};
use super::sweep::{self as study, Study};
use crate::config::{self, Config, ParseOptions};
use crate::fracture::{Extent, FIRST_DIAMETERS, FractureRun, MM_PER_M};
use crate::ga::OptimiseSettings;
use crate::layering::{LayeringMode, LayeringSettings};
use crate::output::Format;

/// The jobs gapack runs, as a front end names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum JobKind {
    /// Pack the scene (or each fracture of a `[fracture]` config).
    Pack,
    /// Search for the `[optimise]` target porosity.
    Optimise,
    /// Lay the `[[materials]]` out along the `[layering]` profile.
    Layer,
    /// Run every generator of `[compare]` on the scene.
    Compare,
    /// Sweep the `[compare]` methods over gradings, widths and shapes.
    Stability,
    /// Run the parameter study of `[sweep]`: the config's job at every
    /// combination of the swept values, over seeds.
    Sweep,
}

impl JobKind {
    /// Every job, in the order front ends list them.
    pub const ALL: [JobKind; 6] = [
        JobKind::Pack,
        JobKind::Optimise,
        JobKind::Layer,
        JobKind::Compare,
        JobKind::Stability,
        JobKind::Sweep,
    ];

    /// The job's name (`pack`, `optimise`, …).
    pub fn name(self) -> &'static str {
        match self {
            JobKind::Pack => "pack",
            JobKind::Optimise => "optimise",
            JobKind::Layer => "layer",
            JobKind::Compare => "compare",
            JobKind::Stability => "stability",
            JobKind::Sweep => "sweep",
        }
    }

    /// The job called `name` (`pack`, `optimise`, …), if there is one.
    pub fn named(name: &str) -> Option<JobKind> {
        JobKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Every job's name, for a message that lists them: `pack, optimise, …`.
    pub fn names() -> String {
        JobKind::ALL.map(JobKind::name).join(", ")
    }

    /// The job a config is written for: `sweep` with a `[sweep]` table,
    /// else `optimise` with an `[optimise]` one, else `layer` with a
    /// `[layering]` one, else `pack`.
    pub fn natural(config: &Config) -> JobKind {
        if config.sweep.is_some() {
            JobKind::Sweep
        } else {
            JobKind::single(config)
        }
    }

    /// The job one run of the config is, `[sweep]` aside: `optimise` with
    /// an `[optimise]` table, else `layer` with a `[layering]` one, else `pack`.
    pub fn single(config: &Config) -> JobKind {
        if config.optimise.is_some() {
            JobKind::Optimise
        } else if config.layering.is_some() {
            JobKind::Layer
        } else {
            JobKind::Pack
        }
    }
}

/// What a front end asks for besides the config.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// Which job.
    pub kind: JobKind,
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
            kind,
            seed: None,
            force: false,
            resume: false,
            checkpoint_every: 10,
            time_cap: Duration::from_secs(10),
        }
    }
}

/// The job-specific part of a plan.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub enum Job {
    /// Pack one scene.
    Pack,
    /// Pack each fracture of `[fracture]`: whole or as a window, a batch
    /// writing one folder per well and `wells.csv`.
    Wells {
        /// Whether the wells go to folders of their own (a `wells` list).
        batch: bool,
    },
    /// The target-porosity search, then the layering if the config has one.
    Optimise {
        /// `[optimise]`.
        settings: OptimiseSettings,
        /// Go on from the store's checkpoint.
        resume: bool,
        /// Checkpoint every this many generations (0: only when cancelled).
        checkpoint_every: usize,
    },
    /// Pack once, then lay the materials out.
    Layer {
        /// `[layering]`.
        settings: LayeringSettings,
    },
    /// Every `[compare]` method variant on the scene.
    Compare {
        /// `[optimise] target_porosity`, which gives each run's error.
        target: Option<f64>,
    },
    /// The stability sweep.
    Stability {
        /// Time cap of one run.
        time_cap: Duration,
    },
    /// A parameter study: every run planned.
    Sweep {
        /// The study.
        study: Box<Study>,
    },
}

/// A job ready to run: the validated config (seed applied), what to do with
/// it, and the warnings about tables it ignores.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Which job was asked for.
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
    /// Parse `text` (named `origin` in messages) and plan the job `request` asks for.
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
    /// `text`, named `origin`).
    ///
    /// # Errors
    /// [`JobError::Input`] when the job needs a table the config lacks or
    /// the request is out of range.
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
        let mut warnings = Vec::new();
        let mut ignore = |table: &str, used: &str| {
            warnings.push(Warning {
                kind: WarningKind::IgnoredTable,
                message: format!(
                    "{origin}: [{table}] is not used by the {} job ({used})",
                    request.kind.name()
                ),
            });
        };
        let lays_out = config
            .layering
            .as_ref()
            .is_some_and(|l| l.mode != LayeringMode::Sizes);
        let job = match request.kind {
            JobKind::Pack => {
                if config.optimise.is_some() {
                    ignore(
                        "optimise",
                        "the optimise job searches for its target porosity",
                    );
                }
                if lays_out {
                    ignore(
                        "layering",
                        "the layer and optimise jobs lay the materials out",
                    );
                }
                match &config.fracture {
                    Some(run) => Job::Wells { batch: run.batch },
                    None => Job::Pack,
                }
            }
            JobKind::Optimise => {
                let Some(settings) = config.optimise else {
                    return Err(JobError::Input(format!(
                        "{origin}:1:1: optimise: missing table [optimise]; the optimise job needs one with at least target_porosity"
                    )));
                };
                Job::Optimise {
                    settings,
                    resume: request.resume,
                    checkpoint_every: request.checkpoint_every,
                }
            }
            JobKind::Layer => {
                let Some(settings) = config.layering.clone() else {
                    return Err(JobError::Input(format!(
                        "{origin}:1:1: layering: missing table [layering]; the layer job needs one with at least profile, and [[materials]]"
                    )));
                };
                if config.optimise.is_some() {
                    ignore(
                        "optimise",
                        "the layer job packs the scene once; the optimise job searches and then lays out",
                    );
                }
                Job::Layer { settings }
            }
            JobKind::Compare => {
                if lays_out {
                    ignore("layering", "every generator packs the scene alone");
                }
                Job::Compare {
                    target: config.optimise.map(|o| o.target_porosity),
                }
            }
            JobKind::Stability => {
                if config.optimise.is_some() {
                    ignore("optimise", "the sweep packs its own cases");
                }
                if lays_out {
                    ignore("layering", "the sweep packs its own cases");
                }
                if config.fracture.is_some() {
                    ignore(
                        "fracture",
                        "the sweep takes the grading, packer settings and seed, and packs its own shapes",
                    );
                }
                if request.time_cap.is_zero() {
                    return Err(JobError::Input(
                        "the time cap of a stability run must be a positive number of seconds"
                            .to_owned(),
                    ));
                }
                Job::Stability {
                    time_cap: request.time_cap,
                }
            }
            JobKind::Sweep => Job::Sweep {
                study: Box::new(study::plan(&config, text, origin, request, &mut warnings)?),
            },
        };
        if config.sweep.is_some() && request.kind != JobKind::Sweep {
            warnings.push(Warning {
                kind: WarningKind::IgnoredTable,
                message: format!(
                    "{origin}: [sweep] is not used by the {} job (gapack sweep runs the study)",
                    request.kind.name()
                ),
            });
        }
        if request.kind == JobKind::Compare
            && let Some(run) = &config.fracture
        {
            compare_fracture(run, origin, &mut warnings)?;
        }
        // A study's runs are sized (and warned of) one by one when planned.
        if request.kind != JobKind::Sweep {
            warnings.extend(size_warning(&config, origin));
        }
        if let Some(w) = density_warning(&config, origin)
            && !warnings.contains(&w)
        {
            warnings.push(w);
        }
        let identity = identity(text, config.scene.seed);
        Ok(Plan {
            kind: request.kind,
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

/// The compare job on a `[fracture]` config runs every generator on the
/// first well's scene, packed whole. A window (`fracture.extent =
/// "window"`) is refused: the user asked not to pack the whole fracture,
/// and a comparison of generators on it would pack it whole every run. A
/// batch of full wells is compared on its first well, with a warning
/// naming `fracture.wells`.
fn compare_fracture(
    run: &FractureRun,
    origin: &str,
    warnings: &mut Vec<Warning>,
) -> Result<(), JobError> {
    let Some(first) = run.wells.first() else {
        return Ok(());
    };
    let others = run.wells.len() - 1;
    if let Extent::Window { .. } = run.extent {
        return Err(JobError::Input(format!(
            "{origin}: fracture.extent = \"window\": the compare job packs one scene whole with every generator and grows no windows, so it would pack all {} m of well \"{}\"{} instead of a window; set fracture.extent = \"full\" to compare on the whole fracture, or give a [domain] the size of a window (its first is {FIRST_DIAMETERS}·d_max = {} mm long) to compare on one",
            first.fracture.length / MM_PER_M,
            first.name,
            if others > 0 {
                format!(" (and none of the other {others} of fracture.wells)")
            } else {
                String::new()
            },
            FIRST_DIAMETERS * first.scene.d_max(),
        )));
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
        Format::Lammps | Format::Mercury => 100.0,
        Format::Yade | Format::Esys => 95.0,
        Format::Pfc => 170.0,
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
