//! Stage one: the config as written, every value with its place in the text.
//!
//! Only TOML syntax, key names and value types are checked here (by serde);
//! meaning is checked in `validate.rs`.

use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::ops::Deref;

use serde::Deserialize;
use serde::de::value::{MapAccessDeserializer, StringDeserializer};
use serde::de::{self, DeserializeSeed, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};
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
    pub optimise: Option<Spanned<Table<WithStop<RawOptimise>>>>,
    /// `[optimise]` spelt the American way; one of the two at most. (Not a
    /// serde alias: with both tables given, serde's "duplicate field" error
    /// named neither.)
    pub optimize: Option<Spanned<Table<WithStop<RawOptimise>>>>,
    pub materials: Option<Vec<Spanned<Table<RawMaterial>>>>,
    pub layering: Option<Spanned<Table<WithStop<RawLayering>>>>,
    pub limits: Option<Table<RawLimits>>,
    pub compare: Option<Spanned<Table<RawCompare>>>,
    pub output: Option<Spanned<Table<RawOutput>>>,
    /// `[sweep]`: its keys are config paths, read with their places from
    /// the text (`validate/sweep.rs`).
    pub sweep: Option<Spanned<Table<toml::Table>>>,
    /// `[shape]`: the particles' outlines; disks without it.
    pub shape: Option<Spanned<Table<RawShape>>>,
}

/// `[shape]`: the family of outlines, its parameters, the orientation and
/// which size the grading measures.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShape {
    pub kind: Option<Spanned<String>>,
    pub aspect: Option<Spanned<RawSpread>>,
    pub alpha: Option<Spanned<RawSpread>>,
    pub beta: Option<Spanned<RawSpread>>,
    pub orientation: Option<Spanned<String>>,
    pub angle: Option<Spanned<f64>>,
    pub spread: Option<Spanned<f64>>,
    pub size: Option<Spanned<String>>,
    pub templates: Option<Vec<Spanned<Table<RawTemplate>>>>,
    /// A common proppant's shape (`ceramic`, ...), instead of the family's keys.
    pub preset: Option<Spanned<String>>,
}

/// `[[shape.templates]]`: one convex polygon and its share of the particles.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTemplate {
    pub vertices: Spanned<Vec<Pair>>,
    pub rounding: Option<Spanned<f64>>,
    pub share: Option<Spanned<f64>>,
}

/// A quantity of `[shape]` as written: a number, a range `[low, high]`,
/// or a table `{ values = [...], shares = [...] }`.
///
/// Read by hand, not as an untagged enum: serde buffers an untagged value,
/// and a buffered value loses its places (`toml::Spanned` refuses it), so
/// the elements could not be blamed by line and column.
#[derive(Debug)]
pub(crate) enum RawSpread {
    /// One value.
    Fixed(f64),
    /// `[low, high]`.
    Range(Spanned<f64>, Spanned<f64>),
    /// Values with their shares.
    Shares(RawShares),
}

/// The table form of a [`RawSpread`].
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShares {
    pub values: Spanned<Vec<Spanned<f64>>>,
    pub shares: Spanned<Vec<Spanned<f64>>>,
}

impl<'de> Deserialize<'de> for RawSpread {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SpreadVisitor;

        /// What a range is, for its length error.
        const RANGE: &str = "a range [low, high] of 2 numbers";

        impl<'de> Visitor<'de> for SpreadVisitor {
            type Value = RawSpread;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a number, a range [low, high] or a table { values = [...], shares = [...] }",
                )
            }

            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawSpread, E> {
                Ok(RawSpread::Fixed(v))
            }

            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawSpread, E> {
                Ok(RawSpread::Fixed(v as f64))
            }

            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawSpread, E> {
                Ok(RawSpread::Fixed(v as f64))
            }

            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawSpread, A::Error> {
                let lo = element(&mut seq, 0, RANGE)?;
                let hi = element(&mut seq, 1, RANGE)?;
                let mut extra = 0;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    extra += 1;
                }
                if extra > 0 {
                    return Err(de::Error::invalid_length(2 + extra, &RANGE));
                }
                Ok(RawSpread::Range(lo, hi))
            }

            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RawSpread, A::Error> {
                RawShares::deserialize(MapAccessDeserializer::new(map)).map(RawSpread::Shares)
            }
        }

        deserializer.deserialize_any(SpreadVisitor)
    }
}

/// `[output]`: where runs write and what.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOutput {
    pub dir: Option<Spanned<String>>,
    pub formats: Option<Spanned<Vec<Spanned<String>>>>,
    pub density: Option<Spanned<f64>>,
    pub units: Option<Spanned<String>>,
    pub clump_coverage: Option<Spanned<f64>>,
    pub clump_max_disks: Option<Spanned<i64>>,
    pub colour: Option<Spanned<String>>,
    pub vtp_compression: Option<Spanned<String>>,
    pub per_particle: Option<Spanned<Vec<Spanned<String>>>>,
}

/// `[compare]`: the methods `gapack compare` runs, and how many seeds.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCompare {
    pub methods: Option<Spanned<Vec<Spanned<String>>>>,
    pub repeats: Option<Spanned<i64>>,
}

/// `[[materials]]`: a name, free-form numeric properties, in size-graded
/// mode a grading, and a shape of its own. Any other key is a property
/// (checked to be a number).
#[derive(Debug, Deserialize)]
pub(crate) struct RawMaterial {
    pub name: Spanned<String>,
    pub grading: Option<Spanned<Table<RawGrading>>>,
    /// `[materials.shape]`: the material's own particle shape.
    pub shape: Option<Spanned<Table<RawShape>>>,
    #[serde(flatten)]
    pub properties: BTreeMap<String, toml::Value>,
}

/// `[layering]`: where materials go along an axis (read as a
/// [`WithStop`], which adds the GA's keys).
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
}

impl GaKeys for RawLayering {
    const KEYS: &'static [&'static str] = &with_stop_keys::<8, 0, 13>(
        [
            "mode",
            "axis",
            "bins",
            "profile",
            "exponent",
            "layers",
            "table",
            "tolerance",
        ],
        [],
    );
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

/// `packer.strips`: `"auto"` or a number of strips, or any other value,
/// kept for the validator to refuse by the key's own rule.
///
/// Read by hand, not as an untagged enum: serde refused a value that is
/// neither (`2.5`, `true`) with its own words ("data did not match any
/// variant of untagged enum"), naming neither the rule nor the value.
#[derive(Debug)]
pub(crate) enum RawStrips {
    /// A whole number.
    Count(i64),
    /// A string (`"auto"` is the one name).
    Name(String),
    /// Anything else: a fraction, a boolean, an array, a table, a date.
    Other(toml::Value),
}

impl<'de> Deserialize<'de> for RawStrips {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Ok(match toml::Value::deserialize(deserializer)? {
            toml::Value::Integer(n) => RawStrips::Count(n),
            toml::Value::String(s) => RawStrips::Name(s),
            other => RawStrips::Other(other),
        })
    }
}

/// `[optimise]` (or `[optimize]`): a target-porosity run (read as a
/// [`WithStop`], which adds the GA's keys).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawOptimise {
    pub target_porosity: Option<Spanned<f64>>,
    pub tolerance: Option<Spanned<f64>>,
    pub window_disks: Option<Spanned<i64>>,
    pub max_psd_ks: Option<Spanned<f64>>,
    /// `[optimise.shape]`: what the search may move of the `[shape]`.
    pub shape: Option<Spanned<Table<RawShapeSearch>>>,
}

impl GaKeys for RawOptimise {
    const KEYS: &'static [&'static str] = &with_stop_keys::<2, 3, 10>(
        ["target_porosity", "tolerance"],
        ["window_disks", "max_psd_ks", "shape"],
    );
}

/// `[optimise.shape]`: the bounds within which the target-porosity search
/// moves a superellipse shape, and the constraints its shapes keep.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawShapeSearch {
    pub aspect: Option<Pair>,
    pub exponent: Option<Pair>,
    /// Degrees.
    pub orientation_spread: Option<Pair>,
    pub min_sphericity: Option<Spanned<f64>>,
    pub min_roundness: Option<Spanned<f64>>,
    pub max_shape_ks: Option<Spanned<f64>>,
}

/// The keys of a GA search that `[optimise]` and `[layering]` share
/// (`ga::StopRules`), read by [`WithStop`] beside each table's own.
#[derive(Debug, Default)]
pub(crate) struct RawStopRules {
    pub population: Option<Spanned<i64>>,
    pub generations: Option<Spanned<i64>>,
    pub stagnation: Option<Spanned<i64>>,
    pub time_limit_s: Option<Spanned<f64>>,
    pub max_evaluations: Option<Spanned<i64>>,
}

impl RawStopRules {
    /// The keys, as written in the tables.
    const KEYS: [&'static str; 5] = [
        "population",
        "generations",
        "stagnation",
        "time_limit_s",
        "max_evaluations",
    ];

    /// Read the value of `key` (one of [`RawStopRules::KEYS`]) from `map`.
    fn read<'de, A: MapAccess<'de>>(&mut self, key: &str, map: &mut A) -> Result<(), A::Error> {
        match key {
            "population" => self.population = map.next_value()?,
            "generations" => self.generations = map.next_value()?,
            "stagnation" => self.stagnation = map.next_value()?,
            "time_limit_s" => self.time_limit_s = map.next_value()?,
            _ => self.max_evaluations = map.next_value()?,
        }
        Ok(())
    }
}

/// A table of the GA (`[optimise]`, `[layering]`) that holds the table's own
/// keys `T` and the [`RawStopRules`] they share.
///
/// Not `#[serde(flatten)]`: a flattened struct is read from serde's buffer
/// of the table, where `toml::Spanned` has no span (toml 1.2 refuses
/// `b = 2` with "invalid type: integer `2`, expected a spanned value"), and
/// beside `deny_unknown_fields` an unknown key is refused at the table's
/// header, not its own line, with no list of the valid keys. Here the
/// table is read in one pass: each key is told apart while the TOML reader
/// reads it (so an unknown key is refused at its own line and column,
/// listing [`GaKeys::KEYS`]), a shared key's value is read into `stop`, and
/// every other key goes to `T`'s own derived reader, spans and all.
#[derive(Debug)]
pub(crate) struct WithStop<T> {
    /// The table's own keys.
    pub own: T,
    /// The keys every GA table has.
    pub stop: RawStopRules,
}

impl<T> Deref for WithStop<T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.own
    }
}

/// A GA table's own keys ([`WithStop`]'s `T`).
pub(crate) trait GaKeys {
    /// Every key of the table, its own and [`RawStopRules::KEYS`], in the
    /// order an unknown key's message lists them.
    const KEYS: &'static [&'static str];
}

/// A GA table's key list ([`GaKeys::KEYS`]), `N` keys in all: its own keys
/// `before` the shared ones, [`RawStopRules::KEYS`], then its own `after`.
const fn with_stop_keys<const A: usize, const B: usize, const N: usize>(
    before: [&'static str; A],
    after: [&'static str; B],
) -> [&'static str; N] {
    let shared = RawStopRules::KEYS;
    assert!(A + shared.len() + B == N, "N counts every key");
    let mut keys = [""; N];
    let mut i = 0;
    while i < N {
        keys[i] = if i < A {
            before[i]
        } else if i < A + shared.len() {
            shared[i - A]
        } else {
            after[i - A - shared.len()]
        };
        i += 1;
    }
    keys
}

/// A key of a [`WithStop`] table as read: a shared one (handing back the
/// seed the key was meant for), or one of `T`'s.
enum SplitKey<S, K> {
    Stop(&'static str, S),
    Own(K),
}

/// Reads a key of a [`WithStop`] table: a shared key, or one `T` knows
/// (through `seed`, `T`'s own key reader), or else an unknown key, refused
/// while the TOML reader reads it so that the error has the key's place.
struct SplitSeed<S, T> {
    seed: S,
    table: PhantomData<T>,
}

impl<'de, S: DeserializeSeed<'de>, T: GaKeys> DeserializeSeed<'de> for SplitSeed<S, T> {
    type Value = SplitKey<S, S::Value>;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<Self::Value, D::Error> {
        let key = String::deserialize(deserializer)?;
        if let Some(stop) = RawStopRules::KEYS.into_iter().find(|k| *k == key) {
            return Ok(SplitKey::Stop(stop, self.seed));
        }
        if !T::KEYS.contains(&key.as_str()) {
            return Err(de::Error::unknown_field(&key, T::KEYS));
        }
        self.seed
            .deserialize(StringDeserializer::<D::Error>::new(key))
            .map(SplitKey::Own)
    }
}

/// The table as `T` sees it: its own keys only, the shared ones read into `stop` on the way.
struct Split<'s, A, T> {
    map: A,
    stop: &'s mut RawStopRules,
    table: PhantomData<T>,
}

impl<'de, A: MapAccess<'de>, T: GaKeys> MapAccess<'de> for Split<'_, A, T> {
    type Error = A::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        mut seed: K,
    ) -> Result<Option<K::Value>, A::Error> {
        loop {
            let split = SplitSeed::<K, T> {
                seed,
                table: PhantomData,
            };
            match self.map.next_key_seed(split)? {
                None => return Ok(None),
                Some(SplitKey::Own(key)) => return Ok(Some(key)),
                Some(SplitKey::Stop(key, unused)) => {
                    self.stop.read(key, &mut self.map)?;
                    seed = unused;
                }
            }
        }
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, A::Error> {
        self.map.next_value_seed(seed)
    }
}

impl<'de, T: Deserialize<'de> + GaKeys> Deserialize<'de> for WithStop<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct WithStopVisitor<T>(PhantomData<T>);

        impl<'de, T: Deserialize<'de> + GaKeys> Visitor<'de> for WithStopVisitor<T> {
            type Value = WithStop<T>;

            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a table")
            }

            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                let mut stop = RawStopRules::default();
                let own = T::deserialize(MapAccessDeserializer::new(Split::<A, T> {
                    map,
                    stop: &mut stop,
                    table: PhantomData,
                }))?;
                Ok(WithStop { own, stop })
            }
        }

        deserializer.deserialize_map(WithStopVisitor(PhantomData))
    }
}

/// `[limits]`: guards against scenes too large for the machine.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLimits {
    pub max_memory_mb: Option<Spanned<f64>>,
    pub max_particles: Option<Spanned<i64>>,
}

#[cfg(test)]
mod tests {
    use serde::de::value::Error;

    use super::*;

    /// The keys `T`'s derived reader knows, as it names them to a deserializer.
    fn own_keys<T: for<'de> Deserialize<'de>>() -> Vec<String> {
        struct Fields;

        impl<'de> Deserializer<'de> for Fields {
            type Error = Error;

            fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Error> {
                Err(de::Error::custom("not a struct"))
            }

            fn deserialize_struct<V: Visitor<'de>>(
                self,
                _: &'static str,
                fields: &'static [&'static str],
                _: V,
            ) -> Result<V::Value, Error> {
                Err(de::Error::custom(fields.join(" ")))
            }

            serde::forward_to_deserialize_any! {
                bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string
                bytes byte_buf option unit unit_struct newtype_struct seq tuple
                tuple_struct map enum identifier ignored_any
            }
        }

        let Err(fields) = T::deserialize(Fields) else {
            unreachable!("Fields gives no value");
        };
        fields.to_string().split(' ').map(str::to_owned).collect()
    }

    /// Each GA table's key list, which unknown-key messages give, is its
    /// own keys and the shared ones, each once.
    fn keys_are_own_and_shared<T: GaKeys + for<'de> Deserialize<'de>>() {
        let mut listed = T::KEYS.to_vec();
        let mut known = own_keys::<T>();
        known.extend(RawStopRules::KEYS.map(str::to_owned));
        listed.sort_unstable();
        known.sort_unstable();
        assert_eq!(listed, known);
    }

    #[test]
    fn ga_tables_list_their_own_keys_and_the_shared_ones() {
        keys_are_own_and_shared::<RawOptimise>();
        keys_are_own_and_shared::<RawLayering>();
    }
}
