//! Articulated and animated bodies at each sub-step (ours, DESIGN §3
//! "Articulated bodies", "Deforming meshes"; issue 13).
//!
//! `pose_rig` runs when a body is posed ([`super::Body::set_time`]):
//! - an animated body ([`crate::object::AnimatedMesh`]) has its skin posed
//!   at t and its OBB tree refitted to the new vertices
//!   ([`crate::obb::ObbTree::refit`], same triangles, boxes and Eq. 3's
//!   EqN recomputed bottom-up, reach boxes too), every sub-step;
//! - an articulated body's parts are posed from the body's pose
//!   ([`Articulation::poses_into`]): each part is a collider with its own
//!   tree, pose and velocities, so Eq. 2's contact speed is the part's own
//!   surface speed (a rolling wheel's contact point is at rest). Wheels'
//!   spin angles come from a [`WheelOdometer`] advanced from the last
//!   posed time in slices of at most [`ODOMETER_SLICE_S`].
//!
//! The collision stages then iterate over colliders
//! ([`super::Body::colliders`]): the body's own mesh, then its parts; the
//! object's settings (precision, track) hold for all of them.

use super::bodies::BodyError;
use super::body::{Body, BodyId};
use super::host_mesh::HostVertices;
use super::simulation::Simulation;
use crate::collision::broad_phase::world_obb;
use crate::obb::refit::{AxisRule, Nesting, RefitMap, RefitScratch};
use crate::obb::{Obb, ObbTree};
use crate::object::animated::AnimatedScratch;
use crate::object::parts::Joint;
use crate::object::parts::{PartPose, PartsInput, WheelOdometer};
use crate::object::{Articulation, Object, Pose, unit_rotation};
use glam::Vec3;

/// Longest time slice, seconds, over which the wheel odometer integrates
/// rolling speeds in one trapezoid (a body posed after a longer jump, e.g.
/// `trample collide --time T`, is integrated in slices up to T, so a
/// wheel's spin angle at T hardly depends on how the time was stepped).
pub const ODOMETER_SLICE_S: f32 = 1.0 / 120.0;

/// One part of an articulated body as a collider: its OBB tree (built once
/// from the part's mesh, in the part's frame) and its world pose.
#[derive(Clone, Debug)]
pub struct PartCollider {
    /// The part's OBB tree (shared with every part and body of the same
    /// mesh, like [`super::Body::tree`]).
    pub tree: std::sync::Arc<ObbTree>,
    /// World pose and velocities at the latest sub-step.
    pub pose: Pose,
    /// The tree's root box in world space at that pose.
    pub world_root: Obb,
}

impl PartCollider {
    /// A part whose tree is already built, posed at `pose`.
    #[must_use]
    pub fn with_tree(tree: std::sync::Arc<ObbTree>, pose: Pose) -> Self {
        let world_root = world_obb(&tree.nodes[0].obb, &pose);
        Self {
            tree,
            pose,
            world_root,
        }
    }
}

/// What a body keeps between sub-steps to pose its rig.
#[derive(Clone, Debug, Default)]
pub(crate) struct RigState {
    /// Distance rolled per wheel part.
    odometer: WheelOdometer,
    /// Time the odometer was last advanced to; `None` before the first pose.
    odometer_t: Option<f32>,
    /// The parts' poses at the latest pose.
    part_poses: Vec<PartPose>,
    /// An animated body's refit map (tree triangle → mesh vertices); a
    /// host-animated one's from the host's first vertices.
    pub(crate) refit_map: Option<RefitMap>,
    /// Scratch memory of the skin and the refit.
    skin_scratch: AnimatedScratch,
    refit_scratch: RefitScratch,
    /// The posed vertices.
    positions: Vec<Vec3>,
    /// Time the mesh was last posed at.
    skinned_t: Option<f32>,
    /// An animation whose clock runs with the ground speed
    /// ([`crate::object::AnimationParams::ground_speed_mps`]): its own
    /// time, seconds, and the simulation time it was advanced to.
    clock: f32,
    clock_t: Option<f32>,
    /// The nodes' box centres before the latest refit (scratch).
    centres: Vec<Vec3>,
    /// The host's vertices of the mesh, once it has given some
    /// ([`Simulation::set_body_vertices`]).
    pub(crate) host: Option<HostVertices>,
}

impl RigState {
    /// The state of a body of `object` whose tree is `tree`.
    pub(crate) fn new(object: &Object, tree: &ObbTree) -> Self {
        Self {
            refit_map: object
                .animated
                .as_ref()
                .and_then(|_| RefitMap::new(tree, &object.mesh).ok()),
            ..Self::default()
        }
    }
}

/// Poses `body`'s skin and parts at time `t` (its own pose is already set
/// to its pose at `t`). See the module documentation.
pub(crate) fn pose_rig(body: &mut Body, t: f32) {
    advance_clock(body, t);
    skin_and_refit(body, t);
    if body.parts.is_empty() {
        return;
    }
    advance_odometer(body, t);
    pose_parts(body, t);
}

/// Poses `body`'s parts at `t` from the body's pose and the wheels' spin
/// as it stands (the odometer not advanced): a far body between its turns
/// ([`Body::pose_for_pass`]).
pub(crate) fn pose_parts(body: &mut Body, t: f32) {
    if body.parts.is_empty() {
        return;
    }
    let rig = &mut body.rig;
    let input = PartsInput {
        t,
        body: body.pose,
        rolled_m: &rig.odometer.rolled_m,
        host: &body.host_poses,
    };
    body.object.parts.poses_into(&input, &mut rig.part_poses);
    for (part, pose) in body.parts.iter_mut().zip(&rig.part_poses) {
        part.pose = pose.world;
        part.world_root = world_obb(&part.tree.nodes[0].obb, &part.pose);
    }
}

/// [`skin_and_refit`] at `t` even when the mesh was posed there already (a
/// body that starts to deform: [`Simulation::set_body_vertices`]).
pub(crate) fn refit_now(body: &mut Body, t: f32) {
    body.rig.skinned_t = None;
    skin_and_refit(body, t);
    body.world_root = world_obb(&body.tree.nodes[0].obb, &body.pose);
}

/// An animated body (a glTF skin, or the host's vertices,
/// [`Simulation::set_body_vertices`]): its mesh posed at `t` and its tree
/// refitted (once per distinct `t`). A refit refused (a non-finite posed
/// vertex) leaves the mesh and tree as they were.
fn skin_and_refit(body: &mut Body, t: f32) {
    let RigState {
        refit_map: Some(map),
        skin_scratch,
        refit_scratch,
        positions,
        skinned_t,
        clock,
        centres,
        host,
        ..
    } = &mut body.rig
    else {
        return;
    };
    if *skinned_t == Some(t) {
        return;
    }
    match (&body.object.animated, host) {
        (Some(animated), _) => {
            let clock = match animated.ground_speed_mps {
                Some(_) => *clock,
                None => animated.animation_time(t),
            };
            animated.pose_at_clock(clock, skin_scratch, positions);
        }
        (None, Some(host)) => host.at(t, positions),
        (None, None) => return,
    }
    centres.clear();
    centres.extend(body.tree.nodes.iter().map(|n| n.obb.center));
    let tree = std::sync::Arc::make_mut(&mut body.tree);
    // The simulation's contact walk decides with the boxes alone: refitting
    // the tilted boxes (`obb::slabs`) at every pose would double the refit
    // (measured on the walker: BENCHMARKS.md, "Session 18"), so a posed
    // tree has none; the queries that use them fit them again
    // (`Simulation::bodies_at`).
    tree.slabs.clear();
    let refitted = tree.refit(
        map,
        positions,
        AxisRule::Fixed,
        Nesting::Tight,
        refit_scratch,
    );
    if refitted.is_ok() {
        body.object.mesh.positions.clone_from(positions);
        // Each node's own velocity: how far its box's centre moved since
        // the last pose, over the time between (zero at the first pose or
        // after time went back).
        let tree = std::sync::Arc::make_mut(&mut body.tree);
        let span = skinned_t.map_or(0.0, |t0| t - t0);
        tree.velocity.clear();
        tree.velocity
            .extend(tree.nodes.iter().zip(centres.iter()).map(|(n, c)| {
                if span > 0.0 {
                    (n.obb.center - *c) / span
                } else {
                    Vec3::ZERO
                }
            }));
        *skinned_t = Some(t);
    }
}

/// An animation whose clock runs with the body's ground speed: the clock
/// advanced from the last posed time to `t`, by trapezoids of
/// [`crate::object::AnimatedMesh::clock_rate`] over slices of at most
/// [`ODOMETER_SLICE_S`] of the body's poses (from its path or drive), as
/// the wheels' odometer; restarted at 0 when `t` is earlier than the last
/// time (the first pose, at 0, starts it).
fn advance_clock(body: &mut Body, t: f32) {
    let Some(animated) = body
        .object
        .animated
        .as_ref()
        .filter(|a| a.ground_speed_mps.is_some())
    else {
        return;
    };
    let start = match body.rig.clock_t {
        Some(t0) if t >= t0 => t0,
        _ => {
            body.rig.clock = 0.0;
            body.rig.clock_t = Some(t);
            return;
        }
    };
    let span = t - start;
    if span <= 0.0 {
        return;
    }
    let slices = (span / ODOMETER_SLICE_S).ceil().clamp(1.0, 1.0e6) as u32;
    let dt = span / slices as f32;
    let mut rate = animated.clock_rate(body.pose_at(start).velocity);
    for k in 1..=slices {
        let velocity = if k == slices {
            body.pose.velocity
        } else {
            body.pose_at(start + dt * k as f32).velocity
        };
        let next = animated.clock_rate(velocity);
        body.rig.clock += 0.5 * (rate + next) * dt;
        rate = next;
    }
    body.rig.clock_t = Some(t);
}

/// Advances the wheels' odometer from the last posed time to `t` in slices
/// of at most [`ODOMETER_SLICE_S`] (the body's poses between from its path
/// or drive); restarts it at 0 when `t` is earlier than the last time.
fn advance_odometer(body: &mut Body, t: f32) {
    let parts = &body.object.parts;
    let start = match body.rig.odometer_t {
        Some(t0) if t >= t0 => t0,
        _ => {
            body.rig.part_poses = part_poses(parts, t, body.pose, &[], &body.host_poses);
            body.rig.odometer = WheelOdometer::new(&body.rig.part_poses);
            body.rig.odometer_t = Some(t);
            return;
        }
    };
    let span = t - start;
    let slices = (span / ODOMETER_SLICE_S).ceil().clamp(1.0, 1.0e6) as u32;
    let dt = span / slices as f32;
    for k in 1..=slices {
        let tk = if k == slices {
            t
        } else {
            start + dt * k as f32
        };
        let pose = if k == slices {
            body.pose
        } else {
            body.pose_at(tk)
        };
        let now = part_poses(parts, tk, pose, &[], &body.host_poses);
        body.rig.odometer.advance(dt, &now);
    }
    body.rig.odometer_t = Some(t);
}

/// The parts' poses at `t` for the body at `body` (spin angles from
/// `rolled_m`).
fn part_poses(
    parts: &Articulation,
    t: f32,
    body: Pose,
    rolled_m: &[f32],
    host: &[Option<Pose>],
) -> Vec<PartPose> {
    let mut out = Vec::with_capacity(parts.parts.len());
    parts.poses_into(
        &PartsInput {
            t,
            body,
            rolled_m,
            host,
        },
        &mut out,
    );
    out
}

impl Body {
    /// The world poses of the body's parts at time `t` (from
    /// [`Body::pose_at`], spin angles as now): what sub-step planning
    /// measures each part's travel with. Empty for a rigid body.
    #[must_use]
    pub fn part_poses_at(&self, t: f32) -> Vec<Pose> {
        if self.parts.is_empty() {
            return Vec::new();
        }
        part_poses(
            &self.object.parts,
            t,
            self.pose_at(t),
            &self.rig.odometer.rolled_m,
            &self.host_poses,
        )
        .into_iter()
        .map(|p| p.world)
        .collect()
    }
}

/// A part of a body, by name or by index in [`Articulation::parts`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartRef<'a> {
    /// The part's name, as in the scene file.
    Name(&'a str),
    /// Its index in [`Articulation::parts`] (parents before children: see
    /// [`Articulation::index_of`]).
    Index(usize),
}

impl Simulation {
    /// Sets the pose of a `host`-jointed part of body `id` (issue 13: the
    /// host poses a turret, an arm, a door): `pose` is the part's position
    /// and rotation in its joint frame (metres, relative to the joint's
    /// rest) and their rates in the parent's frame (m/s, rad/s: they set
    /// Eq. 2's contact speed of the part). It holds from the next
    /// [`Simulation::step`] until set again; `None` puts the part back at
    /// rest.
    ///
    /// # Errors
    /// [`BodyError::Unknown`] for no such body, [`BodyError::Part`] for no
    /// such part or a part whose joint is not `host`,
    /// [`BodyError::NotFinite`] for a pose with a NaN or infinite value or
    /// a zero rotation.
    pub fn set_part_pose(
        &mut self,
        id: BodyId,
        part: PartRef<'_>,
        pose: Option<Pose>,
    ) -> Result<(), BodyError> {
        let index = self.index_of(id)?;
        let body = &mut self.bodies[index];
        let parts = &body.object.parts;
        let host_parts = || {
            let names: Vec<String> = parts
                .parts
                .iter()
                .enumerate()
                .filter(|(_, p)| p.joint == Joint::Host)
                .map(|(i, p)| format!("{:?} ({i})", p.name))
                .collect();
            if names.is_empty() {
                "none (this body has no part with a host joint)".to_owned()
            } else {
                names.join(", ")
            }
        };
        let (k, shown) = match part {
            PartRef::Name(name) => (parts.index_of(name), format!("{name:?}")),
            PartRef::Index(i) => ((i < parts.parts.len()).then_some(i), i.to_string()),
        };
        let Some(k) = k else {
            return Err(BodyError::Part {
                id,
                part: shown,
                problem: "no such part",
                allowed: host_parts(),
            });
        };
        if parts.parts[k].joint != Joint::Host {
            return Err(BodyError::Part {
                id,
                part: shown,
                problem: "its joint is not a host joint",
                allowed: host_parts(),
            });
        }
        let pose = pose
            .map(|p| {
                let finite = p.position.is_finite()
                    && p.velocity.is_finite()
                    && p.angular_velocity.is_finite();
                unit_rotation(p.rotation)
                    .filter(|_| finite)
                    .map(|rotation| Pose { rotation, ..p })
                    .ok_or_else(|| BodyError::NotFinite {
                        id,
                        what: format!("part {shown} pose = {p:?}"),
                        extra: "; the rotation not zero",
                    })
            })
            .transpose()?;
        body.host_poses.resize(parts.parts.len(), None);
        body.host_poses[k] = pose;
        Ok(())
    }
}
