//! `[grading]` (and a material's own): one source of the curve, its
//! values checked; and the scene's curves, from `[grading]` or the materials.

use toml::Spanned;

use super::Validator;
use super::materials::MaterialPlan;
use crate::config::error::{ConfigError, Location};
use crate::config::raw::{Pair, RawConfig, RawGrading, Table};
use crate::grading::{Basis, Grading, Interpolation};
use crate::layering::{LayeringMode, LayeringSettings, SizeGradient};
use crate::names::{BASES, INTERPOLATIONS};

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

/// A checked `[grading]`, not yet built.
#[derive(Clone)]
pub(super) struct GradingPlan {
    curve: Curve,
    interpolation: Interpolation,
    basis: Basis,
    /// Where the curve was given (`grading.table`), blamed for the constructor's errors.
    pub key: String,
    pub at: Location,
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

impl Validator<'_> {
    /// A grading table at key path `path` (`grading`, `materials[1].grading`).
    pub(super) fn grading(
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

    /// The scene's curves: `[grading]`, or in size-graded mode the two
    /// materials' own (the second becomes the gradient). Several materials
    /// need a `[layering]` to place them; material gradings only serve
    /// size-graded mode.
    pub(super) fn curves(
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
                    Some(SizeGradient::new(l.axis, l.profile.clone(), second?)),
                ))
            }
        }
    }
}
