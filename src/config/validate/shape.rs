//! `[shape]`: the particles' outlines, their orientation and the size the
//! grading measures; and the scenes this version packs them in.

use std::ops::Range;

use toml::Spanned;

use super::Validator;
use crate::config::error::ConfigError;
use crate::config::raw::{RawShape, RawSpread, RawTemplate, Table};
use crate::geometry::{Outline, WallMode};
use crate::names::{ConfigName, Names};
use crate::scene::{
    Family, Fill, FrontRules, MAX_ASPECT, MAX_EXPONENT, Method, Orientation, PackerSettings,
    Proppant, ShapeSpec, SizeMeasure, Spread, Strips, template_vertices,
};

/// How far from 1 the shares of a table or of the templates may sum.
const SHARE_TOLERANCE: f64 = 1e-9;

/// Most `[[shape.templates]]`: a template's index is kept in 16 bits, and
/// a mix of more templates than this describes no real material.
const MAX_TEMPLATES: usize = 1000;

/// Most vertices of a template: every contact test visits them all.
const MAX_TEMPLATE_VERTICES: usize = 100;

/// What this version packs particle shapes with, said by every refusal of
/// a scene that cannot have them.
const SUPPORTED: &str = "particle shapes are packed in this version with packer.method = \"advancing-front\" (two or one contact) or \"rsa\", in a [domain] or [fracture] with walls = \"exact\", or as a periodic cell";

/// The outline families, as `shape.kind` names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Kind {
    #[default]
    Superellipse,
    Polygon,
}

const KINDS: Names<Kind> = Names {
    what: "particle shape",
    entries: &[
        ("superellipse", Kind::Superellipse),
        ("polygon", Kind::Polygon),
    ],
};

/// The orientations, as `shape.orientation` names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Turning {
    #[default]
    Random,
    Aligned,
}

const ORIENTATIONS: Names<Turning> = Names {
    what: "orientation",
    entries: &[("random", Turning::Random), ("aligned", Turning::Aligned)],
};

/// The proppant presets, as `shape.preset` names them.
const PRESETS: Names<Proppant> = Names {
    what: "proppant preset",
    entries: &[
        ("ceramic", Proppant::Ceramic),
        ("resin-coated-sand", Proppant::ResinCoatedSand),
        ("angular-sand", Proppant::AngularSand),
    ],
};

const SIZES: Names<SizeMeasure> = Names {
    what: "size measure",
    entries: &[
        ("sieve", SizeMeasure::Sieve),
        ("equivalent", SizeMeasure::Equivalent),
    ],
};

/// The values a quantity of `[shape]` may take, in words for the messages.
pub(super) struct Bounds {
    least: f64,
    least_words: String,
    most: f64,
    most_words: String,
}

/// `shape.aspect`: from a disk's 1 to [`MAX_ASPECT`].
pub(super) fn aspect_bounds() -> Bounds {
    Bounds {
        least: 1.0,
        least_words: "at least 1 (the long axis over the short one, a/b)".to_owned(),
        most: MAX_ASPECT,
        most_words: format!(
            "at most {MAX_ASPECT}: thinner particles make the contact solving lose precision"
        ),
    }
}

/// `shape.alpha`, `shape.beta`: from a rhombus' 1 to [`MAX_EXPONENT`].
pub(super) fn exponent_bounds() -> Bounds {
    Bounds {
        least: 1.0,
        least_words: "at least 1: an exponent below 1 makes the particle non-convex (its sides curve inwards), and gapack certifies no overlap between non-convex particles; use exponents of 1 or more".to_owned(),
        most: MAX_EXPONENT,
        most_words: format!(
            "at most {MAX_EXPONENT}: blockier particles make the contact solving lose precision"
        ),
    }
}

/// `x` to 12 decimals, for a message (`0.3`, not `0.30000000000000004`).
fn tidy(x: f64) -> f64 {
    (x * 1e12).round() / 1e12
}

impl Validator<'_> {
    /// `[shape]`, its values checked and its templates built.
    pub(super) fn shape(&self, raw: &Spanned<Table<RawShape>>) -> Result<ShapeSpec, ConfigError> {
        let s = raw.get_ref();
        if let Some(preset) = &s.preset {
            return Ok(ShapeSpec {
                family: self.preset(s, preset)?.family(),
                orientation: self.orientation(s)?,
                size: self.name(&SIZES, "shape.size", s.size.as_ref())?,
            });
        }
        let kind = self.name(&KINDS, "shape.kind", s.kind.as_ref())?;
        if s.kind.is_none() {
            return Err(ConfigError::Missing {
                at: self.at(&raw.span()),
                key: "shape.kind".to_owned(),
                reason: format!(
                    "give kind = \"superellipse\" or \"polygon\" with its outline, or a proppant's preset ({})",
                    PRESETS.valid().join(", ")
                ),
            });
        }
        let family = match kind {
            Kind::Superellipse => {
                if let Some(t) = s.templates.as_ref().and_then(|t| t.first()) {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&t.span()),
                        key: "shape.templates".to_owned(),
                        reason: "applies only to kind = \"polygon\"".to_owned(),
                    });
                }
                let Some(aspect) = &s.aspect else {
                    return Err(ConfigError::Missing {
                        at: self.at(&raw.span()),
                        key: "shape.aspect".to_owned(),
                        reason: "kind = \"superellipse\" needs its aspect ratio a/b (1 for a round outline)".to_owned(),
                    });
                };
                let aspect = self.spread("shape.aspect", aspect, &aspect_bounds())?;
                let alpha = match &s.alpha {
                    None => Spread::Fixed(2.0),
                    Some(v) => self.spread("shape.alpha", v, &exponent_bounds())?,
                };
                let beta = match &s.beta {
                    None => alpha.clone(),
                    Some(v) => self.spread("shape.beta", v, &exponent_bounds())?,
                };
                Family::Superellipse {
                    aspect,
                    alpha,
                    beta,
                }
            }
            Kind::Polygon => {
                let keys = [
                    ("aspect", &s.aspect),
                    ("alpha", &s.alpha),
                    ("beta", &s.beta),
                ];
                if let Some((key, Some(v))) = keys.into_iter().find(|(_, v)| v.is_some()) {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&v.span()),
                        key: format!("shape.{key}"),
                        reason: "applies only to kind = \"superellipse\" (a polygon's outline is its template's)".to_owned(),
                    });
                }
                let templates = match s.templates.as_deref() {
                    None | Some([]) => {
                        return Err(ConfigError::Missing {
                            at: self.at(&raw.span()),
                            key: "shape.templates".to_owned(),
                            reason: "kind = \"polygon\" needs at least one [[shape.templates]] with its vertices".to_owned(),
                        });
                    }
                    Some(t) => self.templates(t)?,
                };
                Family::Polygons { templates }
            }
        };
        Ok(ShapeSpec {
            family,
            orientation: self.orientation(s)?,
            size: self.name(&SIZES, "shape.size", s.size.as_ref())?,
        })
    }

    /// `shape.preset`: a known proppant, given without the keys of an
    /// outline family (the preset is the outline).
    fn preset(&self, s: &RawShape, preset: &Spanned<String>) -> Result<Proppant, ConfigError> {
        let proppant = PRESETS
            .get(preset.get_ref())
            .ok_or_else(|| ConfigError::UnknownName {
                at: self.at(&preset.span()),
                key: "shape.preset".to_owned(),
                what: PRESETS.what,
                given: format!("{:?}", preset.get_ref()),
                valid: PRESETS.valid(),
            })?;
        let spans = [
            ("kind", s.kind.as_ref().map(Spanned::span)),
            ("aspect", s.aspect.as_ref().map(Spanned::span)),
            ("alpha", s.alpha.as_ref().map(Spanned::span)),
            ("beta", s.beta.as_ref().map(Spanned::span)),
            (
                "templates",
                s.templates
                    .as_ref()
                    .and_then(|t| t.first())
                    .map(Spanned::span),
            ),
        ];
        if let Some((key, span)) = spans
            .into_iter()
            .filter_map(|(k, span)| span.map(|span| (k, span)))
            .min_by_key(|(_, span)| span.start)
        {
            return Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: format!("shape.{key}"),
                reason: format!(
                    "preset = {:?} gives the particles' outline: give a preset, or kind with aspect, alpha, beta or templates, not both (a preset takes size and orientation)",
                    preset.get_ref()
                ),
            });
        }
        Ok(proppant)
    }

    /// `shape.orientation` with its `angle` and `spread` (degrees in the
    /// config, radians in the spec).
    fn orientation(&self, s: &RawShape) -> Result<Orientation, ConfigError> {
        let turning = self.name(&ORIENTATIONS, "shape.orientation", s.orientation.as_ref())?;
        let keys = [("angle", &s.angle), ("spread", &s.spread)];
        if turning == Turning::Random {
            if let Some((key, Some(v))) = keys.into_iter().find(|(_, v)| v.is_some()) {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&v.span()),
                    key: format!("shape.{key}"),
                    reason: "applies only to orientation = \"aligned\" (random orientations have no mean angle or spread)".to_owned(),
                });
            }
            return Ok(Orientation::Random);
        }
        let mean = match &s.angle {
            None => 0.0,
            Some(v) if v.get_ref().is_finite() => *v.get_ref(),
            Some(v) => {
                return Err(ConfigError::NotFinite {
                    at: self.at(&v.span()),
                    key: "shape.angle".to_owned(),
                    value: *v.get_ref(),
                });
            }
        };
        let spread = match &s.spread {
            None => 0.0,
            Some(v) => self.checked("shape.spread", v, "a finite number ≥ 0 (degrees)", |v| {
                v.is_finite() && v >= 0.0
            })?,
        };
        Ok(Orientation::Aligned {
            mean: mean.to_radians(),
            spread: spread.to_radians(),
        })
    }

    /// A value of a quantity at `key`: positive, finite and within `bounds`.
    pub(super) fn bounded(
        &self,
        key: &str,
        value: f64,
        span: &Range<usize>,
        bounds: &Bounds,
    ) -> Result<f64, ConfigError> {
        let out_of_range = |range: &str| ConfigError::OutOfRange {
            at: self.at(span),
            key: key.to_owned(),
            range: range.to_owned(),
            value,
        };
        if !(value.is_finite() && value > 0.0) {
            Err(ConfigError::NotPositive {
                at: self.at(span),
                key: key.to_owned(),
                value,
            })
        } else if value < bounds.least {
            Err(out_of_range(&bounds.least_words))
        } else if value > bounds.most {
            Err(out_of_range(&bounds.most_words))
        } else {
            Ok(value)
        }
    }

    /// A quantity at `key` in any of its forms, every value within `bounds`.
    fn spread(
        &self,
        key: &str,
        raw: &Spanned<RawSpread>,
        bounds: &Bounds,
    ) -> Result<Spread, ConfigError> {
        match raw.get_ref() {
            RawSpread::Fixed(v) => Ok(Spread::Fixed(self.bounded(key, *v, &raw.span(), bounds)?)),
            RawSpread::Range(lo, hi) => {
                let l = self.bounded(&format!("{key}[0]"), *lo.get_ref(), &lo.span(), bounds)?;
                let h = self.bounded(&format!("{key}[1]"), *hi.get_ref(), &hi.span(), bounds)?;
                if l > h {
                    return Err(ConfigError::OutOfRange {
                        at: self.at(&hi.span()),
                        key: format!("{key}[1]"),
                        range: format!("at least the low end {l}: a range is [low, high]"),
                        value: h,
                    });
                }
                Ok(Spread::Range(l, h))
            }
            RawSpread::Shares(table) => {
                let (values, shares) = (&table.values, &table.shares);
                if values.get_ref().is_empty() {
                    return Err(ConfigError::Schema {
                        at: self.at(&values.span()),
                        key: format!("{key}.values"),
                        message: "needs at least one value".to_owned(),
                    });
                }
                if shares.get_ref().len() != values.get_ref().len() {
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&shares.span()),
                        key: format!("{key}.shares"),
                        reason: format!(
                            "has {} shares for {} values: give one share per value",
                            shares.get_ref().len(),
                            values.get_ref().len()
                        ),
                    });
                }
                let mut rows = Vec::with_capacity(values.get_ref().len());
                let mut given = Vec::with_capacity(rows.capacity());
                for (i, (v, s)) in values.get_ref().iter().zip(shares.get_ref()).enumerate() {
                    let v = self.bounded(
                        &format!("{key}.values[{i}]"),
                        *v.get_ref(),
                        &v.span(),
                        bounds,
                    )?;
                    let share_key = format!("{key}.shares[{i}]");
                    let share = self.positive(&share_key, s)?;
                    given.push((share_key, s.span(), share));
                    rows.push((v, share));
                }
                self.shares_sum(&given)?;
                Ok(Spread::Shares(rows))
            }
        }
    }

    /// Shares (key, place, value) that must sum to 1 within
    /// [`SHARE_TOLERANCE`]; the last one is blamed, with the value that
    /// would make the sum 1.
    fn shares_sum(&self, shares: &[(String, Range<usize>, f64)]) -> Result<(), ConfigError> {
        let sum: f64 = shares.iter().map(|s| s.2).sum();
        let Some((key, span, last)) = shares.last() else {
            return Ok(());
        };
        if (sum - 1.0).abs() <= SHARE_TOLERANCE {
            return Ok(());
        }
        let others = sum - last;
        let range = if others < 1.0 {
            format!(
                "{} for the shares to sum to 1 (within {SHARE_TOLERANCE:e}; they sum to {})",
                tidy(1.0 - others),
                tidy(sum)
            )
        } else {
            format!(
                "smaller: the shares must sum to 1 (within {SHARE_TOLERANCE:e}), and those before it sum to {} already",
                tidy(others)
            )
        };
        Err(ConfigError::OutOfRange {
            at: self.at(span),
            key: key.clone(),
            range,
            value: *last,
        })
    }

    /// `[[shape.templates]]`: each polygon built (convex, at least 3
    /// vertices, aspect at most [`MAX_ASPECT`]) with its share.
    fn templates(
        &self,
        raw: &[Spanned<Table<RawTemplate>>],
    ) -> Result<Vec<(Outline, f64)>, ConfigError> {
        if let Some(extra) = raw.get(MAX_TEMPLATES) {
            return Err(ConfigError::OutOfRange {
                at: self.at(&extra.span()),
                key: "shape.templates".to_owned(),
                range: format!("at most {MAX_TEMPLATES} templates"),
                value: raw.len() as f64,
            });
        }
        let mut outlines = Vec::with_capacity(raw.len());
        let mut shares = Vec::with_capacity(raw.len());
        for (i, t) in raw.iter().enumerate() {
            let key = format!("shape.templates[{i}]");
            let vertices = &t.get_ref().vertices;
            let vertices_key = format!("{key}.vertices");
            if vertices.get_ref().len() > MAX_TEMPLATE_VERTICES {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&vertices.span()),
                    key: vertices_key,
                    range: format!(
                        "at most {MAX_TEMPLATE_VERTICES} vertices: every contact test visits them all"
                    ),
                    value: vertices.get_ref().len() as f64,
                });
            }
            let mut points = Vec::with_capacity(vertices.get_ref().len());
            for (j, p) in vertices.get_ref().iter().enumerate() {
                points.push(self.finite_pair(&format!("{vertices_key}[{j}]"), p)?);
            }
            let rounding = match &t.get_ref().rounding {
                None => 0.0,
                Some(v) => self.checked(
                    &format!("{key}.rounding"),
                    v,
                    "a finite number ≥ 0 (in the template's units)",
                    |v| v.is_finite() && v >= 0.0,
                )?,
            };
            // MAX_TEMPLATES keeps the index within 16 bits.
            let index = u16::try_from(i).unwrap_or(u16::MAX);
            let outline = Outline::polygon(index, &template_vertices(&points), rounding).map_err(
                |error| ConfigError::Outline {
                    at: self.at(&vertices.span()),
                    key: vertices_key.clone(),
                    error,
                },
            )?;
            let aspect = outline.aspect();
            if aspect > MAX_ASPECT {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&vertices.span()),
                    key: vertices_key,
                    range: format!(
                        "a particle of aspect at most {MAX_ASPECT} (greatest over least width): thinner particles make the contact solving lose precision"
                    ),
                    value: aspect,
                });
            }
            let share_key = format!("{key}.share");
            let share = t
                .get_ref()
                .share
                .as_ref()
                .map(|v| {
                    self.positive(&share_key, v)
                        .map(|s| (share_key, v.span(), s))
                })
                .transpose()?;
            outlines.push(outline);
            shares.push((t.span(), share));
        }
        let given: Vec<_> = shares.iter().filter_map(|(_, s)| s.clone()).collect();
        if given.is_empty() {
            let share = 1.0 / outlines.len() as f64;
            return Ok(outlines.into_iter().map(|o| (o, share)).collect());
        }
        if let Some(i) = shares.iter().position(|(_, s)| s.is_none()) {
            return Err(ConfigError::Missing {
                at: self.at(&shares[i].0),
                key: format!("shape.templates[{i}].share"),
                reason: "give every template a share, or none (equal shares)".to_owned(),
            });
        }
        self.shares_sum(&given)?;
        Ok(outlines
            .into_iter()
            .zip(given)
            .map(|(o, (_, _, share))| (o, share))
            .collect())
    }

    /// Refuse `[shape]` (or a material's shape table) in a config this
    /// version cannot pack shapes for: another job's table, another
    /// method, strips, filling right, a one-contact gap, the thesis' front
    /// rules, or wall disks. A
    /// `[sweep]` is taken: its runs are pack jobs (planning refuses the
    /// others for shapes).
    pub(super) fn check_shape_support(
        &self,
        shape: &Spanned<Table<RawShape>>,
        packer: &PackerSettings,
        walls: WallMode,
    ) -> Result<(), ConfigError> {
        let conflict = if !matches!(packer.method, Method::AdvancingFront | Method::Rsa) {
            Some(format!(
                "packer.method = \"{}\"",
                packer.method.config_name()
            ))
        } else if matches!(packer.strips, Strips::Count(n) if n > 1) {
            Some("packer.strips (packing in strips)".to_owned())
        } else if packer.fill == Fill::Right {
            Some("packer.fill = \"right\" (the scene mirrored and packed as disks); leave fill = \"up\"".to_owned())
        } else if packer.gap > 0.0 {
            Some("packer.gap (the one-contact clearance is kept between disks only; shapes at one contact keep none)".to_owned())
        } else if packer.rules == FrontRules::Thesis {
            Some("packer.rules = \"thesis\" (shapes follow the robust rules: failing fronts parked, sizes deferred)".to_owned())
        } else if walls == WallMode::Disks {
            Some(
                "walls = \"disks\" (wall disks would need shape-aware wall particles; use walls = \"exact\")"
                    .to_owned(),
            )
        } else {
            None
        };
        match conflict {
            None => Ok(()),
            Some(what) => Err(ConfigError::NotApplicable {
                at: self.at(&shape.span()),
                key: "shape".to_owned(),
                reason: format!("particle shapes cannot be packed with {what}; {SUPPORTED}"),
            }),
        }
    }
}
