//! Angle-weighted pseudo-normals of an open mesh's edges and corners (ours,
//! DESIGN §5 "Contact": which side of an open mesh a blade vertex is on).
//!
//! J. A. Bærentzen, H. Aanæs, *Signed distance computation using the angle
//! weighted pseudonormal*, IEEE TVCG 11(3), 2005: when the point of a
//! surface closest to `p` lies on an edge or a corner, the side of `p` is
//! the sign of `(p − q) · n` with `n` the **pseudo-normal** of that feature —
//! for an edge the sum of its faces' normals, for a corner the sum of its
//! faces' normals each weighted by the face's angle there. Taking instead
//! the normal of *one* of the triangles that share the feature (the first
//! one the walk finds, as the contact test did before) answers differently
//! for the two triangles of a sharp fold: a point just outside the fold is
//! in front of one face's plane and behind the other's, and which of them
//! is "first" can turn on a rounding of the distances (CPU and GPU differ
//! there). The pseudo-normal is one vector per feature, whichever triangle
//! reports it.
//!
//! Closed meshes do not need it: their inside test at an edge or a corner
//! is the exact ray parity ([`crate::collision::exact::point_inside_by_ray`]).

use std::collections::HashMap;

use glam::Vec3;

/// Index of a triangle's feature in [`MeshFeatures::normals`]' per-triangle
/// array: edges `ab`, `bc`, `ca`, then corners `a`, `b`, `c`.
pub const EDGE_AB: u8 = 0;
/// See [`EDGE_AB`].
pub const EDGE_BC: u8 = 1;
/// See [`EDGE_AB`].
pub const EDGE_CA: u8 = 2;
/// See [`EDGE_AB`]; corner `k` (0, 1, 2) is `CORNER_A + k`.
pub const CORNER_A: u8 = 3;
/// The face's interior: the face normal, not a pseudo-normal.
pub const FACE: u8 = 6;

/// The unit normal of triangle `t` (its corners counter-clockwise seen
/// from the side it points to), zero for a degenerate one: a face's
/// normal here and the closest point's
/// ([`crate::collision::closest_point::SurfacePoint::normal`]).
#[must_use]
#[inline]
pub fn face_normal(t: &[Vec3; 3]) -> Vec3 {
    (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero()
}

/// Which corners and edges the triangles of a mesh share, by position (the
/// bits of the coordinates, −0.0 = +0.0: an unwelded mesh counts as
/// welded), computed once; [`MeshFeatures::normals`] turns positions into
/// pseudo-normals without hashing, so that a refitted (skinned) mesh gets
/// its pseudo-normals every pose for a few passes over its triangles.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshFeatures {
    /// Per triangle: the id of each corner's vertex.
    corners: Vec<[u32; 3]>,
    /// Per triangle: the id of each edge `ab`, `bc`, `ca`.
    edges: Vec<[u32; 3]>,
    /// Distinct vertices.
    vertex_count: usize,
    /// Distinct undirected edges.
    edge_count: usize,
}

impl MeshFeatures {
    /// The shared corners and edges of `triangles`.
    #[must_use]
    pub fn new(triangles: &[[Vec3; 3]]) -> Self {
        let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
        let mut vertices: HashMap<[u32; 3], u32> = HashMap::with_capacity(triangles.len());
        let corners: Vec<[u32; 3]> = triangles
            .iter()
            .map(|t| {
                t.map(|c| {
                    let next = vertices.len() as u32;
                    *vertices.entry(key(c)).or_insert(next)
                })
            })
            .collect();
        let mut edge_ids: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 2);
        let edges = corners
            .iter()
            .map(|c| {
                [0, 1, 2].map(|e| {
                    let (a, b) = (c[e], c[(e + 1) % 3]);
                    let next = edge_ids.len() as u32;
                    *edge_ids.entry((a.min(b), a.max(b))).or_insert(next)
                })
            })
            .collect();
        Self {
            corners,
            edges,
            vertex_count: vertices.len(),
            edge_count: edge_ids.len(),
        }
    }

    /// The rim of the mesh (corners identified by position, as
    /// [`MeshFeatures::new`] identifies them): every undirected edge whose
    /// directed uses do not cancel, once, at its first triangle in mesh
    /// order, in the order the edges first appear
    /// ([`crate::collision::winding::Rim`]).
    #[must_use]
    pub fn rims(&self) -> Vec<crate::collision::winding::Rim> {
        // Per edge id: its first triangle and edge, and its net uses from
        // its smaller corner id.
        let mut first: Vec<Option<(u32, u8)>> = vec![None; self.edge_count];
        let mut net = vec![0i64; self.edge_count];
        for (t, (c, e)) in self.corners.iter().zip(&self.edges).enumerate() {
            for k in 0..3 {
                let id = e[k] as usize;
                first[id].get_or_insert((t as u32, k as u8));
                net[id] += if c[k] < c[(k + 1) % 3] { 1 } else { -1 };
            }
        }
        first
            .into_iter()
            .zip(net)
            .filter_map(|(f, n)| {
                let (tri, edge) = f?;
                (n != 0).then(|| crate::collision::winding::Rim {
                    tri,
                    edge,
                    count: n.unsigned_abs() as u32,
                })
            })
            .collect()
    }

    /// Number of triangles described.
    #[must_use]
    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// True when no triangle is described.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }

    /// Per triangle of `triangles` (the same triangles as [`MeshFeatures::new`]
    /// saw, possibly moved): the unit pseudo-normals of edges `ab`, `bc`,
    /// `ca` (the sum of the unit normals of the triangles that use the edge)
    /// and corners `a`, `b`, `c` (the sum of the unit normals of the
    /// triangles at the corner, each times its angle there). A feature whose
    /// sum is zero (faces that cancel: a sheet folded flat onto itself, or
    /// opposite windings) gets the triangle's own unit normal; a degenerate
    /// triangle adds nothing. Deterministic: sums in triangle order.
    ///
    /// # Panics
    /// Never for the triangles `new` saw; `triangles` of another length
    /// give normals for the shorter of the two.
    #[must_use]
    pub fn normals(&self, triangles: &[[Vec3; 3]]) -> Vec<[Vec3; 6]> {
        let mut out = Vec::new();
        self.normals_into(triangles, &mut out, &mut NormalScratch::default());
        out
    }

    /// [`MeshFeatures::normals`] written into `out` (cleared first), with
    /// `scratch`'s memory: no allocation once both have grown to the mesh
    /// (a refit of an open animated mesh every sub-step,
    /// [`super::ObbTree::refit`]).
    pub fn normals_into(
        &self,
        triangles: &[[Vec3; 3]],
        out: &mut Vec<[Vec3; 6]>,
        scratch: &mut NormalScratch,
    ) {
        let NormalScratch {
            faces,
            at_edge,
            at_corner,
        } = scratch;
        faces.clear();
        faces.extend(triangles.iter().map(face_normal));
        at_edge.clear();
        at_edge.resize(self.edge_count, Vec3::ZERO);
        at_corner.clear();
        at_corner.resize(self.vertex_count, Vec3::ZERO);
        for ((t, n), (c, e)) in triangles
            .iter()
            .zip(faces.iter())
            .zip(self.corners.iter().zip(&self.edges))
        {
            for k in 0..3 {
                at_edge[e[k] as usize] += *n;
                at_corner[c[k] as usize] += *n * corner_angle(t, k);
            }
        }
        out.clear();
        out.extend(
            faces
                .iter()
                .zip(self.corners.iter().zip(&self.edges))
                .map(|(n, (c, e))| {
                    let unit = |v: Vec3| v.try_normalize().unwrap_or(*n);
                    let (e, c) = (
                        e.map(|i| unit(at_edge[i as usize])),
                        c.map(|i| unit(at_corner[i as usize])),
                    );
                    [e[0], e[1], e[2], c[0], c[1], c[2]]
                }),
        );
    }
}

/// Scratch memory of [`MeshFeatures::normals_into`]: per triangle its face
/// normal, per edge and per corner the sums of their pseudo-normals.
#[derive(Clone, Debug, Default)]
pub struct NormalScratch {
    faces: Vec<Vec3>,
    at_edge: Vec<Vec3>,
    at_corner: Vec<Vec3>,
}

/// The angle of triangle `t` at corner `k`, radians (0 for a degenerate
/// corner).
fn corner_angle(t: &[Vec3; 3], k: usize) -> f32 {
    let (p, a, b) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
    let (u, v) = ((a - p).normalize_or_zero(), (b - p).normalize_or_zero());
    if u == Vec3::ZERO || v == Vec3::ZERO {
        return 0.0;
    }
    u.dot(v).clamp(-1.0, 1.0).acos()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A roof: two triangles meeting at a ridge along x at a right angle.
    fn roof() -> Vec<[Vec3; 3]> {
        let (r0, r1) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 0.0));
        let (s0, s1) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, -1.0));
        vec![[r0, s0, r1], [r1, s1, r0]]
    }

    /// The rim: none on a closed mesh, even where a corner is written with
    /// −0 in one triangle and +0 in another (the same position); the two
    /// outer edges of the roof each way round, its ridge not.
    #[test]
    fn the_rim_is_the_edges_whose_uses_do_not_cancel() {
        let s = crate::object::shapes::sphere(1.0, 2);
        let mut tris: Vec<[Vec3; 3]> = s
            .indices
            .iter()
            .map(|t| t.map(|i| s.positions[i as usize]))
            .collect();
        let mut flipped = 0;
        for t in &mut tris[..40] {
            for c in t.iter_mut() {
                for x in [&mut c.x, &mut c.y, &mut c.z] {
                    if *x == 0.0 {
                        *x = -0.0;
                        flipped += 1;
                    }
                }
            }
        }
        assert!(flipped > 0);
        assert!(MeshFeatures::new(&tris).rims().is_empty());
        let rims = MeshFeatures::new(&roof()).rims();
        assert_eq!(rims.len(), 4, "{rims:?}");
        assert!(rims.iter().all(|r| r.count == 1));
        // The ridge (r0–r1) is edge 2 of triangle 0 and edge 2 of triangle 1.
        assert!(!rims.iter().any(|r| r.edge == 2));
    }

    #[test]
    fn a_shared_edge_has_one_normal_between_its_faces() {
        let t = roof();
        let f = MeshFeatures::new(&t);
        let n = f.normals(&t);
        // Ridge r0–r1: edge ca of the first triangle, edge ca of the second.
        let ridge = n[0][EDGE_CA as usize];
        assert_eq!(ridge, n[1][EDGE_CA as usize]);
        assert!((ridge - Vec3::Y).length() < 1e-6, "{ridge}");
        // A border edge keeps its face's normal.
        let face = (t[0][1] - t[0][0]).cross(t[0][2] - t[0][0]).normalize();
        assert!((n[0][EDGE_AB as usize] - face).length() < 1e-6);
        // A ridge corner: one angle-weighted normal for both triangles.
        assert_eq!(n[0][CORNER_A as usize], n[1][CORNER_A as usize + 2]);
    }

    /// Reused memory (a refit every sub-step) gives the normals of a fresh
    /// computation: nothing of the previous mesh's sums is left in it.
    #[test]
    fn normals_into_reused_memory_equal_fresh_normals() {
        let t = roof();
        let f = MeshFeatures::new(&t);
        let mut out = vec![[Vec3::splat(9.0); 6]; 5];
        let mut scratch = NormalScratch::default();
        let mut bent = t.clone();
        bent[1][1].y -= 0.3;
        f.normals_into(&bent, &mut out, &mut scratch);
        assert_eq!(out, f.normals(&bent));
        f.normals_into(&t, &mut out, &mut scratch);
        assert_eq!(out, f.normals(&t));
    }

    #[test]
    fn unwelded_copies_of_a_vertex_are_one_vertex() {
        let mut t = roof();
        t[1][0] = Vec3::new(1.0, 1.0, -0.0);
        t[0][2] = Vec3::new(1.0, 1.0, 0.0);
        let f = MeshFeatures::new(&t);
        assert_eq!((f.vertex_count, f.edge_count), (4, 5));
    }
}
