//! Spatial indexes for the neighbour search (to come).
