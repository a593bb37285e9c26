//! Splitting a node's triangles in two for [`super::ObbTree::build`]
//! (issue 16, item 5: tighter trees).
//!
//! Two rules, chosen per node:
//!
//! 1. **Apart pieces stay whole.** When the node's triangles form two or
//!    more pieces that share no edge (vertices identified by position), each
//!    holding at least [`PIECE_SHARE`] of them — strands of a knot or of a
//!    tube that a box cut across, the wheels and the body of a car — the
//!    node is split between pieces, never through one: the pieces are
//!    ordered by their mean centroid along each of the node's box axes, and
//!    of the cuts between consecutive pieces the one whose children's boxes
//!    cost least is taken. Cost of a cut: `n_L c(L) + n_R c(R)` with `n` the
//!    triangle counts (the surface-area heuristic's weighting, J. D.
//!    MacDonald, K. S. Booth, *Heuristics for ray tracing using space
//!    subdivision*, 1990) and `c` the segment-hit measure of a child's box
//!    (its extent in the node's box frame): for segments of length `ℓ` in
//!    uniformly random position and direction, the chance of meeting a
//!    convex body is proportional to `V + ℓ S / 4` (Crofton's formula for
//!    segments, L. A. Santaló, *Integral Geometry and Geometric
//!    Probability*, 1976, §I.5), with `ℓ` [`SEGMENT_LENGTH_M`].
//! 2. **Otherwise**, the rule of Gottschalk et al. (*OBBTree*, 1996): along
//!    the box's longest axis at the mean of the triangle centroids, else
//!    along the other axes by decreasing extent, else at the median.
//!
//! Why: splitting by space alone cuts a curved tube lengthwise and leaves
//! boxes spanning two strands. Measured on the knot (6,144 triangles) at
//! depth 7, false positives fell from 60 % to 18 % (with the wider
//! orientation search of [`super::fit`]); the sphere, one piece at every
//! node, keeps rule 2 (BENCHMARKS.md, "Collision accuracy").

use std::collections::HashMap;

use glam::Vec3;

use super::node::Obb;

/// Smallest share of a node's triangles that each of two pieces must hold
/// for rule 1: a stray triangle that touches the rest only at a vertex
/// (common on tessellated spheres cut by a plane) must not turn a balanced
/// split into a sliver. Measured: at 0 the torus of the precision tests
/// went from 19 % to 38 % false positives at depth 7; 5 % and 15 % gave the
/// same trees on the test meshes.
pub const PIECE_SHARE: f32 = 0.1;

/// Segment length `ℓ` of the cut cost (metres, object frame): about a
/// blade's length (the default blade is 0.45 m), the segments whose hits
/// the tree decides. Measured on the knot at depth 7: 23 % false positives
/// with the surface area alone, 18 % with 0.4 m.
pub const SEGMENT_LENGTH_M: f32 = 0.4;

/// A vertex by the bits of its position.
type VertexKey = [u32; 3];

/// Marks "no neighbour" in [`Topology::neighbours`].
const NONE: u32 = u32::MAX;

/// Which triangles share an edge, and scratch space for finding a node's
/// pieces, for one build.
pub(super) struct Topology {
    /// Per triangle (its index in the mesh order): the triangle across each
    /// edge, [`NONE`] at a border or where more than two triangles meet.
    neighbours: Vec<[u32; 3]>,
    /// Per triangle: the number of the node being split when it is in it.
    stamp: Vec<u32>,
    /// Per triangle: its position in the node's slice (valid with `stamp`).
    slot: Vec<u32>,
    /// Nodes split so far.
    visits: u32,
    /// Every undirected edge is used by exactly two triangles, no triangle
    /// has two equal corners, and there is at least one triangle.
    pub(super) every_edge_twice: bool,
}

impl Topology {
    /// The edge neighbours of `triangles` (mesh order), vertices identified
    /// by position (−0.0 = +0.0), and whether they close a surface.
    pub(super) fn new(triangles: &[[Vec3; 3]]) -> Self {
        let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
        // Per undirected edge: its first two (triangle, edge) uses and how
        // many triangles use it (no allocation per edge).
        type Uses = ([(u32, usize); 2], u32);
        let mut edges: HashMap<(VertexKey, VertexKey), Uses> =
            HashMap::with_capacity(triangles.len() * 2);
        let mut every_edge_twice = !triangles.is_empty();
        for (t, tri) in triangles.iter().enumerate() {
            for e in 0..3 {
                let (a, b) = (key(tri[e]), key(tri[(e + 1) % 3]));
                every_edge_twice &= a != b;
                if a != b {
                    let edge = if a < b { (a, b) } else { (b, a) };
                    let uses = edges.entry(edge).or_insert(([(0, 0); 2], 0));
                    if uses.1 < 2 {
                        uses.0[uses.1 as usize] = (t as u32, e);
                    }
                    uses.1 += 1;
                }
            }
        }
        let mut neighbours = vec![[NONE; 3]; triangles.len()];
        for ([(a, ea), (b, eb)], count) in edges.into_values() {
            every_edge_twice &= count == 2;
            if count == 2 {
                neighbours[a as usize][ea] = b;
                neighbours[b as usize][eb] = a;
            }
        }
        Self {
            neighbours,
            stamp: vec![u32::MAX; triangles.len()],
            slot: vec![0; triangles.len()],
            visits: 0,
            every_edge_twice,
        }
    }

    /// The piece (0, 1, …) of each triangle of a node whose triangles have
    /// the mesh indices `ids`, and the number of pieces.
    fn pieces(&mut self, ids: &[u32]) -> (Vec<u32>, u32) {
        self.visits = self.visits.wrapping_add(1);
        let stamp = self.visits;
        for (s, &id) in ids.iter().enumerate() {
            self.stamp[id as usize] = stamp;
            self.slot[id as usize] = s as u32;
        }
        let mut piece = vec![NONE; ids.len()];
        let mut count = 0;
        let mut stack = Vec::new();
        for start in 0..ids.len() {
            if piece[start] != NONE {
                continue;
            }
            piece[start] = count;
            stack.push(start);
            while let Some(s) = stack.pop() {
                for &nb in &self.neighbours[ids[s] as usize] {
                    if nb == NONE || self.stamp[nb as usize] != stamp {
                        continue;
                    }
                    let t = self.slot[nb as usize] as usize;
                    if piece[t] == NONE {
                        piece[t] = count;
                        stack.push(t);
                    }
                }
            }
            count += 1;
        }
        (piece, count)
    }
}

/// Reorders a node's triangles `tris` (at least two; `ids` their mesh
/// indices, reordered alike) into a left and a right part, both non-empty,
/// and returns the size of the left part. `obb` is the node's box. See the
/// module doc for the rules.
pub(super) fn split(
    tris: &mut [[Vec3; 3]],
    ids: &mut [u32],
    obb: &Obb,
    topo: &mut Topology,
) -> usize {
    let order =
        split_between_pieces(tris, ids, obb, topo).unwrap_or_else(|| split_at_mean(tris, obb));
    let (left, order) = order;
    let t: Vec<[Vec3; 3]> = order.iter().map(|&i| tris[i as usize]).collect();
    let d: Vec<u32> = order.iter().map(|&i| ids[i as usize]).collect();
    tris.copy_from_slice(&t);
    ids.copy_from_slice(&d);
    left
}

fn centroid(t: &[Vec3; 3]) -> Vec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

/// Rule 1: the best cut between pieces, as (left size, new order), or
/// `None` when fewer than two pieces hold [`PIECE_SHARE`] each.
fn split_between_pieces(
    tris: &[[Vec3; 3]],
    ids: &[u32],
    obb: &Obb,
    topo: &mut Topology,
) -> Option<(usize, Vec<u32>)> {
    let n = tris.len();
    let (piece, count) = topo.pieces(ids);
    let mut sizes = vec![0usize; count as usize];
    for &p in &piece {
        sizes[p as usize] += 1;
    }
    let least = PIECE_SHARE * n as f32;
    if sizes.iter().filter(|&&s| s as f32 >= least).count() < 2 {
        return None;
    }
    // Each triangle's box in the node's frame.
    let bounds: Vec<(Vec3, Vec3)> = tris
        .iter()
        .map(|t| {
            let q = t.map(|c| obb.to_box(c));
            (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]))
        })
        .collect();
    let cost = |(lo, hi): (Vec3, Vec3)| {
        let h = (hi - lo).max(Vec3::ZERO) * 0.5;
        let volume = 8.0 * h.x * h.y * h.z;
        let surface = 8.0 * (h.x * h.y + h.y * h.z + h.z * h.x);
        volume + SEGMENT_LENGTH_M * surface / 4.0
    };
    let union = |a: (Vec3, Vec3), b: (Vec3, Vec3)| (a.0.min(b.0), a.1.max(b.1));
    let empty = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut best: Option<(f32, usize, Vec<u32>)> = None;
    for axis in obb.axes {
        let key: Vec<f32> = tris.iter().map(|t| centroid(t).dot(axis)).collect();
        let mut mean = vec![0.0f64; count as usize];
        for (&p, &k) in piece.iter().zip(&key) {
            mean[p as usize] += f64::from(k);
        }
        for (m, &s) in mean.iter_mut().zip(&sizes) {
            *m /= s as f64;
        }
        // Pieces by mean along the axis, then by number; inside a piece by
        // key, then slot: a total, deterministic order.
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by(|&a, &b| {
            let (pa, pb) = (piece[a as usize] as usize, piece[b as usize] as usize);
            mean[pa]
                .total_cmp(&mean[pb])
                .then(pa.cmp(&pb))
                .then(key[a as usize].total_cmp(&key[b as usize]))
                .then(a.cmp(&b))
        });
        let mut suffix = vec![empty; n + 1];
        for j in (0..n).rev() {
            suffix[j] = union(suffix[j + 1], bounds[order[j] as usize]);
        }
        let mut left = empty;
        for j in 1..n {
            left = union(left, bounds[order[j - 1] as usize]);
            let between = piece[order[j - 1] as usize] != piece[order[j] as usize];
            if !between || (j.min(n - j) as f32) < least {
                continue;
            }
            let c = j as f32 * cost(left) + (n - j) as f32 * cost(suffix[j]);
            if c.is_finite() && best.as_ref().is_none_or(|b| c < b.0) {
                best = Some((c, j, order.clone()));
            }
        }
    }
    best.map(|(_, j, order)| (j, order))
}

/// Rule 2 (Gottschalk et al. 1996): (left size, new order).
fn split_at_mean(tris: &[[Vec3; 3]], obb: &Obb) -> (usize, Vec<u32>) {
    let n = tris.len();
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| obb.half[b].total_cmp(&obb.half[a]));
    for &k in &axes {
        let axis = obb.axes[k];
        let key: Vec<f32> = tris.iter().map(|t| centroid(t).dot(axis)).collect();
        let mean = key.iter().sum::<f32>() / n as f32;
        let (left, right): (Vec<u32>, Vec<u32>) =
            (0..n as u32).partition(|&i| key[i as usize] < mean);
        if !left.is_empty() && !right.is_empty() {
            let l = left.len();
            return (l, left.into_iter().chain(right).collect());
        }
    }
    // All centroids project to the same value on every axis: median split.
    let axis = obb.axes[axes[0]];
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_by(|&a, &b| {
        centroid(&tris[a as usize])
            .dot(axis)
            .total_cmp(&centroid(&tris[b as usize]).dot(axis))
            .then(a.cmp(&b))
    });
    (n / 2, order)
}
