//! Geometric predicates and tolerances (to come).
