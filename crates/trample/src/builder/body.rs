//! [`BodyBuilder`]: a body (object) from values — a built-in shape or
//! triangles, where it is and how it moves — with the scene file's checks.

use super::error::BuildError;
use crate::obb::build::DEFAULT_MAX_DEPTH;
use crate::object::{
    AnimationParams, Object, ObjectParams, Orientation, PartParams, PathParams, Scale, ShapeParams,
    TrackParams, TriMesh,
};
use crate::step::Body;
use glam::Vec3;
use std::path::Path;

/// A body to build: exactly what one `[[objects]]` entry of a scene file
/// says ([`ObjectParams`], every key available), built by the same code
/// and checks. The setters return the builder, so a body reads as one
/// expression:
///
/// ```
/// use trample::builder::BodyBuilder;
/// let crate_box = BodyBuilder::cuboid("crate", [0.4, 0.4, 0.4])
///     .at([1.0, 0.4, -2.0])
///     .build()?;
/// assert_eq!(crate_box.object.name, "crate");
/// # Ok::<(), trample::builder::BuildError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct BodyBuilder {
    /// The values, as a scene file's `[[objects]]` entry holds them.
    pub params: ObjectParams,
}

impl BodyBuilder {
    /// A body named `name` of `shape`, standing still at the origin with a
    /// fixed orientation (move it with [`BodyBuilder::at`] or
    /// [`BodyBuilder::path`], or from the host each frame with
    /// [`crate::Simulation::move_body`]).
    #[must_use]
    pub fn new(name: impl Into<String>, shape: ShapeParams) -> Self {
        Self {
            params: ObjectParams {
                name: name.into(),
                shape,
                scale: Scale::default(),
                rotation_deg: [0.0; 3],
                orientation: Orientation::default(),
                path: PathParams::Static { position: [0.0; 3] },
                start_s: 0.0,
                track: TrackParams::default(),
                parts: Vec::new(),
                animation: None,
            },
        }
    }

    /// A body from a scene file's entry.
    #[must_use]
    pub fn from_params(params: ObjectParams) -> Self {
        Self { params }
    }

    /// An icosphere of `radius_m` metres (3 subdivisions, 1,280 triangles).
    #[must_use]
    pub fn sphere(name: impl Into<String>, radius_m: f32) -> Self {
        Self::new(
            name,
            ShapeParams::Sphere {
                radius_m,
                subdivisions: 3,
            },
        )
    }

    /// A box of half extents (x, y, z) metres, centred on its origin.
    #[must_use]
    pub fn cuboid(name: impl Into<String>, half_extents_m: [f32; 3]) -> Self {
        Self::new(name, ShapeParams::Box { half_extents_m })
    }

    /// A body of the host's own triangles (metres, local frame, origin
    /// kept; sanitised like any mesh).
    #[must_use]
    pub fn mesh(name: impl Into<String>, mesh: &TriMesh) -> Self {
        Self::new(
            name,
            ShapeParams::Triangles {
                positions: mesh.positions.iter().map(|p| p.to_array()).collect(),
                indices: mesh.indices.clone(),
            },
        )
    }

    /// Stands still at `position` (metres).
    #[must_use]
    pub fn at(mut self, position: impl Into<Vec3>) -> Self {
        self.params.path = PathParams::Static {
            position: position.into().to_array(),
        };
        self
    }

    /// Follows `path` (any path a scene file can name).
    #[must_use]
    pub fn path(mut self, path: PathParams) -> Self {
        self.params.path = path;
        self
    }

    /// Turns as `orientation` says along its path.
    #[must_use]
    pub fn orientation(mut self, orientation: Orientation) -> Self {
        self.params.orientation = orientation;
        self
    }

    /// Scales the mesh (before `rotation_deg`).
    #[must_use]
    pub fn scale(mut self, scale: Scale) -> Self {
        self.params.scale = scale;
        self
    }

    /// Rotation baked into the mesh, Euler degrees (y, x, z order).
    #[must_use]
    pub fn rotation_deg(mut self, rotation_deg: [f32; 3]) -> Self {
        self.params.rotation_deg = rotation_deg;
        self
    }

    /// Simulation time at which it starts along its path, seconds (for a
    /// body added to a running simulation: its current time, to start now).
    #[must_use]
    pub fn start_s(mut self, start_s: f32) -> Self {
        self.params.start_s = start_s;
        self
    }

    /// The track it leaves: its own recovery time, trail and press
    /// (`[objects.track]`), instead of `[sim]`'s.
    #[must_use]
    pub fn track(mut self, track: TrackParams) -> Self {
        self.params.track = track;
        self
    }

    /// Adds parts: the body becomes articulated (a tree of rigid parts
    /// hanging from its own mesh: wheels, limbs; `[[objects.parts]]`, see
    /// [`PartParams`]). Each part gets its own OBB tree and collides with
    /// its own motion.
    #[must_use]
    pub fn parts(mut self, parts: impl IntoIterator<Item = PartParams>) -> Self {
        self.params.parts.extend(parts);
        self
    }

    /// Plays the animation `name` of the body's skinned glTF (its shape
    /// must be a `.gltf` / `.glb` mesh file) at `speed` (1 = the file's
    /// rate), looping (`animation = { name, speed }`).
    #[must_use]
    pub fn animation(mut self, name: impl Into<String>, speed: f32) -> Self {
        self.params.animation = Some(AnimationParams {
            name: name.into(),
            speed,
            ground_speed_mps: None,
        });
        self
    }

    /// The ground speed (m/s) the animation's cycle is made for: its clock
    /// then runs with the body's horizontal speed, so that it stands still
    /// when the body does and strides at the speed a host drives it
    /// (`animation = { ..., ground_speed_mps }`; see
    /// [`AnimationParams::ground_speed_mps`]). Call after
    /// [`BodyBuilder::animation`]; without an animation it does nothing.
    #[must_use]
    pub fn animation_ground_speed(mut self, ground_speed_mps: f32) -> Self {
        if let Some(a) = &mut self.params.animation {
            a.ground_speed_mps = Some(ground_speed_mps);
        }
        self
    }

    /// Builds the body (mesh, checks, OBB tree); a mesh file is looked for
    /// in the current folder. Messages name it `objects[0] (NAME)`.
    ///
    /// # Errors
    /// [`BuildError::Object`] for a value out of range or a mesh refused.
    pub fn build(&self) -> Result<Body, BuildError> {
        self.build_in(0, Path::new("."))
    }

    /// Builds the body as entry `index` of a scene whose files are in
    /// `base_dir` (mesh files must stay inside it).
    ///
    /// # Errors
    /// [`BuildError::Object`] naming `objects[INDEX] (NAME)`.
    pub fn build_in(&self, index: usize, base_dir: &Path) -> Result<Body, BuildError> {
        let object = Object::from_params(&self.params, index, base_dir)?;
        Ok(Body::new(object, DEFAULT_MAX_DEPTH))
    }
}
