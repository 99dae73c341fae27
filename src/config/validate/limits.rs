//! `[limits]`: the memory and particle limits, and the refusals of a scene
//! over them.

use super::{KeyAt, Validator};
use crate::Scene;
use crate::config::error::ConfigError;
use crate::config::raw::RawLimits;
use crate::packer::{BYTES_PER_MB, PackError, estimated_peak_bytes, peak_bytes_per_particle};

/// `limits.max_memory_mb` when not given.
pub const DEFAULT_MAX_MEMORY_MB: f64 = 4096.0;

/// `limits.max_particles` when not given: about a minute of packing.
pub const DEFAULT_MAX_PARTICLES: u64 = 20_000_000;

impl Validator<'_> {
    /// The memory limit in MB and the key that set it, if given.
    pub(super) fn limit(
        &self,
        raw: Option<&RawLimits>,
    ) -> Result<(f64, Option<KeyAt>), ConfigError> {
        match raw.and_then(|l| l.max_memory_mb.as_ref()) {
            None => Ok((DEFAULT_MAX_MEMORY_MB, None)),
            Some(v) => {
                let key = "limits.max_memory_mb";
                let mb = self.positive(key, v)?;
                Ok((
                    mb,
                    Some(KeyAt {
                        key: key.to_owned(),
                        span: v.span(),
                    }),
                ))
            }
        }
    }

    /// `limits.max_particles` and the key that set it, if given.
    pub(super) fn particles_limit(
        &self,
        raw: Option<&RawLimits>,
    ) -> Result<(u64, Option<KeyAt>), ConfigError> {
        match raw.and_then(|l| l.max_particles.as_ref()) {
            None => Ok((DEFAULT_MAX_PARTICLES, None)),
            Some(v) => {
                let key = "limits.max_particles";
                let n = self.whole(key, v, 1, None)?;
                Ok((
                    n as u64,
                    Some(KeyAt {
                        key: key.to_owned(),
                        span: v.span(),
                    }),
                ))
            }
        }
    }

    /// Refuse a scene that could hold more disks than the limit (the solid
    /// upper bound: the domain filled with disks of the grading's mean area).
    pub(super) fn check_particles(
        &self,
        scene: &Scene,
        width_key: &KeyAt,
        (limit, limit_key): (u64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let disks = scene.max_disks();
        if self.force || disks <= limit as f64 {
            return Ok(());
        }
        let (blame, hint) = match limit_key {
            Some(k) => (k, "; raise it to allow this scene".to_owned()),
            None => (
                width_key.clone(),
                format!(
                    "; set limits.max_particles (default {DEFAULT_MAX_PARTICLES}) to raise the limit"
                ),
            ),
        };
        Err(ConfigError::Scene {
            at: self.at(&blame.span),
            key: blame.key,
            error: PackError::TooManyParticles { disks, limit },
            hint,
        })
    }

    /// Refuse a scene whose estimated peak memory is over the limit.
    pub(super) fn check_memory(
        &self,
        scene: &Scene,
        width_key: &KeyAt,
        (limit_mb, limit_key): (f64, Option<KeyAt>),
    ) -> Result<(), ConfigError> {
        let bytes = estimated_peak_bytes(scene);
        let estimate_mb = bytes / BYTES_PER_MB;
        if self.force || estimate_mb <= limit_mb {
            return Ok(());
        }
        let (blame, hint) = match limit_key {
            Some(k) => (k, "; raise it to allow this scene".to_owned()),
            None => (
                KeyAt {
                    key: width_key.key.clone(),
                    span: width_key.span.clone(),
                },
                format!(
                    "; set limits.max_memory_mb (default {DEFAULT_MAX_MEMORY_MB}) to raise the limit"
                ),
            ),
        };
        Err(ConfigError::Scene {
            at: self.at(&blame.span),
            key: blame.key,
            error: PackError::TooLarge {
                disks: bytes / peak_bytes_per_particle(scene),
                estimate_mb,
                limit_mb,
            },
            hint,
        })
    }
}
