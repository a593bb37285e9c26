//! What counts as far (ours, issue 16): the one rule by which bodies take
//! turns ([`super::passes`]) and patches' blades recover in turns
//! ([`super::recovery_turns`]) when `sim.far_every` is above 1. Far is
//! wholly farther than `sim.far_beyond_m` from the camera, horizontally
//! ([`is_far`], [`patch_is_far`]); with `sim.far_outside_view`, also wholly
//! out of the camera's view with the grass it can bend (a body:
//! [`is_out_of_view`]; a patch: its box, which holds its blades however
//! they bend, outside the view frustum — the patches culling leaves out).

use super::body::Body;
use super::passes::{is_far, is_out_of_view};
use super::recovery_turns::patch_is_far;
use super::simulation::Simulation;
use crate::field::Frustum;
use glam::Vec3;

/// The far rule of one step, from the camera in charge at its start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarRule {
    /// The viewpoint ([`Simulation::eye`]).
    pub eye: Vec3,
    /// `sim.far_beyond_m`.
    pub beyond: f32,
    /// The view frustum ([`Simulation::frustum`]) when
    /// `sim.far_outside_view`, else `None`.
    pub view: Option<Frustum>,
    /// How far the grass a body bends reaches past its root box, metres:
    /// the longest blade and the contact shell.
    pub reach: f32,
}

impl FarRule {
    /// The rule of `sim` now.
    #[must_use]
    pub fn of(sim: &Simulation) -> Self {
        Self {
            eye: sim.eye(),
            beyond: sim.params.far_beyond_m,
            view: sim.params.far_outside_view.then(|| sim.frustum()),
            reach: sim.field.max_blade_length + sim.params.contact_shell_m,
        }
    }

    /// By distance alone: no view, no reach.
    #[must_use]
    pub fn by_distance(eye: Vec3, beyond: f32) -> Self {
        Self {
            eye,
            beyond,
            view: None,
            reach: 0.0,
        }
    }

    /// Whether `body` is far (it may take turns if it may step far,
    /// [`Body::may_step_far`]).
    #[must_use]
    pub fn body(&self, body: &Body) -> bool {
        is_far(body, self.eye, self.beyond)
            || self
                .view
                .is_some_and(|f| is_out_of_view(body, &f, self.reach))
    }

    /// Whether the patch with box `min..max` (its blades' reach included)
    /// is far.
    #[must_use]
    pub fn patch(&self, min: Vec3, max: Vec3) -> bool {
        patch_is_far(min, max, self.eye, self.beyond)
            || self.view.is_some_and(|f| !f.intersects_aabb(min, max))
    }
}
