//! The thin layer between the plugin and the core's host API (issue 14:
//! [`trample::builder`], bodies with stable [`BodyId`]s, host poses, the
//! host's camera, change lists): every call the plugin makes into
//! [`Simulation`] goes through here, so that a change of the core's API
//! changes this file and nothing else. It also converts between Bevy's
//! math types (glam 0.32) and the core's (glam 0.34): the same floats.

use bevy::math::{Mat4, Quat, Vec3};
use std::ops::Range;
use trample::Simulation;
use trample::builder::BodyBuilder;
use trample::field::ChangeSet;
use trample::object::{Scale, ShapeParams, TrackParams, TriMesh};
use trample::step::{Body, HostView};

pub use trample::step::BodyId;

/// Adds `body` to `sim` at the current time and returns its stable id. The
/// body appears where it is posed, without sweeping the grass on the way.
pub fn add_body(sim: &mut Simulation, body: Body) -> BodyId {
    sim.add_body(body)
}

/// Removes the body `id` (`false` when there is no such body). The blades
/// it bent stay where they are and recover as `[sim]`'s `recovery_s` and
/// `trail` say; the other bodies keep their ids.
pub fn remove_body(sim: &mut Simulation, id: BodyId) -> bool {
    sim.remove_body(id).is_ok()
}

/// Where body `id` is now (metres), if the simulation has it.
#[must_use]
pub fn body_position(sim: &Simulation, id: BodyId) -> Option<Vec3> {
    sim.body(id).map(|b| bevy_vec3(b.pose.position))
}

/// Moves body `id` over the next step of `dt` seconds from where it is to
/// `position` with `rotation` (world from local), sweeping the grass on the
/// way (the contact speed of Eq. 2 is the displacement over `dt`).
///
/// # Errors
/// The core's message (and the body stays) for an unknown id, a value that
/// is not finite, `dt ≤ 0` or a zero rotation.
pub fn move_body(
    sim: &mut Simulation,
    id: BodyId,
    position: Vec3,
    rotation: Quat,
    dt: f32,
) -> Result<(), String> {
    sim.move_body(id, core_vec3(position), core_quat(rotation), dt)
        .map_err(|e| e.to_string())
}

/// Moves body `id` to `position` with `rotation` at once, without sweeping
/// the grass between where it was and there (a respawn).
///
/// # Errors
/// The core's message (and the body stays) for an unknown id, a value that
/// is not finite or a zero rotation.
pub fn teleport_body(
    sim: &mut Simulation,
    id: BodyId,
    position: Vec3,
    rotation: Quat,
) -> Result<(), String> {
    sim.teleport_body(id, core_vec3(position), core_quat(rotation))
        .map_err(|e| e.to_string())
}

/// Gives body `id`'s mesh the vertices `positions` (the body's frame, one
/// per vertex of the mesh it was made from, in its order) over the next
/// step of `dt` seconds: a skinned mesh as its joints pose it. The body's
/// tree is refitted at every sub-step.
///
/// # Errors
/// The core's message (and the body keeps its shape) for an unknown id, a
/// wrong count, a value that is not finite or `dt ≤ 0`.
pub fn set_body_vertices(
    sim: &mut Simulation,
    id: BodyId,
    positions: &[Vec3],
    dt: f32,
) -> Result<(), String> {
    let core: Vec<glam::Vec3> = positions.iter().map(|&p| core_vec3(p)).collect();
    sim.set_body_vertices(id, &core, dt)
        .map_err(|e| e.to_string())
}

/// Hands the host's camera to `sim` for the level of detail and culling:
/// the eye at `eye` (metres) and the world → clip matrix `view_proj` with
/// clip z in [0, 1]. Returns `false` (and the scene's camera stays in
/// charge) for values that are not finite or a matrix without inverse.
pub fn set_view(sim: &mut Simulation, eye: Vec3, view_proj: Mat4) -> bool {
    let m = glam::Mat4::from_cols_array(&view_proj.to_cols_array());
    HostView::new(core_vec3(eye), m)
        .and_then(|v| sim.set_view(v))
        .is_ok()
}

/// Hands the level of detail back to the scene's camera path.
pub fn clear_view(sim: &mut Simulation) {
    if sim.host_view().is_some() {
        sim.clear_view();
    }
}

/// Bevy's `Vec3` (glam 0.32) as the core's (glam 0.34): the same three floats.
#[must_use]
pub fn core_vec3(v: Vec3) -> glam::Vec3 {
    glam::Vec3::from_array(v.to_array())
}

/// The core's `Vec3` as Bevy's.
#[must_use]
pub fn bevy_vec3(v: glam::Vec3) -> Vec3 {
    Vec3::from_array(v.to_array())
}

/// Bevy's `Quat` as the core's.
#[must_use]
pub fn core_quat(q: Quat) -> glam::Quat {
    glam::Quat::from_array(q.to_array())
}

/// A body from a triangle mesh in its local frame (metres, scale already
/// baked in), at rest at the origin until the host poses it; its OBB tree
/// built `max_depth` deep (paper §4.2, root = 1).
///
/// # Errors
/// What the core's checks refuse (an empty mesh, bad indices, non-finite
/// vertices, a mesh too large or too small, bad track values), naming `name`.
pub fn body_from_mesh(
    name: &str,
    mesh: &TriMesh,
    track: TrackParams,
    max_depth: u32,
) -> Result<Body, crate::TrampleError> {
    build(BodyBuilder::mesh(name, mesh).track(track), name, max_depth)
}

/// A body from a built-in shape of the scene format (sphere, box, capsule,
/// cylinder, knot; `scale` per axis), at rest at the origin until the host
/// poses it.
///
/// # Errors
/// The shape's parameters out of range, as a scene file would report them.
pub fn body_from_shape(
    name: &str,
    shape: &ShapeParams,
    scale: Vec3,
    track: TrackParams,
    max_depth: u32,
) -> Result<Body, crate::TrampleError> {
    let builder = BodyBuilder::new(name, shape.clone())
        .scale(Scale::PerAxis(scale.to_array()))
        .track(track);
    build(builder, name, max_depth)
}

fn build(builder: BodyBuilder, name: &str, max_depth: u32) -> Result<Body, crate::TrampleError> {
    let body = builder
        .build()
        .map_err(|e| crate::TrampleError::Object(name.to_owned(), e.to_string()))?;
    Ok(Body::new(body.object, max_depth.max(1)))
}

/// Blades whose vertices changed since the renderer last took them: the
/// union of the core's per-step change lists
/// ([`Simulation::changed_blades`]) over the steps in between (a frame may
/// run zero or several fixed steps).
#[derive(Debug)]
pub struct BladeChanges {
    /// Blades written by the steps since the last [`BladeChanges::take`].
    changed: ChangeSet,
    /// Set until the first take (and after [`BladeChanges::reset`]): the
    /// renderer has none of the vertices yet.
    stale: bool,
}

impl Default for BladeChanges {
    fn default() -> Self {
        Self {
            changed: ChangeSet::default(),
            stale: true,
        }
    }
}

/// Blades farther apart than this start a new run: nearer ones are sent
/// together with the unchanged blades between (fewer, larger copies).
pub const RUN_GAP_BLADES: u32 = 32;

impl BladeChanges {
    /// Adds what the step just taken changed. Call after every step.
    pub fn after_step(&mut self, sim: &Simulation) {
        for b in sim.changed_blades() {
            self.changed.mark(b as usize);
        }
    }

    /// Forgets what was gathered: the next [`BladeChanges::take`] lists
    /// every blade (a new renderer, a new field).
    pub fn reset(&mut self) {
        self.changed.clear();
        self.stale = true;
    }

    /// Appends to `runs` the blades changed since the last call as ascending
    /// runs `first..end` (runs closer than [`RUN_GAP_BLADES`] merged) and
    /// returns true when that is every blade (the first call, or after
    /// [`BladeChanges::reset`]).
    pub fn take(&mut self, sim: &Simulation, runs: &mut Vec<Range<u32>>) -> bool {
        if self.stale {
            self.stale = false;
            self.changed.clear();
            runs.push(0..sim.field.blades.count as u32);
            return true;
        }
        self.changed.sort();
        for r in self.changed.ranges() {
            match runs.last_mut() {
                Some(last) if r.start <= last.end + RUN_GAP_BLADES => last.end = r.end,
                _ => runs.push(r),
            }
        }
        self.changed.clear();
        false
    }
}

/// The cells the simulation's steps changed since the ground last took
/// them (their level, billboard slope and flatness: `Cells::flatness`, the
/// track the ground shows), gathered step by step as [`BladeChanges`]
/// gathers blades: several fixed steps may run between two frames.
#[derive(Debug)]
pub struct CellChanges {
    /// Cells written by the steps since the last [`CellChanges::take`].
    changed: ChangeSet,
    /// Set until the first take: the ground has none of the cells yet.
    stale: bool,
}

impl Default for CellChanges {
    fn default() -> Self {
        Self {
            changed: ChangeSet::default(),
            stale: true,
        }
    }
}

impl CellChanges {
    /// Adds what the step just taken changed. Call after every step.
    pub fn after_step(&mut self, sim: &Simulation) {
        for c in sim.changed_cells() {
            self.changed.mark(c as usize);
        }
    }

    /// Marks cell `c` changed (the GPU path's flatness read back).
    pub fn mark(&mut self, c: usize) {
        self.changed.mark(c);
    }

    /// Appends to `cells` the cells changed since the last call, ascending,
    /// each once, and returns true when that is every cell (the first
    /// call: then `cells` is left as it was).
    pub fn take(&mut self, cells: &mut Vec<u32>) -> bool {
        if self.stale {
            self.stale = false;
            self.changed.clear();
            return true;
        }
        self.changed.sort();
        cells.extend(self.changed.iter());
        self.changed.clear();
        false
    }
}
