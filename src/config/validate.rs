//! Stage two: check the meaning of a [`RawConfig`] and build the [`Scene`].
//!
//! Three steps, the first fault ends the run:
//! 1. the values of `[domain]`, `[grading]`, `[packer]`, `[limits]`, in that
//!    order: positive, finite, known names, keys that apply to the shape;
//! 2. the [`Domain`] and [`Grading`] constructors, which check the structure
//!    of polygons and grading tables; their typed errors are wrapped with
//!    the key and position;
//! 3. the scene as a whole: domain wide enough, memory within the limit.

use std::ops::Range;

use toml::Spanned;

use super::error::{ConfigError, Location};
use super::parse::Config;
use super::raw::{
    Pair, RawCompare, RawConfig, RawDomain, RawGrading, RawLayering, RawLimits, RawOptimise,
    RawPacker, RawStrips, Table,
};
use crate::compare::CompareSettings;
use crate::fracture::{Extent, FractureRun, Well};
use crate::ga::{OptimiseSettings, RULE_GENES};
use crate::geometry::predicates::{OVERLAP_REL, RESOLUTION_REL};
use crate::geometry::{Domain, GeometryError, Point, WallMode};
use crate::grading::{Basis, Grading, Interpolation};
use crate::layering::{LayeringMode, LayeringSettings, SizeGradient};
use crate::names::{
    BASES, CONTACTS, FILLS, INDEXES, INTERPOLATIONS, METHODS, Names, RULES, SHAPES, ShapeKind,
    WALLS,
};
use crate::packer::{
    DEFAULT_ATTEMPTS, Densify, Fill, MAX_DEFERRED, MAX_GAP, Method, PEAK_BYTES_PER_DISK, PackError,
    PackerSettings, Relaxation, Strips, estimated_peak_bytes, size_count, strips,
};
use crate::{Limits, Scene};

/// `limits.max_memory_mb` when not given.
pub const DEFAULT_MAX_MEMORY_MB: f64 = 4096.0;

/// `limits.max_particles` when not given: about a minute of packing.
pub const DEFAULT_MAX_PARTICLES: u64 = 20_000_000;

/// Hint of every limit refusal.
const FORCE_HINT: &str = ", or run with --force to go ahead";

/// Largest `packer.attempts`: more tries per disk than this would run for hours.
const MAX_ATTEMPTS: i64 = 10_000_000;

/// Largest `packer.strips`.
const MAX_STRIPS: i64 = 100_000;

/// Largest `packer.relaxation_iterations` and `packer.densify_iterations`, for the same reason.
const MAX_ITERATIONS: i64 = 1_000_000;

/// Largest `compare.repeats`.
const MAX_REPEATS: i64 = 1000;

/// Smallest `wall_disk` as a fraction of the smallest diameter. Finer wall
/// disks leave the same packing (the wall is already flat to 1 %) while the
/// packer's work at a wall grows with the wall disks a particle touches: a
/// 400-disk square packs in 0.15 s at 1/100 and in minutes at 1/50 000.
const MIN_WALL_DISK_FRACTION: f64 = 0.01;

use crate::packer::BYTES_PER_MB;

/// The four ways to give a grading, in the order messages list them.
const GRADING_SOURCES: &str = "table, uniform, constant, preset";

/// The one key of `[grading]` that gives the curve.
#[derive(Clone, Copy)]
enum Source<'r> {
    Table(&'r Spanned<Vec<Pair>>),
    Uniform(&'r Pair),
    Constant(&'r Spanned<f64>),
    Preset(&'r Spanned<String>),
}

impl Source<'_> {
    fn key(self) -> &'static str {
        match self {
            Source::Table(_) => "table",
            Source::Uniform(_) => "uniform",
            Source::Constant(_) => "constant",
            Source::Preset(_) => "preset",
        }
    }
}

/// The key of a config and where its value is.
#[derive(Clone)]
struct KeyAt {
    key: String,
    span: Range<usize>,
}

/// Where the scene is: a `[domain]` (with its raw table, for messages) or a `[fracture]`.
enum Place<'r> {
    Domain(DomainPlan, &'r RawDomain),
    Fracture(FracturePlan),
}

/// A checked `[domain]`, not yet built.
struct DomainPlan {
    shape: ShapePlan,
    walls: WallMode,
    wall_disk: Option<f64>,
    /// The key that sets how wide the domain is (blamed when it is too narrow).
    width_key: KeyAt,
}

/// Checked shape sizes (mm).
enum ShapePlan {
    Rectangle { width: f64, height: f64 },
    Polygon(Vec<Point>),
    Circle { center: Point, radius: f64 },
    Trapezoid { bottom: f64, top: f64, height: f64 },
}

/// The `[domain]` keys that multiply into an area, with their values (mm).
type AreaSizes = Vec<(&'static str, f64)>;

impl ShapePlan {
    /// The area (mm²), how it is computed, and the `[domain]` keys that
    /// multiply into it with their values; `None` for a polygon, whose
    /// constructor measures (and names) its own area.
    fn area(&self) -> Option<(f64, &'static str, AreaSizes)> {
        match *self {
            ShapePlan::Rectangle { width, height } => Some((
                width * height,
                "width × height",
                vec![("width", width), ("height", height)],
            )),
            ShapePlan::Circle { radius, .. } => Some((
                std::f64::consts::PI * radius * radius,
                "π × radius²",
                vec![("radius", radius)],
            )),
            ShapePlan::Trapezoid {
                bottom,
                top,
                height,
            } => Some((
                0.5 * (bottom + top) * height,
                "(bottom + top) / 2 × height",
                vec![("bottom", bottom), ("top", top), ("height", height)],
            )),
            ShapePlan::Polygon(_) => None,
        }
    }
}

mod fracture;
mod materials;
mod output;
mod periodic;
mod study;

use fracture::FracturePlan;
use materials::MaterialPlan;

/// How many times the widest disk the domain holds the smallest size must
/// be for the grading, not the domain, to be blamed.
const SIZES_DWARF: f64 = 2.0;

/// A checked `[grading]`, not yet built.
#[derive(Clone)]
struct GradingPlan {
    curve: Curve,
    interpolation: Interpolation,
    basis: Basis,
    /// Where the curve was given (`grading.table`), blamed for the constructor's errors.
    key: String,
    at: Location,
}

/// The curve as given, values checked.
#[derive(Clone)]
enum Curve {
    Table(Vec<(f64, f64)>),
    Uniform(f64, f64),
    Constant(f64),
    Preset(String),
}

impl GradingPlan {
    /// Build the grading; its constructor checks the curve's structure.
    fn build(self) -> Result<Grading, ConfigError> {
        let (interpolation, basis) = (self.interpolation, self.basis);
        match &self.curve {
            Curve::Table(rows) => Grading::from_table(rows, interpolation, basis),
            Curve::Uniform(a, b) => Grading::uniform(*a, *b, basis),
            Curve::Constant(d) => Grading::constant(*d),
            Curve::Preset(name) => Grading::preset(name, interpolation, basis),
        }
        .map_err(|error| ConfigError::Grading {
            at: self.at,
            key: self.key,
            error,
        })
    }
}

/// Validates one config text; knows the text and its origin to report positions.
pub(crate) struct Validator<'a> {
    pub text: &'a str,
    pub origin: &'a str,
    /// Skip the `[limits]` checks (particles, memory): `--force`.
    pub force: bool,
}

impl Validator<'_> {
    /// Check `raw` and build the config.
    pub fn config(&self, mut raw: RawConfig) -> Result<Config, ConfigError> {
        raw.optimise = self.one_spelling(raw.optimise.take(), raw.optimize.take())?;
        // Values first, in file order; then the constructors; then the whole.
        let place = match (&raw.domain, &raw.fracture) {
            (Some(d), None) => Place::Domain(self.domain(d)?, d.get_ref()),
            (None, Some(f)) => Place::Fracture(self.fracture(f)?),
            (Some(d), Some(_)) => {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&d.span()),
                    key: "domain".to_owned(),
                    reason: "give [domain] or [fracture], not both: the fracture is the domain"
                        .to_owned(),
                });
            }
            (None, None) => {
                return Err(ConfigError::Schema {
                    at: self.at(&(0..0)),
                    key: "domain".to_owned(),
                    message: "missing table [domain] (or [fracture])".to_owned(),
                });
            }
        };
        let grading = raw
            .grading
            .as_ref()
            .map(|g| self.grading(g, "grading"))
            .transpose()?;
        let packer = self.packer(raw.packer.as_deref())?;
        let optimise = raw
            .optimise
            .as_ref()
            .map(|o| self.optimise(o))
            .transpose()?;
        let materials = self.materials(raw.materials.as_deref().unwrap_or(&[]))?;
        let layering = raw
            .layering
            .as_ref()
            .map(|l| self.layering(l, &materials))
            .transpose()?;
        let limit = self.limit(raw.limits.as_deref())?;
        let particles = self.particles_limit(raw.limits.as_deref())?;
        // Blamed instead of the domain when the sizes dwarf it (a table in µm).
        let sizes_key = grading.as_ref().map(|g| (g.key.clone(), g.at.clone()));
        let (grading, gradient) = self.curves(grading, &raw, &materials, layering.as_ref())?;
        let seed = raw.seed.as_ref().map_or(0, |s| *s.get_ref());
        // The limits hold during the run too, `--force` or not: it skips
        // only the refusals made on the upper bounds before the run.
        let limits = Limits::none()
            .with_max_particles(particles.0)
            .with_max_memory_bytes(limit.0 * BYTES_PER_MB);
        let scene_of = |domain, walls, wall_disk_diameter| Scene {
            domain,
            walls,
            wall_disk_diameter,
            grading: grading.clone(),
            gradient: gradient.clone(),
            packer,
            seed,
            limits,
        };
        let (scene, fracture) = match place {
            Place::Domain(plan, raw_domain) => {
                let built = self
                    .build_domain(&plan, raw_domain)?
                    .with_periodic(plan.walls == WallMode::Periodic);
                let scene = scene_of(built, plan.walls, plan.wall_disk);
                self.check_width(&scene, &plan.width_key, sizes_key.as_ref())?;
                self.check_periodic(&scene, &raw, &plan.width_key)?;
                self.check_resolution(&scene, &coordinate_key(&plan, raw_domain))?;
                self.check_particles(&scene, &plan.width_key, particles.clone())?;
                let walls = (raw_domain.walls.as_ref(), raw_domain.wall_disk.as_ref());
                self.check_walls(&scene, "domain", walls, &plan.width_key)?;
                self.check_strips(&scene, raw.packer.as_deref())?;
                self.check_memory(&scene, &plan.width_key, limit.clone())?;
                (scene, None)
            }
            Place::Fracture(plan) => {
                self.fracture_runs(&plan, &raw)?;
                let mut wells = Vec::with_capacity(plan.wells.len());
                for well in &plan.wells {
                    let f = well.fracture;
                    let (area, formula) = match f.tip_width {
                        None => (f.width * f.length, "width × length"),
                        Some(tip) => (
                            0.5 * (f.width + tip) * f.length,
                            "(width + tip width) / 2 × length",
                        ),
                    };
                    let sizes = [
                        (well.width_key.clone(), f.width),
                        (well.length_key.clone(), f.length),
                    ];
                    self.check_area(area, formula, &sizes)?;
                    let domain = well
                        .fracture
                        .domain()
                        .map_err(|error| ConfigError::Geometry {
                            at: self.at(&well.width_key.span),
                            key: well.width_key.key.clone(),
                            error,
                        })?;
                    let mut scene = scene_of(domain, plan.walls, plan.wall_disk);
                    scene.packer.fill = well.fill.unwrap_or(scene.packer.fill);
                    self.check_width(&scene, &well.width_key, sizes_key.as_ref())
                        .map_err(|e| match e {
                            ConfigError::Scene { at, key, error, .. } => ConfigError::Scene {
                                at,
                                key,
                                error,
                                hint: "; no proppant grain fits in this fracture".to_owned(),
                            },
                            other => other,
                        })?;
                    let longest = if f.width.max(f.tip_width.unwrap_or(0.0)) > f.length {
                        &well.width_key
                    } else {
                        &well.length_key
                    };
                    self.check_resolution(&scene, longest)?;
                    self.check_particles(&scene, &well.width_key, particles.clone())?;
                    let walls = raw.fracture.as_ref().map(Spanned::get_ref);
                    let walls = (
                        walls.and_then(|f| f.walls.as_ref()),
                        walls.and_then(|f| f.wall_disk.as_ref()),
                    );
                    self.check_walls(&scene, "fracture", walls, &well.width_key)?;
                    self.check_memory(&scene, &well.width_key, limit.clone())?;
                    wells.push(Well {
                        name: well.name.clone(),
                        fracture: well.fracture,
                        scene,
                    });
                }
                let scene = wells[0].scene.clone();
                let run = FractureRun {
                    extent: plan.extent,
                    batch: plan.batch,
                    wells,
                };
                (scene, Some(run))
            }
        };
        if let (Some(settings), Some(table)) = (&optimise, &raw.optimise) {
            self.check_optimise_memory(&scene, settings, table, limit.clone())?;
        }
        self.check_method(&scene, &raw)?;
        if let (Some(settings), Some(table)) = (&layering, &raw.layering) {
            self.check_bins(&scene, settings, table)?;
            self.check_layering_memory(&scene, settings, table, limit.clone())?;
        }
        let compare = self.compare(raw.compare.as_ref())?;
        let compare = self.periodic_compare(&scene, raw.compare.as_ref(), compare)?;
        Ok(Config {
            scene,
            optimise,
            materials: materials.into_iter().map(|m| m.material).collect(),
            layering,
            fracture,
            compare,
            output: self.output(raw.output.as_ref())?,
            sweep: raw.sweep.as_ref().map(|s| self.sweep(s)).transpose()?,
        })
    }

    /// `[optimise]` or `[optimize]`: one table under either spelling, not both.
    fn one_spelling(
        &self,
        optimise: Option<Spanned<Table<RawOptimise>>>,
        optimize: Option<Spanned<Table<RawOptimise>>>,
    ) -> Result<Option<Spanned<Table<RawOptimise>>>, ConfigError> {
        match (optimise, optimize) {
            (Some(a), Some(b)) => {
                let (first, second, later) = if a.span().start <= b.span().start {
                    ("optimise", "optimize", b.span())
                } else {
                    ("optimize", "optimise", a.span())
                };
                Err(ConfigError::NotApplicable {
                    at: self.at(&later),
                    key: second.to_owned(),
                    reason: format!(
                        "[{first}] is given too: [optimise] and [optimize] are one table under two spellings; give only one"
                    ),
                })
            }
            (a, b) => Ok(a.or(b)),
        }
    }

    /// `[compare]`: known method names, given once; at least one repeat.
    fn compare(
        &self,
        raw: Option<&Spanned<Table<RawCompare>>>,
    ) -> Result<CompareSettings, ConfigError> {
        let mut settings = CompareSettings::default();
        let Some(raw) = raw else {
            return Ok(settings);
        };
        let c = raw.get_ref();
        if let Some(methods) = &c.methods {
            let mut out = Vec::new();
            for (i, name) in methods.get_ref().iter().enumerate() {
                let key = format!("compare.methods[{i}]");
                let method = self.name(&METHODS, &key, Some(name))?;
                if out.contains(&method) {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&name.span()),
                        key,
                        reason: format!("{:?} is given twice", name.get_ref()),
                    });
                }
                out.push(method);
            }
            if out.is_empty() {
                return Err(ConfigError::Missing {
                    at: self.at(&methods.span()),
                    key: "compare.methods".to_owned(),
                    reason: "name at least one method".to_owned(),
                });
            }
            settings.methods = out;
        }
        if let Some(v) = &c.repeats {
            settings.repeats = self.whole("compare.repeats", v, 1, Some(MAX_REPEATS))?;
        }
        Ok(settings)
    }

    /// Refuse a comparison method where only the advancing front serves:
    /// the GA's packing kernel and size-graded packing.
    fn check_method(&self, scene: &Scene, raw: &RawConfig) -> Result<(), ConfigError> {
        let method = scene.packer.method;
        let Some(span) = raw
            .packer
            .as_ref()
            .and_then(|p| p.method.as_ref())
            .map(Spanned::span)
        else {
            return Ok(());
        };
        let why = if method == Method::AdvancingFront {
            return Ok(());
        } else if raw.optimise.is_some() {
            "the genetic algorithm packs with the advancing front; [optimise] needs method = \"advancing-front\""
        } else if scene.gradient.is_some() {
            "size-graded packing ([layering] mode = \"sizes\") needs method = \"advancing-front\""
        } else {
            return Ok(());
        };
        Err(ConfigError::NotApplicable {
            at: self.at(&span),
            key: "packer.method".to_owned(),
            reason: why.to_owned(),
        })
    }

    /// Refuse an `[optimise]` or `[layering]` beside a batch of wells or a
    /// window: those run with `gapack pack` only.
    fn fracture_runs(&self, plan: &FracturePlan, raw: &RawConfig) -> Result<(), ConfigError> {
        let why = match (plan.batch, plan.extent) {
            (true, _) => {
                "a batch of wells runs with gapack pack; give one fracture to optimise or layer"
            }
            (false, Extent::Window { .. }) => {
                "a window (extent = \"window\") runs with gapack pack; use extent = \"full\""
            }
            (false, Extent::Full) => return Ok(()),
        };
        let table = [
            ("optimise", raw.optimise.as_ref().map(Spanned::span)),
            ("layering", raw.layering.as_ref().map(Spanned::span)),
        ]
        .into_iter()
        .find_map(|(key, span)| span.map(|s| (key, s)));
        match table {
            None => Ok(()),
            Some((key, span)) => Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: key.to_owned(),
                reason: why.to_owned(),
            }),
        }
    }

    /// The scene's curves: `[grading]`, or in size-graded mode the two
    /// materials' own (the second becomes the gradient). Several materials
    /// need a `[layering]` to place them; material gradings only serve
    /// size-graded mode.
    fn curves(
        &self,
        grading: Option<GradingPlan>,
        raw: &RawConfig,
        materials: &[MaterialPlan],
        layering: Option<&LayeringSettings>,
    ) -> Result<(Grading, Option<SizeGradient>), ConfigError> {
        let sizes = layering.is_some_and(|l| l.mode == LayeringMode::Sizes);
        if let (None, Some(second)) = (layering, materials.get(1)) {
            return Err(ConfigError::NotApplicable {
                at: self.at(&second.at),
                key: "materials".to_owned(),
                reason: "several materials need a [layering] table that places them".to_owned(),
            });
        }
        if !sizes && let Some((_, at)) = materials.iter().find_map(|m| m.grading.as_ref()) {
            return Err(ConfigError::NotApplicable {
                at: self.at(&at.span),
                key: at.key.clone(),
                reason: "a material's own grading serves [layering] mode = \"sizes\" only"
                    .to_owned(),
            });
        }
        match (grading, sizes) {
            (Some(_), true) => {
                let span = raw.grading.as_ref().map_or(0..0, Spanned::span);
                Err(ConfigError::NotApplicable {
                    at: self.at(&span),
                    key: "grading".to_owned(),
                    reason:
                        "not used with [layering] mode = \"sizes\": each material gives its grading"
                            .to_owned(),
                })
            }
            (None, false) => Err(ConfigError::Schema {
                at: self.at(&(0..0)),
                key: "grading".to_owned(),
                message: "missing table [grading]".to_owned(),
            }),
            (Some(plan), false) => Ok((plan.build()?, None)),
            (None, true) => {
                let mut curves = materials
                    .iter()
                    .filter_map(|m| m.grading.as_ref())
                    .map(|(plan, _)| plan.clone().build());
                let (Some(first), Some(second), Some(l)) = (curves.next(), curves.next(), layering)
                else {
                    // Checked by `layering`: size-graded mode has two graded materials.
                    return Err(ConfigError::Schema {
                        at: self.at(&(0..0)),
                        key: "grading".to_owned(),
                        message: "missing table [grading]".to_owned(),
                    });
                };
                Ok((
                    first?,
                    Some(SizeGradient {
                        axis: l.axis,
                        profile: l.profile.clone(),
                        second: second?,
                    }),
                ))
            }
        }
    }

    /// Refuse more bins than particles: a bin's fraction needs particles to measure.
    fn check_bins(
        &self,
        scene: &Scene,
        settings: &LayeringSettings,
        raw: &Spanned<Table<RawLayering>>,
    ) -> Result<(), ConfigError> {
        // The most particles this domain holds: solid at the densest (0.9).
        let particles = (0.9 * scene.max_disks()).floor();
        if settings.bins as f64 <= particles {
            return Ok(());
        }
        let span = raw
            .get_ref()
            .bins
            .as_ref()
            .map_or(raw.span(), Spanned::span);
        Err(ConfigError::OutOfRange {
            at: self.at(&span),
            key: "layering.bins".to_owned(),
            range: format!(
                "at most the number of particles the domain holds, about {particles:.0}"
            ),
            value: settings.bins as f64,
        })
    }

    /// `[optimise]`: every key checked against its range.
    fn optimise(&self, raw: &Spanned<Table<RawOptimise>>) -> Result<OptimiseSettings, ConfigError> {
        let o = raw.get_ref();
        let Some(target) = &o.target_porosity else {
            return Err(ConfigError::Missing {
                at: self.at(&raw.span()),
                key: "optimise.target_porosity".to_owned(),
                reason: "[optimise] needs the porosity to reach, in [0, 1)".to_owned(),
            });
        };
        let mut s = OptimiseSettings::new(self.checked(
            "optimise.target_porosity",
            target,
            "in [0, 1)",
            |v| (0.0..1.0).contains(&v),
        )?);
        if let Some(v) = &o.tolerance {
            s.tolerance = self.checked("optimise.tolerance", v, "a finite number ≥ 0", |v| {
                v.is_finite() && v >= 0.0
            })?;
        }
        if let Some(v) = &o.max_psd_ks {
            s.max_psd_ks = self.checked("optimise.max_psd_ks", v, "in (0, 1]", |v| {
                v > 0.0 && v <= 1.0
            })?;
        }
        if let Some(v) = &o.time_limit_s {
            s.time_limit_s = self.positive("optimise.time_limit_s", v)?;
        }
        if let Some(v) = &o.max_evaluations {
            s.max_evaluations = Some(self.whole("optimise.max_evaluations", v, 1, None)? as u64);
        }
        if let Some(v) = &o.window_disks {
            s.window_disks = self.whole("optimise.window_disks", v, 0, None)? as u64;
        }
        if let Some(v) = &o.population {
            s.population = self.whole("optimise.population", v, 2, None)?;
        }
        if let Some(v) = &o.generations {
            s.generations = self.whole("optimise.generations", v, 1, None)?;
        }
        if let Some(v) = &o.stagnation {
            s.stagnation = self.whole("optimise.stagnation", v, 1, None)?;
        }
        Ok(s)
    }

    /// A whole number of at least `least` and, if given, at most `most`.
    fn whole(
        &self,
        key: &str,
        v: &Spanned<i64>,
        least: i64,
        most: Option<i64>,
    ) -> Result<usize, ConfigError> {
        let n = *v.get_ref();
        if n >= least && most.is_none_or(|m| n <= m) {
            return Ok(n as usize);
        }
        Err(ConfigError::OutOfRange {
            at: self.at(&v.span()),
            key: key.to_owned(),
            range: match most {
                None => format!("a whole number ≥ {least}"),
                Some(m) => format!("a whole number in [{least}, {m}]"),
            },
            value: n as f64,
        })
    }

    /// A number that must pass `ok`, described as `range` in the message.
    fn checked(
        &self,
        key: &str,
        value: &Spanned<f64>,
        range: &str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if ok(v) {
            Ok(v)
        } else {
            Err(ConfigError::OutOfRange {
                at: self.at(&value.span()),
                key: key.to_owned(),
                range: range.to_owned(),
                value: v,
            })
        }
    }

    /// Refuse an optimisation whose genomes and packings would not fit the
    /// memory limit ([`OptimiseSettings::peak_bytes`]).
    fn check_optimise_memory(
        &self,
        scene: &Scene,
        settings: &OptimiseSettings,
        raw: &Spanned<Table<RawOptimise>>,
        (limit_mb, limit_key): (f64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let estimate_mb = settings.peak_bytes(scene) / BYTES_PER_MB;
        if self.force || estimate_mb <= limit_mb {
            return Ok(());
        }
        let genes = size_count(&scene.domain, scene.d_min()) as f64 + RULE_GENES as f64;
        let disks = scene.max_disks();
        let (key, span, hint) = match (limit_key, &raw.get_ref().population) {
            (Some(k), _) => (
                k.key,
                k.span,
                format!("; raise it to allow this run{FORCE_HINT}"),
            ),
            (None, Some(p)) => (
                "optimise.population".to_owned(),
                p.span(),
                format!(
                    "; lower it, or set limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB}){FORCE_HINT}"
                ),
            ),
            (None, None) => (
                "optimise".to_owned(),
                raw.span(),
                format!(
                    "; set a smaller optimise.population or limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB}){FORCE_HINT}"
                ),
            ),
        };
        Err(ConfigError::Memory {
            at: self.at(&span),
            key,
            reason: format!(
                "the optimisation ({} genomes of {genes:.0} genes, {disks:.0} disks each) needs an estimated {estimate_mb:.0} MB, over the limit of {limit_mb:.0} MB{hint}",
                settings.population
            ),
        })
    }

    fn at(&self, span: &Range<usize>) -> Location {
        Location::at(self.origin, self.text, span.start)
    }

    /// A value that must be a positive finite number.
    fn positive(&self, key: &str, value: &Spanned<f64>) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(ConfigError::NotPositive {
                at: self.at(&value.span()),
                key: key.to_owned(),
                value: v,
            })
        }
    }

    /// A pair of numbers that must both be finite.
    fn finite_pair(&self, key: &str, pair: &Pair) -> Result<[f64; 2], ConfigError> {
        let p = pair.get_ref().0;
        match p.iter().find(|v| !v.is_finite()) {
            None => Ok(p),
            Some(&value) => Err(ConfigError::NotFinite {
                at: self.at(&pair.span()),
                key: key.to_owned(),
                value,
            }),
        }
    }

    /// A name looked up in its table; the type's default when the key is absent.
    fn name<T: Copy + PartialEq + Default>(
        &self,
        names: &Names<T>,
        key: &str,
        value: Option<&Spanned<String>>,
    ) -> Result<T, ConfigError> {
        let Some(value) = value else {
            return Ok(T::default());
        };
        names
            .get(value.get_ref())
            .ok_or_else(|| ConfigError::UnknownName {
                at: self.at(&value.span()),
                key: key.to_owned(),
                what: names.what,
                given: format!("{:?}", value.get_ref()),
                valid: names.valid(),
            })
    }

    fn domain(&self, raw: &Spanned<Table<RawDomain>>) -> Result<DomainPlan, ConfigError> {
        let d = raw.get_ref();
        let kind = SHAPES
            .get(d.shape.get_ref())
            .ok_or_else(|| ConfigError::UnknownName {
                at: self.at(&d.shape.span()),
                key: "domain.shape".to_owned(),
                what: SHAPES.what,
                given: format!("{:?}", d.shape.get_ref()),
                valid: SHAPES.valid(),
            })?;
        let shape_name = d.shape.get_ref();
        let (required, optional) = kind.size_keys();
        let takes = required
            .iter()
            .chain(optional)
            .copied()
            .collect::<Vec<_>>()
            .join(", ");

        // A size key of another shape, the first one in the file.
        let stray = size_key_spans(d)
            .into_iter()
            .filter(|(k, _)| !required.contains(k) && !optional.contains(k))
            .min_by_key(|(_, span)| span.start);
        if let Some((key, span)) = stray {
            return Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: format!("domain.{key}"),
                reason: format!("not a key of shape {shape_name:?}, which takes {takes}"),
            });
        }

        let shape_span = d.shape.span();
        let size = |key: &str, value: &Option<Spanned<f64>>| match value {
            Some(v) => self.positive(&format!("domain.{key}"), v),
            None => Err(ConfigError::Missing {
                at: self.at(&shape_span),
                key: format!("domain.{key}"),
                reason: format!("shape {shape_name:?} needs {}", required.join(", ")),
            }),
        };
        let key_at = |key: &str, value: &Option<Spanned<f64>>| KeyAt {
            key: format!("domain.{key}"),
            span: value.as_ref().map_or(shape_span.clone(), Spanned::span),
        };

        let (shape, width_key) = match kind {
            ShapeKind::Rectangle => {
                let width = size("width", &d.width)?;
                let height = size("height", &d.height)?;
                let width_key = if width <= height {
                    key_at("width", &d.width)
                } else {
                    key_at("height", &d.height)
                };
                (ShapePlan::Rectangle { width, height }, width_key)
            }
            ShapeKind::Polygon => {
                let Some(vertices) = &d.vertices else {
                    return Err(ConfigError::Missing {
                        at: self.at(&shape_span),
                        key: "domain.vertices".to_owned(),
                        reason: "shape \"polygon\" needs vertices = [[x, y], ...]".to_owned(),
                    });
                };
                let points = vertices
                    .get_ref()
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        let [x, y] = self.finite_pair(&format!("domain.vertices[{i}]"), v)?;
                        Ok(Point::new(x, y))
                    })
                    .collect::<Result<Vec<_>, ConfigError>>()?;
                let width_key = KeyAt {
                    key: "domain.vertices".to_owned(),
                    span: vertices.span(),
                };
                (ShapePlan::Polygon(points), width_key)
            }
            ShapeKind::Circle => {
                let radius = size("radius", &d.radius)?;
                let [x, y] = match &d.center {
                    Some(c) => self.finite_pair("domain.center", c)?,
                    None => [0.0, 0.0],
                };
                let center = Point::new(x, y);
                (
                    ShapePlan::Circle { center, radius },
                    key_at("radius", &d.radius),
                )
            }
            ShapeKind::Trapezoid => {
                let bottom = size("bottom", &d.bottom)?;
                let top = size("top", &d.top)?;
                let height = size("height", &d.height)?;
                let width_key = if height <= bottom.max(top) {
                    key_at("height", &d.height)
                } else if bottom >= top {
                    key_at("bottom", &d.bottom)
                } else {
                    key_at("top", &d.top)
                };
                (
                    ShapePlan::Trapezoid {
                        bottom,
                        top,
                        height,
                    },
                    width_key,
                )
            }
        };
        let raw_size = |key: &'static str| match key {
            "width" => &d.width,
            "height" => &d.height,
            "radius" => &d.radius,
            "bottom" => &d.bottom,
            _ => &d.top,
        };
        if let Some((area, formula, sizes)) = shape.area() {
            let sizes: Vec<(KeyAt, f64)> = sizes
                .iter()
                .map(|&(key, value)| (key_at(key, raw_size(key)), value))
                .collect();
            self.check_area(area, formula, &sizes)?;
        }
        let (walls, wall_disk) = self.walls("domain", d.walls.as_ref(), d.wall_disk.as_ref())?;
        self.periodic_shape(walls, kind, d)?;
        Ok(DomainPlan {
            shape,
            walls,
            wall_disk,
            width_key,
        })
    }

    /// Refuse sizes, each positive and finite, whose product `area` (mm²,
    /// computed as `formula` says) is not a positive finite number: the
    /// domain constructors would call the shape a degenerate polygon. The
    /// largest of `sizes` (key, value in mm) is blamed for an overflow, the
    /// smallest for an underflow.
    fn check_area(
        &self,
        area: f64,
        formula: &str,
        sizes: &[(KeyAt, f64)],
    ) -> Result<(), ConfigError> {
        if area.is_finite() && area > 0.0 {
            return Ok(());
        }
        let by_value = |a: &&(KeyAt, f64), b: &&(KeyAt, f64)| a.1.total_cmp(&b.1);
        let blamed = if area == 0.0 {
            sizes.iter().min_by(by_value)
        } else {
            sizes.iter().max_by(by_value)
        };
        let (key, span) = blamed.map_or_else(
            || (String::new(), 0..0),
            |(k, _)| (k.key.clone(), k.span.clone()),
        );
        Err(ConfigError::Area {
            at: self.at(&span),
            key,
            formula: formula.to_owned(),
            area,
        })
    }

    /// `walls` and `wall_disk` of table `table`: the wall model, and the
    /// wall-disk diameter (only with wall disks).
    fn walls(
        &self,
        table: &str,
        walls: Option<&Spanned<String>>,
        wall_disk: Option<&Spanned<f64>>,
    ) -> Result<(WallMode, Option<f64>), ConfigError> {
        let mode = self.name(&WALLS, &format!("{table}.walls"), walls)?;
        let key = format!("{table}.wall_disk");
        let diameter = match wall_disk {
            None => None,
            Some(v) if mode == WallMode::Disks => Some(self.positive(&key, v)?),
            Some(v) => {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&v.span()),
                    key,
                    reason: "applies only with walls = \"disks\"".to_owned(),
                });
            }
        };
        Ok((mode, diameter))
    }

    /// Build the domain; its constructor checks the shape's structure.
    fn build_domain(&self, plan: &DomainPlan, raw: &RawDomain) -> Result<Domain, ConfigError> {
        match &plan.shape {
            ShapePlan::Rectangle { width, height } => Domain::rectangle(*width, *height),
            ShapePlan::Polygon(points) => Domain::polygon(points),
            ShapePlan::Circle { center, radius } => Domain::circle(*center, *radius),
            ShapePlan::Trapezoid {
                bottom,
                top,
                height,
            } => Domain::trapezoid(*bottom, *top, *height),
        }
        .map_err(|e| self.geometry_error(e, raw))
    }

    /// Wrap a domain constructor's error with the key and position it concerns.
    fn geometry_error(&self, error: GeometryError, d: &RawDomain) -> ConfigError {
        let vertex = |i: usize| {
            d.vertices
                .as_ref()
                .and_then(|v| v.get_ref().get(i))
                .map(Spanned::span)
        };
        let whole_vertices = d.vertices.as_ref().map(Spanned::span);
        let place = match &error {
            GeometryError::BadSize { what, .. } => size_key_spans(d)
                .into_iter()
                .find(|(k, _)| what.contains(k))
                .map(|(k, span)| (format!("domain.{k}"), span)),
            GeometryError::NonFiniteVertex { index } => {
                vertex(*index).map(|span| (format!("domain.vertices[{index}]"), span))
            }
            GeometryError::SelfIntersecting { first_from, .. } => vertex(*first_from)
                .or(whole_vertices)
                .map(|span| ("domain.vertices".to_owned(), span)),
            _ => whole_vertices.map(|span| ("domain.vertices".to_owned(), span)),
        };
        let (key, span) = place.unwrap_or_else(|| ("domain.shape".to_owned(), d.shape.span()));
        ConfigError::Geometry {
            at: self.at(&span),
            key,
            error,
        }
    }

    /// A grading table at key path `path` (`grading`, `materials[1].grading`).
    fn grading(
        &self,
        raw: &Spanned<Table<RawGrading>>,
        path: &str,
    ) -> Result<GradingPlan, ConfigError> {
        let g = raw.get_ref();
        let mut sources = [
            g.table.as_ref().map(|v| (v.span(), Source::Table(v))),
            g.uniform.as_ref().map(|v| (v.span(), Source::Uniform(v))),
            g.constant.as_ref().map(|v| (v.span(), Source::Constant(v))),
            g.preset.as_ref().map(|v| (v.span(), Source::Preset(v))),
        ]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>();
        sources.sort_by_key(|(span, _)| span.start);
        let (span, source) = match sources.as_slice() {
            [] => {
                return Err(ConfigError::Missing {
                    at: self.at(&raw.span()),
                    key: format!("{path}.table"),
                    reason: format!("[{path}] needs exactly one of {GRADING_SOURCES}"),
                });
            }
            [(span, source)] => (span.clone(), *source),
            [(_, first), (span, second), ..] => {
                return Err(ConfigError::NotApplicable {
                    at: self.at(span),
                    key: format!("{path}.{}", second.key()),
                    reason: format!(
                        "give only one of {GRADING_SOURCES} (`{}` is given too)",
                        first.key()
                    ),
                });
            }
        };

        if let (Some(v), Source::Uniform(_) | Source::Constant(_)) = (&g.interpolation, source) {
            return Err(ConfigError::NotApplicable {
                at: self.at(&v.span()),
                key: format!("{path}.interpolation"),
                reason: "applies only to a table or a preset".to_owned(),
            });
        }
        if let (Some(v), Source::Constant(_)) = (&g.basis, source) {
            return Err(ConfigError::NotApplicable {
                at: self.at(&v.span()),
                key: format!("{path}.basis"),
                reason: "does not apply to a constant size".to_owned(),
            });
        }
        let interpolation = self.name(
            &INTERPOLATIONS,
            &format!("{path}.interpolation"),
            g.interpolation.as_ref(),
        )?;
        let basis = self.name(&BASES, &format!("{path}.basis"), g.basis.as_ref())?;

        let curve = match source {
            Source::Table(table) => Curve::Table(
                table
                    .get_ref()
                    .iter()
                    .enumerate()
                    .map(|(i, row)| {
                        let [d, p] = self.finite_pair(&format!("{path}.table[{i}]"), row)?;
                        Ok((d, p))
                    })
                    .collect::<Result<Vec<_>, ConfigError>>()?,
            ),
            Source::Uniform(range) => {
                let [a, b] = range.get_ref().0;
                for value in [a, b] {
                    self.positive(
                        &format!("{path}.uniform"),
                        &Spanned::new(span.clone(), value),
                    )?;
                }
                Curve::Uniform(a, b)
            }
            Source::Constant(d) => Curve::Constant(self.positive(&format!("{path}.constant"), d)?),
            Source::Preset(name) => Curve::Preset(name.get_ref().clone()),
        };
        Ok(GradingPlan {
            curve,
            interpolation,
            basis,
            key: format!("{path}.{}", source.key()),
            at: self.at(&span),
        })
    }

    fn packer(&self, raw: Option<&RawPacker>) -> Result<PackerSettings, ConfigError> {
        let Some(p) = raw else {
            return Ok(PackerSettings::default());
        };
        let method = self.name(&METHODS, "packer.method", p.method.as_ref())?;
        let attempts = p
            .attempts
            .as_ref()
            .map(|v| self.whole("packer.attempts", v, 1, Some(MAX_ATTEMPTS)))
            .transpose()?
            .unwrap_or(DEFAULT_ATTEMPTS);
        let mut relaxation = Relaxation::default();
        if let Some(v) = &p.relaxation_porosity {
            relaxation.porosity =
                self.checked("packer.relaxation_porosity", v, "in [0, 1)", |v| {
                    (0.0..1.0).contains(&v)
                })?;
        }
        if let Some(v) = &p.relaxation_iterations {
            relaxation.iterations =
                self.whole("packer.relaxation_iterations", v, 1, Some(MAX_ITERATIONS))?;
        }
        if let Some(v) = &p.relaxation_tolerance {
            let key = "packer.relaxation_tolerance";
            relaxation.tolerance = self.positive(key, v)?;
            if method == Method::Relaxation && relaxation.tolerance > OVERLAP_REL {
                // The sweeps would stop with overlaps the write check refuses.
                return Err(ConfigError::OutOfRange {
                    at: self.at(&v.span()),
                    key: key.to_owned(),
                    range: format!(
                        "at most {OVERLAP_REL:e} with method = \"relaxation\": a packing is written only if no overlap exceeds {OVERLAP_REL:e} of the radii sum, and the sweeps stop at this tolerance; {:e} (the default) passes",
                        Relaxation::default().tolerance
                    ),
                    value: relaxation.tolerance,
                });
            }
        }
        let mut densify = Densify::default();
        if let Some(v) = &p.densify_porosity {
            densify.porosity = self.checked("packer.densify_porosity", v, "in [0, 1)", |v| {
                (0.0..1.0).contains(&v)
            })?;
        }
        if let Some(v) = &p.densify_iterations {
            densify.iterations =
                self.whole("packer.densify_iterations", v, 1, Some(MAX_ITERATIONS))?;
        }
        let contacts = p
            .contacts
            .as_ref()
            .map(|c| Spanned::new(c.span(), c.get_ref().to_string()));
        let contact_share = self.name(&CONTACTS, "packer.contacts", contacts.as_ref())?;
        let one_contact_share = match (&p.one_contact_share, &p.contacts) {
            (None, _) => contact_share,
            (Some(share), Some(_)) => {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&share.span()),
                    key: "packer.one_contact_share".to_owned(),
                    reason: "give packer.contacts or packer.one_contact_share, not both".to_owned(),
                });
            }
            (Some(share), None) => self.in_range("packer.one_contact_share", share, 0.0, 1.0)?,
        };
        let gap = match &p.gap {
            None => 0.0,
            Some(g) => self.in_range("packer.gap", g, 0.0, MAX_GAP)?,
        };
        let max_deferred = match &p.max_deferred {
            None => MAX_DEFERRED,
            Some(v) => self.whole("packer.max_deferred", v, 0, Some(MAX_DEFERRED as i64))?,
        };
        Ok(PackerSettings {
            method,
            attempts,
            relaxation,
            densify,
            index: self.name(&INDEXES, "packer.index", p.index.as_ref())?,
            rules: self.name(&RULES, "packer.rules", p.rules.as_ref())?,
            one_contact_share,
            gap,
            max_deferred,
            fill: self.name(&FILLS, "packer.fill", p.fill.as_ref())?,
            strips: self.strips(p.strips.as_ref())?,
        })
    }

    /// `packer.strips`: `"auto"` or a whole number of strips (1, the default: one piece).
    fn strips(&self, raw: Option<&Spanned<RawStrips>>) -> Result<Strips, ConfigError> {
        let Some(v) = raw else {
            return Ok(Strips::default());
        };
        match v.get_ref() {
            RawStrips::Name(name) if name == "auto" => Ok(Strips::Auto),
            RawStrips::Name(name) => Err(ConfigError::UnknownName {
                at: self.at(&v.span()),
                key: "packer.strips".to_owned(),
                what: "strip setting",
                given: format!("{name:?}"),
                valid: Box::new(["auto", "a whole number of strips"]),
            }),
            RawStrips::Count(n) => {
                let n = Spanned::new(v.span(), *n);
                let n = self.whole("packer.strips", &n, 1, Some(MAX_STRIPS))?;
                Ok(Strips::Count(n as u32))
            }
        }
    }

    /// Strips asked for (`packer.strips` above 1) must suit the scene:
    /// the advancing front's dense packs with exact walls, strips no
    /// narrower than [`strips::MIN_WIDTH_DIAMETERS`] largest diameters.
    fn check_strips(&self, scene: &Scene, raw: Option<&RawPacker>) -> Result<(), ConfigError> {
        let (Strips::Count(n), Some(v)) =
            (scene.packer.strips, raw.and_then(|p| p.strips.as_ref()))
        else {
            return Ok(());
        };
        if n < 2 {
            return Ok(());
        }
        let at = self.at(&v.span());
        let key = "packer.strips".to_owned();
        let reason = if scene.packer.method != Method::AdvancingFront {
            Some("the advancing front only".to_owned())
        } else {
            strips::unsupported(scene).map(|needs| format!("strips need {needs}"))
        };
        if let Some(reason) = reason {
            return Err(ConfigError::NotApplicable { at, key, reason });
        }
        let (lo, hi) = scene.domain.bounds();
        let across = if scene.packer.fill == Fill::Right {
            hi.y - lo.y
        } else {
            hi.x - lo.x
        };
        let width = across / f64::from(n);
        let least = strips::MIN_WIDTH_DIAMETERS * scene.d_max();
        if width < least {
            return Err(ConfigError::OutOfRange {
                at,
                key,
                range: format!(
                    "at most {:.0} here: strips {width:.4} mm wide are narrower than {} largest diameters ({least:.4} mm)",
                    (across / least).floor(),
                    strips::MIN_WIDTH_DIAMETERS
                ),
                value: f64::from(n),
            });
        }
        Ok(())
    }

    /// A number that must lie in `[lo, hi]`.
    fn in_range(
        &self,
        key: &str,
        value: &Spanned<f64>,
        lo: f64,
        hi: f64,
    ) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(ConfigError::OutOfRange {
                at: self.at(&value.span()),
                key: key.to_owned(),
                range: format!("in [{lo}, {hi}]"),
                value: v,
            })
        }
    }

    /// The memory limit in MB and the key that set it, if given.
    fn limit(&self, raw: Option<&RawLimits>) -> Result<(f64, Option<KeyAt>), ConfigError> {
        match raw.and_then(|l| l.max_memory_mb.as_ref()) {
            None => Ok((DEFAULT_MAX_MEMORY_MB, None)),
            Some(v) => {
                let key = "limits.max_memory_mb";
                let mb = self.positive(key, v)?;
                Ok((
                    mb,
                    Some(KeyAt {
                        key: key.to_owned(),
                        span: v.span(),
                    }),
                ))
            }
        }
    }

    /// Refuse a domain whose largest disk inside the walls (wall disks
    /// included) is smaller than the smallest disk. Sizes [`SIZES_DWARF`]
    /// times what the domain holds are the grading's fault, most likely
    /// given in micrometres: `sizes_key` (the curve's key) is blamed then.
    fn check_width(
        &self,
        scene: &Scene,
        width_key: &KeyAt,
        sizes_key: Option<&(String, Location)>,
    ) -> Result<(), ConfigError> {
        let inscribed = scene.inscribed_diameter();
        let d_min = scene.d_min();
        if inscribed >= d_min {
            return Ok(());
        }
        // The domain's own room, wall disks aside (they have their own hint).
        let room = 2.0 * scene.domain.inradius();
        if let Some((key, at)) = sizes_key
            && d_min >= SIZES_DWARF * room
        {
            return Err(ConfigError::Scene {
                at: at.clone(),
                key: key.clone(),
                error: PackError::DomainTooNarrow { inscribed, d_min },
                hint: format!(
                    "; the smallest size is {:.1} times the widest disk the domain holds: sizes and lengths are both in millimetres (a grading in µm reads 1000 times too large)",
                    d_min / room
                ),
            });
        }
        let hint = if scene.walls == WallMode::Disks && 2.0 * scene.domain.inradius() >= d_min {
            format!(
                "; the wall disks ({:.4} mm, centred on the boundary) take that room: use smaller wall disks or walls = \"exact\"",
                scene.wall_disk()
            )
        } else {
            String::new()
        };
        Err(ConfigError::Scene {
            at: self.at(&width_key.span),
            key: width_key.key.clone(),
            error: PackError::DomainTooNarrow { inscribed, d_min },
            hint,
        })
    }

    /// `limits.max_particles` and the key that set it, if given.
    fn particles_limit(
        &self,
        raw: Option<&RawLimits>,
    ) -> Result<(u64, Option<KeyAt>), ConfigError> {
        match raw.and_then(|l| l.max_particles.as_ref()) {
            None => Ok((DEFAULT_MAX_PARTICLES, None)),
            Some(v) => {
                let key = "limits.max_particles";
                let n = self.whole(key, v, 1, None)?;
                Ok((
                    n as u64,
                    Some(KeyAt {
                        key: key.to_owned(),
                        span: v.span(),
                    }),
                ))
            }
        }
    }

    /// Refuse a scene that could hold more disks than the limit (the solid
    /// upper bound: the domain filled with disks of the grading's mean area).
    fn check_particles(
        &self,
        scene: &Scene,
        width_key: &KeyAt,
        (limit, limit_key): (u64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let disks = scene.max_disks();
        if self.force || disks <= limit as f64 {
            return Ok(());
        }
        let (blame, hint) = match limit_key {
            Some(k) => (k, format!("; raise it to allow this scene{FORCE_HINT}")),
            None => (
                width_key.clone(),
                format!(
                    "; set limits.max_particles (default {DEFAULT_MAX_PARTICLES}) to raise the limit{FORCE_HINT}"
                ),
            ),
        };
        Err(ConfigError::Scene {
            at: self.at(&blame.span),
            key: blame.key,
            error: PackError::TooManyParticles { disks, limit },
            hint,
        })
    }

    /// Refuse a scene whose smallest disk is below
    /// [`RESOLUTION_REL`] of its largest |coordinate|, blaming `key` (the
    /// key that sets that coordinate): floating point could not keep its
    /// disks from overlapping there.
    fn check_resolution(&self, scene: &Scene, key: &KeyAt) -> Result<(), ConfigError> {
        let (lo, hi) = scene.domain.bounds();
        let coordinate = [lo.x, lo.y, hi.x, hi.y]
            .into_iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let d_min = scene.d_min();
        if d_min >= RESOLUTION_REL * coordinate {
            return Ok(());
        }
        Err(ConfigError::Scene {
            at: self.at(&key.span),
            key: key.key.clone(),
            error: PackError::Unresolvable { d_min, coordinate },
            hint: "; bring the domain nearer the origin, or pack a smaller domain or larger disks"
                .to_owned(),
        })
    }

    /// With `walls = "disks"` in table `table` (its `walls` and `wall_disk`
    /// keys as given): refuse a `wall_disk` finer than
    /// [`MIN_WALL_DISK_FRACTION`] of the smallest diameter, and a boundary
    /// that needs more than [`Domain::MAX_BOUNDARY_DISKS`] wall disks
    /// (blaming `wall_disk` if given, else `walls`).
    fn check_walls(
        &self,
        scene: &Scene,
        table: &str,
        (walls, wall_disk): (Option<&Spanned<String>>, Option<&Spanned<f64>>),
        width_key: &KeyAt,
    ) -> Result<(), ConfigError> {
        if scene.walls != WallMode::Disks {
            return Ok(());
        }
        let d_min = scene.d_min();
        let key = format!("{table}.wall_disk");
        if let Some(v) = wall_disk {
            let least = d_min * MIN_WALL_DISK_FRACTION;
            if *v.get_ref() < least {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&v.span()),
                    key,
                    range: format!(
                        "at least 1/{:.0} of the smallest diameter ({d_min} mm), {least} mm: finer wall disks only slow the packer",
                        1.0 / MIN_WALL_DISK_FRACTION
                    ),
                    value: *v.get_ref(),
                });
            }
        }
        let diameter = scene.wall_disk();
        if scene.domain.boundary_disk_count(diameter).is_some() {
            return Ok(());
        }
        let (key, span) = match (wall_disk, walls) {
            (Some(v), _) => (key, v.span()),
            (None, Some(w)) => (format!("{table}.walls"), w.span()),
            (None, None) => (width_key.key.clone(), width_key.span.clone()),
        };
        Err(ConfigError::Scene {
            at: self.at(&span),
            key,
            error: PackError::TooManyWallDisks {
                diameter,
                max: Domain::MAX_BOUNDARY_DISKS,
            },
            hint: String::new(),
        })
    }

    /// Refuse a scene whose estimated peak memory is over the limit.
    fn check_memory(
        &self,
        scene: &Scene,
        width_key: &KeyAt,
        (limit_mb, limit_key): (f64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let bytes = estimated_peak_bytes(scene);
        let estimate_mb = bytes / BYTES_PER_MB;
        if self.force || estimate_mb <= limit_mb {
            return Ok(());
        }
        let (blame, hint) = match limit_key {
            Some(k) => (k, format!("; raise it to allow this scene{FORCE_HINT}")),
            None => (
                KeyAt {
                    key: width_key.key.clone(),
                    span: width_key.span.clone(),
                },
                format!(
                    "; set limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB}) to raise the limit{FORCE_HINT}"
                ),
            ),
        };
        Err(ConfigError::Scene {
            at: self.at(&blame.span),
            key: blame.key,
            error: PackError::TooLarge {
                disks: bytes / PEAK_BYTES_PER_DISK,
                estimate_mb,
                limit_mb,
            },
            hint,
        })
    }
}

/// The key of `[domain]` whose value sets the domain's largest |coordinate|.
fn coordinate_key(plan: &DomainPlan, d: &RawDomain) -> KeyAt {
    let key_at = |key: &str, span: Option<Range<usize>>| KeyAt {
        key: format!("domain.{key}"),
        span: span.unwrap_or_else(|| d.shape.span()),
    };
    let span = |v: &Option<Spanned<f64>>| v.as_ref().map(Spanned::span);
    match &plan.shape {
        ShapePlan::Rectangle { width, height } if width >= height => {
            key_at("width", span(&d.width))
        }
        ShapePlan::Rectangle { .. } => key_at("height", span(&d.height)),
        ShapePlan::Trapezoid {
            bottom,
            top,
            height,
        } => {
            // The farthest abscissa is the bottom's right end or the top's.
            if *height >= bottom.max(0.5 * (bottom + top)) {
                key_at("height", span(&d.height))
            } else if bottom >= top {
                key_at("bottom", span(&d.bottom))
            } else {
                key_at("top", span(&d.top))
            }
        }
        ShapePlan::Circle { center, radius } => {
            if center.x.abs().max(center.y.abs()) >= *radius {
                key_at("center", d.center.as_ref().map(Spanned::span))
            } else {
                key_at("radius", span(&d.radius))
            }
        }
        ShapePlan::Polygon(points) => {
            let far = |p: &Point| p.x.abs().max(p.y.abs());
            let i = (0..points.len())
                .max_by(|&a, &b| far(&points[a]).total_cmp(&far(&points[b])))
                .unwrap_or(0);
            let vertex = d
                .vertices
                .as_ref()
                .and_then(|v| v.get_ref().get(i))
                .map(Spanned::span);
            key_at(&format!("vertices[{i}]"), vertex)
        }
    }
}

/// The size keys of `[domain]` that are present, with the spans of their values.
fn size_key_spans(d: &RawDomain) -> Vec<(&'static str, Range<usize>)> {
    [
        ("width", d.width.as_ref().map(Spanned::span)),
        ("height", d.height.as_ref().map(Spanned::span)),
        ("vertices", d.vertices.as_ref().map(Spanned::span)),
        ("radius", d.radius.as_ref().map(Spanned::span)),
        ("center", d.center.as_ref().map(Spanned::span)),
        ("bottom", d.bottom.as_ref().map(Spanned::span)),
        ("top", d.top.as_ref().map(Spanned::span)),
    ]
    .into_iter()
    .filter_map(|(k, span)| span.map(|s| (k, s)))
    .collect()
}
