//! `[[materials]]`: named materials, their numeric properties, and in
//! size-graded mode a grading each.

use std::ops::Range;

use toml::Spanned;

use super::grading::GradingPlan;
use super::{KeyAt, Validator};
use crate::config::error::ConfigError;
use crate::config::raw::{RawMaterial, Table};
use crate::layering::Material;

/// A checked material, with its grading when it gives one.
pub(super) struct MaterialPlan {
    pub material: Material,
    pub grading: Option<(GradingPlan, KeyAt)>,
    /// Where its table starts (`[[materials]]`).
    pub at: Range<usize>,
}

impl Validator<'_> {
    /// `[[materials]]`: names given once, properties numbers.
    pub(super) fn materials(
        &self,
        raw: &[Spanned<Table<RawMaterial>>],
    ) -> Result<Vec<MaterialPlan>, ConfigError> {
        let mut plans: Vec<MaterialPlan> = Vec::with_capacity(raw.len());
        for (i, table) in raw.iter().enumerate() {
            let m = table.get_ref();
            let name = m.name.get_ref().trim();
            if name.is_empty() || plans.iter().any(|p| p.material.name == name) {
                let reason = if name.is_empty() {
                    "a material needs a name".to_owned()
                } else {
                    format!("{name:?} is given twice")
                };
                return Err(ConfigError::NotApplicable {
                    at: self.at(&m.name.span()),
                    key: format!("materials[{i}].name"),
                    reason,
                });
            }
            let mut properties = Vec::with_capacity(m.properties.len());
            for (key, value) in &m.properties {
                let number = match value {
                    toml::Value::Integer(n) => Some(*n as f64),
                    toml::Value::Float(x) if x.is_finite() => Some(*x),
                    _ => None,
                };
                let Some(number) = number else {
                    return Err(ConfigError::Schema {
                        at: self.at(&self.key_after(table.span().end, key)),
                        key: format!("materials[{i}].{key}"),
                        message: format!(
                            "a material property must be a finite number, got {value}"
                        ),
                    });
                };
                if key == "density" && number <= 0.0 {
                    return Err(ConfigError::NotPositive {
                        at: self.at(&self.key_after(table.span().end, key)),
                        key: format!("materials[{i}].density"),
                        value: number,
                    });
                }
                properties.push((key.clone(), number));
            }
            let path = format!("materials[{i}].grading");
            let grading = match &m.grading {
                None => None,
                Some(g) => Some((
                    self.grading(g, &path)?,
                    KeyAt {
                        key: path,
                        span: g.span(),
                    },
                )),
            };
            plans.push(MaterialPlan {
                material: Material {
                    name: name.to_owned(),
                    properties,
                },
                grading,
                at: table.span(),
            });
        }
        Ok(plans)
    }

    /// Where `key = …` is written in the table whose header ends at `from`
    /// (the header's place if it cannot be found).
    fn key_after(&self, from: usize, key: &str) -> Range<usize> {
        let mut offset = from.min(self.text.len());
        for line in self.text[offset..].split_inclusive('\n') {
            let trimmed = line.trim_start();
            if trimmed.starts_with('[') && offset > from {
                break;
            }
            if let Some(rest) = trimmed.strip_prefix(key)
                && rest.trim_start().starts_with('=')
            {
                let start = offset + (line.len() - trimmed.len());
                return start..start + key.len();
            }
            offset += line.len();
        }
        from..from
    }
}
