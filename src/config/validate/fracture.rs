//! `[fracture]`: one fracture (absolute or normalised form), or a batch of wells.

use toml::Spanned;

use super::{KeyAt, Validator};
use crate::config::error::ConfigError;
use crate::config::raw::{RawConfig, RawFracture, RawWell, Table};
use crate::fracture::{DEFAULT_WINDOW_TOLERANCE, Extent, Fracture, MM_PER_M};
use crate::geometry::WallMode;
use crate::names::{EXTENTS, ExtentKind, FILLS};
use crate::output::WELLS_CSV;
use crate::packer::Fill;

/// Largest `window_tolerance` accepted: beyond it a window estimates nothing.
const MAX_WINDOW_TOLERANCE: f64 = 0.1;

/// The files a batch writes at the top of its folder, beside one folder per
/// well (`jobs::run`: the wells table, the manifest, and the checkpoint of
/// the jobs that keep one): a well named like one of them would collide
/// with it. The jobs layer sits above this one, so its names are repeated
/// here; a test pins them to `jobs::MANIFEST_JSON` and `jobs::CHECKPOINT_JSON`.
pub(crate) const BATCH_FILES: [&str; 3] = [WELLS_CSV, "manifest.json", "checkpoint.json"];

/// Whether two well names give one folder: equal, or equal but for case
/// (output folders may be on a case-insensitive file system: macOS, Windows).
fn same_folder(a: &str, b: &str) -> bool {
    a == b || a.to_lowercase() == b.to_lowercase()
}

/// A checked `[fracture]`, its scenes not yet built.
pub(super) struct FracturePlan {
    pub extent: Extent,
    pub batch: bool,
    pub walls: WallMode,
    pub wall_disk: Option<f64>,
    pub wells: Vec<WellPlan>,
}

/// One fracture of the plan, and the key blamed when it is too narrow.
pub(super) struct WellPlan {
    pub name: String,
    /// The well's own `fill`, overriding `packer.fill`.
    pub fill: Option<Fill>,
    pub fracture: Fracture,
    pub width_key: KeyAt,
    /// The key that sets how long it is (blamed when it is too long to resolve its disks).
    pub length_key: KeyAt,
}

/// The keys of the normalised form, in the order messages list them.
const NORMALISED: [&str; 3] = ["width_ratio", "length_ratio", "mean_diameter"];

impl Validator<'_> {
    /// `[fracture]`: the form of the geometry, the walls, the extent and the wells.
    pub(super) fn fracture(
        &self,
        raw: &Spanned<Table<RawFracture>>,
    ) -> Result<FracturePlan, ConfigError> {
        let f = raw.get_ref();
        let absolute = [("width_mm", &f.width_mm), ("height_m", &f.height_m)];
        let normalised = [
            (NORMALISED[0], &f.width_ratio),
            (NORMALISED[1], &f.length_ratio),
            (NORMALISED[2], &f.mean_diameter),
        ];
        let first = |keys: &[(&'static str, &Option<Spanned<f64>>)]| {
            keys.iter()
                .filter_map(|(k, v)| v.as_ref().map(|v| (*k, v.span())))
                .min_by_key(|(_, span)| span.start)
        };
        let (first_absolute, first_normalised) = (first(&absolute), first(&normalised));
        if let (Some(a), Some(n)) = (&first_absolute, &first_normalised) {
            let (key, span) = if a.1.start > n.1.start { a } else { n };
            return Err(ConfigError::NotApplicable {
                at: self.at(span),
                key: format!("fracture.{key}"),
                reason: "give the fracture as width_mm and height_m, or as width_ratio, length_ratio and mean_diameter, not both".to_owned(),
            });
        }
        let (walls, wall_disk) = self.walls("fracture", f.walls.as_ref(), f.wall_disk.as_ref())?;
        self.periodic_fracture(walls, f.walls.as_ref())?;
        let tolerance = match &f.window_tolerance {
            None => DEFAULT_WINDOW_TOLERANCE,
            Some(v) => self.checked(
                "fracture.window_tolerance",
                v,
                &format!("in (0, {MAX_WINDOW_TOLERANCE}]"),
                |v| v > 0.0 && v <= MAX_WINDOW_TOLERANCE,
            )?,
        };
        let extent = match self.name(&EXTENTS, "fracture.extent", f.extent.as_ref())? {
            ExtentKind::Full => Extent::Full,
            ExtentKind::Window => Extent::Window { tolerance },
        };
        let optional = |key: &str, v: &Option<Spanned<f64>>| {
            v.as_ref()
                .map(|v| self.positive(&format!("fracture.{key}"), v))
                .transpose()
        };
        let width = optional("width_mm", &f.width_mm)?;
        let height = optional("height_m", &f.height_m)?;
        let tip = optional("tip_width_mm", &f.tip_width_mm)?;
        let key_of = |key: &str, v: &Option<Spanned<f64>>| {
            v.as_ref().map(|v| KeyAt {
                key: format!("fracture.{key}"),
                span: v.span(),
            })
        };

        let wells = if let Some(wells) = &f.wells {
            if let Some((key, span)) = first_normalised {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&span),
                    key: format!("fracture.{key}"),
                    reason: "the wells of a batch are given by width_mm and height_m; the normalised form describes one fracture cell".to_owned(),
                });
            }
            if wells.is_empty() {
                return Err(ConfigError::Missing {
                    at: self.at(&raw.span()),
                    key: "fracture.wells".to_owned(),
                    reason: "a batch needs at least one [[fracture.wells]]".to_owned(),
                });
            }
            let defaults = Defaults {
                width: width.zip(key_of("width_mm", &f.width_mm)),
                height: height.zip(key_of("height_m", &f.height_m)),
                tip: tip.zip(key_of("tip_width_mm", &f.tip_width_mm)),
            };
            let mut plans: Vec<WellPlan> = Vec::with_capacity(wells.len());
            for (i, well) in wells.iter().enumerate() {
                let plan = self.well(i, well, &defaults)?;
                let clash = plans
                    .iter()
                    .enumerate()
                    .find(|(_, p)| same_folder(&p.name, &plan.name));
                if let Some((j, earlier)) = clash {
                    let reason = if earlier.name == plan.name {
                        format!(
                            "{:?} is given twice (fracture.wells[{j}].name): each well needs its own folder",
                            plan.name
                        )
                    } else {
                        format!(
                            "{:?} and {:?} (fracture.wells[{j}].name) differ only in case: one folder on a case-insensitive file system; give each well a distinct name",
                            plan.name, earlier.name
                        )
                    };
                    return Err(ConfigError::NotApplicable {
                        at: self.at(&well.get_ref().name.span()),
                        key: format!("fracture.wells[{i}].name"),
                        reason,
                    });
                }
                plans.push(plan);
            }
            plans
        } else if first_normalised.is_some() {
            let mut values = [0.0; 3];
            for (slot, (key, value)) in values.iter_mut().zip(normalised) {
                *slot = match value {
                    Some(v) => self.positive(&format!("fracture.{key}"), v)?,
                    None => {
                        return Err(ConfigError::Missing {
                            at: self.at(&raw.span()),
                            key: format!("fracture.{key}"),
                            reason: format!("the normalised form needs {}", NORMALISED.join(", ")),
                        });
                    }
                };
            }
            if let Some(v) = &f.tip_width_mm {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&v.span()),
                    key: "fracture.tip_width_mm".to_owned(),
                    reason: "a normalised cell has parallel walls; give width_mm and height_m for a tapered fracture".to_owned(),
                });
            }
            let [ratio, length, mean] = values;
            vec![WellPlan {
                name: "fracture".to_owned(),
                fill: None,
                fracture: Fracture::normalised(ratio, length, mean),
                width_key: key_of("width_ratio", &f.width_ratio).unwrap_or(KeyAt {
                    key: "fracture".to_owned(),
                    span: raw.span(),
                }),
                length_key: key_of("length_ratio", &f.length_ratio).unwrap_or(KeyAt {
                    key: "fracture".to_owned(),
                    span: raw.span(),
                }),
            }]
        } else {
            let need = |key: &str| {
                ConfigError::Missing {
                at: self.at(&raw.span()),
                key: format!("fracture.{key}"),
                reason: "[fracture] needs width_mm and height_m (or width_ratio, length_ratio and mean_diameter, or [[fracture.wells]])".to_owned(),
            }
            };
            let width = width.ok_or_else(|| need("width_mm"))?;
            let height = height.ok_or_else(|| need("height_m"))?;
            let width_key = key_of("width_mm", &f.width_mm).unwrap_or(KeyAt {
                key: "fracture".to_owned(),
                span: raw.span(),
            });
            let tip = tip.zip(key_of("tip_width_mm", &f.tip_width_mm));
            let length_key = key_of("height_m", &f.height_m).unwrap_or(KeyAt {
                key: "fracture".to_owned(),
                span: raw.span(),
            });
            vec![WellPlan {
                name: "fracture".to_owned(),
                fill: None,
                fracture: self.tapered(width, height, tip, &width_key)?,
                width_key,
                length_key,
            }]
        };
        if let (Extent::Window { .. }, Some(tapered)) = (
            extent,
            wells.iter().find(|w| w.fracture.tip_width.is_some()),
        ) {
            let span = f.extent.as_ref().map_or(raw.span(), Spanned::span);
            return Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: "fracture.extent".to_owned(),
                reason: format!(
                    "a window needs parallel walls, and {:?} is tapered (its aperture changes along its length); use extent = \"full\"",
                    tapered.name
                ),
            });
        }
        Ok(FracturePlan {
            extent,
            batch: f.wells.is_some(),
            walls,
            wall_disk,
            wells,
        })
    }

    /// One `[[fracture.wells]]`: its name, and its sizes or the defaults.
    fn well(
        &self,
        i: usize,
        raw: &Spanned<Table<RawWell>>,
        defaults: &Defaults,
    ) -> Result<WellPlan, ConfigError> {
        let w = raw.get_ref();
        let path = format!("fracture.wells[{i}]");
        let name = w.name.get_ref().trim();
        let bad_name = if name.is_empty() {
            Some("a well needs a name".to_owned())
        } else if name == "." || name == ".." || name.contains(['/', '\\', ':']) {
            Some(format!(
                "{name:?} cannot name its output directory: no /, \\ or :, and not . or .."
            ))
        } else {
            BATCH_FILES.iter().find(|f| same_folder(f, name)).map(|file| {
                format!(
                    "{name:?} would be a folder named like the batch's own {file} beside the wells' folders; reserved: {}",
                    BATCH_FILES.join(", ")
                )
            })
        };
        if let Some(reason) = bad_name {
            return Err(ConfigError::NotApplicable {
                at: self.at(&w.name.span()),
                key: format!("{path}.name"),
                reason,
            });
        }
        let missing = |key: &str| ConfigError::Missing {
            at: self.at(&raw.span()),
            key: format!("{path}.{key}"),
            reason: format!("each well needs {key}, or [fracture] gives it for all"),
        };
        let (width, width_key) = match &w.width_mm {
            Some(v) => (
                self.positive(&format!("{path}.width_mm"), v)?,
                KeyAt {
                    key: format!("{path}.width_mm"),
                    span: v.span(),
                },
            ),
            None => defaults.width.clone().ok_or_else(|| missing("width_mm"))?,
        };
        let (height, length_key) = match &w.height_m {
            Some(v) => (
                self.positive(&format!("{path}.height_m"), v)?,
                KeyAt {
                    key: format!("{path}.height_m"),
                    span: v.span(),
                },
            ),
            None => defaults.height.clone().ok_or_else(|| missing("height_m"))?,
        };
        let tip = match &w.tip_width_mm {
            Some(v) => Some((
                self.positive(&format!("{path}.tip_width_mm"), v)?,
                KeyAt {
                    key: format!("{path}.tip_width_mm"),
                    span: v.span(),
                },
            )),
            None => defaults.tip.clone(),
        };
        Ok(WellPlan {
            name: name.to_owned(),
            fill: w
                .fill
                .as_ref()
                .map(|f| self.name(&FILLS, &format!("{path}.fill"), Some(f)))
                .transpose()?,
            fracture: self.tapered(width, height, tip, &width_key)?,
            width_key,
            length_key,
        })
    }

    /// A fracture of `width` (mm) and `height` (m), tapering to `tip` (mm) if given:
    /// the tip may not be wider than the wellbore.
    fn tapered(
        &self,
        width: f64,
        height: f64,
        tip: Option<(f64, KeyAt)>,
        width_key: &KeyAt,
    ) -> Result<Fracture, ConfigError> {
        let tip_width = match tip {
            Some((tip, key)) if tip > width => {
                return Err(ConfigError::OutOfRange {
                    at: self.at(&key.span),
                    key: key.key,
                    range: format!(
                        "at most the width at the wellbore ({} = {width} mm): a fracture narrows to its tip",
                        width_key.key
                    ),
                    value: tip,
                });
            }
            Some((tip, _)) => Some(tip),
            None => None,
        };
        Ok(Fracture {
            width,
            length: height * MM_PER_M,
            tip_width,
        })
    }

    /// Refuse an `[optimise]` or `[layering]` beside a batch of wells or a
    /// window: those run with `gapack pack` only.
    pub(super) fn fracture_runs(
        &self,
        plan: &FracturePlan,
        raw: &RawConfig,
    ) -> Result<(), ConfigError> {
        self.well_fills_with_shape(raw)?;
        let why = match (plan.batch, plan.extent) {
            (true, _) => {
                "a batch of wells runs with gapack pack; give one fracture to optimise or layer"
            }
            (false, Extent::Window { .. }) => {
                "a window (extent = \"window\") runs with gapack pack; use extent = \"full\""
            }
            (false, Extent::Full) => return Ok(()),
        };
        let table = [
            ("optimise", raw.optimise.as_ref().map(Spanned::span)),
            ("layering", raw.layering.as_ref().map(Spanned::span)),
        ]
        .into_iter()
        .find_map(|(key, span)| span.map(|s| (key, s)));
        match table {
            None => Ok(()),
            Some((key, span)) => Err(ConfigError::NotApplicable {
                at: self.at(&span),
                key: key.to_owned(),
                reason: why.to_owned(),
            }),
        }
    }
}

impl Validator<'_> {
    /// Refuse a well's own `fill = "right"` beside a `[shape]`: filling
    /// right mirrors the scene and packs disks (`packer.fill` is refused
    /// with the shape's other settings).
    fn well_fills_with_shape(&self, raw: &RawConfig) -> Result<(), ConfigError> {
        let (Some(_), Some(f)) = (&raw.shape, &raw.fracture) else {
            return Ok(());
        };
        let wells = f.get_ref().wells.iter().flatten().enumerate();
        for (i, well) in wells {
            if let Some(fill) = &well.get_ref().fill
                && FILLS.get(fill.get_ref()) == Some(Fill::Right)
            {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&fill.span()),
                    key: format!("fracture.wells[{i}].fill"),
                    reason: "\"right\" mirrors the scene and packs it as disks, which particle shapes ([shape]) cannot be; leave fill = \"up\"".to_owned(),
                });
            }
        }
        Ok(())
    }
}

/// What `[fracture]` gives every well of a batch that does not give its own.
struct Defaults {
    width: Option<(f64, KeyAt)>,
    height: Option<(f64, KeyAt)>,
    tip: Option<(f64, KeyAt)>,
}

#[cfg(test)]
mod tests {
    use super::BATCH_FILES;

    #[test]
    fn batch_files_are_the_names_the_jobs_write() {
        // Repeated here because config sits below jobs: pinned to the originals.
        for file in [
            crate::output::WELLS_CSV,
            crate::jobs::MANIFEST_JSON,
            crate::jobs::CHECKPOINT_JSON,
        ] {
            assert!(BATCH_FILES.contains(&file), "{file} is not reserved");
        }
    }
}
