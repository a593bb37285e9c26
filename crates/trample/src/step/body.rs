//! A body: an [`Object`] inside a running [`super::Simulation`], with its
//! OBB tree (the paper's HBV, §4), its pose at the current sub-step and its
//! stable [`BodyId`]; an articulated body also has one tree and pose per
//! part, and the collision stages see every body as a list of
//! [`Collider`]s (its own mesh, then its parts).

use super::drive::Drive;
use super::rig::{PartCollider, RigState};
use crate::collision::broad_phase::world_obb;
use crate::obb::shared::Winding;
use crate::obb::{Obb, ObbTree};
use crate::object::{Object, Pose, TriMesh};

/// One rigid mesh of a body as the collision stages see it: the body's own
/// mesh (collider 0) or one of its parts (collider `1 + part`), each with
/// its own OBB tree and its own pose and velocities (Eq. 2's contact speed
/// is the collider's own surface speed).
#[derive(Clone, Copy, Debug)]
pub struct Collider<'a> {
    /// The OBB tree, in the collider's frame.
    pub tree: &'a ObbTree,
    /// The mesh the tree was built from (for an animated body, its latest
    /// posed vertices).
    pub mesh: &'a TriMesh,
    /// World pose and velocities at the latest sub-step.
    pub pose: &'a Pose,
    /// The tree's root box in world space at that pose.
    pub world_root: &'a Obb,
}

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
    /// The HBV of the mesh (built once, off-line stage of the paper); shared
    /// by every body of the scene with the same mesh (one copy in memory,
    /// [`crate::obb::shared::build_shared`]). A body whose mesh deforms
    /// refits its own copy ([`std::sync::Arc::make_mut`]).
    pub tree: std::sync::Arc<ObbTree>,
    /// Pose at the latest sub-step.
    pub pose: Pose,
    /// The tree's root box in world space at that pose.
    pub world_root: Obb,
    /// Set while the host moves the body ([`super::Simulation::drive`],
    /// [`super::Simulation::move_body`], [`super::Simulation::teleport_body`]):
    /// its poses come from this instead of its path. `None` for bodies that
    /// follow their paths.
    pub drive: Option<Drive>,
    /// The parts of an articulated body, in [`Object::parts`] order: tree,
    /// pose at the latest sub-step, root box. Empty for a rigid body.
    pub parts: Vec<PartCollider>,
    /// The host's pose of each part with a `host` joint, in its joint frame
    /// ([`crate::object::parts::PartsInput::host`]); set with
    /// [`super::Simulation::set_part_pose`]. `None`: the rest pose.
    pub host_poses: Vec<Option<Pose>>,
    /// Wheel odometry, the skin's scratch memory and refit map.
    pub(crate) rig: RigState,
    /// The time up to which the body has touched the grass, seconds: the
    /// end of the last step it took part in ([`crate::step::passes`]).
    pub(crate) stepped_to: f64,
    /// Its turn among the far bodies while it is far
    /// ([`crate::step::passes::far_schedule`]): it steps on the frames where
    /// `(frame + turn) % sim.far_every == 0`. `None` while it is near (or
    /// before its first step).
    pub(crate) far_turn: Option<super::passes::FarTurn>,
    /// What each collider kept while at rest ([`super::at_rest`]), by
    /// collider index; grown on first use.
    pub(crate) rest: Vec<super::at_rest::ColliderMemo>,
}

impl Body {
    /// Builds the tree of `object` (to `max_depth`) and poses it at time 0.
    /// Its [`Body::id`] is set when it joins a simulation.
    #[must_use]
    pub fn new(object: Object, max_depth: u32) -> Self {
        let tree = ObbTree::build(&object.mesh, max_depth).into();
        let part_trees = object
            .parts
            .parts
            .iter()
            .map(|p| ObbTree::build(&p.mesh, max_depth).into())
            .collect();
        Self::with_trees(object, tree, part_trees)
    }

    /// [`Body::new`] with the trees already built: `tree` of `object.mesh`
    /// and `part_trees` of its parts' meshes, in order (what
    /// [`crate::obb::shared::build_shared`] gives a scene of many bodies).
    /// Not public: one tree per part is the caller's promise (the scene
    /// builder keeps it by building the trees from the same lists); it
    /// panics when they differ in number.
    #[must_use]
    pub(crate) fn with_trees(
        object: Object,
        mut tree: std::sync::Arc<ObbTree>,
        mut part_trees: Vec<std::sync::Arc<ObbTree>>,
    ) -> Self {
        assert_eq!(
            part_trees.len(),
            object.parts.parts.len(),
            "one tree per part"
        );
        // An open mesh's hollow counts as inside by the winding rule: its
        // trees get the winding number's data (a shared tree is copied
        // first; a skinned mesh's without the grid its first refit would
        // drop).
        let trees = std::iter::once(&mut tree).chain(&mut part_trees);
        for (t, winding) in trees.zip(Winding::of(&object)) {
            if winding != Winding::Off && !t.closed && !t.winds() {
                winding.enable(std::sync::Arc::make_mut(t));
            }
        }
        let pose = object.pose_at(0.0);
        let world_root = world_obb(&tree.nodes[0].obb, &pose);
        let parts = part_trees
            .into_iter()
            .map(|tree| PartCollider::with_tree(tree, pose))
            .collect();
        let rig = RigState::new(&object, &tree);
        let mut body = Self {
            id: BodyId::default(),
            host_poses: vec![None; object.parts.parts.len()],
            object,
            tree,
            pose,
            world_root,
            drive: None,
            parts,
            rig,
            stepped_to: 0.0,
            far_turn: None,
            rest: Vec::new(),
        };
        body.set_time(0.0);
        body
    }

    /// The time up to which the body has touched the grass, seconds: the
    /// end of the last step it took part in (with `sim.far_every > 1`, a far
    /// body's last turn; [`crate::step::passes`]).
    #[must_use]
    pub fn stepped_to(&self) -> f64 {
        self.stepped_to
    }

    /// Whether the body's mesh deforms: a skinned glTF playing an animation,
    /// or a mesh whose vertices the host has set
    /// ([`super::Simulation::set_body_vertices`]). Its tree is refitted at
    /// every sub-step, so nothing keyed by the tree is kept between them.
    #[must_use]
    pub fn deforms(&self) -> bool {
        self.object.animated.is_some() || self.rig.host.is_some()
    }

    /// Whether the body may be stepped less often when far from the camera
    /// ([`crate::step::SimParams::far_every`]): a pass may pose it at any
    /// time since its last turn — on its scene path, or driven by the host
    /// (whose moves between two turns are joined into one,
    /// [`crate::step::Simulation::move_body`]). Every body may: an
    /// articulated body's wheel odometer and an animated body's skin and
    /// clock run forwards only, and between its turns the main pass leaves
    /// them where its last turn did ([`Body::pose_for_pass`]).
    #[must_use]
    pub fn may_step_far(&self) -> bool {
        true
    }

    /// Poses the body for a pass at time `t` (the CPU's and the GPU's
    /// loops both call this at each sub-step): a body the pass steps
    /// (`stepped`) is posed with its rig ([`Body::set_time`]); a body a
    /// main pass does not step (far, waiting for its turn) follows its path
    /// — its pose, its parts' poses from its wheels' spin as it stands, its
    /// root box — but its rig's integrators (the wheels' odometer, a
    /// ground-speed animation clock) and its skin stay at its last turn, so
    /// that its next far pass, which starts there, runs them forwards (posed
    /// at `t` first, they would restart at the turn's earlier times): far
    /// away, its wheels turn and its mesh moves once a turn. A far pass
    /// poses only the bodies it steps.
    pub fn pose_for_pass(&mut self, t: f32, main: bool, stepped: bool) {
        if stepped {
            self.set_time(t);
        } else if main {
            self.pose = self.pose_at(t);
            super::rig::pose_parts(self, t);
            self.world_root = world_obb(&self.tree.nodes[0].obb, &self.pose);
        }
    }

    /// How many colliders the body has: 1 (its own mesh) + its parts.
    #[must_use]
    pub fn collider_count(&self) -> usize {
        1 + self.parts.len()
    }

    /// Collider `k`: 0 is the body's own mesh, `1 + i` its part `i`.
    ///
    /// # Panics
    /// When `k >= self.collider_count()`.
    #[must_use]
    pub fn collider(&self, k: usize) -> Collider<'_> {
        if k == 0 {
            Collider {
                tree: &self.tree,
                mesh: &self.object.mesh,
                pose: &self.pose,
                world_root: &self.world_root,
            }
        } else {
            let part = &self.parts[k - 1];
            Collider {
                tree: &part.tree,
                mesh: &self.object.parts.parts[k - 1].mesh,
                pose: &part.pose,
                world_root: &part.world_root,
            }
        }
    }

    /// Every collider, in order ([`Body::collider`]).
    pub fn colliders(&self) -> impl Iterator<Item = Collider<'_>> {
        (0..self.collider_count()).map(|k| self.collider(k))
    }

    /// Every collider's triangles in world space at the latest sub-step,
    /// the body's own first, then its parts' (the `--dump-object` layout).
    #[must_use]
    pub fn world_triangles(&self) -> Vec<[glam::Vec3; 3]> {
        let mut out = Vec::new();
        for c in self.colliders() {
            let m = c.mesh;
            out.extend((0..m.triangle_count()).map(|i| m.triangle(i).map(|v| c.pose.to_world(v))));
        }
        out
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

    /// Moves the body to its pose at time `t` ([`Body::pose_at`]); an
    /// animated body's mesh is posed and its tree refitted, an articulated
    /// body's parts are posed from the body's pose (`step/rig.rs`).
    pub fn set_time(&mut self, t: f32) {
        self.pose = self.pose_at(t);
        super::rig::pose_rig(self, t);
        self.world_root = world_obb(&self.tree.nodes[0].obb, &self.pose);
    }
}
