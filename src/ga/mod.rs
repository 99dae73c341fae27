//! Genetic algorithm: genevo's selection behind our own loop, which evaluates
//! each new genome once, in parallel (rayon), with results independent of the
//! number of threads. The packer is its fitness kernel through
//! [`PorosityProblem`]; the packer knows nothing of the GA.

mod checkpoint;
mod engine;
mod layering;
mod operators;
mod optimise;
mod porosity;
mod score;
mod settings;
mod shapes;
pub mod window;

pub use crate::layering::StopRules;
pub use checkpoint::{Checkpoint, ResumeError};
pub use engine::{
    Evaluation, Evolution, Generation, Limits, Problem, Search, StopReason, Variation,
};
pub use layering::{Layered, LayeringProblem, lay_out};
pub use optimise::{
    OptimiseError, OptimiseObserver, Optimised, Start, TargetWarning, TargetWarningKind, optimise,
};
pub use porosity::{CONCLUSIVE_POPULATION, PorosityProblem, RULE_GENES, Verdict};
pub use score::Score;
pub use settings::OptimiseSettings;
pub use shapes::{AskedShape, DEFAULT_MAX_SHAPE_KS, SHAPE_GENES, ShapeBounds, ShapeMeasures};
