//! The scene as a whole, whatever table gives its domain: wide enough for
//! the smallest disk, resolvable in floating point, walls it can hold.

use toml::Spanned;

use super::{KeyAt, Validator};
use crate::Scene;
use crate::config::error::{ConfigError, Location};
use crate::geometry::predicates::RESOLUTION_REL;
use crate::geometry::{Domain, WallMode};
use crate::packer::PackError;

/// How many times the widest disk the domain holds the smallest size must
/// be for the grading, not the domain, to be blamed.
const SIZES_DWARF: f64 = 2.0;

/// Smallest `wall_disk` as a fraction of the smallest diameter. Finer wall
/// disks leave the same packing (the wall is already flat to 1 %) while the
/// packer's work at a wall grows with the wall disks a particle touches: a
/// 400-disk square packs in 0.15 s at 1/100 and in minutes at 1/50 000.
const MIN_WALL_DISK_FRACTION: f64 = 0.01;

impl Validator<'_> {
    /// Refuse a domain whose largest disk inside the walls (wall disks
    /// included) is smaller than the smallest disk. Sizes [`SIZES_DWARF`]
    /// times what the domain holds are the grading's fault, most likely
    /// given in micrometres: `sizes_key` (the curve's key) is blamed then.
    pub(super) fn check_width(
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

    /// Refuse a scene whose smallest disk is below
    /// [`RESOLUTION_REL`] of its largest |coordinate|, blaming `key` (the
    /// key that sets that coordinate): floating point could not keep its
    /// disks from overlapping there.
    pub(super) fn check_resolution(&self, scene: &Scene, key: &KeyAt) -> Result<(), ConfigError> {
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
    pub(super) fn check_walls(
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
}
