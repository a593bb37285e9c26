//! Dynamic objects (DESIGN §3): triangle meshes (built-in shapes, OBJ and
//! glTF/GLB files), sanitised on load (DESIGN §9), moved along paths.
//!
//! - [`mesh`]: [`TriMesh`]; [`shapes`]: the built-in shapes;
//!   [`obj`], [`gltf`] and [`load_mesh_file`]: mesh files;
//!   [`mod@sanitize`]: what every mesh goes through; [`error`]: [`MeshError`].
//! - [`path`]: where an object is at time t ([`spline`] for `spline` paths);
//!   [`motion`]: its whole [`Pose`] at time t ([`rolling`] for rolling ones).
//! - [`mod@object`]: an [`Object`] (mesh + motion) made from its scene-file
//!   [`ObjectParams`]. In a running simulation each object is a
//!   [`crate::step::Body`] (object + OBB tree + current pose).
//! - [`skin`]: a skinned glTF mesh ([`SkinnedMesh`]) and linear blend
//!   skinning; [`animation`]: its keyframed [`Animation`]s;
//!   [`rig_error`]: [`RigError`].
//! - [`animated`]: an object playing its skinned glTF's animation
//!   ([`AnimatedMesh`], scene key `animation`).
//! - [`parts`]: articulated objects, a tree of rigid parts
//!   ([`Articulation`]) with wheels, keyframed and host-posed joints.

pub mod animated;
pub mod animation;
pub mod error;
pub mod gltf;
pub mod mesh;
pub mod motion;
pub mod obj;
// Named after its module so that `Object` is found where it is looked for.
#[allow(clippy::module_inception)]
pub mod object;
pub mod parts;
pub mod path;
mod piecewise;
pub mod pose;
pub mod rig_error;
pub mod rolling;
pub mod sanitize;
pub mod shapes;
pub mod skin;
pub mod spline;

pub use animated::{AnimatedMesh, AnimatedScratch, AnimationParams};
pub use animation::Animation;
pub use error::MeshError;
pub use mesh::TriMesh;
pub use motion::{Motion, MotionError};
pub use object::{
    Anchor, Object, ObjectError, ObjectErrorKind, ObjectParams, OpenInside, Orientation, Scale,
    ShapeParams, SourceVertices, TrackParams,
};
pub use parts::{Articulation, PartError, PartParams};
pub use path::{Path, PathError, PathParams};
pub use pose::{Pose, unit_rotation};
pub use rig_error::RigError;
pub use sanitize::{SanitizeReport, sanitize};
pub use skin::{NodeTransform, Skeleton, SkinnedMesh};

/// Loads a mesh file, choosing the loader by extension (case-insensitive):
/// `.obj` → [`obj::load_obj`], `.gltf` / `.glb` → [`gltf::load_gltf`]. The
/// mesh is not sanitised.
///
/// # Errors
/// [`MeshError::UnsupportedExtension`] for any other extension, else the
/// loader's errors.
pub fn load_mesh_file(path: &std::path::Path) -> Result<TriMesh, MeshError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    match extension.as_str() {
        "obj" => obj::load_obj(path),
        "gltf" | "glb" => gltf::load_gltf(path),
        _ => Err(MeshError::UnsupportedExtension {
            source_name: path.display().to_string(),
            extension,
        }),
    }
}

/// Largest mesh file read, bytes (1 GiB): a text OBJ of that size holds
/// some 20 million triangles, far more than an object crossing grass needs;
/// a larger file is refused before it is read (DESIGN §9 "absurd sizes").
pub const MAX_MESH_FILE_BYTES: u64 = 1 << 30;

/// The bytes of a mesh file: a regular file of at most
/// [`MAX_MESH_FILE_BYTES`] (see [`crate::paths::read_regular_file`]).
///
/// # Errors
/// [`MeshError::Io`] naming the file.
pub fn read_mesh_bytes(path: &std::path::Path) -> Result<Vec<u8>, MeshError> {
    crate::paths::read_regular_file(path, MAX_MESH_FILE_BYTES).map_err(|reason| MeshError::Io {
        source_name: path.display().to_string(),
        reason,
    })
}

/// Runs a third-party parser, turning a panic inside it into
/// [`MeshError::ParserPanic`] (meaningful with the default `panic = "unwind"`).
pub(crate) fn catch_parser_panic<T>(
    source: &str,
    parser: &'static str,
    parse: impl FnOnce() -> T,
) -> Result<T, MeshError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(parse)).map_err(|payload| {
        let reason = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        MeshError::ParserPanic {
            source_name: source.to_owned(),
            parser,
            reason,
        }
    })
}
