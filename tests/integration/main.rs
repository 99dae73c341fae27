//! The integration tests, one binary (one link, one build of the crate's
//! test harness) with a module per subject: `cargo test --test integration`
//! runs them all, `cargo test --test integration sweep::` one subject.

mod common;

mod binary_outputs;
mod browser;
mod cli;
mod cli_conventions;
mod clumps;
mod compare;
mod configs;
mod densify;
mod exports;
mod fracture;
mod generators;
mod inspect;
mod jobs;
mod layer_shapes;
mod layering;
mod layers;
mod memory;
mod mpi;
mod optimise;
mod packing_properties;
mod parameter_study;
mod periodic;
mod pipeline;
mod readme;
mod reliability;
mod replay;
mod round3;
mod scales;
mod serve;
mod serve_cluster;
mod serve_edges;
mod serve_files;
mod shape_properties;
mod stability;
mod sweep_resume;
mod thesis;
mod verify_r3;
mod wells_shapes;
