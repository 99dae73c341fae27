//! Parameter studies (`gapack sweep`): what the `[sweep]` table asks for,
//! the runs it makes — the Cartesian product of the swept values, each
//! over `seeds` seeds — their names, and the row each run leaves in
//! `sweep.csv`.
//!
//! # Behavior
//! Runs come in product order: the first swept key varies slowest, the
//! seeds fastest, so the runs of one point (one value of every key) are
//! neighbours and point `p`'s seed `k` is run `p · seeds + k`.
//!
//! Plain data and arithmetic only: the config layer reads the table and
//! builds each point's config (`config::SweepConfigs`), the jobs layer runs
//! them, and the output layer writes the rows and draws the chart.

use std::ops::Range;

use serde::{Deserialize, Serialize};

/// `[sweep]`: the keys swept and their values, the seeds, what to keep and chart.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSettings {
    /// The swept keys, in the order the table lists them (at least one).
    pub keys: Vec<SweptKey>,
    /// Runs per point, on seeds `seed`, `seed + 1`, … (at least one).
    pub seeds: usize,
    /// Which files of each run the study keeps.
    pub keep: Keep,
    /// The measure the chart draws.
    pub measure: Measure,
    /// The job each run is; `None`: the config's own (optimise with an
    /// `[optimise]` table, else layer with a `[layering]` one, else pack).
    pub job: Option<RunJob>,
}

impl SweepSettings {
    /// Points of the study: the number of value combinations.
    pub fn points(&self) -> usize {
        self.keys.iter().map(|k| k.values.len()).product()
    }

    /// Runs of the study: points × seeds.
    pub fn runs(&self) -> usize {
        self.points() * self.seeds
    }
}

/// One swept key: its config path, the values it takes and where the
/// table writes them (byte ranges of the config's text, for messages).
#[derive(Debug, Clone, PartialEq)]
pub struct SweptKey {
    /// The config key, its tables joined by dots (`fracture.width_mm`).
    pub path: String,
    /// The values, in order (at least one).
    pub values: Vec<toml::Value>,
    /// Where the entry's key is written.
    pub span: Range<usize>,
    /// Where each value is written.
    pub value_spans: Vec<Range<usize>>,
}

impl SweptKey {
    /// The entry as messages name it: `sweep."fracture.width_mm"`.
    pub fn label(&self) -> String {
        format!("sweep.{:?}", self.path)
    }

    /// Value `i` as messages name it: `sweep."fracture.width_mm"[2]`.
    pub fn value_label(&self, i: usize) -> String {
        format!("{}[{i}]", self.label())
    }

    /// The values as `sweep.csv` and the chart show them: a string as
    /// written, a number in its shortest exact form (`2.5`, `3`), an array
    /// or a table as inline TOML.
    pub fn texts(&self) -> Vec<String> {
        self.values.iter().map(value_text).collect()
    }

    /// The values as numbers, if every one is a number.
    pub fn numbers(&self) -> Option<Vec<f64>> {
        self.values
            .iter()
            .map(|v| match v {
                toml::Value::Integer(i) => Some(*i as f64),
                toml::Value::Float(f) => Some(*f),
                _ => None,
            })
            .collect()
    }
}

/// A value as a cell of `sweep.csv`.
fn value_text(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => f.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        other => {
            // Inline TOML; a value the writer cannot express (none that a
            // config parses to) shows as its debug form.
            let mut text = String::new();
            match other.serialize(toml::ser::ValueSerializer::new(&mut text)) {
                Ok(_) => text,
                Err(_) => format!("{other:?}"),
            }
        }
    }
}

/// Which files of each run a study keeps, under `runs/<run name>/`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Keep {
    /// None: only the study's own files (`keep` absent, or `"none"`).
    #[default]
    None,
    /// Each run's `summary.json` (one per well of a batch).
    Summary,
    /// Every file of each run, as `gapack pack` (or optimise, layer) writes them.
    All,
}

/// The measure a study's chart draws against the first swept key.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Measure {
    /// Porosity (a window's estimate in window mode).
    #[default]
    Porosity,
    /// Disks packed.
    Particles,
    /// KS distance between the packed sizes and the grading.
    PsdKs,
    /// Mean contacts per disk.
    Coordination,
    /// The error against the target (`target_error`).
    Error,
    /// Time of the run's main work (s).
    Seconds,
}

impl Measure {
    /// The measure of a finished run, `None` otherwise (or without a target).
    pub fn of(self, row: &Row) -> Option<f64> {
        let Status::Finished(m) = &row.status else {
            return None;
        };
        let v = match self {
            Measure::Porosity => m.porosity,
            Measure::Particles => m.particles as f64,
            Measure::PsdKs => m.psd_ks,
            Measure::Coordination => m.coordination,
            Measure::Error => m.target_error?,
            Measure::Seconds => m.seconds,
        };
        v.is_finite().then_some(v)
    }

    /// The measure as an axis names it, with its unit.
    pub fn title(self) -> &'static str {
        match self {
            Measure::Porosity => "porosity",
            Measure::Particles => "disks packed",
            Measure::PsdKs => "psd_ks (KS distance to the grading)",
            Measure::Coordination => "coordination (contacts per disk)",
            Measure::Error => "target error",
            Measure::Seconds => "seconds (s)",
        }
    }
}

/// The job each run of a study is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RunJob {
    /// Pack the scene, or each fracture of `[fracture]`.
    #[default]
    Pack,
    /// The target-porosity search.
    Optimise,
    /// Pack once, then lay the materials out.
    Layer,
}

/// What a finished run measured.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Measures {
    /// Disks packed (summed over the wells of a batch).
    pub particles: usize,
    /// Porosity (a window's estimate in window mode; the mean over the
    /// wells of a batch).
    pub porosity: f64,
    /// KS distance to the grading (the mean over the wells of a batch).
    pub psd_ks: f64,
    /// Mean contacts per disk (the mean over the wells of a batch).
    pub coordination: f64,
    /// `|porosity − optimise.target_porosity|` when the config has a
    /// target; the profile's RMS error for the layer job; else `None`.
    pub target_error: Option<f64>,
    /// Time of the run's main work (s): not reproducible, unlike the rest.
    pub seconds: f64,
}

/// How a run of a study ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Status {
    /// It ran to its end.
    Finished(Measures),
    /// It could not run or failed: the reason, in one line.
    Failed(String),
    /// It was not run (the study was stopped first) or was cut short.
    NotRun,
}

impl Status {
    /// The status column of `sweep.csv`: `finished`, `failed: <reason>`, `not run`.
    pub fn text(&self) -> String {
        match self {
            Status::Finished(_) => "finished".to_owned(),
            Status::Failed(why) => format!("failed: {why}"),
            Status::NotRun => "not run".to_owned(),
        }
    }
}

/// One run of a study, as `sweep.csv` lists it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The run's name (its folder under `runs/` when files are kept).
    pub run: String,
    /// The value of each swept key, as [`SweptKey::texts`] shows it.
    pub values: Vec<String>,
    /// The seed it ran with.
    pub seed: u64,
    /// How it ended, with its measures when it finished.
    pub status: Status,
}

/// The value indices of every point, in product order (the first key
/// varies slowest): `[[0, 0], [0, 1], [1, 0], …]`.
pub fn points(keys: &[SweptKey]) -> Vec<Vec<usize>> {
    let mut out = vec![Vec::new()];
    for key in keys {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                (0..key.values.len()).map(move |i| {
                    let mut p = prefix.clone();
                    p.push(i);
                    p
                })
            })
            .collect();
    }
    out
}

/// Longest value in a run name; longer values are named by their index.
const NAME_VALUE_CHARS: usize = 24;

/// The name of every point, in product order: `key=value` per swept key,
/// joined by commas (`width_mm=2.5,preset=20-40`). A key is named by its
/// last part unless two keys share it (then by its whole path); a value by
/// its text with every character but letters, digits, `.`, `_` and `-`
/// made a `-` (arrays' elements joined by `-`), or by `v` and its index
/// when that is empty, long, a table, or names two values alike. Names
/// are short, deterministic and safe as folder names on every system.
pub fn point_names(keys: &[SweptKey]) -> Vec<String> {
    let short: Vec<String> = keys
        .iter()
        .map(|k| {
            let last = k.path.rsplit('.').next().unwrap_or(&k.path);
            let shared = keys
                .iter()
                .filter(|o| o.path.rsplit('.').next() == Some(last))
                .count()
                > 1;
            if shared {
                k.path.clone()
            } else {
                last.to_owned()
            }
        })
        .collect();
    let values: Vec<Vec<String>> = keys.iter().map(value_names).collect();
    points(keys)
        .iter()
        .map(|point| {
            point
                .iter()
                .enumerate()
                .map(|(k, &i)| format!("{}={}", short[k], values[k][i]))
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect()
}

/// The name of run `seed` of the point named `point`.
pub fn run_name(point: &str, seed: u64) -> String {
    format!("{point},seed={seed}")
}

/// Each value of `key` as a run name shows it (see [`point_names`]).
fn value_names(key: &SweptKey) -> Vec<String> {
    let safe = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "._-".contains(c) {
                    c
                } else {
                    '-'
                }
            })
            .collect()
    };
    let mut names: Vec<String> = key
        .values
        .iter()
        .map(|v| match v {
            toml::Value::Table(_) => String::new(),
            toml::Value::Array(items) => items
                .iter()
                .map(|item| safe(&value_text(item)))
                .collect::<Vec<_>>()
                .join("-"),
            other => safe(&value_text(other)),
        })
        .collect();
    let unusable = |n: &String| n.is_empty() || n.len() > NAME_VALUE_CHARS;
    // A set, not a pairwise search: a study may sweep 100,000 values.
    let clash = {
        let mut seen = std::collections::HashSet::with_capacity(names.len());
        !names.iter().all(|n| seen.insert(n.as_str()))
    };
    if clash || names.iter().any(unusable) {
        names = (0..names.len()).map(|i| format!("v{i}")).collect();
    }
    names
}

/// A point's measure over its seeds: mean, smallest, largest, and the
/// runs that gave one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Mean over the runs that finished.
    pub mean: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Runs that gave a value.
    pub runs: usize,
}

/// The measure of every point over its seeds, in product order; `None`
/// for a point none of whose runs gave one. `rows` are a study's, in
/// product order, `seeds` to a point.
pub fn spreads(rows: &[Row], seeds: usize, measure: Measure) -> Vec<Option<Spread>> {
    rows.chunks(seeds.max(1))
        .map(|point| {
            let values: Vec<f64> = point.iter().filter_map(|r| measure.of(r)).collect();
            if values.is_empty() {
                return None;
            }
            let n = values.len();
            Some(Spread {
                mean: values.iter().sum::<f64>() / n as f64,
                min: values.iter().copied().fold(f64::INFINITY, f64::min),
                max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                runs: n,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(path: &str, values: Vec<toml::Value>) -> SweptKey {
        let n = values.len();
        SweptKey {
            path: path.to_owned(),
            values,
            span: 0..0,
            value_spans: vec![0..0; n],
        }
    }

    fn floats(v: &[f64]) -> Vec<toml::Value> {
        v.iter().map(|&f| toml::Value::Float(f)).collect()
    }

    fn strings(v: &[&str]) -> Vec<toml::Value> {
        v.iter()
            .map(|s| toml::Value::String((*s).to_owned()))
            .collect()
    }

    #[test]
    fn the_product_varies_the_first_key_slowest() {
        let keys = [
            key("fracture.width_mm", floats(&[2.0, 2.5, 3.0])),
            key("grading.preset", strings(&["20/40", "30/50"])),
        ];
        assert_eq!(
            points(&keys),
            [[0, 0], [0, 1], [1, 0], [1, 1], [2, 0], [2, 1]]
        );
        assert_eq!(
            point_names(&keys),
            [
                "width_mm=2,preset=20-40",
                "width_mm=2,preset=30-50",
                "width_mm=2.5,preset=20-40",
                "width_mm=2.5,preset=30-50",
                "width_mm=3,preset=20-40",
                "width_mm=3,preset=30-50",
            ]
        );
        assert_eq!(run_name("width_mm=2", 3), "width_mm=2,seed=3");
        assert!(points(&[]).len() == 1 && point_names(&[]) == [""]);
    }

    #[test]
    fn names_stay_unique_and_safe() {
        // Two keys ending alike are named by their paths.
        let keys = [
            key("domain.width", floats(&[10.0])),
            key("other.width", floats(&[1.0])),
        ];
        assert_eq!(point_names(&keys), ["domain.width=10,other.width=1"]);
        // Values that would name two folders alike, or none, go by index.
        let clash = [key("grading.preset", strings(&["20/40", "20-40"]))];
        assert_eq!(point_names(&clash), ["preset=v0", "preset=v1"]);
        let empty = [key("a.b", strings(&["", "x"]))];
        assert_eq!(point_names(&empty), ["b=v0", "b=v1"]);
        let arrays = [key(
            "grading.uniform",
            vec![toml::Value::Array(floats(&[1.0, 1.5]))],
        )];
        assert_eq!(point_names(&arrays), ["uniform=1-1.5"]);
        for name in point_names(&[key("a.b", strings(&["../x y:*"]))]) {
            assert!(
                name.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "._-=,".contains(c))
            );
        }
    }

    fn row(status: Status) -> Row {
        Row {
            run: String::new(),
            values: Vec::new(),
            seed: 0,
            status,
        }
    }

    fn finished(porosity: f64) -> Status {
        Status::Finished(Measures {
            particles: 10,
            porosity,
            psd_ks: 0.1,
            coordination: 3.0,
            target_error: None,
            seconds: 0.5,
        })
    }

    #[test]
    fn spreads_skip_the_runs_that_did_not_finish() {
        let rows = [
            row(finished(0.2)),
            row(finished(0.4)),
            row(Status::Failed("too narrow".to_owned())),
            row(Status::Failed("too narrow".to_owned())),
            row(finished(0.3)),
            row(Status::NotRun),
        ];
        let s = spreads(&rows, 2, Measure::Porosity);
        assert_eq!(s.len(), 3);
        let first = s[0].expect("two runs");
        assert!((first.mean - 0.3).abs() < 1e-12 && first.min == 0.2 && first.max == 0.4);
        assert_eq!(first.runs, 2);
        assert_eq!(s[1], None);
        assert_eq!(s[2].map(|p| (p.mean, p.runs)), Some((0.3, 1)));
        // No target: no error to draw.
        assert!(
            spreads(&rows, 2, Measure::Error)
                .iter()
                .all(Option::is_none)
        );
        assert_eq!(Status::NotRun.text(), "not run");
        assert_eq!(Status::Failed("x".to_owned()).text(), "failed: x");
    }
}
