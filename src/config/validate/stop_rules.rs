//! The population and stop rules `[optimise]` and `[layering]` share.

use super::Validator;
use crate::config::error::ConfigError;
use crate::config::raw::RawStopRules;
use crate::ga::StopRules;

impl Validator<'_> {
    /// The stop rules of GA table `table` (`optimise`, `layering`), their
    /// defaults where not given, each key checked against its range in the
    /// order of [`StopRules`]' fields.
    pub(super) fn stop_rules(
        &self,
        table: &str,
        raw: &RawStopRules,
    ) -> Result<StopRules, ConfigError> {
        let key = |name: &str| format!("{table}.{name}");
        let mut s = StopRules::default();
        if let Some(v) = &raw.population {
            s.population = self.whole(&key("population"), v, 2, None)?;
        }
        if let Some(v) = &raw.generations {
            s.generations = self.whole(&key("generations"), v, 1, None)?;
        }
        if let Some(v) = &raw.stagnation {
            s.stagnation = self.whole(&key("stagnation"), v, 1, None)?;
        }
        if let Some(v) = &raw.time_limit_s {
            s.time_limit_s = self.positive(&key("time_limit_s"), v)?;
        }
        if let Some(v) = &raw.max_evaluations {
            s.max_evaluations = Some(self.whole(&key("max_evaluations"), v, 1, None)? as u64);
        }
        Ok(s)
    }
}
