//! One simulation step (DESIGN §7) and the parameters and timings around it.

mod collide;
mod deform;
pub mod drive;
pub mod params;
pub mod query;
mod recover;
pub mod rescan;
pub mod simulation;
pub mod stages;
pub mod timings;

pub use drive::Drive;
pub use params::{SimError, SimParams};
pub use simulation::{BladeClass, Simulation, SubstepClamp};
pub use timings::StepTimings;
