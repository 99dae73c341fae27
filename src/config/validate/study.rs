//! `[sweep]`: the keys a parameter study sweeps, each a path to a key of
//! a table the config has, with the places the table writes them, and the
//! study's options (`seeds`, `keep`, `measure`, `job`). Whether each value
//! fits its key is checked on the configs the values make, when the study
//! is planned ([`crate::config::SweepConfigs`]).

use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::Validator;
use crate::config::error::ConfigError;
use crate::config::raw::Table;
use crate::names::{KEEPS, MEASURES, Names, RUN_JOBS};
use crate::study::{Keep, Measure, SweepSettings, SweptKey};

/// Most seeds per point of a study.
const MAX_SEEDS: i64 = 10_000;

/// Most runs of a study (points × seeds).
const MAX_RUNS: usize = 100_000;

/// The keys of `[sweep]` that are the study's options, not swept keys.
const OPTIONS: [&str; 4] = ["seeds", "keep", "measure", "job"];

/// Keys and tables a study does not sweep, and why.
const NOT_SWEPT: [(&str, &str); 4] = [
    ("sweep", "a study does not sweep its own [sweep] table"),
    (
        "seed",
        "the seeds are the study's own: sweep.seeds = N runs each point on seed, seed + 1, …, seed + N − 1 (the first is the config's seed, or the run's)",
    ),
    (
        "output",
        "the study writes its runs' files itself (sweep.keep): [output] is not swept",
    ),
    (
        "compare",
        "[compare] belongs to the compare and stability jobs, which a study does not run",
    ),
];

impl Validator<'_> {
    /// `[sweep]`: its options and swept keys, every path checked against
    /// the tables of the config.
    pub(super) fn sweep(
        &self,
        raw: &Spanned<Table<toml::Table>>,
    ) -> Result<SweepSettings, ConfigError> {
        let place = raw.span();
        let unreadable = || ConfigError::Schema {
            at: self.at(&place),
            key: "sweep".to_owned(),
            message: "cannot be read as a table".to_owned(),
        };
        // The text parsed before it got here: these only fail on a bug.
        let tree = DeTable::parse(self.text).map_err(|_| unreadable())?;
        let doc: toml::Table = toml::from_str(self.text).map_err(|_| unreadable())?;
        let table = tree
            .get_ref()
            .iter()
            .find(|(k, _)| k.get_ref() == "sweep")
            .and_then(|(_, v)| v.get_ref().as_table())
            .ok_or_else(unreadable)?;
        let values: &toml::Table = raw.get_ref();
        let mut settings = SweepSettings {
            keys: Vec::new(),
            seeds: 1,
            keep: Keep::None,
            measure: Measure::Porosity,
            job: None,
        };
        for (key, value) in table.iter() {
            let name: &str = key.get_ref();
            let Some(given) = values.get(name) else {
                continue;
            };
            let at = value.span();
            match name {
                "seeds" => settings.seeds = self.sweep_seeds(at, given)?,
                "keep" => settings.keep = self.sweep_name(&KEEPS, "sweep.keep", at, given)?,
                "measure" => {
                    settings.measure = self.sweep_name(&MEASURES, "sweep.measure", at, given)?;
                }
                "job" => settings.job = Some(self.sweep_name(&RUN_JOBS, "sweep.job", at, given)?),
                _ => self.swept(
                    name.to_owned(),
                    key.span(),
                    value,
                    given,
                    &mut settings.keys,
                )?,
            }
        }
        settings.keys.sort_by_key(|k| k.span.start);
        for (i, key) in settings.keys.iter().enumerate() {
            if let Some(earlier) = settings.keys[..i].iter().find(|k| k.path == key.path) {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&key.span),
                    key: key.label(),
                    reason: format!(
                        "{} is swept twice (also at line {})",
                        key.path,
                        self.at(&earlier.span).line
                    ),
                });
            }
            self.swept_path(key, &doc)?;
        }
        if settings.keys.is_empty() {
            return Err(ConfigError::Missing {
                at: self.at(&place),
                key: "sweep".to_owned(),
                reason: format!(
                    "name at least one config key and the values it takes, e.g. \"fracture.width_mm\" = [2.0, 2.5, 3.0] (besides the options {})",
                    OPTIONS.join(", ")
                ),
            });
        }
        let runs = settings
            .keys
            .iter()
            .try_fold(settings.seeds, |n, k| n.checked_mul(k.values.len()));
        if runs.is_none_or(|n| n > MAX_RUNS) {
            return Err(ConfigError::OutOfRange {
                at: self.at(&place),
                key: "sweep".to_owned(),
                range: format!("at most {MAX_RUNS} runs (the values' product × seeds)"),
                value: settings
                    .keys
                    .iter()
                    .fold(settings.seeds as f64, |n, k| n * k.values.len() as f64),
            });
        }
        Ok(settings)
    }

    /// `sweep.seeds`: a whole number of seeds per point.
    fn sweep_seeds(&self, at: Range<usize>, given: &toml::Value) -> Result<usize, ConfigError> {
        let toml::Value::Integer(n) = given else {
            return Err(ConfigError::Schema {
                at: self.at(&at),
                key: "sweep.seeds".to_owned(),
                message: format!(
                    "invalid type: {}, expected a whole number",
                    given.type_str()
                ),
            });
        };
        self.whole("sweep.seeds", &Spanned::new(at, *n), 1, Some(MAX_SEEDS))
    }

    /// An option of `[sweep]` given by name (`keep`, `measure`, `job`).
    fn sweep_name<T: Copy + PartialEq + Default>(
        &self,
        names: &Names<T>,
        key: &str,
        at: Range<usize>,
        given: &toml::Value,
    ) -> Result<T, ConfigError> {
        let toml::Value::String(name) = given else {
            return Err(ConfigError::Schema {
                at: self.at(&at),
                key: key.to_owned(),
                message: format!("invalid type: {}, expected a string", given.type_str()),
            });
        };
        self.name(names, key, Some(&Spanned::new(at, name.clone())))
    }

    /// A swept key (`"fracture.width_mm" = [2.0, 2.5]`), or a table of
    /// them written with dotted keys (`fracture.width_mm = [2.0, 2.5]`).
    fn swept(
        &self,
        path: String,
        key: Range<usize>,
        value: &Spanned<DeValue<'_>>,
        given: &toml::Value,
        out: &mut Vec<SweptKey>,
    ) -> Result<(), ConfigError> {
        let label = format!("sweep.{path:?}");
        match (value.get_ref(), given) {
            (DeValue::Table(table), toml::Value::Table(values)) => {
                for (k, v) in table.iter() {
                    let name: &str = k.get_ref();
                    if let Some(inner) = values.get(name) {
                        self.swept(format!("{path}.{name}"), k.span(), v, inner, out)?;
                    }
                }
                Ok(())
            }
            (DeValue::Array(items), toml::Value::Array(values)) => {
                if values.is_empty() {
                    return Err(ConfigError::Missing {
                        at: self.at(&value.span()),
                        key: label,
                        reason: "give at least one value".to_owned(),
                    });
                }
                out.push(SweptKey {
                    path,
                    values: values.clone(),
                    span: key,
                    value_spans: items.iter().map(Spanned::span).collect(),
                });
                Ok(())
            }
            _ => Err(ConfigError::Schema {
                at: self.at(&value.span()),
                key: label,
                message: format!(
                    "invalid type: {}, expected an array of the values the key takes (e.g. [2.0, 2.5, 3.0]), or one of the options {}",
                    given.type_str(),
                    OPTIONS.join(", ")
                ),
            }),
        }
    }

    /// A swept key's path: parts made of letters, digits, `_` and `-`,
    /// leading through tables the config has to a key of the last one.
    fn swept_path(&self, key: &SweptKey, doc: &toml::Table) -> Result<(), ConfigError> {
        let fault = |reason: String| ConfigError::NotApplicable {
            at: self.at(&key.span),
            key: key.label(),
            reason,
        };
        let parts: Vec<&str> = key.path.split('.').collect();
        let bare = |p: &&str| {
            !p.is_empty()
                && p.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        };
        if !parts.iter().all(bare) {
            return Err(fault(
                "not a config key: write the key's tables and its name joined by dots, e.g. \"fracture.width_mm\"".to_owned(),
            ));
        }
        if let Some((_, why)) = NOT_SWEPT.iter().find(|(t, _)| *t == parts[0]) {
            return Err(fault((*why).to_owned()));
        }
        let mut table = doc;
        for (i, part) in parts[..parts.len() - 1].iter().enumerate() {
            let here = parts[..=i].join(".");
            table = match table.get(*part) {
                Some(toml::Value::Table(t)) => t,
                Some(toml::Value::Array(_)) => {
                    let hint = if here == "fracture.wells" {
                        "; sweep fracture.width_mm, fracture.height_m or fracture.tip_width_mm to set every well's"
                    } else {
                        ""
                    };
                    return Err(fault(format!(
                        "{here} is a list of tables, which a swept key cannot reach into{hint}"
                    )));
                }
                Some(other) => {
                    return Err(fault(format!(
                        "{here} is a {}, not a table",
                        other.type_str()
                    )));
                }
                None => {
                    return Err(fault(format!(
                        "the config has no [{here}] table: write it, with the keys it needs, to sweep {}",
                        key.path
                    )));
                }
            };
        }
        Ok(())
    }
}
