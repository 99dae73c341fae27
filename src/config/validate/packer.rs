//! `[packer]`: the method and its settings, and the strips and methods the
//! scene allows.

use toml::Spanned;

use super::Validator;
use crate::Scene;
use crate::config::error::ConfigError;
use crate::config::raw::{RawConfig, RawPacker, RawStrips};
use crate::geometry::predicates::OVERLAP_REL;
use crate::names::{CONTACTS, FILLS, INDEXES, METHODS, RULES};
use crate::packer::{
    DEFAULT_ATTEMPTS, Densify, Fill, MAX_DEFERRED, MAX_GAP, Method, PackerSettings, Relaxation,
    Strips, strips,
};

/// Largest `packer.attempts`: more tries per disk than this would run for hours.
const MAX_ATTEMPTS: i64 = 10_000_000;

/// Largest `packer.strips`.
const MAX_STRIPS: i64 = 100_000;

/// Largest `packer.relaxation_iterations` and `packer.densify_iterations`, for the same reason.
const MAX_ITERATIONS: i64 = 1_000_000;

impl Validator<'_> {
    pub(super) fn packer(&self, raw: Option<&RawPacker>) -> Result<PackerSettings, ConfigError> {
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
    pub(super) fn strips(&self, raw: Option<&Spanned<RawStrips>>) -> Result<Strips, ConfigError> {
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
            RawStrips::Other(value) => Err(ConfigError::Schema {
                at: self.at(&v.span()),
                key: "packer.strips".to_owned(),
                message: format!(
                    "must be a whole number in [1, {MAX_STRIPS}] or \"auto\", got {}",
                    written(value)
                ),
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
    pub(super) fn check_strips(
        &self,
        scene: &Scene,
        raw: Option<&RawPacker>,
    ) -> Result<(), ConfigError> {
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

    /// Refuse a comparison method where only the advancing front serves:
    /// the GA's packing kernel and size-graded packing.
    pub(super) fn check_method(&self, scene: &Scene, raw: &RawConfig) -> Result<(), ConfigError> {
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
}

/// A value as a message quotes it: its TOML text (`2.5`, `true`, `[1]`),
/// or its type when that text is long.
fn written(value: &toml::Value) -> String {
    /// Longest text quoted whole.
    const LONGEST: usize = 40;
    let text = value.to_string();
    if text.len() <= LONGEST && !text.contains('\n') {
        return text;
    }
    match value {
        toml::Value::Array(_) => "an array".to_owned(),
        toml::Value::Table(_) => "a table".to_owned(),
        other => other.type_str().to_owned(),
    }
}
