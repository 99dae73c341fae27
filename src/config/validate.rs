//! Stage two: check the meaning of a [`RawConfig`] and build the [`Scene`].
//!
//! Three steps, the first fault ends the run:
//! 1. the values of `[domain]`, `[grading]`, `[packer]`, `[optimise]`,
//!    `[[materials]]`, `[layering]`, `[shape]`, `[limits]`, in that order:
//!    positive, finite, known names, keys that apply to the shape (a
//!    `[shape]` is refused here too where this version cannot pack it);
//! 2. the [`Domain`](crate::geometry::Domain) and
//!    [`Grading`](crate::grading::Grading) constructors, which check the
//!    structure of polygons and grading tables; their typed errors are
//!    wrapped with the key and position;
//! 3. the scene as a whole: domain wide enough, memory within the limit.
//!
//! This file holds the [`Validator`] and the order of the checks
//! ([`Validator::config`]); each table's checks are in a file of their own
//! below `validate/`, the checks every table shares in `values.rs`.

use std::ops::Range;

use toml::Spanned;

use super::error::{ConfigError, Location};
use super::parse::Config;
use super::raw::{RawConfig, RawDomain};
use crate::fracture::{FractureRun, Well};
use crate::geometry::WallMode;
use crate::packer::BYTES_PER_MB;
use crate::{Limits, Scene};

mod compare;
mod domain;
mod fracture;
mod grading;
mod layering;
mod limits;
mod materials;
mod optimise;
mod output;
mod packer;
mod periodic;
mod scene;
mod shape;
mod stop_rules;
mod study;
mod values;

use domain::{DomainPlan, coordinate_key};
use fracture::FracturePlan;
pub use layering::layering_peak_bytes;
pub use limits::{DEFAULT_MAX_MEMORY_MB, DEFAULT_MAX_PARTICLES};

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

/// Validates one config text; knows the text and its origin to report positions.
pub(crate) struct Validator<'a> {
    pub text: &'a str,
    pub origin: &'a str,
    /// Skip the `[limits]` refusals (particles, memory): [`ParseOptions::force`](super::ParseOptions::force).
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
        let shape = match &raw.shape {
            None => None,
            Some(table) => {
                let spec = self.shape(table)?;
                let walls = match &place {
                    Place::Domain(plan, _) => plan.walls,
                    Place::Fracture(plan) => plan.walls,
                };
                self.check_shape_support(table, &packer, walls)?;
                Some(spec)
            }
        };
        let optimise = match (optimise, raw.optimise.as_ref()) {
            (Some(mut settings), Some(table)) => {
                if let Some(search) = &table.get_ref().shape {
                    settings.shape = Some(self.shape_search(search, shape.as_ref())?);
                }
                Some(settings)
            }
            (settings, _) => settings,
        };
        let limit = self.limit(raw.limits.as_deref())?;
        let particles = self.particles_limit(raw.limits.as_deref())?;
        // Blamed instead of the domain when the sizes dwarf it (a table in µm).
        let sizes_key = grading.as_ref().map(|g| (g.key.clone(), g.at.clone()));
        let (grading, gradient) = self.curves(grading, &raw, &materials, layering.as_ref())?;
        let walls = match &place {
            Place::Domain(plan, _) => plan.walls,
            Place::Fracture(plan) => plan.walls,
        };
        let (shape, gradient) = self.material_shapes(
            &raw,
            &materials,
            layering.as_ref(),
            (shape, gradient),
            (&packer, walls),
        )?;
        let seed = raw.seed.as_ref().map_or(0, |s| *s.get_ref());
        // The limits hold during the run too, forced or not: force skips
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
            shape: shape.clone(),
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
        let compare = self.shape_compare(&scene, raw.compare.as_ref(), compare)?;
        let output = self.output(
            raw.output.as_ref(),
            scene.shape.is_some(),
            !materials.is_empty(),
        )?;
        Ok(Config {
            scene,
            optimise,
            materials: materials.into_iter().map(|m| m.material).collect(),
            layering,
            fracture,
            compare,
            output,
            sweep: raw.sweep.as_ref().map(|s| self.sweep(s)).transpose()?,
        })
    }

    /// The place in the text where `span` starts.
    fn at(&self, span: &Range<usize>) -> Location {
        Location::at(self.origin, self.text, span.start)
    }
}
