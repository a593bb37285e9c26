//! Refitting an OBB tree to a deformed mesh (ours, DESIGN §3 "Deforming
//! meshes"): same triangles, new vertex positions (skinning, morphs, a
//! host's animated mesh); the tree keeps its topology and only its boxes and
//! equivalent normals (Eq. 3) are recomputed, bottom-up, never rebuilt.
//!
//! Bottom-up as in G. van den Bergen, *Efficient collision detection of
//! complex deformable models using AABB trees* (JGT 1997), with oriented
//! boxes: level by level from the deepest (children before parents), the
//! nodes of a level in parallel (rayon; each writes only itself, so the
//! result does not depend on the thread count). Every box is
//! fitted to the exact extents of its own triangles' corners (plus the fit's
//! padding), so every triangle lies in its node's box and every ancestor's
//! ([`ObbTree::validate`]) and no segment crossing a triangle is missed.
//!
//! How the orientations follow the deformation is [`AxisRule`]:
//! - [`AxisRule::Fixed`] (the default) keeps the internal nodes' build axes
//!   and recomputes centres and extents; leaves take the best of their old
//!   axes, their triangle's own frame and the world axes. At the bind pose
//!   it gives the built boxes back; where a limb turns, boxes along the old
//!   axes grow.
//! - [`AxisRule::Fit`] fits every node again as the build does
//!   ([`fit_obb_searched`]: covariance axes, world axes, and the orientation
//!   search where the build searches, [`searched_at`]): boxes as tight as a
//!   rebuilt tree's, with the old topology, at the cost of the fits.
//!
//! Whether a parent must also contain its children's boxes is [`Nesting`].
//! Measured (`tests/obb_refit.rs`, BENCHMARKS.md), `Contain` compounds: a
//! box that holds the corners of its children's boxes, turned against it,
//! is larger than their triangles need, its parent larger again, and on a
//! 1,280-triangle sphere at its bind pose the root's surface came out 18×
//! the built root's (3.9× at depth 7), 97 % false positives at depth 7
//! against 24 % for `Tight`. `Tight` is the default.
//!
//! Eq. 3 is kept as two sums per node, `Σ S·N` and `Σ S` (f64): a leaf's
//! from its triangles, a parent's as the sum of its children's; `eqn` is
//! their ratio ([`super::build::equivalent_normal`]'s own sums).
//!
//! The inside grid ([`crate::collision::inside_grid::InsideGrid`]) of a
//! closed mesh is dropped by a refit (see [`ObbTree::refit`] for why):
//! [`crate::collision::point_inside`] then answers every query with the
//! exact ray-parity test through the refitted tree. Same answers.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::build::searched_at;
use super::build::{equivalent_normal_from_sums, equivalent_normal_sums};
use super::fit::{fit_obb_searched, padding};
use super::node::{Obb, ObbTree};
use super::pseudo_normals::NormalScratch;
use super::slabs::NodeSlabs;
use crate::object::TriMesh;

/// How node orientations follow a deformation; see the module documentation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AxisRule {
    /// Internal nodes keep the axes they were built with (centres and
    /// extents are recomputed exactly); leaves take the smallest of the
    /// boxes along their old axes, their first triangle's own frame and the
    /// world axes (a few triangles: cheap). At the bind pose this gives the
    /// built tree back, box for box.
    #[default]
    Fixed,
    /// Every node is fitted again as the build fits it
    /// ([`super::fit::fit_obb_searched`] with the build's search rule,
    /// [`super::build::searched_at`]): the boxes a build would give these
    /// triangles, for about the cost of a build's fitting (no sorting).
    Fit,
}

/// Whether a parent's box must contain its children's boxes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Nesting {
    /// Every box is fitted to its own triangles (as [`ObbTree::build`]
    /// fits them): tight; a child's box may stick out of its parent's.
    #[default]
    Tight,
    /// Every box also contains its children's boxes, so a segment that
    /// meets a child's box meets its parent's. Boxes of boxes turned
    /// against one another compound level by level: see BENCHMARKS.md.
    Contain,
}

/// Why a refit was refused. The tree is left as it was.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RefitError {
    /// A tree triangle uses a vertex the given positions do not have.
    #[error(
        "refit: triangle {triangle} uses vertex {vertex} but {count} positions were given; allowed: the mesh's vertex count"
    )]
    VertexOutOfRange {
        /// Tree triangle (index into [`ObbTree::triangles`]).
        triangle: usize,
        /// The vertex index it uses.
        vertex: u32,
        /// How many positions were given.
        count: usize,
    },
    /// A position used by the tree is NaN or infinite.
    #[error("refit: vertex {vertex} is not finite ({position}); allowed: finite coordinates")]
    NonFiniteVertex {
        /// The vertex index.
        vertex: u32,
        /// Its position.
        position: Vec3,
    },
    /// The map was made for another tree.
    #[error(
        "refit: the map covers {map} triangles but the tree holds {tree}; make the map from this tree"
    )]
    MapMismatch {
        /// Triangles in the map.
        map: usize,
        /// Triangles in the tree.
        tree: usize,
    },
    /// [`RefitMap::new`]: a tree triangle is not a triangle of the mesh.
    #[error(
        "refit map: tree triangle {triangle} ({corners:?}) is not a triangle of the mesh; allowed: the mesh the tree was built from (same positions, same corner order)"
    )]
    TriangleNotInMesh {
        /// Tree triangle index.
        triangle: usize,
        /// Its corners.
        corners: [Vec3; 3],
    },
}

/// Which mesh vertices make each tree triangle: the link between the tree's
/// reordered triangles ([`ObbTree::triangles`]) and the vertex array a
/// deformation writes. Made once, at bind time.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RefitMap {
    /// Per tree triangle, the mesh vertex index of each corner, in the
    /// tree triangle's corner order.
    pub corners: Vec<[u32; 3]>,
    /// Per node, its distinct vertices: `node_vertices[i]` is a range of
    /// `vertices`. A closed mesh has about half as many vertices as
    /// triangles, so projecting each distinct vertex once instead of three
    /// corners per triangle does a sixth of the work.
    node_vertices: Vec<(u32, u32)>,
    /// The distinct vertices of every node, node after node.
    vertices: Vec<u32>,
    /// Node indices by depth: `levels[d]` holds the nodes of depth `d + 1`.
    levels: Vec<Vec<u32>>,
}

impl RefitMap {
    /// Matches every triangle of `tree` with a triangle of `mesh` that has
    /// the same three corner positions, bit for bit, in the same order
    /// (what [`ObbTree::build`] keeps of a triangle; [`crate::object::sanitize::sanitize`]
    /// keeps positions and corner order too, so `mesh` may be the mesh
    /// before sanitising, whose vertices a skin deforms). Each mesh triangle
    /// is used at most once; mesh triangles the tree does not hold (dropped
    /// as degenerate or duplicate) are ignored. O(triangles).
    ///
    /// # Errors
    /// [`RefitError::TriangleNotInMesh`] for the first tree triangle with no
    /// unused match.
    pub fn new(tree: &ObbTree, mesh: &TriMesh) -> Result<Self, RefitError> {
        let key = |t: [Vec3; 3]| t.map(|p| p.to_array().map(f32::to_bits));
        let mut by_corners: HashMap<[[u32; 3]; 3], Vec<[u32; 3]>> =
            HashMap::with_capacity(mesh.indices.len());
        // Reverse, so that popping gives duplicates back in mesh order.
        for idx in mesh.indices.iter().rev() {
            let corners = idx.map(|i| mesh.positions.get(i as usize).copied());
            if let [Some(a), Some(b), Some(c)] = corners {
                by_corners.entry(key([a, b, c])).or_default().push(*idx);
            }
        }
        let corners: Vec<[u32; 3]> = tree
            .triangles
            .iter()
            .enumerate()
            .map(|(triangle, t)| {
                by_corners.get_mut(&key(*t)).and_then(Vec::pop).ok_or(
                    RefitError::TriangleNotInMesh {
                        triangle,
                        corners: *t,
                    },
                )
            })
            .collect::<Result<_, _>>()?;
        let (node_vertices, vertices) = distinct_vertices(tree, &corners);
        let mut levels: Vec<Vec<u32>> = Vec::new();
        for (i, node) in tree.nodes.iter().enumerate() {
            let d = node.depth.max(1) as usize - 1;
            if levels.len() <= d {
                levels.resize(d + 1, Vec::new());
            }
            levels[d].push(i as u32);
        }
        Ok(Self {
            corners,
            node_vertices,
            vertices,
            levels,
        })
    }
}

impl RefitMap {
    /// The positions of node `i`'s distinct vertices.
    fn node_points<'a>(
        &'a self,
        i: usize,
        positions: &'a [Vec3],
    ) -> impl Iterator<Item = Vec3> + Clone + 'a {
        let (start, len) = self.node_vertices[i];
        self.vertices[start as usize..(start + len) as usize]
            .iter()
            .map(move |&v| positions[v as usize])
    }
}

/// Each node's distinct vertices (in first-use order), as ranges into one
/// array. O(triangles × depth), once.
fn distinct_vertices(tree: &ObbTree, corners: &[[u32; 3]]) -> (Vec<(u32, u32)>, Vec<u32>) {
    let count = corners
        .iter()
        .flatten()
        .max()
        .map_or(0, |&v| v as usize + 1);
    let mut stamp = vec![u32::MAX; count];
    let mut ranges = Vec::with_capacity(tree.nodes.len());
    let mut vertices = Vec::new();
    for (i, node) in tree.nodes.iter().enumerate() {
        let start = vertices.len() as u32;
        let first = node.first_tri as usize;
        let last = (first + node.tri_count as usize).min(corners.len());
        for &v in corners[first.min(last)..last].iter().flatten() {
            if stamp[v as usize] != i as u32 {
                stamp[v as usize] = i as u32;
                vertices.push(v);
            }
        }
        ranges.push((start, vertices.len() as u32 - start));
    }
    (ranges, vertices)
}

/// Scratch memory of [`ObbTree::refit`], reused across frames (no
/// allocation per refit once it has grown to the tree).
#[derive(Clone, Debug, Default)]
pub struct RefitScratch {
    /// Eq. 3's `Σ S·N` and `Σ S` (square metres) per node, f64.
    sums: Vec<(DVec3, f64)>,
    /// One level's new boxes and sums, in the level's node order.
    level: Vec<(Obb, (DVec3, f64), Option<NodeSlabs>)>,
    /// An open mesh's pseudo-normal sums.
    normals: NormalScratch,
}

impl ObbTree {
    /// Refits the tree to new vertex `positions` of the mesh it was built
    /// from (same triangles; `map` from [`RefitMap::new`]), bottom-up: the
    /// triangles are rewritten, each node's box is fitted to its triangles
    /// (and, with [`Nesting::Contain`], to its children's boxes), and every
    /// node's `eqn` (Eq. 3) is recomputed. Orientations follow `rule`.
    /// The boxes are padded as [`super::fit::fit_obb`] pads them, so
    /// [`ObbTree::validate`] holds afterwards; topology, triangle ranges,
    /// depths and `closed` are unchanged; the reach boxes
    /// ([`super::reach`]) are recomputed from the new boxes, and a
    /// [`ObbTree::nested`] tree has its boxes grown again
    /// ([`ObbTree::nest_boxes`]). The tilted boxes ([`super::slabs`]) are
    /// refitted where the tree has them (about as much again as the boxes:
    /// measured on the walker, BENCHMARKS.md "Session 18"); a tree without
    /// them stays without ([`ObbTree::fit_slabs`] fits them).
    ///
    /// The inside grid is dropped (`inside = None`): rebuilding it casts one
    /// ray per empty voxel (≈ 14 k rays, milliseconds: a whole step's
    /// budget; see BENCHMARKS.md), while without it
    /// [`crate::collision::point_inside`] casts one ray per query, and only
    /// segments that meet the root box but no final-depth box ask. The
    /// answers are the same either way (the grid only caches the ray test).
    ///
    /// Cost: every node's distinct vertices are projected once
    /// (O(vertices × depth)), plus, with [`AxisRule::Fit`], a covariance
    /// fit per node; no allocation after the first call with `scratch`.
    /// Measured in `benches/obb_refit.rs` (BENCHMARKS.md).
    ///
    /// # Errors
    /// [`RefitError`] when the map is not this tree's, a corner index is out
    /// of range of `positions` or a used position is not finite; the tree
    /// is then unchanged.
    pub fn refit(
        &mut self,
        map: &RefitMap,
        positions: &[Vec3],
        rule: AxisRule,
        nesting: Nesting,
        scratch: &mut RefitScratch,
    ) -> Result<(), RefitError> {
        if map.corners.len() != self.triangles.len() || map.node_vertices.len() != self.nodes.len()
        {
            return Err(RefitError::MapMismatch {
                map: map.corners.len(),
                tree: self.triangles.len(),
            });
        }
        for (triangle, idx) in map.corners.iter().enumerate() {
            for &vertex in idx {
                let position =
                    *positions
                        .get(vertex as usize)
                        .ok_or(RefitError::VertexOutOfRange {
                            triangle,
                            vertex,
                            count: positions.len(),
                        })?;
                if !position.is_finite() {
                    return Err(RefitError::NonFiniteVertex { vertex, position });
                }
            }
        }
        for (tri, idx) in self.triangles.iter_mut().zip(&map.corners) {
            *tri = idx.map(|i| positions[i as usize]);
        }
        self.inside = None;
        if !self.features.is_empty() {
            // An open mesh's sides at its edges and corners move with it.
            self.features.normals_into(
                &self.triangles,
                &mut self.feature_normals,
                &mut scratch.normals,
            );
        }
        if self.triangles.is_empty() {
            return Ok(());
        }
        let n = self.nodes.len();
        scratch.sums.clear();
        scratch.sums.resize(n, (DVec3::ZERO, 0.0));
        // Level by level from the deepest: a node's children are final
        // before it is refitted; the nodes of one level are independent and
        // refitted in parallel (each writes only itself: the same bits on
        // any thread count).
        // The tilted boxes are refitted where the tree has them (every
        // node is written below, level by level).
        if self.nested || self.slabs.len() != n {
            self.slabs.clear();
        }
        for level in map.levels.iter().rev() {
            let tree = &*self;
            let sums = &scratch.sums;
            let slabs = !tree.slabs.is_empty();
            level
                .par_iter()
                .map(|&i| {
                    let i = i as usize;
                    let node = &tree.nodes[i];
                    let first = node.first_tri as usize;
                    let tris = &tree.triangles[first..first + node.tri_count as usize];
                    let points = map.node_points(i, positions);
                    let search = searched_at(node.depth, tris.len());
                    let (obb, sum) = if node.is_leaf() {
                        let sum = equivalent_normal_sums(tris);
                        (leaf_box(tris, points.clone(), &node.obb, rule, search), sum)
                    } else {
                        let [l, r] = node.children.map(|c| c as usize);
                        let sum = (sums[l].0 + sums[r].0, sums[l].1 + sums[r].1);
                        let children = (&tree.nodes[l].obb, &tree.nodes[r].obb);
                        let obb = parent_box(
                            tris,
                            points.clone(),
                            children,
                            &node.obb,
                            (rule, search),
                            nesting,
                        );
                        (obb, sum)
                    };
                    (obb, sum, slabs.then(|| NodeSlabs::fit(&obb, points)))
                })
                .collect_into_vec(&mut scratch.level);
            for (&i, &(obb, sum, slabs)) in level.iter().zip(&scratch.level) {
                if let Some(s) = slabs {
                    self.slabs[i as usize] = s;
                }
                let node = &mut self.nodes[i as usize];
                node.obb = obb;
                node.eqn = equivalent_normal_from_sums(sum.0, sum.1);
                scratch.sums[i as usize] = sum;
            }
        }
        if !self.dipoles.is_empty() {
            // An open mesh's dipoles (its winding number) move with it.
            self.dipoles = crate::collision::winding::dipoles(self);
            // Its grid would need a tree sum at every corner: dropped.
            self.winding_grid = None;
        }
        if self.nested {
            // A nested tree stays nested (the refitted boxes grown again).
            self.nest_boxes();
        } else {
            self.reach = super::reach::reach_boxes(&self.nodes);
        }
        Ok(())
    }
}

/// The world axes x, y, z.
const WORLD_AXES: [Vec3; 3] = [Vec3::X, Vec3::Y, Vec3::Z];

/// A leaf's new box around `tris`, whose vertices are `points`. `Fixed`:
/// one triangle: the smaller of the boxes in its own frame and along
/// `old`'s axes; several: the smallest of the boxes
/// along `old`'s axes, the first triangle's frame (longest edge, normal)
/// and the world axes. `Fit`: [`fit_obb_searched`] (with the orientation
/// search when `search`: the build's rule, [`searched_at`]).
fn leaf_box(
    tris: &[[Vec3; 3]],
    points: impl Iterator<Item = Vec3> + Clone,
    old: &Obb,
    rule: AxisRule,
    search: bool,
) -> Obb {
    if rule == AxisRule::Fit {
        return fit_obb_searched(tris, search);
    }
    let own = tris.first().and_then(triangle_frame);
    if let (Some(axes), 1) = (own, tris.len()) {
        // One triangle: its own frame gives a box of zero thickness; the
        // build's orientation search may have found a rectangle in the
        // plane a little smaller than the one flush with the longest edge,
        // so the old axes compete (at the bind pose they win back the
        // built box).
        // Compared padded: on a near tie the padding, which grows with the
        // longest extent, decides.
        let surface = |o: &Obb| o.half.x * o.half.y + o.half.y * o.half.z + o.half.z * o.half.x;
        let own = Extents::along(points.clone(), axes).padded();
        let kept = Extents::along(points, old.axes).padded();
        return if surface(&kept) < surface(&own) {
            kept
        } else {
            own
        };
    }
    let mut best = Extents::along(points.clone(), old.axes);
    for axes in own.into_iter().chain([WORLD_AXES]) {
        best = best.smaller(Extents::along(points.clone(), axes));
    }
    best.padded()
}

/// A parent's new box: the exact extents of its vertices `points` (those of
/// its triangles `tris`) along `old`'s axes (`Fixed`) or
/// [`fit_obb_searched`] of `tris` (`Fit`, searched as `rule.1` says); with
/// [`Nesting::Contain`], grown to the corners of its children's boxes
/// `left` and `right` too.
fn parent_box(
    tris: &[[Vec3; 3]],
    points: impl Iterator<Item = Vec3> + Clone,
    (left, right): (&Obb, &Obb),
    old: &Obb,
    (rule, search): (AxisRule, bool),
    nesting: Nesting,
) -> Obb {
    let axes = match (rule, nesting) {
        (AxisRule::Fit, Nesting::Tight) => return fit_obb_searched(tris, search),
        (AxisRule::Fit, Nesting::Contain) => fit_obb_searched(tris, search).axes,
        (AxisRule::Fixed, _) => old.axes,
    };
    match nesting {
        Nesting::Contain => {
            let (lc, rc) = (left.corners(), right.corners());
            Extents::along(lc.into_iter().chain(rc).chain(points), axes).padded()
        }
        Nesting::Tight => Extents::along(points, axes).padded(),
    }
}

/// An orthonormal right-handed frame of a triangle: u along its longest
/// edge, w its normal, v = w × u. `None` for a degenerate triangle.
fn triangle_frame(tri: &[Vec3; 3]) -> Option<[Vec3; 3]> {
    let [a, b, c] = *tri;
    let edges = [b - a, c - b, a - c];
    let longest = edges
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let u = longest.try_normalize()?;
    let w = (b - a).cross(c - a).try_normalize()?;
    let v = w.cross(u).try_normalize()?;
    // Re-derive w so the frame is orthogonal to f32 precision.
    let w = u.cross(v);
    Some([u, v, w])
}

/// A box before padding: axes, centre and exact half extents of a point set.
#[derive(Clone, Copy)]
struct Extents {
    axes: [Vec3; 3],
    center: Vec3,
    half: Vec3,
}

impl Extents {
    /// Exact extents of `points` along orthonormal `axes` (projections
    /// relative to the first point, to keep the numbers small).
    fn along(points: impl Iterator<Item = Vec3> + Clone, axes: [Vec3; 3]) -> Self {
        let origin = points.clone().next().unwrap_or(Vec3::ZERO);
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in points {
            let d = p - origin;
            let q = Vec3::new(d.dot(axes[0]), d.dot(axes[1]), d.dot(axes[2]));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let mid = (lo + hi) * 0.5;
        Self {
            axes,
            center: origin + axes[0] * mid.x + axes[1] * mid.y + axes[2] * mid.z,
            half: (hi - lo) * 0.5,
        }
    }

    /// Surface area over 8 (`hu hv + hv hw + hw hu`), enough to compare.
    fn surface(&self) -> f32 {
        let h = self.half;
        h.x * h.y + h.y * h.z + h.z * h.x
    }

    /// `self`, or `other` when its surface is strictly smaller.
    fn smaller(self, other: Self) -> Self {
        if other.surface() < self.surface() {
            other
        } else {
            self
        }
    }

    /// The box with [`padding`] added to every half extent, as the fit pads.
    fn padded(self) -> Obb {
        let pad = padding(self.half.max_element(), self.center);
        Obb {
            center: self.center,
            axes: self.axes,
            half: self.half + Vec3::splat(pad),
        }
    }
}
