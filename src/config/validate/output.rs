//! `[output]`: the directory, known format names given once, the export
//! settings, the pictures' colouring, the compression of `packing.vtp`,
//! the per-particle columns added to the tables.

use toml::Spanned;

use super::Validator;
use crate::config::error::ConfigError;
use crate::config::raw::{RawOutput, Table};
use crate::names::Names;
use crate::output::{
    COLOURINGS, ClumpOptions, Colouring, FORMATS, Format, OutputSettings, PER_PARTICLE, UNITS,
    VTP_COMPRESSIONS,
};

impl Validator<'_> {
    /// `[output]`: its defaults when the table is absent. `shapes`: the
    /// particles are not disks (a `[shape]`); `materials`: the config names
    /// materials. `colour = "orientation"` needs the first, `"material"`
    /// the second.
    pub(in crate::config) fn output(
        &self,
        raw: Option<&Spanned<Table<RawOutput>>>,
        shapes: bool,
        materials: bool,
    ) -> Result<OutputSettings, ConfigError> {
        let mut settings = OutputSettings::default();
        let Some(raw) = raw else {
            return Ok(settings);
        };
        let o = raw.get_ref();
        if let Some(dir) = &o.dir {
            if dir.get_ref().trim().is_empty() {
                return Err(ConfigError::Missing {
                    at: self.at(&dir.span()),
                    key: "output.dir".to_owned(),
                    reason: "give a directory, or leave the key out for out/<config name>"
                        .to_owned(),
                });
            }
            settings.dir = Some(dir.get_ref().clone());
        }
        if let Some(formats) = &o.formats {
            settings.formats = self.names_once(&FORMATS, "output.formats", formats)?;
        }
        if let Some(columns) = &o.per_particle {
            settings.per_particle =
                self.names_once(&PER_PARTICLE, "output.per_particle", columns)?;
            let tables = [Format::Csv, Format::Vtp, Format::Npz];
            if !settings.per_particle.is_empty() && !tables.iter().any(|&f| settings.wants(f)) {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&columns.span()),
                    key: "output.per_particle".to_owned(),
                    reason: "the columns go into packing.csv, packing.vtp and packing.npz, and formats asks for none of them: add \"csv\", \"vtp\" or \"npz\" to formats".to_owned(),
                });
            }
        }
        if let Some(v) = &o.density {
            settings.export.density = self.positive("output.density", v)?;
        }
        settings.export.units = self.name(&UNITS, "output.units", o.units.as_ref())?;
        settings.vtp_compression = self.name(
            &VTP_COMPRESSIONS,
            "output.vtp_compression",
            o.vtp_compression.as_ref(),
        )?;
        if let Some(v) = &o.clump_coverage {
            settings.export.clumps.coverage = self.checked(
                "output.clump_coverage",
                v,
                &format!("in (0, {}]", ClumpOptions::MAX_COVERAGE),
                |c| c > 0.0 && c <= ClumpOptions::MAX_COVERAGE,
            )?;
        }
        if let Some(v) = &o.clump_max_disks {
            settings.export.clumps.max_disks = self.whole(
                "output.clump_max_disks",
                v,
                1,
                Some(ClumpOptions::MOST_DISKS as i64),
            )?;
        }
        if let Some(given) = &o.colour {
            let colour = self.name(&COLOURINGS, "output.colour", Some(given))?;
            let refusal = match colour {
                Colouring::Orientation if !shapes => Some(
                    "\"orientation\" colours particles by the angle of their long axis, and disks have none: add a [shape] table, or use colour = \"size\" or \"material\"",
                ),
                Colouring::Material if !materials => Some(
                    "\"material\" colours particles by their material, and the config names none: add [[materials]], or use colour = \"size\"",
                ),
                _ => None,
            };
            if let Some(reason) = refusal {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&given.span()),
                    key: "output.colour".to_owned(),
                    reason: reason.to_owned(),
                });
            }
            settings.colour = Some(colour);
        }
        Ok(settings)
    }

    /// The values of the array `key`, each a name of `names` given once,
    /// in order; an unknown or repeated name is refused at its place
    /// (`key[i]`).
    fn names_once<T: Copy + PartialEq>(
        &self,
        names: &Names<T>,
        key: &str,
        given: &Spanned<Vec<Spanned<String>>>,
    ) -> Result<Vec<T>, ConfigError> {
        let mut out = Vec::new();
        for (i, name) in given.get_ref().iter().enumerate() {
            let key = format!("{key}[{i}]");
            let value = names
                .get(name.get_ref())
                .ok_or_else(|| ConfigError::UnknownName {
                    at: self.at(&name.span()),
                    key: key.clone(),
                    what: names.what,
                    given: format!("{:?}", name.get_ref()),
                    valid: names.valid(),
                })?;
            if out.contains(&value) {
                return Err(ConfigError::NotApplicable {
                    at: self.at(&name.span()),
                    key,
                    reason: format!("{:?} is given twice", name.get_ref()),
                });
            }
            out.push(value);
        }
        Ok(out)
    }
}
