//! A voxel classification of a closed mesh's root box, built once with the
//! tree (the paper's off-line stage), that answers most inside queries of the
//! narrow phase without casting a ray (ours).
//!
//! The root box is cut into `n³` voxels. A voxel that a triangle may meet
//! (its plane and bounding box, grown a little for rounding) is *boundary*;
//! every other voxel meets no triangle, and neither does a connected region
//! of them, so each region lies wholly inside or wholly outside the mesh:
//! the ray-parity test at a few of its voxels' centres decides it for all
//! its points. Queries in boundary voxels fall back to the exact ray cast,
//! so answers are exactly those of the ray-parity test.

use glam::{UVec3, Vec3};
use rayon::prelude::*;

use crate::obb::{Obb, ObbTree};

/// Voxels per side. 64³ ≈ 262 k voxels (two bits each): a 2 m sphere gets
/// 3 cm voxels, a third of a blade segment, so most blade vertices near an
/// object but a few centimetres out of it are answered here; classified
/// in a few milliseconds per mesh (one labelling pass, a few rays).
pub const GRID_SIDE: u32 = 64;

/// Voxel centres of one region whose ray-parity tests vote on the region
/// ([`InsideGrid::build`]): one ray that grazes an edge cannot turn a
/// region.
pub const SAMPLES_PER_REGION: usize = 9;

/// How far (in voxels) a triangle's box is grown before marking voxels: far
/// above the float error of the transform (~1e-6 voxel), so a triangle never
/// touches a voxel that is not marked boundary.
const ROUNDING_MARGIN: f32 = 0.01;

const OUTSIDE: u8 = 0;
const INSIDE: u8 = 1;
const BOUNDARY: u8 = 2;

/// A boundary voxel's label ([`labels`]).
const BOUNDARY_LABEL: u32 = u32::MAX;

/// Inside/outside/boundary per voxel of the root box.
#[derive(Clone, Debug, PartialEq)]
pub struct InsideGrid {
    /// The root box the grid covers (object-local frame).
    pub obb: Obb,
    /// Voxels per side.
    pub side: u32,
    /// Voxel classes, two bits each, 16 to a word (voxel `i` in bits
    /// `2 (i % 16)` of word `i / 16`; x fastest, then y, then z: box axes
    /// u, v, w): 64 KiB a mesh, so that the lookups of many meshes stay
    /// in the caches (and the GPU takes the words as they are).
    pub words: Vec<u32>,
    /// Voxels per metre along each box axis, `side / (2 half)`: a
    /// product instead of a division on every lookup.
    per_metre: Vec3,
}

impl InsideGrid {
    /// Classifies the voxels of `tree`'s root box with `inside_by_ray` (the
    /// exact test). `None` for an open or empty mesh.
    ///
    /// A voxel is boundary when a triangle's plane passes through it
    /// (grown a little for rounding) within the triangle's bounding box.
    /// The other voxels fall into connected regions (voxels sharing a face
    /// — their union meets no triangle either), each wholly inside or wholly
    /// outside the mesh: one labelling pass finds them, and the ray-parity test
    /// at a few of each region's voxel centres (the majority of up to
    /// [`SAMPLES_PER_REGION`]) decides each region — a few rays per mesh
    /// instead of one per voxel.
    #[must_use]
    pub fn build(tree: &ObbTree, inside_by_ray: impl Fn(Vec3) -> bool + Sync) -> Option<Self> {
        let root = tree.nodes.first()?;
        if !tree.closed || tree.triangles.is_empty() || root.obb.half.min_element() <= 0.0 {
            return None;
        }
        let side = GRID_SIDE;
        let mut grid = Self {
            obb: root.obb,
            side,
            words: Vec::new(),
            per_metre: side as f32 / (2.0 * root.obb.half),
        };
        let mut classes = vec![OUTSIDE; (side * side * side) as usize];
        for tri in &tree.triangles {
            mark_boundary(&mut classes, side, tri.map(|p| grid.to_grid(p)));
        }
        let labels = labels(&classes, side);
        let regions = regions(&labels);
        let inside: Vec<bool> = regions
            .par_iter()
            .map(|voxels| {
                let votes = voxels
                    .iter()
                    .filter(|&&i| inside_by_ray(grid.centre(i as usize)))
                    .count();
                votes * 2 > voxels.len()
            })
            .collect();
        for (v, label) in classes.iter_mut().zip(labels) {
            if label != BOUNDARY_LABEL && inside[label as usize] {
                *v = INSIDE;
            }
        }
        grid.words = classes
            .chunks(16)
            .map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0, |w, (j, &v)| w | (u32::from(v) << (2 * j)))
            })
            .collect();
        Some(grid)
    }

    /// How many voxels the grid has (`side³`).
    #[must_use]
    pub fn voxel_count(&self) -> usize {
        (self.side as usize).pow(3)
    }

    /// The class of voxel `i` (0 outside, 1 inside, 2 boundary; 2 past
    /// the grid).
    #[must_use]
    pub fn voxel(&self, i: usize) -> u8 {
        self.words
            .get(i / 16)
            .map_or(BOUNDARY, |w| ((w >> (2 * (i % 16))) & 3) as u8)
    }

    /// `Some(inside)` when `p` (object-local) is in a voxel that meets no
    /// triangle, or outside the root box (`Some(false)`); `None` when the
    /// exact test must decide.
    #[must_use]
    pub fn classify(&self, p: Vec3) -> Option<bool> {
        let g = self.to_grid(p);
        if !g.is_finite() {
            return None;
        }
        let n = self.side as f32;
        if g.cmplt(Vec3::ZERO).any() || g.cmpge(Vec3::splat(n)).any() {
            return Some(false);
        }
        match self.voxel(index(self.side, g.as_uvec3())) {
            INSIDE => Some(true),
            OUTSIDE => Some(false),
            _ => None,
        }
    }

    /// Continuous grid coordinates of `p`: 0 at the box's lower corner, `side` at its upper.
    fn to_grid(&self, p: Vec3) -> Vec3 {
        (self.obb.to_box(p) + self.obb.half) * self.per_metre
    }

    /// Object-local centre of voxel `i`.
    fn centre(&self, i: usize) -> Vec3 {
        let s = self.side as usize;
        let v = Vec3::new((i % s) as f32, ((i / s) % s) as f32, (i / (s * s)) as f32) + 0.5;
        let q = v / self.side as f32 * (2.0 * self.obb.half) - self.obb.half;
        self.obb.center + self.obb.axes[0] * q.x + self.obb.axes[1] * q.y + self.obb.axes[2] * q.z
    }
}

/// Index of voxel `v` in a grid of `side³` (x fastest, then y, then z).
fn index(side: u32, v: UVec3) -> usize {
    ((v.z * side + v.y) * side + v.x) as usize
}

/// Marks boundary (in `classes`, a grid of `side³`) the voxels that the
/// triangle with grid coordinates `q` may meet: those of its bounding box that its plane passes
/// through, both grown by [`ROUNDING_MARGIN`] (a degenerate triangle
/// marks its whole box).
fn mark_boundary(classes: &mut [u8], side: u32, q: [Vec3; 3]) {
    let lo = (q[0].min(q[1]).min(q[2]) - ROUNDING_MARGIN).floor();
    let hi = (q[0].max(q[1]).max(q[2]) + ROUNDING_MARGIN).floor();
    if !(lo.is_finite() && hi.is_finite()) {
        return;
    }
    let clamp = |v: Vec3| {
        v.clamp(Vec3::ZERO, Vec3::splat((side - 1) as f32))
            .as_uvec3()
    };
    let (lo, hi) = (clamp(lo), clamp(hi));
    let n = (q[1] - q[0]).cross(q[2] - q[0]);
    // Half the voxel's extent across the plane, grown by the margin.
    let reach = n.abs().element_sum() * (0.5 + ROUNDING_MARGIN);
    for z in lo.z..=hi.z {
        for y in lo.y..=hi.y {
            for x in lo.x..=hi.x {
                let v = UVec3::new(x, y, z);
                let centre = v.as_vec3() + 0.5;
                if n.dot(centre - q[0]).abs() <= reach {
                    classes[index(side, v)] = BOUNDARY;
                }
            }
        }
    }
}

/// Per voxel of `classes` (a grid of `side³`), the region it belongs to
/// ([`BOUNDARY_LABEL`] for a boundary voxel): voxels sharing a face
/// joined, regions numbered in the order of their first voxel (x fastest,
/// then y, then z).
fn labels(classes: &[u8], side: u32) -> Vec<u32> {
    let s = side as usize;
    // One pass in scan order joining each free voxel to its free
    // neighbours at -x, -y and -z (union–find, each set kept by the root
    // with the lowest index), then each set numbered in the order of its
    // first voxel.
    let mut parent: Vec<u32> = (0..classes.len() as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    let mut i = 0;
    for z in 0..s {
        for y in 0..s {
            for x in 0..s {
                if classes[i] != BOUNDARY {
                    let before = [
                        (x > 0).then(|| i - 1),
                        (y > 0).then(|| i - s),
                        (z > 0).then(|| i - s * s),
                    ];
                    // The root of voxel i's set so far (itself at first).
                    let mut r = i as u32;
                    for j in before.into_iter().flatten() {
                        if classes[j] != BOUNDARY {
                            let rj = root(&mut parent, j as u32);
                            if rj != r {
                                let (lo, hi) = (r.min(rj), r.max(rj));
                                parent[hi as usize] = lo;
                                r = lo;
                            }
                        }
                    }
                }
                i += 1;
            }
        }
    }
    let mut labels = vec![BOUNDARY_LABEL; classes.len()];
    let mut next = 0;
    for i in 0..classes.len() {
        if classes[i] == BOUNDARY {
            continue;
        }
        let r = root(&mut parent, i as u32) as usize;
        // A root has the set's lowest index: it is labelled first.
        if r == i {
            labels[i] = next;
            next += 1;
        } else {
            labels[i] = labels[r];
        }
    }
    labels
}

/// The connected regions of non-boundary voxels given their `labels`
/// ([`labels`]), each as up to [`SAMPLES_PER_REGION`] of its
/// voxels spread over it, in label order.
fn regions(labels: &[u32]) -> Vec<Vec<u32>> {
    let mut members: Vec<Vec<u32>> = Vec::new();
    for (i, &label) in labels.iter().enumerate() {
        if label == BOUNDARY_LABEL {
            continue;
        }
        if label as usize == members.len() {
            members.push(Vec::new());
        }
        members[label as usize].push(i as u32);
    }
    members
        .into_iter()
        .map(|m| {
            let step = m.len().div_ceil(SAMPLES_PER_REGION).max(1);
            m.into_iter().step_by(step).collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::exact::{point_inside, point_inside_by_ray};
    use crate::object::shapes::{cuboid, knot, sphere};
    use crate::test_rng::XorShift;

    #[test]
    fn grid_answers_equal_the_ray_test_and_cover_most_of_the_box() {
        for (name, mesh) in [
            ("sphere", sphere(1.0, 3)),
            ("knot", knot(2.4)),
            ("box", cuboid(Vec3::new(0.5, 0.2, 0.9))),
        ] {
            let tree = ObbTree::build(&mesh, 32);
            let grid = tree.inside.as_ref().expect("closed mesh has a grid");
            let root = tree.nodes[0].obb;
            let (mut answered, mut inside, total) = (0, 0, 20_000);
            let mut rng = XorShift(0x2545_F491_4F6C_DD1Du64);
            let mut next = || rng.range(-1.1, 1.1);
            for _ in 0..total {
                let q = Vec3::new(next(), next(), next()) * root.half;
                let p = root.center + root.axes[0] * q.x + root.axes[1] * q.y + root.axes[2] * q.z;
                let exact = point_inside_by_ray(&tree, p);
                assert_eq!(point_inside(&tree, p), exact, "{name}: {p}");
                if let Some(v) = grid.classify(p) {
                    assert_eq!(v, exact, "{name}: grid wrong at {p}");
                    answered += 1;
                }
                inside += usize::from(exact);
            }
            assert!(inside > 100, "{name}: samples must reach the inside");
            println!("{name}: grid answered {answered} of {total}");
            assert!(
                answered * 2 > total,
                "{name}: grid answered only {answered} of {total}"
            );
        }
    }

    /// Every voxel the regions classified gets the class the ray-parity
    /// test gives at its own centre (what the grid did before regions: one
    /// ray per voxel), on the built-in shapes and the cow; both sides are
    /// reached where the mesh leaves room outside it in its box.
    #[test]
    fn each_classified_voxel_agrees_with_a_ray_at_its_centre() {
        let spot = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meshes/spot.obj");
        let spot = crate::object::load_mesh_file(std::path::Path::new(spot)).expect("spot.obj");
        let (spot, _) = crate::object::sanitize(spot, "spot.obj").expect("valid");
        for (name, mesh) in [
            ("sphere", sphere(1.0, 3)),
            ("knot", knot(2.4)),
            ("box", cuboid(Vec3::new(0.5, 0.2, 0.9))),
            ("spot", spot),
        ] {
            let tree = ObbTree::build(&mesh, 32);
            let grid = tree.inside.as_ref().expect("closed mesh has a grid");
            let (mut inside, mut outside, mut boundary) = (0, 0, 0);
            // Every 7th voxel: all of them take a few seconds in debug.
            for i in (0..grid.voxel_count()).step_by(7) {
                let c = grid.centre(i);
                match grid.voxel(i) {
                    BOUNDARY => boundary += 1,
                    class => {
                        assert_eq!(
                            class == INSIDE,
                            point_inside_by_ray(&tree, c),
                            "{name}: voxel {i} at {c}"
                        );
                        if class == INSIDE {
                            inside += 1;
                        } else {
                            outside += 1;
                        }
                    }
                }
            }
            println!("{name}: {inside} inside, {outside} outside, {boundary} boundary");
            // The box fills its root box: nothing of it is outside.
            let outside_ok = outside > 100 || name == "box";
            assert!(inside > 100 && outside_ok && boundary > 100, "{name}");
        }
    }

    /// A voxel that a triangle crosses is boundary: points sampled on every
    /// triangle fall in boundary voxels (so no region holds a piece of the
    /// surface).
    #[test]
    fn the_surface_lies_in_boundary_voxels() {
        let mut rng = XorShift(0x1234_5678_9abc_def1u64);
        for mesh in [sphere(1.0, 3), knot(2.4), cuboid(Vec3::new(0.5, 0.2, 0.9))] {
            let tree = ObbTree::build(&mesh, 32);
            let grid = tree.inside.as_ref().expect("closed mesh has a grid");
            for t in &tree.triangles {
                for _ in 0..4 {
                    let (a, b) = (rng.unit(), rng.unit());
                    let (a, b) = if a + b > 1.0 {
                        (1.0 - a, 1.0 - b)
                    } else {
                        (a, b)
                    };
                    let p = t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b;
                    assert_eq!(grid.classify(p), None, "{p} on a triangle");
                }
            }
        }
    }

    #[test]
    fn open_meshes_have_no_grid() {
        let mut mesh = cuboid(Vec3::ONE);
        mesh.indices.pop();
        assert!(ObbTree::build(&mesh, 8).inside.is_none());
    }
}
