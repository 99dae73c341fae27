//! Writers (to come).
