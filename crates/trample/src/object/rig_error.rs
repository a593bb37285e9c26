//! Why a rigged glTF (skin, skeleton, animations) was refused (DESIGN §9).
//!
//! Like [`MeshError`], every message is one line that starts with the file,
//! names the offending item (mesh, primitive, vertex, skin, joint,
//! animation, channel) and says what is allowed.

use super::error::MeshError;

/// Why a skinned or animated glTF could not be loaded ([`super::skin`],
/// [`super::animation`]), or an animation could not be found.
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// The file could not be read or its meshes could not be loaded.
    #[error("{0}")]
    Mesh(#[from] MeshError),
    /// A primitive of a skinned mesh lacks `JOINTS_0` or `WEIGHTS_0`.
    #[error(
        "{source_name}: mesh {mesh} primitive {primitive} is skinned (its node has skin {skin}) but has no {attribute}; allowed: JOINTS_0 and WEIGHTS_0 on every primitive of a skinned mesh"
    )]
    MissingAttribute {
        /// The file.
        source_name: String,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// The skin of the node.
        skin: usize,
        /// `"JOINTS_0"` or `"WEIGHTS_0"`.
        attribute: &'static str,
    },
    /// A vertex refers to a joint its skin does not have.
    #[error(
        "{source_name}: mesh {mesh} primitive {primitive} vertex {vertex}: JOINTS_0 names joint {joint} (weight {weight}) but skin {skin} has {joints} joints; allowed: 0..{joints}"
    )]
    JointOutOfRange {
        /// The file.
        source_name: String,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// Vertex index in the primitive.
        vertex: usize,
        /// The skin.
        skin: usize,
        /// The joint index as written.
        joint: u32,
        /// Its weight.
        weight: f32,
        /// How many joints the skin has.
        joints: usize,
    },
    /// A vertex's weights do not sum to 1.
    #[error(
        "{source_name}: mesh {mesh} primitive {primitive} vertex {vertex}: WEIGHTS_0 {weights:?} sum to {sum}; allowed: non-negative weights summing to 1 ± {tolerance}"
    )]
    WeightSum {
        /// The file.
        source_name: String,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// Vertex index in the primitive.
        vertex: usize,
        /// The four weights.
        weights: [f32; 4],
        /// Their sum.
        sum: f32,
        /// The tolerance ([`super::skin::WEIGHT_SUM_TOLERANCE`]).
        tolerance: f32,
    },
    /// An accessor of a skin or an animation cannot be read as what it
    /// must hold.
    #[error("{source_name}: {item}: {problem}")]
    Accessor {
        /// The file.
        source_name: String,
        /// What it is, e.g. `skin 0 inverseBindMatrices`,
        /// `animation "walk" sampler 2 output`,
        /// `mesh 1 primitive 0 WEIGHTS_0`.
        item: String,
        /// What is wrong, and what is allowed.
        problem: String,
    },
    /// No animation of that name.
    #[error("{source_name}: no animation named {name:?}; the file has {available}")]
    AnimationNotFound {
        /// The file.
        source_name: String,
        /// The name asked for.
        name: String,
        /// The animations the file has, quoted, or "none".
        available: String,
    },
}
