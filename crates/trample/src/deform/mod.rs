//! Deformation (paper §6): blade bending with length preservation (Eq. 5–7,
//! Fig. 7), billboard slopes (Eq. 8) and transitions between the levels of
//! detail (Eq. 9–13); and (ours) the contact response that moves blades
//! out of objects whatever their speed.
//!
//! Conventions shared by the files here:
//! - A blade is a slice of `n + 1` vertices, world space, metres: vertex 0 is
//!   the root (never moved), vertex `n` the tip; all its segments have the
//!   same rest length `seg_len`.
//! - Forces (m/s, Eq. 2 and 4) reach the bending as this step's displacement
//!   `v1 = F · dt`, metres (DESIGN §6, ours: frame-rate independence).
//! - Billboard slopes are dimensionless directions per unit height; the top
//!   edge is `base + normalize(slope) · height` (DESIGN §6).
//! - No vertex goes below `terrain + clearance` (the ground guard, ours).
//! - Bad input (NaN, ∞, non-positive lengths) leaves a blade unchanged
//!   rather than poisoning it; nothing panics; nothing allocates.

pub mod bend;
pub mod billboard;
pub mod contact;
pub mod transition;
