//! Each collider's closest triangles of the blade vertices its contact
//! response asked about last (ours; a cost, not a result).
//!
//! The contact response asks, for every vertex of a blade it checks, where
//! the closest point of the object's surface is
//! ([`crate::collision::contact::push_out_hinted`]). A triangle near the
//! vertex answers the question for a vertex resting within the tolerance of
//! it, and bounds the tree walk for any other: the walk then skips every box
//! farther than that triangle. Any triangle gives the same answers bit for
//! bit (`closest_point_within_sq`); a near one saves the most. Within a
//! sub-step the rounds of [`crate::deform::contact::resolve_contact`] hand
//! each vertex its last triangle; these hints carry them to the collider's
//! next sub-step, where the same blades are mostly asked again with their
//! vertices moved by a few millimetres.
//!
//! Kept per collider for the blades of its latest contact response only (a
//! blade it no longer checks drops out): `MAX_SEGMENTS + 1` words a blade
//! at most.

use crate::collision::contact::NO_HINT;
use crate::field::MAX_SEGMENTS;

/// One collider's hints: per blade it checked last, in ascending order, the
/// triangle of each vertex's last closest point ([`NO_HINT`]: none).
#[derive(Clone, Debug, Default)]
pub(crate) struct ContactHints {
    /// Blades, ascending.
    blades: Vec<u32>,
    /// `stride` triangles per blade, in the order of `blades`.
    triangles: Vec<u32>,
    /// Vertices per blade (segments + 1) when the hints were kept.
    stride: usize,
}

/// A blade's hints, one per vertex, root first.
pub(crate) type BladeHints = [u32; MAX_SEGMENTS + 1];

impl ContactHints {
    /// The hints kept for blade `b` of `stride` vertices, or none.
    pub(crate) fn of(&self, b: u32, stride: usize) -> BladeHints {
        let mut out = [NO_HINT; MAX_SEGMENTS + 1];
        if stride == self.stride
            && let Ok(i) = self.blades.binary_search(&b)
            && let Some(kept) = self.triangles.get(i * stride..(i + 1) * stride)
        {
            out[..stride].copy_from_slice(kept);
        }
        out
    }

    /// Hints for `blades` (ascending) of `stride` vertices each, from
    /// `hints` (one per blade, in the same order).
    pub(crate) fn keep(blades: Vec<u32>, hints: &[BladeHints], stride: usize) -> Self {
        let stride = stride.min(MAX_SEGMENTS + 1);
        let mut triangles = Vec::with_capacity(blades.len() * stride);
        for h in hints {
            triangles.extend_from_slice(&h[..stride]);
        }
        Self {
            blades,
            triangles,
            stride,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hints_are_found_by_blade_and_none_for_others() {
        let mut a = [NO_HINT; MAX_SEGMENTS + 1];
        let mut b = [NO_HINT; MAX_SEGMENTS + 1];
        a[..5].copy_from_slice(&[1, 2, 3, 4, 5]);
        b[..5].copy_from_slice(&[6, 7, 8, 9, 10]);
        let kept = ContactHints::keep(vec![3, 9], &[a, b], 5);
        assert_eq!(kept.of(3, 5), a);
        assert_eq!(kept.of(9, 5), b);
        assert_eq!(kept.of(4, 5), [NO_HINT; MAX_SEGMENTS + 1]);
        // Kept for another blade shape: none.
        assert_eq!(kept.of(3, 4), [NO_HINT; MAX_SEGMENTS + 1]);
        assert_eq!(
            ContactHints::default().of(3, 5),
            [NO_HINT; MAX_SEGMENTS + 1]
        );
    }
}
