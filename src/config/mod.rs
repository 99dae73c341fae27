//! TOML configuration (to come).
