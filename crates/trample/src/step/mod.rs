//! One simulation step (DESIGN §7) and the parameters and timings around it.

mod at_rest;
pub mod blade_class;
pub mod bodies;
pub mod body;
pub mod changes;
mod collide;
mod contact_hints;
mod deform;
pub mod drive;
pub mod far_rule;
pub mod far_shape;
mod host_mesh;
pub mod params;
pub mod passes;
pub mod query;
mod recover;
pub mod recovery_turns;
pub mod rescan;
pub mod rig;
pub mod simulation;
pub mod stages;
pub mod timings;
pub mod view;

pub use blade_class::BladeClass;
pub use bodies::BodyError;
pub use body::{Body, BodyId, Collider};
pub use drive::Drive;
pub use params::{SimError, SimParams};
pub use passes::Pass;
pub use simulation::{Simulation, SubstepClamp};
pub use timings::StepTimings;
pub use view::{HostView, ViewError};
