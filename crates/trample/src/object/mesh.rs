//! Indexed triangle mesh in the object's local frame.

use glam::{DVec3, Vec3};
use std::collections::HashMap;

/// An indexed triangle mesh. Counter-clockwise triangles face outwards.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions, metres, object-local frame.
    pub positions: Vec<Vec3>,
    /// Triangles as three indices into `positions`.
    pub indices: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Corners of triangle `i`.
    #[must_use]
    pub fn triangle(&self, i: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[i];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Axis-aligned bounds (min, max); `None` for an empty mesh.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }

    /// Whether the mesh is closed: every undirected edge (pair of vertex
    /// indices) is used by exactly two triangles. Index-based, so vertices
    /// must be shared ([`super::sanitize::sanitize`] welds equal positions).
    /// An empty mesh is not closed.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        if self.indices.is_empty() {
            return false;
        }
        let mut uses: HashMap<(u32, u32), u32> = HashMap::with_capacity(self.indices.len() * 3 / 2);
        for &[a, b, c] in &self.indices {
            for (p, q) in [(a, b), (b, c), (c, a)] {
                *uses.entry((p.min(q), p.max(q))).or_insert(0) += 1;
            }
        }
        uses.values().all(|&n| n == 2)
    }

    /// Signed volume enclosed by the triangles, cubic metres (divergence
    /// theorem, summed in f64). Positive when a closed mesh's
    /// counter-clockwise triangles face outwards; meaningless for an open
    /// mesh. Triangles with an out-of-range index are skipped.
    #[must_use]
    pub fn signed_volume(&self) -> f64 {
        let corner = |i: u32| self.positions.get(i as usize).map(|p| p.as_dvec3());
        let mut six_volume = 0.0;
        for &[a, b, c] in &self.indices {
            if let (Some(a), Some(b), Some(c)) = (corner(a), corner(b), corner(c)) {
                six_volume += a.dot(b.cross(c));
            }
        }
        six_volume / 6.0
    }

    /// Area of triangle `i`, square metres (f64 cross product), or `None`
    /// when `i` or one of its indices is out of range.
    #[must_use]
    pub fn triangle_area(&self, i: usize) -> Option<f64> {
        let tri = self.indices.get(i)?;
        let p =
            |k: usize| -> Option<DVec3> { Some(self.positions.get(tri[k] as usize)?.as_dvec3()) };
        let (a, b, c) = (p(0)?, p(1)?, p(2)?);
        Some(0.5 * (b - a).cross(c - a).length())
    }
}
