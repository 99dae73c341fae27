//! The configs of a parameter study: the study's config with each point's
//! values set, validated as any config, each fault placed at the `[sweep]`
//! entry that caused it.

use super::error::{ConfigError, Location};
use super::locate::from_toml_error;
use super::parse::{Config, ParseOptions, parse_with};
use crate::study::{SweepSettings, SweptKey};

/// One point of a study: a value of every swept key.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct SweepPoint {
    /// The index of each key's value, in the keys' order.
    pub values: Vec<usize>,
    /// The point's config as TOML: the study's with the values set and
    /// `[sweep]` left out (comments and layout are not kept).
    pub text: String,
    /// Its config; or, when its scene cannot be packed (a fracture
    /// narrower than the grading's smallest disk, a scene over a limit),
    /// why, in one line: that point's runs fail, the others run.
    pub config: Result<Config, String>,
}

/// The grading keys that give the curve: setting one by a sweep removes
/// the others, so `"grading.preset"` swept over a config with a `table` replaces it.
const GRADING_SOURCES: [&str; 4] = ["table", "uniform", "constant", "preset"];

/// The keys of `[fracture]` that a `[[fracture.wells]]` entry may give
/// for itself: swept, they set every well's (the wells' own are removed).
const WELL_KEYS: [&str; 3] = ["width_mm", "height_m", "tip_width_mm"];

/// The configs of a study, made a point at a time ([`SweepConfigs::point`]):
/// the study's config without `[sweep]`, and what places a fault.
///
/// # Performance
/// Holds the study's config once, whatever the number of points: a point's
/// config is made (one parse of a short text) when it is asked for, and a
/// caller that walks the points keeps only what it needs of each.
#[derive(Debug, Clone)]
pub struct SweepConfigs {
    /// The study's config as a TOML tree, `[sweep]` removed.
    doc: toml::Table,
    /// The study's text (for the places of faults).
    text: String,
    /// Names the study's config in messages.
    origin: String,
    /// How each point's config is parsed.
    options: ParseOptions,
}

impl SweepConfigs {
    /// The configs of the study of `text` (named `origin`), each point
    /// parsed with `options`.
    ///
    /// # Errors
    /// The text's TOML fault, placed as [`super::parse`] places it.
    pub fn new(text: &str, origin: &str, options: ParseOptions) -> Result<Self, ConfigError> {
        let mut doc: toml::Table =
            toml::from_str(text).map_err(|e| from_toml_error(&e, text, origin))?;
        doc.remove("sweep");
        Ok(SweepConfigs {
            doc,
            text: text.to_owned(),
            origin: origin.to_owned(),
            options,
        })
    }

    /// The point of `settings` whose value indices are `values` (one per
    /// key, each in range: [`crate::study::points`] gives them).
    ///
    /// # Behavior
    /// A swept key's value replaces the config's: `fracture.width_mm` (and
    /// `height_m`, `tip_width_mm`) on a batch of `[[fracture.wells]]` sets
    /// every well's; one of `grading.table`, `uniform`, `constant`, `preset`
    /// replaces the curve the config gives. A point whose scene cannot be
    /// packed (`ConfigError::Scene` or `ConfigError::Memory`: values valid
    /// in themselves that the rest of the config cannot pack) is not a
    /// fault of the study: its runs fail alone. Any other fault is placed
    /// at the `[sweep]` entry that makes it: each of the point's values is
    /// then checked alone on the study's config
    /// (`study.toml:14:23: sweep."fracture.width_mm"[2]: …`).
    ///
    /// # Errors
    /// The point's first value (or key) at fault alone, placed at its
    /// entry of `[sweep]`; a fault only the values together make is
    /// placed at the first swept key and names the point (`name`).
    pub fn point(
        &self,
        settings: &SweepSettings,
        values: &[usize],
        name: &str,
    ) -> Result<SweepPoint, ConfigError> {
        let mut config = self.doc.clone();
        for (key, &i) in settings.keys.iter().zip(values) {
            set(&mut config, &key.path, &key.values[i]);
        }
        let Some(first) = settings.keys.first() else {
            return Err(ConfigError::NotApplicable {
                at: Location::at(&self.origin, &self.text, 0),
                key: "sweep".to_owned(),
                reason: "no key is swept".to_owned(),
            });
        };
        let text = self.write(&config, first, values.first().copied().unwrap_or(0))?;
        let config = match parse_with(&text, &self.origin, self.options) {
            Ok(config) => Ok(config),
            Err(e) if cannot_pack(&e) => Err(e.detail()),
            Err(e) => {
                for (key, &i) in settings.keys.iter().zip(values) {
                    self.alone(key, i)?;
                }
                return Err(ConfigError::NotApplicable {
                    at: self.at(&first.span),
                    key: "sweep".to_owned(),
                    reason: format!("the values {name} together: {}", e.detail()),
                });
            }
        };
        Ok(SweepPoint {
            values: values.to_vec(),
            text,
            config,
        })
    }

    /// Check value `i` of `key` alone on the study's config: its fault
    /// placed at its entry (or at the key, when the key is none).
    fn alone(&self, key: &SweptKey, i: usize) -> Result<(), ConfigError> {
        let mut one = self.doc.clone();
        set(&mut one, &key.path, &key.values[i]);
        let alone = self.write(&one, key, i)?;
        match parse_with(&alone, &self.origin, self.options) {
            Ok(_) => Ok(()),
            Err(e) if cannot_pack(&e) => Ok(()),
            Err(e) if names_the_key(&e, key) => Err(ConfigError::NotApplicable {
                at: self.at(&key.span),
                key: key.label(),
                reason: format!("not a config key: {}", e.message()),
            }),
            Err(e) if e.key() == Some(key.path.as_str()) => {
                Err(e.relocated(self.at(&key.value_spans[i]), key.value_label(i)))
            }
            Err(e) => Err(ConfigError::Schema {
                at: self.at(&key.value_spans[i]),
                key: key.value_label(i),
                message: e.detail(),
            }),
        }
    }

    /// `doc` as TOML text; a fault placed at value `i` of `key`.
    fn write(&self, doc: &toml::Table, key: &SweptKey, i: usize) -> Result<String, ConfigError> {
        toml::to_string(doc).map_err(|e| ConfigError::Schema {
            at: self.at(&key.value_spans[i]),
            key: key.value_label(i),
            message: format!("cannot be set in the config: {e}"),
        })
    }

    /// The place in the study's text where `span` starts.
    fn at(&self, span: &std::ops::Range<usize>) -> Location {
        Location::at(&self.origin, &self.text, span.start)
    }
}

/// A scene that cannot be packed, though each value is valid.
fn cannot_pack(e: &ConfigError) -> bool {
    matches!(e, ConfigError::Scene { .. } | ConfigError::Memory { .. })
}

/// Whether `e` refuses the swept key itself as unknown to its table.
fn names_the_key(e: &ConfigError, key: &SweptKey) -> bool {
    let (table, last) = key.path.rsplit_once('.').unwrap_or(("", &key.path));
    matches!(e, ConfigError::Schema { key: k, message, .. }
        if (k == table || *k == key.path) && message.starts_with(&format!("unknown key `{last}`")))
}

/// Set `path` of `doc` to `value` (its tables exist: the validator checked them).
fn set(doc: &mut toml::Table, path: &str, value: &toml::Value) {
    let parts: Vec<&str> = path.split('.').collect();
    let Some((last, tables)) = parts.split_last() else {
        return;
    };
    let mut table = doc;
    for part in tables {
        table = match table
            .entry(*part)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        {
            toml::Value::Table(t) => t,
            _ => return,
        };
    }
    if tables == ["grading"] && GRADING_SOURCES.contains(last) {
        for other in GRADING_SOURCES {
            table.remove(other);
        }
    }
    if tables == ["fracture"]
        && WELL_KEYS.contains(last)
        && let Some(toml::Value::Array(wells)) = table.get_mut("wells")
    {
        for well in wells {
            if let toml::Value::Table(well) = well {
                well.remove(*last);
            }
        }
    }
    table.insert((*last).to_owned(), value.clone());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::parse;
    use crate::study::{point_names, points};

    /// Every point of the study, in product order; the first fault.
    fn sweep_points(
        text: &str,
        origin: &str,
        options: ParseOptions,
        settings: &SweepSettings,
    ) -> Result<Vec<SweepPoint>, ConfigError> {
        let configs = SweepConfigs::new(text, origin, options)?;
        points(&settings.keys)
            .iter()
            .zip(point_names(&settings.keys))
            .map(|(values, name)| configs.point(settings, values, &name))
            .collect()
    }

    const STUDY: &str = "seed = 3
[fracture]
width_mm = 2.0
height_m = 0.2
extent = \"window\"
[grading]
preset = \"20/40\"
[sweep]
\"fracture.width_mm\" = [1.5, 2.5]
grading.preset = [\"20/40\", \"30/50\"]
seeds = 2
";

    #[test]
    fn each_point_sets_its_values_and_drops_the_sweep() {
        let config = parse(STUDY, "s.toml").expect("valid");
        let settings = config.sweep.expect("a sweep");
        assert_eq!(settings.seeds, 2);
        let paths: Vec<&str> = settings.keys.iter().map(|k| k.path.as_str()).collect();
        assert_eq!(paths, ["fracture.width_mm", "grading.preset"]);
        let points =
            sweep_points(STUDY, "s.toml", ParseOptions::default(), &settings).expect("points");
        assert_eq!(points.len(), 4);
        let widths: Vec<f64> = points
            .iter()
            .map(|p| {
                let c = p.config.as_ref().expect("packable");
                assert!(c.sweep.is_none());
                assert_eq!(c.scene.seed, 3);
                c.fracture.as_ref().expect("fracture").wells[0]
                    .fracture
                    .width
            })
            .collect();
        assert_eq!(widths, [1.5, 1.5, 2.5, 2.5]);
        let d_max = |p: &SweepPoint| p.config.as_ref().expect("config").scene.d_max();
        assert!(d_max(&points[0]) > d_max(&points[1]), "20/40 is coarser");
    }

    #[test]
    fn a_swept_width_sets_every_well_and_a_preset_replaces_a_table() {
        let text = "[fracture]
[[fracture.wells]]
name = \"a\"
width_mm = 6
height_m = 0.05
[[fracture.wells]]
name = \"b\"
width_mm = 8
height_m = 0.05
[grading]
uniform = [1.0, 1.5]
[sweep]
\"fracture.width_mm\" = [3.0]
\"grading.preset\" = [\"16/30\"]
";
        let config = parse(text, "w.toml").expect("valid");
        let points = sweep_points(
            text,
            "w.toml",
            ParseOptions::default(),
            config.sweep.as_ref().expect("sweep"),
        )
        .expect("points");
        let c = points[0].config.as_ref().expect("config");
        let widths: Vec<f64> = c
            .fracture
            .as_ref()
            .expect("wells")
            .wells
            .iter()
            .map(|w| w.fracture.width)
            .collect();
        assert_eq!(widths, [3.0, 3.0]);
        assert!((c.scene.d_max() - 1.18).abs() < 1e-9, "{}", c.scene.d_max());
    }

    /// The fault of a value is placed at the value, of a key at the key.
    #[test]
    fn faults_are_placed_at_their_entry() {
        let bad_value = STUDY.replace("[1.5, 2.5]", "[1.5, 2.5, -1]");
        let config = parse(&bad_value, "s.toml").expect("parses: values are checked when planned");
        let err = sweep_points(
            &bad_value,
            "s.toml",
            ParseOptions::default(),
            config.sweep.as_ref().expect("sweep"),
        )
        .expect_err("-1 is no width");
        assert_eq!(
            err.to_string(),
            "s.toml:9:34: sweep.\"fracture.width_mm\"[2]: must be a positive finite number, got -1"
        );
        let bad_key = STUDY.replace("\"fracture.width_mm\"", "\"fracture.widthmm\"");
        let config = parse(&bad_key, "s.toml").expect("parses");
        let err = sweep_points(
            &bad_key,
            "s.toml",
            ParseOptions::default(),
            config.sweep.as_ref().expect("sweep"),
        )
        .expect_err("no such key");
        let said = err.to_string();
        assert!(
            said.starts_with(
                "s.toml:9:1: sweep.\"fracture.widthmm\": not a config key: unknown key `widthmm`"
            ),
            "{said}"
        );
        // A preset that does not exist, named as the grading names it.
        let bad_name = STUDY.replace("\"30/50\"]", "\"30-50\"]");
        let config = parse(&bad_name, "s.toml").expect("parses");
        let err = sweep_points(
            &bad_name,
            "s.toml",
            ParseOptions::default(),
            config.sweep.as_ref().expect("sweep"),
        )
        .expect_err("no such preset");
        assert!(
            err.to_string()
                .starts_with("s.toml:10:28: sweep.\"grading.preset\"[1]: "),
            "{err}"
        );
    }

    /// A width narrower than the grading's smallest disk fails its runs, not the study.
    #[test]
    fn a_point_that_cannot_be_packed_is_not_a_fault() {
        let narrow = STUDY.replace("[1.5, 2.5]", "[0.2, 2.5]");
        let config = parse(&narrow, "s.toml").expect("parses");
        let points = sweep_points(
            &narrow,
            "s.toml",
            ParseOptions::default(),
            config.sweep.as_ref().expect("sweep"),
        )
        .expect("points");
        let why = points[0].config.as_ref().expect_err("too narrow");
        assert!(why.contains("the domain is too narrow"), "{why}");
        assert!(points[2].config.is_ok());
    }
}
