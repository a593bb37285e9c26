//! The hierarchical bounding volume (HBV) of the paper: a binary tree of
//! oriented bounding boxes, built once per mesh (paper §3.2 off-line stage,
//! §4.2; DESIGN §3). One operation per file, parry-style: [`fit`] (one box
//! around triangles), [`build`] (the tree, Eq. 3, EqN direction), [`refit`]
//! (the same tree around a deformed mesh), [`reach`] (the pruning boxes of
//! the contact walk), [`slabs`] (tilted boxes that tighten each node), [`pseudo_normals`] (an open mesh's sides at edges
//! and corners), [`shared`] (many meshes, each distinct one built once), [`validation`] (invariants); the types are in [`node`].

pub mod build;
pub mod calipers;
pub mod fit;
pub mod nest;
pub mod node;
pub mod pseudo_normals;
pub mod reach;
pub mod refit;
pub mod shared;
pub mod slabs;
pub mod split;
pub mod validation;

pub use build::{DEFAULT_MAX_DEPTH, EQN_EPSILON, MAX_TREE_DEPTH, equivalent_normal};
pub use fit::fit_obb;
pub use node::{NO_CHILD, Obb, ObbNode, ObbTree};
pub use refit::{AxisRule, RefitError, RefitMap, RefitScratch};
