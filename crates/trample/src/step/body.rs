//! A body: an [`Object`] inside a running [`super::Simulation`], with its
//! OBB tree (the paper's HBV, §4), its pose at the current sub-step and its
//! stable [`BodyId`].

use super::drive::Drive;
use crate::collision::broad_phase::world_obb;
use crate::obb::{Obb, ObbTree};
use crate::object::{Object, Pose};

/// A body's handle in a [`super::Simulation`]: given when the body is added
/// ([`super::Simulation::add_body`], or in order `0, 1, ...` to the bodies a
/// simulation is made with) and never reused, so it stays valid while other
/// bodies are added and removed (unlike an index into
/// [`super::Simulation::bodies`], which shifts when an earlier body goes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct BodyId(pub u32);

impl std::fmt::Display for BodyId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "body {}", self.0)
    }
}

/// An object in the simulation: its mesh and motion, its OBB tree, and its
/// pose at the current sub-step.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its handle; set by the simulation the body is in (see [`BodyId`]).
    pub id: BodyId,
    /// Mesh, motion and name.
    pub object: Object,
    /// The HBV of the mesh (built once, off-line stage of the paper).
    pub tree: ObbTree,
    /// Pose at the latest sub-step.
    pub pose: Pose,
    /// The tree's root box in world space at that pose.
    pub world_root: Obb,
    /// Set while the host moves the body ([`super::Simulation::drive`],
    /// [`super::Simulation::move_body`], [`super::Simulation::teleport_body`]):
    /// its poses come from this instead of its path. `None` for bodies that
    /// follow their paths.
    pub drive: Option<Drive>,
}

impl Body {
    /// Builds the tree of `object` (to `max_depth`) and poses it at time 0.
    /// Its [`Body::id`] is set when it joins a simulation.
    #[must_use]
    pub fn new(object: Object, max_depth: u32) -> Self {
        let tree = ObbTree::build(&object.mesh, max_depth);
        let pose = object.pose_at(0.0);
        let world_root = world_obb(&tree.nodes[0].obb, &pose);
        Self {
            id: BodyId::default(),
            object,
            tree,
            pose,
            world_root,
            drive: None,
        }
    }

    /// The pose at time `t`: from [`Body::drive`] while driven, else from
    /// the object's path ([`Object::pose_at`]).
    #[must_use]
    pub fn pose_at(&self, t: f32) -> Pose {
        match &self.drive {
            Some(d) => d.pose_at(t),
            None => self.object.pose_at(t),
        }
    }

    /// Moves the body to its pose at time `t` ([`Body::pose_at`]).
    pub fn set_time(&mut self, t: f32) {
        self.pose = self.pose_at(t);
        self.world_root = world_obb(&self.tree.nodes[0].obb, &self.pose);
    }
}
