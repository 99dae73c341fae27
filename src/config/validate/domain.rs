//! `[domain]`: the shape and the keys that size it, the wall model, and
//! the domain built by its constructor.

use std::ops::Range;

use toml::Spanned;

use super::{KeyAt, Validator};
use crate::config::error::ConfigError;
use crate::config::raw::{RawDomain, Table};
use crate::geometry::{Domain, GeometryError, Point, WallMode};
use crate::names::{SHAPES, ShapeKind, WALLS};

/// A checked `[domain]`, not yet built.
pub(super) struct DomainPlan {
    shape: ShapePlan,
    pub walls: WallMode,
    pub wall_disk: Option<f64>,
    /// The key that sets how wide the domain is (blamed when it is too narrow).
    pub width_key: KeyAt,
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

impl Validator<'_> {
    pub(super) fn domain(
        &self,
        raw: &Spanned<Table<RawDomain>>,
    ) -> Result<DomainPlan, ConfigError> {
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
    pub(super) fn check_area(
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
    pub(super) fn walls(
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
    pub(super) fn build_domain(
        &self,
        plan: &DomainPlan,
        raw: &RawDomain,
    ) -> Result<Domain, ConfigError> {
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
    pub(super) fn geometry_error(&self, error: GeometryError, d: &RawDomain) -> ConfigError {
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
}

/// The key of `[domain]` whose value sets the domain's largest |coordinate|.
pub(super) fn coordinate_key(plan: &DomainPlan, d: &RawDomain) -> KeyAt {
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
