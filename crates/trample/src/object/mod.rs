//! Dynamic objects (DESIGN §3): triangle meshes (built-in shapes, OBJ and
//! glTF/GLB files), sanitised on load (DESIGN §9), moved along paths.

pub mod body;
pub mod error;
pub mod gltf;
pub mod mesh;
pub mod obj;
pub mod path;
pub mod pose;
pub mod sanitize;
pub mod shapes;

pub use body::{Object, ObjectParams, ShapeParams};
pub use error::MeshError;
pub use mesh::TriMesh;
pub use path::{Path, PathParams};
pub use pose::Pose;
