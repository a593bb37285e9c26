//! # trample — grass that bends under moving objects of any shape
//!
//! The CPU reference path of the method in *"Simulation of grass–object
//! interaction with three levels of detail"* (see `shared/reference/paper.txt`),
//! specified by `DESIGN.md`. One [`step::Simulation::step`] runs the stages of
//! DESIGN §7 in order:
//!
//! poses → LOD per cell and frustum culling per patch ([`field`]) → broad phase
//! → narrow phase ([`collision`], through the OBB tree of [`obb`]) → DBG forces
//! (Eq. 2, [`force`]) → propagation (Eq. 4) → deformation (Eq. 5–8,
//! [`deform`]) → transitions (Eq. 9–13) → recovery ([`recovery`]).
//!
//! [`accuracy`] measures the narrow phase against the exact reference.
//!
//! A host program embedding the simulation starts at [`builder`] (a field
//! and bodies from values), moves bodies and hands in its camera between
//! steps ([`Simulation::move_body`], [`Simulation::teleport_body`],
//! [`Simulation::set_view`]) and reads the blades without a copy
//! ([`field::Blades::pos_bytes`], [`Simulation::changed_blades`]); see the
//! README's "Embedding" section and `examples/minimal.rs`.
//!
//! Units: metres, seconds, radians; y is up, the ground is the x–z plane.
#![warn(missing_docs)]

pub mod accuracy;
pub mod blade_shape;
pub mod builder;
pub mod camera;
pub mod collision;
pub mod deform;
pub mod field;
pub mod force;
pub mod fuzz_targets;
pub mod npy;
pub mod obb;
pub mod object;
pub mod paths;
pub mod recovery;
pub mod recovery_wide;
pub mod scene;
pub mod step;
#[cfg(test)]
mod test_rng;
pub mod wind;

pub use builder::{BodyBuilder, BuildError, SimulationBuilder};

/// The README's Rust snippets, compiled and run by `cargo test --doc`.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
pub use step::{Body, BodyId, HostView, Simulation, StepTimings};
