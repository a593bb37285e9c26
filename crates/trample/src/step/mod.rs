//! One simulation step (DESIGN §7) and the parameters and timings around it.

pub mod params;
pub mod query;
pub mod simulation;
pub mod stages;
pub mod timings;

pub use params::{SimError, SimParams};
pub use simulation::{BladeClass, Simulation, SubstepClamp};
pub use timings::StepTimings;
