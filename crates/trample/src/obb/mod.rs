//! The hierarchical bounding volume (HBV) of the paper: a binary tree of
//! oriented bounding boxes, built once per mesh (paper §3.2 off-line stage,
//! §4.2; DESIGN §3). One operation per file, parry-style.

pub mod build;
pub mod fit;
pub mod node;
pub mod validation;

pub use node::{NO_CHILD, Obb, ObbNode, ObbTree};
