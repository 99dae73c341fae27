//! `[[materials]]`: named materials, their numeric properties, in
//! size-graded mode a grading each, and the particle shape each may have
//! (`[materials.shape]`).

use std::ops::Range;

use toml::Spanned;

use super::grading::GradingPlan;
use super::{KeyAt, Validator};
use crate::config::error::ConfigError;
use crate::config::raw::{RawConfig, RawMaterial, Table};
use crate::geometry::WallMode;
use crate::layering::{LayeringMode, LayeringSettings, Material, SizeGradient};
use crate::scene::{PackerSettings, ShapeSpec};

/// A checked material, with its grading when it gives one.
pub(super) struct MaterialPlan {
    pub material: Material,
    pub grading: Option<(GradingPlan, KeyAt)>,
    /// Where its table starts (`[[materials]]`).
    pub at: Range<usize>,
    /// Its own particle shape (`[materials.shape]`), if it has one.
    pub shape: Option<ShapeSpec>,
}

/// The shape of a particle of a material that has none of its own in a
/// scene of shapes: a disk, drawn as a superellipse of aspect 1 and
/// exponent 2 (a circle) by the particles' packer.
fn round() -> ShapeSpec {
    ShapeSpec::ellipses(1.0)
}

/// `error`, found in a material's shape table, blamed on
/// `materials[i].shape.…` rather than on the top-level `shape.…`.
fn in_material(error: ConfigError, i: usize) -> ConfigError {
    let Some(key) = error.key().map(|k| format!("materials[{i}].{k}")) else {
        return error;
    };
    let at = error.location().clone();
    error.relocated(at, key)
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
            let shape = m
                .shape
                .as_ref()
                .map(|s| self.shape(s).map_err(|e| in_material(e, i)))
                .transpose()?;
            plans.push(MaterialPlan {
                material: Material {
                    name: name.to_owned(),
                    properties,
                },
                grading,
                at: table.span(),
                shape,
            });
        }
        Ok(plans)
    }

    /// The scene's shape and size gradient once the materials' own shapes
    /// are known (`shape`: the top-level `[shape]`; `gradient`: the
    /// size-graded mode's, if any).
    ///
    /// # Behavior
    /// A material without a shape of its own takes the top-level one; in a
    /// scene where some material has a shape and there is no top-level
    /// one, it is of disks, packed as circles (superellipses of aspect 1,
    /// exponent 2). In size-graded mode the first material's shape is the
    /// scene's and the second's, when it differs, the gradient's
    /// `second_shape`: each particle is drawn with its material's shape.
    /// Otherwise (materials mode: materials assigned to a packing made
    /// once) the geometry cannot depend on the material, so materials of
    /// different shapes are refused at the first shape table that differs,
    /// pointing to `mode = "sizes"`. Each material's shape table is held
    /// to what the scene's `[shape]` is held to (`check_shape_support`).
    pub(super) fn material_shapes(
        &self,
        raw: &RawConfig,
        materials: &[MaterialPlan],
        layering: Option<&LayeringSettings>,
        (shape, gradient): (Option<ShapeSpec>, Option<SizeGradient>),
        (packer, walls): (&PackerSettings, WallMode),
    ) -> Result<(Option<ShapeSpec>, Option<SizeGradient>), ConfigError> {
        let tables = raw.materials.as_deref().unwrap_or(&[]);
        let own = tables
            .iter()
            .enumerate()
            .filter_map(|(i, t)| t.get_ref().shape.as_ref().map(|s| (i, s)));
        for (i, table) in own {
            self.check_shape_support(table, packer, walls)
                .map_err(|e| in_material(e, i))?;
        }
        if materials.iter().all(|m| m.shape.is_none()) {
            return Ok((shape, gradient));
        }
        let resolved: Vec<ShapeSpec> = materials
            .iter()
            .map(|m| {
                m.shape
                    .clone()
                    .or_else(|| shape.clone())
                    .unwrap_or_else(round)
            })
            .collect();
        let sizes = layering.is_some_and(|l| l.mode == LayeringMode::Sizes);
        if sizes && let (Some(g), [first, second]) = (gradient.clone(), resolved.as_slice()) {
            let g = if second == first {
                g
            } else {
                g.with_second_shape(second.clone())
            };
            return Ok((Some(first.clone()), Some(g)));
        }
        if let Some(i) = resolved.iter().position(|s| *s != resolved[0]) {
            // The first material that has a shape of its own and differs
            // from the first material's (or the second, if the first's own
            // shape is the odd one).
            let blamed = (i..materials.len())
                .chain(0..i)
                .find(|&j| materials[j].shape.is_some())
                .unwrap_or(i);
            let span = tables
                .get(blamed)
                .and_then(|t| t.get_ref().shape.as_ref())
                .map_or(materials[blamed].at.clone(), Spanned::span);
            return Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: format!("materials[{blamed}].shape"),
                reason: format!(
                    "materials {:?} and {:?} have different particle shapes: in [layering] mode = \"materials\" the packing is made once and materials are assigned to its particles afterwards, so every material must have the same shape; use mode = \"sizes\" (each particle drawn with its material's shape as it is packed), or give the materials one [shape]",
                    materials[0].material.name, materials[i].material.name
                ),
            });
        }
        Ok((resolved.into_iter().next(), gradient))
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
