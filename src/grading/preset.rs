//! Shorthand gradings users expect: a constant size, a uniform range and
//! proppant mesh designations, each by the name users write.

use super::{Basis, Grading, GradingError, Interpolation};

/// Proppant mesh designations: name, smallest and largest diameter (mm).
const PRESETS: [(&str, f64, f64); 5] = [
    ("12/20", 0.850, 1.700),
    ("16/30", 0.600, 1.180),
    ("20/40", 0.425, 0.850),
    ("30/50", 0.300, 0.600),
    ("40/70", 0.212, 0.425),
];

/// The names of [`PRESETS`], in the same order (one source of truth).
const PRESET_NAMES: [&str; PRESETS.len()] = {
    let mut names = [""; PRESETS.len()];
    let mut i = 0;
    while i < PRESETS.len() {
        names[i] = PRESETS[i].0;
        i += 1;
    }
    names
};

/// The valid preset names joined for an error message.
pub(super) fn preset_list() -> String {
    PRESET_NAMES.join(", ")
}

impl Grading {
    /// Uniform in diameter between `a` and `b` (in the given basis).
    ///
    /// The table `[(a, 0), (b, 100)]` with [`Interpolation::Linear`]; with
    /// [`Basis::Mass`] the *area* is uniform in d, so small disks are more
    /// numerous. `a == b` is a constant grading.
    ///
    /// # Errors
    /// [`GradingError::InvalidUniformRange`] unless `0 < a <= b`, both finite.
    pub fn uniform(a: f64, b: f64, basis: Basis) -> Result<Self, GradingError> {
        if !(a.is_finite() && b.is_finite() && a > 0.0 && a <= b) {
            return Err(GradingError::InvalidUniformRange { min: a, max: b });
        }
        Self::from_table(&[(a, 0.0), (b, 100.0)], Interpolation::Linear, basis)
    }

    /// A single diameter: every disk is `d` mm, the CDF a step at `d`.
    ///
    /// # Errors
    /// [`GradingError::InvalidConstant`] unless `d` is positive and finite.
    pub fn constant(d: f64) -> Result<Self, GradingError> {
        if !(d.is_finite() && d > 0.0) {
            return Err(GradingError::InvalidConstant { diameter: d });
        }
        Self::from_table(&[(d, 0.0), (d, 100.0)], Interpolation::Log, Basis::Number)
    }

    /// A proppant mesh preset such as "20/40".
    ///
    /// The mesh range as the table `[(lo, 0), (hi, 100)]`, interpolated and
    /// counted as asked: "12/20" 0.850–1.700, "16/30" 0.600–1.180,
    /// "20/40" 0.425–0.850, "30/50" 0.300–0.600, "40/70" 0.212–0.425 mm.
    ///
    /// # Errors
    /// [`GradingError::UnknownPreset`], whose message lists the valid names.
    pub fn preset(
        name: &str,
        interpolation: Interpolation,
        basis: Basis,
    ) -> Result<Self, GradingError> {
        let Some(&(_, lo, hi)) = PRESETS.iter().find(|(n, _, _)| *n == name) else {
            return Err(GradingError::UnknownPreset {
                name: name.to_owned(),
            });
        };
        Self::from_table(&[(lo, 0.0), (hi, 100.0)], interpolation, basis)
    }

    /// The names [`Grading::preset`] accepts, finest mesh numbers first,
    /// e.g. to list them in a CLI help text.
    pub fn preset_names() -> &'static [&'static str] {
        &PRESET_NAMES
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_have_their_mesh_ranges() {
        let names = Grading::preset_names();
        assert_eq!(names, ["12/20", "16/30", "20/40", "30/50", "40/70"]);
        for (&name, &(_, lo, hi)) in names.iter().zip(PRESETS.iter()) {
            for interp in [Interpolation::Log, Interpolation::Linear] {
                for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
                    let g = Grading::preset(name, interp, basis).expect("known preset");
                    assert_eq!((g.d_min(), g.d_max()), (lo, hi), "{name}");
                    assert_eq!((g.basis(), g.interpolation()), (basis, interp));
                }
            }
        }
        let g = Grading::preset("20/40", Interpolation::Log, Basis::Number).expect("ok");
        assert!((g.sample(0.5) - (0.425f64 * 0.850).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn unknown_preset_lists_valid_names() {
        let e = Grading::preset("20-40", Interpolation::Log, Basis::Number)
            .expect_err("unknown preset");
        assert_eq!(
            e,
            GradingError::UnknownPreset {
                name: "20-40".into()
            }
        );
        assert_eq!(
            e.to_string(),
            "unknown grading preset \"20-40\"; valid presets: 12/20, 16/30, 20/40, 30/50, 40/70"
        );
    }

    #[test]
    fn uniform_is_linear_table() {
        for basis in [Basis::Number, Basis::Mass, Basis::Mass3d] {
            let u = Grading::uniform(1.2, 2.4, basis).expect("ok");
            let t = Grading::from_table(&[(1.2, 0.0), (2.4, 100.0)], Interpolation::Linear, basis)
                .expect("ok");
            assert_eq!(u, t);
        }
        let g = Grading::uniform(1.2, 2.4, Basis::Number).expect("ok");
        assert!((g.sample(0.25) - 1.5).abs() < 1e-12);
        assert!((g.cdf(1.8) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn uniform_with_equal_bounds_is_constant() {
        let g = Grading::uniform(1.25, 1.25, Basis::Mass).expect("ok");
        let c = Grading::constant(1.25).expect("ok");
        assert_eq!((g.d_min(), g.d_max()), (1.25, 1.25));
        for i in 0..=10 {
            let u = f64::from(i) / 10.0;
            assert_eq!(g.sample(u), c.sample(u));
        }
        assert_eq!(g.mean_disk_area(), c.mean_disk_area());
    }

    #[test]
    fn invalid_uniform_rejected() {
        for (a, b) in [
            (2.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
        ] {
            let e = Grading::uniform(a, b, Basis::Number).expect_err("invalid range");
            assert!(
                matches!(e, GradingError::InvalidUniformRange { .. }),
                "{a} {b}"
            );
        }
        assert_eq!(
            Grading::uniform(2.0, 1.0, Basis::Mass)
                .expect_err("reversed")
                .to_string(),
            "uniform grading: needs finite diameters with 0 < min <= max (mm), got min = 2, max = 1"
        );
    }

    #[test]
    fn constant_samples_its_diameter() {
        let g = Grading::constant(1.2).expect("ok");
        for i in 0..=100 {
            assert_eq!(g.sample(f64::from(i) / 100.0), 1.2);
        }
        assert_eq!(g.ks_distance(&[1.2, 1.2, 1.2]), 0.0);
        assert_eq!((g.d_min(), g.d_max()), (1.2, 1.2));
        assert_eq!((g.cdf(1.2 - 1e-12), g.cdf(1.2)), (0.0, 1.0));
        assert!((g.mean_disk_area() - std::f64::consts::FRAC_PI_4 * 1.44).abs() < 1e-12);
    }

    #[test]
    fn invalid_constant_rejected() {
        for bad in [0.0, -1.2, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                Grading::constant(bad),
                Err(GradingError::InvalidConstant { .. })
            ));
        }
    }
}
