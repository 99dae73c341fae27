//! A named material with free-form numeric properties.

/// A material particles can be made of.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The name written in outputs (`packing.csv`'s `material` column).
    pub name: String,
    /// Properties as given in the config (`density`, `youngs_modulus`, …),
    /// in config order; carried to the outputs, not interpreted.
    pub properties: Vec<(String, f64)>,
}
