//! Simulation::step (lead).
/// Placeholder.
pub struct Simulation;
/// Placeholder.
pub struct StepTimings;
