//! `walls = "periodic"`: a rectangle as a periodic cell, and what a
//! periodic cell cannot be asked for.

use toml::Spanned;

use super::{KeyAt, Validator};
use crate::Scene;
use crate::compare::CompareSettings;
use crate::config::error::ConfigError;
use crate::config::raw::{RawCompare, RawConfig, RawDomain, Table};
use crate::geometry::WallMode;
use crate::names::{ConfigName, ShapeKind};
use crate::packer::{PackError, packs_periodic};

impl Validator<'_> {
    /// Refuse `domain.walls = "periodic"` on a shape other than a
    /// rectangle: only a rectangle tiles the plane as a periodic cell.
    pub(super) fn periodic_shape(
        &self,
        walls: WallMode,
        kind: ShapeKind,
        d: &RawDomain,
    ) -> Result<(), ConfigError> {
        match (walls, &d.walls) {
            (WallMode::Periodic, Some(given)) if kind != ShapeKind::Rectangle => {
                Err(ConfigError::NotApplicable {
                    at: self.at(&given.span()),
                    key: "domain.walls".to_owned(),
                    reason: format!(
                        "\"periodic\" needs shape = \"rectangle\" (only a rectangle tiles the plane as a periodic cell); shape {:?} has walls: use walls = \"exact\" or \"disks\"",
                        d.shape.get_ref()
                    ),
                })
            }
            _ => Ok(()),
        }
    }

    /// Refuse `fracture.walls = "periodic"`: a fracture is bounded by its faces.
    pub(super) fn periodic_fracture(
        &self,
        walls: WallMode,
        given: Option<&Spanned<String>>,
    ) -> Result<(), ConfigError> {
        match given {
            Some(given) if walls == WallMode::Periodic => Err(ConfigError::NotApplicable {
                at: self.at(&given.span()),
                key: "fracture.walls".to_owned(),
                reason: "a fracture is bounded by its faces, not a periodic cell; for a bulk sample without walls give a [domain] rectangle with walls = \"periodic\"".to_owned(),
            }),
            _ => Ok(()),
        }
    }

    /// For a periodic cell: refuse a cell under twice the largest diameter
    /// (blaming its shorter side's key) and a method that packs against
    /// walls (blaming `packer.method`).
    pub(super) fn check_periodic(
        &self,
        scene: &Scene,
        raw: &RawConfig,
        width_key: &KeyAt,
    ) -> Result<(), ConfigError> {
        let Some(period) = scene.domain.period() else {
            return Ok(());
        };
        let (side, d_max) = (period.x.min(period.y), scene.d_max());
        if side < 2.0 * d_max {
            return Err(ConfigError::Scene {
                at: self.at(&width_key.span),
                key: width_key.key.clone(),
                error: PackError::PeriodicCellTooSmall { side, d_max },
                hint: String::new(),
            });
        }
        let method = scene.packer.method;
        if !packs_periodic(method)
            && let Some(given) = raw.packer.as_ref().and_then(|p| p.method.as_ref())
        {
            return Err(ConfigError::NotApplicable {
                at: self.at(&given.span()),
                key: "packer.method".to_owned(),
                reason: format!(
                    "{:?} packs against walls and does not pack periodic cells (domain.walls = \"periodic\"); use \"advancing-front\", \"rsa\", \"relaxation\" or \"densify\"",
                    method.config_name()
                ),
            });
        }
        Ok(())
    }

    /// `[compare]` of a periodic cell: the default methods less those that
    /// pack against walls; a method named that does refused at its key.
    pub(super) fn periodic_compare(
        &self,
        scene: &Scene,
        raw: Option<&Spanned<Table<RawCompare>>>,
        settings: CompareSettings,
    ) -> Result<CompareSettings, ConfigError> {
        if !scene.domain.is_periodic() {
            return Ok(settings);
        }
        self.methods_that(
            raw,
            settings,
            packs_periodic,
            "packs against walls and does not pack periodic cells (domain.walls = \"periodic\")",
        )
    }
}
