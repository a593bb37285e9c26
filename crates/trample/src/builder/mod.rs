//! Building a simulation from values, for hosts (issue 14): no scene file
//! needed, and scene files build through the same code
//! ([`crate::scene::Scene::build`] makes a [`SimulationBuilder`] of the
//! file), so every check is written once and gives the same message either
//! way. Errors are values ([`BuildError`]).
//!
//! - [`SimulationBuilder`]: field, grass maps, terrain, LOD, method
//!   parameters, camera or host view, wind, bodies.
//! - [`BodyBuilder`]: one body (an `[[objects]]` entry): shape or
//!   triangles, scale, rotation, path, orientation. Bodies can also be added
//!   to and removed from a running simulation
//!   ([`crate::Simulation::add_body`], [`crate::Simulation::remove_body`]).

mod body;
mod error;
mod simulation;

pub use body::BodyBuilder;
pub use error::BuildError;
pub use simulation::SimulationBuilder;
