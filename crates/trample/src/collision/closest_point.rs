//! The point of a mesh closest to a given point, through the OBB tree (ours:
//! the contact response of DESIGN §5 moves a blade vertex that lies inside
//! an object to the object's surface).
//!
//! Point–triangle: C. Ericson, *Real-Time Collision Detection*, 2005,
//! §5.1.5 (`ClosestPtPointTriangle`): the point's Voronoi region of the
//! triangle (a vertex, an edge or the face) is found from barycentric
//! tests, and the projection onto that feature is returned. Point–mesh:
//! a depth-first branch-and-bound over the tree — a node is skipped when
//! its box is farther than the best triangle found so far (every box holds
//! its triangles, DESIGN §3), the nearer child first.

use glam::{Vec3, Vec3A};

use super::exact::STACK_SIZE;
use crate::obb::pseudo_normals::{CORNER_A, EDGE_AB, EDGE_BC, EDGE_CA, FACE, face_normal};
use crate::obb::{Obb, ObbTree};

/// Which feature of a triangle a closest point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// The interior of the face: the point projects onto it along the normal.
    Face,
    /// An edge or a corner: the point lies outside the face's prism.
    EdgeOrVertex,
}

impl Feature {
    /// The feature of a region index of [`closest_point_on_triangle_region`].
    #[must_use]
    pub fn of_region(region: u8) -> Self {
        if region == FACE {
            Self::Face
        } else {
            Self::EdgeOrVertex
        }
    }
}

/// The point of triangle `a, b, c` closest to `p`, and the feature it lies
/// on (Ericson §5.1.5). A degenerate triangle gives a point of it (an edge
/// or a corner). No allocation, no branch on NaN beyond comparisons (NaN
/// input gives a NaN or arbitrary corner, never a panic).
#[must_use]
pub fn closest_point_on_triangle(p: Vec3, tri: &[Vec3; 3]) -> (Vec3, Feature) {
    let (q, region) = closest_point_on_triangle_region(p, tri);
    (q, Feature::of_region(region))
}

/// [`closest_point_on_triangle`] with the exact feature: the region index
/// of [`crate::obb::pseudo_normals`] (edges `ab`, `bc`, `ca` = 0, 1, 2,
/// corners `a`, `b`, `c` = 3, 4, 5, the face = 6).
#[must_use]
pub fn closest_point_on_triangle_region(p: Vec3, [a, b, c]: &[Vec3; 3]) -> (Vec3, u8) {
    let (ab, ac, ap) = (*b - *a, *c - *a, p - *a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (*a, CORNER_A);
    }
    let bp = p - *b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (*b, CORNER_A + 1);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (*a + ab * v, EDGE_AB);
    }
    let cp = p - *c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (*c, CORNER_A + 2);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (*a + ac * w, EDGE_CA);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (*b + (*c - *b) * w, EDGE_BC);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (*a + ab * v + ac * w, FACE)
}

/// The closest point of a mesh to a query point: see [`closest_point_on_mesh`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The closest point, object-local frame.
    pub point: Vec3,
    /// Squared distance from the query point to it, m².
    pub distance_sq: f32,
    /// The unit normal of the triangle it lies on (counter-clockwise
    /// triangles face outwards); zero for a degenerate triangle.
    pub normal: Vec3,
    /// The triangle it lies on (index into [`ObbTree::triangles`]).
    pub triangle: u32,
    /// Which feature of that triangle, as [`closest_point_on_triangle_region`]
    /// numbers them.
    pub region: u8,
}

impl SurfacePoint {
    /// Whether it lies inside its triangle's face or on an edge or corner
    /// (from [`SurfacePoint::region`]).
    #[must_use]
    pub fn feature(&self) -> Feature {
        Feature::of_region(self.region)
    }

    /// The normal that says which side of an open mesh the query point is
    /// on: the face normal when the closest point lies inside a face, the
    /// angle-weighted pseudo-normal of the edge or corner it lies on
    /// otherwise ([`crate::obb::pseudo_normals`]; the face normal when
    /// `tree` has none, e.g. a closed mesh).
    #[must_use]
    pub fn side_normal(&self, tree: &ObbTree) -> Vec3 {
        if self.region == FACE {
            return self.normal;
        }
        tree.feature_normals
            .get(self.triangle as usize)
            .and_then(|n| n.get(self.region as usize))
            .copied()
            .unwrap_or(self.normal)
    }
}

/// Squared distance from `p` to the box `obb` (0 inside it).
#[inline]
fn distance_sq_to_box(p: Vec3, obb: &Obb) -> f32 {
    let q = obb.to_box_a(p.into());
    (q.abs() - Vec3A::from(obb.half))
        .max(Vec3A::ZERO)
        .length_squared()
}

/// The point of the mesh of `tree` closest to `p` (object-local frame),
/// among those within `max_distance` of it; `None` when there is none (or
/// the tree is empty, or `p` is not finite). Ties between triangles at the
/// same distance keep the first found (depth first, nearer child first,
/// left child on equal distances): deterministic.
///
/// Cost: a branch-and-bound walk; for a point near the surface of a
/// 1,280-triangle sphere a few dozen box distances and a handful of
/// triangles. No allocation.
#[must_use]
pub fn closest_point_on_mesh(tree: &ObbTree, p: Vec3, max_distance: f32) -> Option<SurfacePoint> {
    if max_distance.is_nan() || max_distance < 0.0 {
        return None;
    }
    closest_point_within_sq(tree, p, max_distance * max_distance)
}

/// [`closest_point_on_mesh`] among the points within `sqrt(max_sq)` of
/// `p`, the bound given squared so that a distance measured earlier
/// (`closest_point_on_triangle_region(p, tri)`, then `distance_squared`)
/// bounds the walk exactly: that triangle is then found, or one nearer.
///
/// With `max_sq` at least the squared distance of the mesh's closest point,
/// the answer is that of the unbounded walk, bit for bit: a bound only
/// skips boxes farther than it, the walk's order does not depend on it,
/// and the triangle the unbounded walk keeps — the first in that order at
/// the least distance — lies in boxes no farther than that distance. (What
/// [`crate::collision::contact::push_out_hinted`] relies on.)
#[must_use]
pub fn closest_point_within_sq(tree: &ObbTree, p: Vec3, max_sq: f32) -> Option<SurfacePoint> {
    walk(tree, p, max_sq, None)
}

/// Most surface points [`closest_point_and_near`] keeps.
pub const NEAR_POINTS_MAX: usize = 8;

/// The triangles' closest points that [`closest_point_and_near`] met
/// within its reach of the closest: `(point, squared distance, triangle)`.
/// When more than [`NEAR_POINTS_MAX`] were met, the nearest are kept
/// (ties: the lower triangle index), so what is kept does not depend on
/// the order the walk met them, nor on its first bound. Some may lie
/// farther than the reach of the final closest point (they were within it
/// of a closer point found before): the caller weighs them.
#[derive(Clone, Copy, Debug, Default)]
pub struct NearPoints {
    /// The points, object-local frame, their squared distances and their
    /// triangles; the first `len` are set, in no particular order.
    pub points: [(Vec3, f32, u32); NEAR_POINTS_MAX],
    /// How many are set.
    pub len: usize,
}

impl NearPoints {
    fn add(&mut self, q: Vec3, d_sq: f32, tri: u32) {
        if self.len < NEAR_POINTS_MAX {
            self.points[self.len] = (q, d_sq, tri);
            self.len += 1;
            return;
        }
        let key = |e: &(Vec3, f32, u32)| (e.1, e.2);
        let mut far = 0;
        for k in 1..NEAR_POINTS_MAX {
            if key(&self.points[k]) > key(&self.points[far]) {
                far = k;
            }
        }
        if (d_sq, tri) < key(&self.points[far]) {
            self.points[far] = (q, d_sq, tri);
        }
    }

    /// The set points in ascending triangle order (a sum over them does
    /// not depend on the walk's order).
    pub fn in_triangle_order(&self) -> impl Iterator<Item = (Vec3, f32)> + '_ {
        let set = &self.points[..self.len.min(NEAR_POINTS_MAX)];
        let mut last = None::<u32>;
        std::iter::from_fn(move || {
            let next = set
                .iter()
                .filter(|e| last.is_none_or(|l| e.2 > l))
                .min_by_key(|e| e.2)?;
            last = Some(next.2);
            Some((next.0, next.1))
        })
    }
}

/// [`closest_point_within_sq`], the same answer bit for bit, and in `near`
/// every triangle's closest point within `reach` metres farther than the
/// closest (up to [`NEAR_POINTS_MAX`], the nearest kept): one walk whose boxes
/// are skipped only beyond `reach` past the closest point found so far.
/// For the contact response's way out
/// ([`crate::collision::contact::push_direction`]); `max_sq` bounds the
/// closest point as in [`closest_point_within_sq`] (pass the bound's
/// distance plus `reach`, squared, to keep every near point).
pub fn closest_point_and_near(
    tree: &ObbTree,
    p: Vec3,
    max_sq: f32,
    reach: f32,
    near: &mut NearPoints,
) -> Option<SurfacePoint> {
    near.len = 0;
    walk(tree, p, max_sq, Some((reach, near)))
}

/// The branch-and-bound walk of [`closest_point_within_sq`] and
/// [`closest_point_and_near`]: with `keep` (reach, points), boxes are
/// skipped beyond `reach` past the best distance (they hold no better
/// point either, so the best is the same), and every point within that is
/// kept.
fn walk(
    tree: &ObbTree,
    p: Vec3,
    max_sq: f32,
    mut keep: Option<(f32, &mut NearPoints)>,
) -> Option<SurfacePoint> {
    if tree.is_empty() || !p.is_finite() || max_sq.is_nan() || max_sq < 0.0 {
        return None;
    }
    let mut best_sq = max_sq;
    let mut bound_sq = max_sq;
    let mut best: Option<SurfacePoint> = None;
    let prune = keep.is_none();
    // (node, its box's squared distance, computed once when it is pushed).
    let mut stack = [(0u32, 0.0f32); STACK_SIZE];
    stack[0].1 = tree
        .nodes
        .first()
        .map_or(f32::INFINITY, |n| distance_sq_to_box(p, &n.obb));
    let mut len = 1;
    while len > 0 {
        len -= 1;
        let (i, box_sq) = stack[len];
        // The bound may have shrunk since the node was pushed.
        if box_sq > bound_sq {
            continue;
        }
        let Some(node) = tree.nodes.get(i as usize) else {
            continue;
        };
        let [l, r] = node.children;
        if node.is_leaf() || l <= i || r <= i || len + 2 > STACK_SIZE {
            let (first, count) = (node.first_tri as usize, node.tri_count as usize);
            let Some(tris) = tree.triangles.get(first..first.saturating_add(count)) else {
                continue;
            };
            for (k, tri) in tris.iter().enumerate() {
                let (q, region) = closest_point_on_triangle_region(p, tri);
                let d = q.distance_squared(p);
                if d <= best_sq && (best.is_none() || d < best_sq) {
                    best_sq = d;
                    // The normal is that of the final triangle, taken
                    // once after the walk.
                    best = Some(SurfacePoint {
                        point: q,
                        distance_sq: d,
                        normal: Vec3::ZERO,
                        triangle: (first + k) as u32,
                        region,
                    });
                    bound_sq = match &keep {
                        Some((reach, _)) => (d.sqrt() + reach) * (d.sqrt() + reach),
                        None => d,
                    };
                }
                if let Some((_, points)) = keep.as_mut()
                    && d <= bound_sq
                {
                    points.add(q, d, (first + k) as u32);
                }
            }
        } else {
            // Nearer child on top of the stack (popped first).
            let (dl, dr) = (
                tree.nodes
                    .get(l as usize)
                    .map_or(f32::INFINITY, |n| distance_sq_to_box(p, &n.obb)),
                tree.nodes
                    .get(r as usize)
                    .map_or(f32::INFINITY, |n| distance_sq_to_box(p, &n.obb)),
            );
            let (near, far) = if dr < dl {
                ((r, dr), (l, dl))
            } else {
                ((l, dl), (r, dr))
            };
            // Without `keep` the bound only shrinks, so a child beyond it
            // now would be skipped when popped: it is not pushed. (With
            // `keep` the bound may grow past `max_sq` at the first hit.)
            if !(prune && far.1 > bound_sq) {
                stack[len] = far;
                len += 1;
            }
            if !(prune && near.1 > bound_sq) {
                stack[len] = near;
                len += 1;
            }
        }
    }
    best.map(|mut b| {
        if let Some(tri) = tree.triangles.get(b.triangle as usize) {
            b.normal = face_normal(tri);
        }
        b
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::object::shapes::{knot, sphere};
    use crate::test_rng::XorShift;

    fn brute_force(tree: &ObbTree, p: Vec3) -> f32 {
        tree.triangles
            .iter()
            .map(|t| closest_point_on_triangle(p, t).0.distance_squared(p))
            .fold(f32::INFINITY, f32::min)
    }

    #[test]
    fn triangle_regions_project_onto_the_right_feature() {
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (q, f) = closest_point_on_triangle(Vec3::new(0.2, 0.3, 5.0), &t);
        assert_eq!((q, f), (Vec3::new(0.2, 0.3, 0.0), Feature::Face));
        let (q, f) = closest_point_on_triangle(Vec3::new(-1.0, -1.0, 0.5), &t);
        assert_eq!((q, f), (Vec3::ZERO, Feature::EdgeOrVertex));
        let (q, f) = closest_point_on_triangle(Vec3::new(0.5, -2.0, 0.0), &t);
        assert_eq!((q, f), (Vec3::new(0.5, 0.0, 0.0), Feature::EdgeOrVertex));
        let (q, _) = closest_point_on_triangle(Vec3::new(1.0, 1.0, 0.0), &t);
        assert!(q.distance(Vec3::new(0.5, 0.5, 0.0)) < 1e-6);
    }

    /// `got` is `want` bit for bit: point, triangle, region and distance.
    fn assert_same_point(got: &SurfacePoint, want: &SurfacePoint, p: Vec3) {
        assert_eq!(
            got.point.to_array().map(f32::to_bits),
            want.point.to_array().map(f32::to_bits),
            "{p}"
        );
        assert_eq!(
            (got.triangle, got.region, got.distance_sq.to_bits()),
            (want.triangle, want.region, want.distance_sq.to_bits()),
            "{p}"
        );
    }

    #[test]
    fn tree_query_equals_brute_force() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15u64);
        let mut next = || rng.range(-1.0, 1.0);
        for mesh in [sphere(1.0, 3), knot(2.4)] {
            let tree = ObbTree::build(&mesh, 32);
            for _ in 0..400 {
                let p = Vec3::new(next(), next(), next()) * 1.6;
                let got = closest_point_on_mesh(&tree, p, f32::INFINITY).unwrap();
                let want = brute_force(&tree, p);
                assert!(
                    (got.distance_sq - want).abs() <= 1e-6 * want.max(1e-6),
                    "{p}"
                );
                // Bounded search: nothing within a radius below the distance.
                assert!(closest_point_on_mesh(&tree, p, want.sqrt() * 0.99 - 1e-4).is_none());
            }
        }
    }
    /// A bound taken from any triangle's distance, measured as the walk
    /// measures it, gives the unbounded walk's answer bit for bit — the
    /// tightest one too (the answer's own triangle), and on a box, whose
    /// faces' diagonals and edges make ties. What `push_out_hinted` relies on.
    #[test]
    fn a_bound_from_a_measured_triangle_keeps_the_answer() {
        let mut rng = XorShift(0x51_7cc1_b727_220au64);
        for mesh in [
            sphere(1.0, 3),
            knot(2.4),
            crate::object::shapes::cuboid(Vec3::new(0.5, 0.2, 0.9)),
        ] {
            let tree = ObbTree::build(&mesh, 32);
            let n = tree.triangles.len();
            let (mut checked, mut tight) = (0, 0);
            for _ in 0..600 {
                // Near the surface: a point of a random triangle (a corner,
                // an edge's middle or inside), moved a little.
                let t = tree.triangles[(rng.next_u64() % n as u64) as usize];
                let on = match rng.next_u64() % 3 {
                    0 => t[0],
                    1 => (t[0] + t[1]) * 0.5,
                    _ => (t[0] + t[1] + t[2]) / 3.0,
                };
                let p = on
                    + Vec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    ) * 0.05;
                let want = closest_point_on_mesh(&tree, p, f32::INFINITY).unwrap();
                let own = want.triangle as usize;
                let other = (own + 1 + (rng.next_u64() % 7) as usize) % n;
                for k in [own, other] {
                    let d = closest_point_on_triangle_region(p, &tree.triangles[k])
                        .0
                        .distance_squared(p);
                    let got = closest_point_within_sq(&tree, p, d)
                        .expect("the bound's triangle is within it");
                    assert_same_point(&got, &want, p);
                    checked += 1;
                    tight += usize::from(k == own);
                }
            }
            assert_eq!((checked, tight), (1200, 600));
        }
    }

    /// [`closest_point_and_near`] answers [`closest_point_within_sq`]'s
    /// closest point bit for bit (point, distance, triangle, region), for
    /// any reach and bound, and keeps exactly the triangles whose closest
    /// points lie within the reach of it (the nearest
    /// [`NEAR_POINTS_MAX`] when more do), found by brute force over every
    /// triangle: points near the surface of a ball, the knot and a box
    /// (whose corners and edges make ties).
    #[test]
    fn the_near_walk_answers_the_closest_point_bit_for_bit_and_keeps_the_near_ones() {
        use crate::object::shapes::cuboid;
        let mut rng = XorShift(0x6a09_e667_f3bc_c908);
        let (mut checked, mut several, mut full) = (0, 0, 0);
        for mesh in [sphere(1.0, 3), knot(2.4), cuboid(Vec3::new(0.5, 0.2, 0.9))] {
            let tree = ObbTree::build(&mesh, 32);
            let n = tree.triangles.len();
            for k in 0..1500 {
                let t = tree.triangles[(rng.next_u64() % n as u64) as usize];
                let on = match k % 3 {
                    0 => t[0],
                    1 => (t[0] + t[1]) * 0.5,
                    _ => (t[0] + t[1] + t[2]) / 3.0,
                };
                let p = on + rng.vec(-1.0, 1.0) * [0.001, 0.01, 0.05][k % 3];
                let want = closest_point_within_sq(&tree, p, f32::INFINITY).unwrap();
                let reach = [0.0005, 0.001, 0.01][k % 3];
                for max_sq in [
                    f32::INFINITY,
                    (want.distance_sq.sqrt() + reach).powi(2) * 1.01,
                ] {
                    let mut near = NearPoints::default();
                    let got = closest_point_and_near(&tree, p, max_sq, reach, &mut near).unwrap();
                    assert_same_point(&got, &want, p);
                    // Every triangle within the reach of the closest point
                    // is kept (the nearest when there are more than fit).
                    let limit = want.distance_sq.sqrt() + reach;
                    let mut within: Vec<(f32, u32)> = tree
                        .triangles
                        .iter()
                        .enumerate()
                        .map(|(i, t)| {
                            let q = closest_point_on_triangle_region(p, t).0;
                            (q.distance_squared(p), i as u32)
                        })
                        .filter(|&(d, _)| d.sqrt() <= limit * (1.0 - 1e-6))
                        .collect();
                    within.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                    let kept: Vec<u32> = near.points[..near.len].iter().map(|e| e.2).collect();
                    for &(_, tri) in within.iter().take(NEAR_POINTS_MAX) {
                        assert!(
                            kept.contains(&tri),
                            "{p}: triangle {tri} not kept: {kept:?}"
                        );
                    }
                    assert!(kept.contains(&want.triangle), "{p}");
                    // The kept points are the triangles' own closest points.
                    for &(q, d, tri) in &near.points[..near.len] {
                        let own =
                            closest_point_on_triangle_region(p, &tree.triangles[tri as usize]).0;
                        assert_eq!(
                            q.to_array().map(f32::to_bits),
                            own.to_array().map(f32::to_bits)
                        );
                        assert_eq!(d.to_bits(), own.distance_squared(p).to_bits());
                    }
                    checked += 1;
                    several += usize::from(within.len() > 1);
                    full += usize::from(within.len() > NEAR_POINTS_MAX);
                }
            }
        }
        assert_eq!(checked, 9000);
        assert!(several > 1000 && full > 10, "{several} {full}");
    }

    /// The walk's order written plainly (both children pushed, the nearer
    /// popped next): the order the GPU twin (`object.wgsl`) keeps, whose
    /// first found triangle wins a tie.
    fn push_both_walk(tree: &ObbTree, p: Vec3) -> (u32, u32) {
        let mut best_sq = f32::INFINITY;
        let mut best = (u32::MAX, u32::MAX);
        let mut stack = vec![(0u32, distance_sq_to_box(p, &tree.nodes[0].obb))];
        while let Some((i, box_sq)) = stack.pop() {
            if box_sq > best_sq {
                continue;
            }
            let node = &tree.nodes[i as usize];
            if node.is_leaf() {
                let first = node.first_tri as usize;
                for k in first..first + node.tri_count as usize {
                    let d = closest_point_on_triangle_region(p, &tree.triangles[k])
                        .0
                        .distance_squared(p);
                    if d <= best_sq && (best.1 == u32::MAX || d < best_sq) {
                        best_sq = d;
                        best = (d.to_bits(), k as u32);
                    }
                }
            } else {
                let [l, r] = node.children;
                let dl = distance_sq_to_box(p, &tree.nodes[l as usize].obb);
                let dr = distance_sq_to_box(p, &tree.nodes[r as usize].obb);
                if dr < dl {
                    stack.extend([(l, dl), (r, dr)]);
                } else {
                    stack.extend([(r, dr), (l, dl)]);
                }
            }
        }
        best
    }

    /// The walk's answer is the push-both walk's, the distance bit for bit
    /// and the triangle, ties included — points near a cube's corners and
    /// edges (equidistant from several triangles) and near the sphere and
    /// knot: a faster walk must keep this order, or the CPU and the GPU
    /// twin pick different triangles on a tie. (Measured 2026-11-26: going
    /// on with the nearer child without the stack's round trip kept the
    /// order and gained nothing.)
    #[test]
    fn the_walk_keeps_the_push_both_order_and_its_ties() {
        use crate::object::shapes::cuboid;
        let mut rng = XorShift(0x2545_f491_4f6c_dd1d);
        let mut ties = 0;
        for mesh in [cuboid(Vec3::new(0.5, 0.5, 0.5)), sphere(1.0, 3), knot(2.4)] {
            let tree = ObbTree::build(&mesh, 32);
            for k in 0..3000 {
                // On a grid of 1/8 m (exact ties on the cube) or anywhere.
                let p = if k % 2 == 0 {
                    (rng.vec(-1.0, 1.0) * 8.0).round() / 8.0
                } else {
                    rng.vec(-1.3, 1.3)
                };
                let got = closest_point_on_mesh(&tree, p, f32::INFINITY).unwrap();
                let want = push_both_walk(&tree, p);
                assert_eq!((got.distance_sq.to_bits(), got.triangle), want, "{p}");
                let equal = tree
                    .triangles
                    .iter()
                    .filter(|t| {
                        closest_point_on_triangle_region(p, t).0.distance_squared(p)
                            == got.distance_sq
                    })
                    .count();
                ties += usize::from(equal > 1);
            }
        }
        assert!(ties > 500, "ties met: {ties}");
    }
}
