//! An object of the scene: mesh + OBB tree + motion.
//!
//! PARAMS ARE THE SCENE-FILE CONTRACT (fixed). Behaviour: object helper.

use super::path::PathParams;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One `[[objects]]` entry of a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectParams {
    /// Name used in messages and by the camera's `look_at`.
    pub name: String,
    /// The mesh.
    pub shape: ShapeParams,
    /// Scale applied to the mesh (uniform or per axis). Default 1.
    #[serde(default)]
    pub scale: Scale,
    /// Rotation baked into the mesh before anything else, Euler degrees
    /// (y, x, z order as in [`super::path::Keyframe`]). Default none.
    #[serde(default)]
    pub rotation_deg: [f32; 3],
    /// How the object turns as it moves. Default `fixed`.
    #[serde(default)]
    pub orientation: Orientation,
    /// Where the object goes.
    pub path: PathParams,
    /// Time at which the object starts along its path, seconds. Default 0.
    #[serde(default)]
    pub start_s: f32,
}

/// A uniform scale or one per axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Scale {
    /// The same on all axes.
    Uniform(f32),
    /// Along x, y, z.
    PerAxis([f32; 3]),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

/// How an object is oriented along its path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    /// Keeps its initial orientation.
    #[default]
    Fixed,
    /// Turns about y to face its direction of motion (+z of the mesh forward).
    FaceMotion,
    /// Rolls without slipping on the ground: spins about `up × v` at
    /// `|v| / r`, r = height of the origin above the mesh's lowest point.
    Rolling,
    /// Takes the orientations of a `keyframes` path.
    Keyframes,
}

/// The mesh of an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeParams {
    /// An icosphere.
    Sphere {
        /// Radius, metres.
        radius_m: f32,
        /// Subdivisions of the icosahedron (0–7). Default 3 (1,280 triangles).
        #[serde(default = "default_subdivisions")]
        subdivisions: u32,
    },
    /// A box.
    Box {
        /// Half extents (x, y, z), metres.
        half_extents_m: [f32; 3],
    },
    /// A capsule along y.
    Capsule {
        /// Radius, metres.
        radius_m: f32,
        /// Length of the cylindrical part, metres.
        length_m: f32,
    },
    /// The built-in complex shape: a (3, 2) torus knot tube of several
    /// thousand triangles, `size_m` across.
    Knot {
        /// Outer diameter, metres.
        size_m: f32,
    },
    /// A mesh file: `.obj`, `.gltf` or `.glb`, relative to the scene file.
    Mesh {
        /// The file.
        path: PathBuf,
        /// Where the mesh's local origin goes. Default `center`.
        #[serde(default)]
        anchor: Anchor,
    },
}

fn default_subdivisions() -> u32 {
    3
}

/// Where a loaded mesh's origin is placed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Anchor {
    /// At the centre of its bounding box.
    #[default]
    Center,
    /// At the centre of the bottom face of its bounding box (cars, animals).
    Bottom,
    /// Where the file has it.
    File,
}

/// STUB
#[derive(Clone, Debug)]
pub struct Object {
    pub name: String,
    pub mesh: super::TriMesh,
    pub closed: bool,
}
impl Object {
    pub fn from_params(
        _p: &ObjectParams,
        _i: usize,
        _b: &std::path::Path,
    ) -> Result<Object, String> {
        todo!()
    }
    pub fn pose_at(&self, _t: f32) -> super::Pose {
        todo!()
    }
}
