//! What counts as far (ours, issue 16): the one rule by which bodies take
//! turns ([`super::passes`]) and patches' blades recover in turns
//! ([`super::recovery_turns`]) when `sim.far_every` is above 1. Far is
//! wholly farther than `sim.far_beyond_m` from the camera, horizontally
//! ([`is_far`], [`patch_is_far`]); with `sim.far_outside_view`, also wholly
//! out of the camera's view with the grass it can bend (a body:
//! [`is_out_of_view`]; a patch: its box, which holds its blades however
//! they bend, outside the view frustum — the patches culling leaves out).
//! The rule's parts live here; `passes` and `recovery_turns` re-export
//! the ones they were born in.

use super::body::Body;
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

/// Whether `body` lies wholly farther than `beyond` metres from `eye`,
/// horizontally: for each of its colliders (its own mesh and its parts),
/// the root box's centre, less the box's half diagonal (its bounding
/// sphere), is farther than that.
#[must_use]
pub fn is_far(body: &Body, eye: Vec3, beyond: f32) -> bool {
    body.colliders().all(|c| {
        let root = c.world_root;
        let d = (root.center.x - eye.x).hypot(root.center.z - eye.z) - root.half_diagonal();
        d > beyond
    })
}

/// Whether `body` lies wholly out of the view `frustum`
/// ([`crate::step::SimParams::far_outside_view`]): for each of its
/// colliders, the root box's bounding sphere grown by `reach` metres (the
/// grass it can bend reaches that far past its box: the longest blade and
/// the contact shell) lies wholly outside one of the frustum's planes.
#[must_use]
pub fn is_out_of_view(body: &Body, frustum: &Frustum, reach: f32) -> bool {
    body.colliders().all(|c| {
        let root = c.world_root;
        frustum.ball_outside(root.center, root.half_diagonal() + reach)
    })
}

/// Whether a patch's box lies wholly farther than `beyond` metres from
/// `eye`, horizontally (the distance from `eye` to the nearest point of its
/// x–z rectangle) — the rule far bodies follow ([`is_far`]).
#[must_use]
pub fn patch_is_far(aabb_min: Vec3, aabb_max: Vec3, eye: Vec3, beyond: f32) -> bool {
    let dx = (aabb_min.x - eye.x).max(eye.x - aabb_max.x).max(0.0);
    let dz = (aabb_min.z - eye.z).max(eye.z - aabb_max.z).max(0.0);
    dx.hypot(dz) > beyond
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_patch_is_far_by_the_nearest_point_of_its_square() {
        let (lo, hi) = (Vec3::new(10.0, 0.0, -1.0), Vec3::new(12.0, 1.0, 1.0));
        assert!(!patch_is_far(lo, hi, Vec3::ZERO, 10.0));
        assert!(patch_is_far(lo, hi, Vec3::ZERO, 9.99));
        assert!(!patch_is_far(lo, hi, Vec3::new(11.0, 50.0, 0.0), 0.0));
        assert!(patch_is_far(lo, hi, Vec3::new(15.0, 0.0, 5.0), 4.99));
    }
}
