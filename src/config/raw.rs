//! Stage one: the config as written, every value with its place in the text.
//!
//! Only TOML syntax, key names and value types are checked here (by serde);
//! meaning is checked in `validate.rs`.

use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::ops::Deref;

use serde::Deserialize;
use serde::de::value::MapAccessDeserializer;
use serde::de::{self, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
use toml::Spanned;

/// A pair of numbers such as `[x, y]` or a grading row `[d, passing]`.
pub(crate) type Pair = Spanned<Exact<[f64; 2]>>;

/// A layer of a steps profile: `[material name, thickness]`.
pub(crate) type Layer = Spanned<Exact<(String, f64)>>;

/// An array of the config with a fixed shape (`[x, y]`, `[d, passing]`,
/// `[name, thickness]`): exactly [`Shape::LEN`] elements, each of its type.
///
/// Every fixed-shape array of [`RawConfig`] is read through this one type.
/// serde's own arrays and tuples stop reading after their last element and
/// leave the rest unread, so `[0, 0, "junk", [1, 2]]` was taken as `[0, 0]`;
/// here the elements past the shape are counted and the array refused with
/// its length (`invalid length 4, expected an array of 2 numbers`), at the
/// array's place and key path like every schema error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Exact<T>(pub T);

impl<T> Deref for Exact<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.0
    }
}

/// The shape of a fixed-length array: how many elements, of which types.
pub(crate) trait Shape: Sized {
    /// The number of elements.
    const LEN: usize;
    /// The shape in words, for messages (`"an array of 2 numbers"`).
    const WHAT: &'static str;
    /// Read the elements in order; fewer than [`Shape::LEN`] is an error.
    fn read<'de, A: SeqAccess<'de>>(seq: &mut A) -> Result<Self, A::Error>;
}

/// Element `index` of a fixed-shape array, or an error naming its length if absent.
fn element<'de, T: Deserialize<'de>, A: SeqAccess<'de>>(
    seq: &mut A,
    index: usize,
    what: &'static str,
) -> Result<T, A::Error> {
    seq.next_element()?
        .ok_or_else(|| de::Error::invalid_length(index, &what))
}

impl Shape for [f64; 2] {
    const LEN: usize = 2;
    const WHAT: &'static str = "an array of 2 numbers";

    fn read<'de, A: SeqAccess<'de>>(seq: &mut A) -> Result<Self, A::Error> {
        Ok([element(seq, 0, Self::WHAT)?, element(seq, 1, Self::WHAT)?])
    }
}

impl Shape for (String, f64) {
    const LEN: usize = 2;
    const WHAT: &'static str = "an array of a material name and a number";

    fn read<'de, A: SeqAccess<'de>>(seq: &mut A) -> Result<Self, A::Error> {
        Ok((element(seq, 0, Self::WHAT)?, element(seq, 1, Self::WHAT)?))
    }
}

/// A table of the config (`[domain]`, each `[[materials]]`, …): read from a
/// TOML table only.
///
/// Every table-typed key of [`RawConfig`] is read through this one type.
/// serde's derived structs also accept an array, filling their fields by
/// position: `[[domain]]` was read as a domain whose `shape` is a table, and
/// `wells = [["a", 1.0]]` as a well named "a" of width 1. Here an array is
/// refused as such ([`NOT_AN_ARRAY_OF_TABLES`] for an array of tables).
#[derive(Debug)]
pub(crate) struct Table<T>(pub T);

impl<T> Deref for Table<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.0
    }
}

/// The message for an array of tables where one table belongs.
pub(crate) const NOT_AN_ARRAY_OF_TABLES: &str = "must be a table, not an array of tables";

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Table<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TableVisitor<T>(PhantomData<T>);

        impl<'de, T: Deserialize<'de>> Visitor<'de> for TableVisitor<T> {
            type Value = Table<T>;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a table")
            }

            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                T::deserialize(MapAccessDeserializer::new(map)).map(Table)
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let tables = matches!(seq.next_element()?, Some(toml::Value::Table(_)));
                Err(de::Error::custom(if tables {
                    NOT_AN_ARRAY_OF_TABLES
                } else {
                    "must be a table, not an array"
                }))
            }
        }

        deserializer.deserialize_any(TableVisitor(PhantomData))
    }
}

impl<'de, T: Shape> Deserialize<'de> for Exact<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ExactVisitor<T>(PhantomData<T>);

        impl<'de, T: Shape> Visitor<'de> for ExactVisitor<T> {
            type Value = Exact<T>;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(T::WHAT)
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let value = T::read(&mut seq)?;
                let mut extra = 0;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    extra += 1;
                }
                if extra > 0 {
                    return Err(de::Error::invalid_length(T::LEN + extra, &T::WHAT));
                }
                Ok(Exact(value))
            }
        }

        deserializer.deserialize_seq(ExactVisitor(PhantomData))
    }
}

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawConfig {
    pub seed: Option<Spanned<u64>>,
    /// Required unless `[fracture]` gives the domain.
    pub domain: Option<Spanned<Table<RawDomain>>>,
    pub fracture: Option<Spanned<Table<RawFracture>>>,
    /// Required unless `[layering] mode = "sizes"` gives each material its own.
    pub grading: Option<Spanned<Table<RawGrading>>>,
    pub packer: Option<Table<RawPacker>>,
    pub optimise: Option<Spanned<Table<RawOptimise>>>,
    /// `[optimise]` spelt the American way; one of the two at most. (Not a
    /// serde alias: with both tables given, serde's "duplicate field" error
    /// named neither.)
    pub optimize: Option<Spanned<Table<RawOptimise>>>,
    pub materials: Option<Vec<Spanned<Table<RawMaterial>>>>,
    pub layering: Option<Spanned<Table<RawLayering>>>,
    pub limits: Option<Table<RawLimits>>,
    pub compare: Option<Spanned<Table<RawCompare>>>,
    pub output: Option<Spanned<Table<RawOutput>>>,
    /// `[sweep]`: its keys are config paths, read with their places from
    /// the text (`validate/sweep.rs`).
    pub sweep: Option<Spanned<Table<toml::Table>>>,
}

/// `[output]`: where runs write and what.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    pub dir: Option<Spanned<String>>,
    pub formats: Option<Spanned<Vec<Spanned<String>>>>,
    pub density: Option<Spanned<f64>>,
    pub units: Option<Spanned<String>>,
}

/// `[compare]`: the methods `gapack compare` runs, and how many seeds.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCompare {
    pub methods: Option<Spanned<Vec<Spanned<String>>>>,
    pub repeats: Option<Spanned<i64>>,
}

/// `[[materials]]`: a name, free-form numeric properties, and in size-graded
/// mode a grading. Any other key is a property (checked to be a number).
#[derive(Debug, Deserialize)]
pub(crate) struct RawMaterial {
    pub name: Spanned<String>,
    pub grading: Option<Spanned<Table<RawGrading>>>,
    #[serde(flatten)]
    pub properties: BTreeMap<String, toml::Value>,
}

/// `[layering]`: where materials go along an axis.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLayering {
    pub mode: Option<Spanned<String>>,
    pub axis: Option<Spanned<String>>,
    pub bins: Option<Spanned<i64>>,
    pub profile: Option<Spanned<String>>,
    pub exponent: Option<Spanned<f64>>,
    pub layers: Option<Spanned<Vec<Layer>>>,
    pub table: Option<Spanned<Vec<Spanned<Vec<f64>>>>>,
    pub tolerance: Option<Spanned<f64>>,
    pub population: Option<Spanned<i64>>,
    pub generations: Option<Spanned<i64>>,
    pub stagnation: Option<Spanned<i64>>,
    pub time_limit_s: Option<Spanned<f64>>,
    pub max_evaluations: Option<Spanned<i64>>,
}

/// `[fracture]`: one fracture (absolute or normalised form), or a batch of wells.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawFracture {
    pub width_mm: Option<Spanned<f64>>,
    pub height_m: Option<Spanned<f64>>,
    pub tip_width_mm: Option<Spanned<f64>>,
    pub width_ratio: Option<Spanned<f64>>,
    pub length_ratio: Option<Spanned<f64>>,
    pub mean_diameter: Option<Spanned<f64>>,
    pub walls: Option<Spanned<String>>,
    pub wall_disk: Option<Spanned<f64>>,
    pub extent: Option<Spanned<String>>,
    pub window_tolerance: Option<Spanned<f64>>,
    pub wells: Option<Vec<Spanned<Table<RawWell>>>>,
}

/// `[[fracture.wells]]`: a named fracture of a batch.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWell {
    pub name: Spanned<String>,
    pub width_mm: Option<Spanned<f64>>,
    pub height_m: Option<Spanned<f64>>,
    pub tip_width_mm: Option<Spanned<f64>>,
    pub fill: Option<Spanned<String>>,
}

/// `[domain]`: one shape and the keys that size it, plus the wall model.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawDomain {
    pub shape: Spanned<String>,
    pub width: Option<Spanned<f64>>,
    pub height: Option<Spanned<f64>>,
    pub vertices: Option<Spanned<Vec<Pair>>>,
    pub radius: Option<Spanned<f64>>,
    pub center: Option<Pair>,
    pub bottom: Option<Spanned<f64>>,
    pub top: Option<Spanned<f64>>,
    pub walls: Option<Spanned<String>>,
    pub wall_disk: Option<Spanned<f64>>,
}

/// `[grading]`: exactly one of `table`, `uniform`, `constant`, `preset`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawGrading {
    pub table: Option<Spanned<Vec<Pair>>>,
    pub uniform: Option<Pair>,
    pub constant: Option<Spanned<f64>>,
    pub preset: Option<Spanned<String>>,
    pub interpolation: Option<Spanned<String>>,
    pub basis: Option<Spanned<String>>,
}

/// `[packer]`: method and its settings.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPacker {
    pub method: Option<Spanned<String>>,
    pub index: Option<Spanned<String>>,
    pub contacts: Option<Spanned<i64>>,
    pub one_contact_share: Option<Spanned<f64>>,
    pub gap: Option<Spanned<f64>>,
    pub max_deferred: Option<Spanned<i64>>,
    pub rules: Option<Spanned<String>>,
    pub fill: Option<Spanned<String>>,
    pub attempts: Option<Spanned<i64>>,
    pub relaxation_porosity: Option<Spanned<f64>>,
    pub relaxation_iterations: Option<Spanned<i64>>,
    pub relaxation_tolerance: Option<Spanned<f64>>,
    pub densify_porosity: Option<Spanned<f64>>,
    pub densify_iterations: Option<Spanned<i64>>,
    pub strips: Option<Spanned<RawStrips>>,
}

/// `packer.strips`: `"auto"` or a number of strips.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum RawStrips {
    Count(i64),
    Name(String),
}

/// `[optimise]` (or `[optimize]`): a target-porosity run.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOptimise {
    pub target_porosity: Option<Spanned<f64>>,
    pub tolerance: Option<Spanned<f64>>,
    pub population: Option<Spanned<i64>>,
    pub generations: Option<Spanned<i64>>,
    pub stagnation: Option<Spanned<i64>>,
    pub time_limit_s: Option<Spanned<f64>>,
    pub max_evaluations: Option<Spanned<i64>>,
    pub window_disks: Option<Spanned<i64>>,
    pub max_psd_ks: Option<Spanned<f64>>,
}

/// `[limits]`: guards against scenes too large for the machine.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLimits {
    pub max_memory_mb: Option<Spanned<f64>>,
    pub max_particles: Option<Spanned<i64>>,
}
