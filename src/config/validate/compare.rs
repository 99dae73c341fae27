//! `[compare]`: the methods `gapack compare` runs, and how many seeds.

use toml::Spanned;

use super::Validator;
use crate::Scene;
use crate::compare::CompareSettings;
use crate::config::error::ConfigError;
use crate::config::raw::{RawCompare, Table};
use crate::names::METHODS;
use crate::packer::Method;

/// Largest `compare.repeats`.
const MAX_REPEATS: i64 = 1000;

impl Validator<'_> {
    /// `[compare]`: known method names, given once; at least one repeat.
    pub(super) fn compare(
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

    /// `[compare]` of particle shapes: the default methods less those that
    /// pack disks only; a method named that does refused at its key.
    pub(super) fn shape_compare(
        &self,
        scene: &Scene,
        raw: Option<&Spanned<Table<RawCompare>>>,
        settings: CompareSettings,
    ) -> Result<CompareSettings, ConfigError> {
        if scene.shape.is_none() {
            return Ok(settings);
        }
        self.methods_that(
            raw,
            settings,
            |m| matches!(m, Method::AdvancingFront | Method::Rsa),
            "packs disks only, not the particles of [shape] (the advancing front and rsa pack them)",
        )
    }

    /// `settings` with only the methods `keep` takes; a method the config
    /// names that it does not take is refused at its key, saying `why`.
    pub(super) fn methods_that(
        &self,
        raw: Option<&Spanned<Table<RawCompare>>>,
        mut settings: CompareSettings,
        keep: impl Fn(Method) -> bool,
        why: &str,
    ) -> Result<CompareSettings, ConfigError> {
        let named = raw.and_then(|c| c.get_ref().methods.as_ref());
        if let Some(methods) = named {
            for (i, (name, &method)) in methods.get_ref().iter().zip(&settings.methods).enumerate()
            {
                if !keep(method) {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&name.span()),
                        key: format!("compare.methods[{i}]"),
                        reason: format!("{:?} {why}; leave it out", name.get_ref()),
                    });
                }
            }
        }
        settings.methods.retain(|&m| keep(m));
        Ok(settings)
    }
}
