//! The checks every table's values share: whole numbers, ranges, positive
//! and finite numbers, pairs, names looked up in their table.

use toml::Spanned;

use super::Validator;
use crate::config::error::ConfigError;
use crate::config::raw::Pair;
use crate::names::Names;

impl Validator<'_> {
    /// A whole number of at least `least` and, if given, at most `most`.
    pub(super) fn whole(
        &self,
        key: &str,
        v: &Spanned<i64>,
        least: i64,
        most: Option<i64>,
    ) -> Result<usize, ConfigError> {
        let n = *v.get_ref();
        if n >= least && most.is_none_or(|m| n <= m) {
            return Ok(n as usize);
        }
        Err(ConfigError::OutOfRange {
            at: self.at(&v.span()),
            key: key.to_owned(),
            range: match most {
                None => format!("a whole number ≥ {least}"),
                Some(m) => format!("a whole number in [{least}, {m}]"),
            },
            value: n as f64,
        })
    }

    /// A number that must pass `ok`, described as `range` in the message.
    pub(super) fn checked(
        &self,
        key: &str,
        value: &Spanned<f64>,
        range: &str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if ok(v) {
            Ok(v)
        } else {
            Err(ConfigError::OutOfRange {
                at: self.at(&value.span()),
                key: key.to_owned(),
                range: range.to_owned(),
                value: v,
            })
        }
    }

    /// A value that must be a positive finite number.
    pub(super) fn positive(&self, key: &str, value: &Spanned<f64>) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(ConfigError::NotPositive {
                at: self.at(&value.span()),
                key: key.to_owned(),
                value: v,
            })
        }
    }

    /// A pair of numbers that must both be finite.
    pub(super) fn finite_pair(&self, key: &str, pair: &Pair) -> Result<[f64; 2], ConfigError> {
        let p = pair.get_ref().0;
        match p.iter().find(|v| !v.is_finite()) {
            None => Ok(p),
            Some(&value) => Err(ConfigError::NotFinite {
                at: self.at(&pair.span()),
                key: key.to_owned(),
                value,
            }),
        }
    }

    /// A name looked up in its table; the type's default when the key is absent.
    pub(super) fn name<T: Copy + PartialEq + Default>(
        &self,
        names: &Names<T>,
        key: &str,
        value: Option<&Spanned<String>>,
    ) -> Result<T, ConfigError> {
        let Some(value) = value else {
            return Ok(T::default());
        };
        names
            .get(value.get_ref())
            .ok_or_else(|| ConfigError::UnknownName {
                at: self.at(&value.span()),
                key: key.to_owned(),
                what: names.what,
                given: format!("{:?}", value.get_ref()),
                valid: names.valid(),
            })
    }

    /// A number that must lie in `[lo, hi]`.
    pub(super) fn in_range(
        &self,
        key: &str,
        value: &Spanned<f64>,
        lo: f64,
        hi: f64,
    ) -> Result<f64, ConfigError> {
        let v = *value.get_ref();
        if (lo..=hi).contains(&v) {
            Ok(v)
        } else {
            Err(ConfigError::OutOfRange {
                at: self.at(&value.span()),
                key: key.to_owned(),
                range: format!("in [{lo}, {hi}]"),
                value: v,
            })
        }
    }
}
