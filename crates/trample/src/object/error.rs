//! Mesh errors (DESIGN §9). Filled in by the object helper.

/// Why a mesh was refused.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The mesh has no triangles.
    #[error("{source_name}: mesh is empty (no triangles)")]
    Empty {
        /// File or shape name.
        source_name: String,
    },
}
