//! A grid of an open mesh's winding number, built once with its tree
//! (ours, DESIGN §5 "Contact"): what most winding-number queries of the
//! contact response read instead of summing down the tree.
//!
//! The tree sum ([`super::winding::winding_number`]) costs about 5 µs a
//! query on the beetle car, and most queries come from far off its surface:
//! the grass under a parked car's floor opening is pushed down to where the
//! winding number falls to the ramp's foot, tens of centimetres from any
//! triangle, and asked again every step (three quarters of the parked
//! beetle's queries were more than 8 cm from its surface; BENCHMARKS.md,
//! "Session 38"). Off the surface the winding number is smooth (harmonic),
//! so a trilinear interpolation of its values at the corners of voxels
//! follows it closely there.
//!
//! The root box is cut into about cubic voxels, at most
//! [`WINDING_GRID_VOXELS`] to a side and about [`WINDING_GRID_MAX_VOXELS`]
//! in all. Each corner keeps the tree sum `w` at it and a *trust*
//! `t`: 0 within [`TRUST_FROM`] voxel diagonals of the surface, 1 from
//! [`TRUST_TO`] on, linear in the corner's distance between. A point's
//! winding number ([`winding_at`]) is
//!
//! `t(p) · w_grid(p) + (1 − t(p)) · w_tree(p)`,
//!
//! `w_grid` and `t` the trilinear interpolations of the corners' values:
//! the tree is summed only where `t < 1`, near the surface. Continuous in
//! `p`: both interpolations are continuous across voxel faces (neighbours
//! share corners) and so is the tree sum. A voxel with any trusted corner
//! lies wholly within `TRUST_FROM` diagonals of that corner, so no triangle
//! crosses it and its eight corners are on the same side of every sheet:
//! the interpolation never mixes values from both sides of the surface.
//!
//! A refitted tree (a deforming mesh) drops the grid: rebuilding it sums
//! the tree at every corner (a fraction of a second), so a deforming
//! mesh's queries sum the tree.

use glam::{UVec3, Vec3};
use rayon::prelude::*;

use super::closest_point::closest_point_within_sq;
use super::winding::winding_number;
use crate::obb::{Obb, ObbTree};

/// Most voxels along a side of the root box.
pub const WINDING_GRID_VOXELS: u32 = 128;

/// Most voxels in all, about: 2¹⁸ (a 64³ grid's), so that a grid takes at
/// most about 2.3 MiB (the beetle car's builds in 0.72 s on two cores). The voxels are about cubic,
/// [`WINDING_GRID_VOXELS`] along the longest side unless that would pass
/// this count.
pub const WINDING_GRID_MAX_VOXELS: f32 = 262_144.0;

/// A corner nearer the surface than this many voxel diagonals is not
/// trusted at all (its voxels may meet a triangle).
pub const TRUST_FROM: f32 = 1.0;

/// A corner this many voxel diagonals or more from the surface is fully
/// trusted. A quarter of a diagonal past [`TRUST_FROM`]: with 2 the moving
/// winding beetle (`scenes/car.toml` on the winding rule) summed the tree
/// for 38 % more queries and stepped 17 % slower, and the blend strays from
/// the tree sum by 0.0026 on the tests' bowl instead of 0.0013, far inside
/// the tree sum's own 0.05 (BENCHMARKS.md, "Session 39"). The blend's
/// slope, 4 / diagonal times the grid's 0.003 at most, stays continuous.
pub const TRUST_TO: f32 = 1.25;

/// Trilinear winding numbers over an open mesh's root box (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct WindingGrid {
    /// The root box the grid covers (object-local frame).
    pub obb: Obb,
    /// Voxels along each box axis (u, v, w).
    pub voxels: UVec3,
    /// Per corner, the tree sum there and the corner's trust: x fastest,
    /// then y, then z, `voxels + 1` corners along each axis.
    pub corners: Vec<[f32; 2]>,
}

impl WindingGrid {
    /// The grid of `tree`'s winding number. `None` for a tree that does not
    /// wind ([`ObbTree::winds`]) or whose root box is flat (a flat mesh has
    /// no winding inside: [`super::winding::root_fade`] is 0 throughout).
    #[must_use]
    pub fn build(tree: &ObbTree) -> Option<Self> {
        let root = tree.nodes.first()?;
        let half = root.obb.half;
        if !tree.winds() {
            return None;
        }
        let voxels = grid_voxels(half)?;
        let diagonal = (2.0 * half / voxels.as_vec3()).length();
        let n = voxels + UVec3::ONE;
        let obb = root.obb;
        let corners = (0..n.x * n.y * n.z)
            .into_par_iter()
            .map(|k| {
                let g = UVec3::new(k % n.x, (k / n.x) % n.y, k / (n.x * n.y));
                let p = corner_point(&obb, voxels, g);
                let w = winding_number(tree, p);
                let d = closest_point_within_sq(tree, p, f32::INFINITY)
                    .map_or(f32::INFINITY, |s| s.distance_sq.sqrt());
                let t = ((d / diagonal - TRUST_FROM) / (TRUST_TO - TRUST_FROM)).clamp(0.0, 1.0);
                [w, if t.is_nan() { 0.0 } else { t }]
            })
            .collect();
        Some(Self {
            obb,
            voxels,
            corners,
        })
    }

    /// The interpolated winding number and trust at `p` (object frame):
    /// `None` outside the box or for a non-finite `p`.
    #[must_use]
    pub fn sample(&self, p: Vec3) -> Option<(f32, f32)> {
        let h = self.obb.half;
        let n = self.voxels.as_vec3();
        let g = (self.obb.to_box(p) + h) / (2.0 * h) * n;
        if !(g.cmpge(Vec3::ZERO).all() && g.cmple(n).all()) {
            return None;
        }
        let i = g.floor().min(n - 1.0);
        let f = g - i;
        let i = i.as_uvec3();
        let (sx, sy) = (self.voxels.x + 1, (self.voxels.x + 1) * (self.voxels.y + 1));
        let at = |x: u32, y: u32, z: u32| {
            self.corners
                .get(((i.z + z) * sy + (i.y + y) * sx + i.x + x) as usize)
                .copied()
                .unwrap_or([0.0, 0.0])
        };
        let mut out = [0.0f32; 2];
        for (k, o) in out.iter_mut().enumerate() {
            let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
            let x00 = lerp(at(0, 0, 0)[k], at(1, 0, 0)[k], f.x);
            let x10 = lerp(at(0, 1, 0)[k], at(1, 1, 0)[k], f.x);
            let x01 = lerp(at(0, 0, 1)[k], at(1, 0, 1)[k], f.x);
            let x11 = lerp(at(0, 1, 1)[k], at(1, 1, 1)[k], f.x);
            *o = lerp(lerp(x00, x10, f.y), lerp(x01, x11, f.y), f.z);
        }
        Some((out[0], out[1]))
    }
}

/// The voxels along each axis of the grid over a root box of half extents
/// `half` (about cubic, at most [`WINDING_GRID_VOXELS`] to a side and
/// about [`WINDING_GRID_MAX_VOXELS`] in all); `None` for a flat or
/// non-finite box (no grid).
#[must_use]
pub fn grid_voxels(half: Vec3) -> Option<UVec3> {
    if !half.is_finite() || half.min_element() <= 0.0 {
        return None;
    }
    let size = ((2.0 * half.max_element()) / WINDING_GRID_VOXELS as f32)
        .max((8.0 * half.x * half.y * half.z / WINDING_GRID_MAX_VOXELS).cbrt());
    Some(
        (2.0 * half / size)
            .ceil()
            .as_uvec3()
            .clamp(UVec3::ONE, UVec3::splat(WINDING_GRID_VOXELS)),
    )
}

/// Corner `g` of a grid of `voxels` over `obb` (object frame).
fn corner_point(obb: &Obb, voxels: UVec3, g: UVec3) -> Vec3 {
    let q = (g.as_vec3() / voxels.as_vec3() * 2.0 - 1.0) * obb.half;
    obb.center + obb.axes[0] * q.x + obb.axes[1] * q.y + obb.axes[2] * q.z
}

/// The winding number of `tree`'s mesh at `p` (object frame) as the contact
/// response takes it: from the tree's [`WindingGrid`] where its trust is
/// whole, blended with the tree sum ([`winding_number`]) by the trust where
/// it is partial, the tree sum alone where it is 0 or where there is no
/// grid (module docs).
#[must_use]
pub fn winding_at(tree: &ObbTree, p: Vec3) -> f32 {
    if let Some((w, t)) = tree.winding_grid.as_ref().and_then(|g| g.sample(p)) {
        if t >= 1.0 {
            return w;
        }
        if t > 0.0 {
            return t * w + (1.0 - t) * winding_number(tree, p);
        }
    }
    winding_number(tree, p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::winding::test_support::{bowl, exact_sum};
    use crate::test_rng::XorShift;

    fn in_box(tree: &ObbTree, rng: &mut XorShift) -> Vec3 {
        let o = tree.nodes[0].obb;
        let q = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ) * o.half;
        o.center + o.axes[0] * q.x + o.axes[1] * q.y + o.axes[2] * q.z
    }

    /// Within the tree sum's own tolerance of the exact sum (0.05), over the
    /// bowl's box, and the grid alone answers most points away from it.
    #[test]
    fn the_grid_follows_the_exact_sum_and_answers_far_points() {
        let tree = bowl(0.3);
        let grid = tree
            .winding_grid
            .as_ref()
            .expect("a winding tree has a grid");
        let mut rng = XorShift(0x3c6e_f372_fe94_f82b);
        let (mut worst, mut whole) = (0.0f32, 0);
        for _ in 0..3000 {
            let p = in_box(&tree, &mut rng);
            let (a, b) = (winding_at(&tree, p), exact_sum(&tree, p));
            worst = worst.max((a - b).abs());
            if grid.sample(p).is_some_and(|(_, t)| t >= 1.0) {
                whole += 1;
            }
        }
        assert!(worst < 0.05, "grid and tree {worst} from the exact sum");
        assert!(whole > 600, "{whole} of 3000 answered by the grid alone");
    }

    /// Continuous: points a few ulp apart get values a few ulp apart,
    /// across voxel faces and where the trust is partial.
    #[test]
    fn the_blend_is_continuous_in_the_point() {
        let tree = bowl(0.3);
        let mut rng = XorShift(0x7137_449e_5b9c_3a1f);
        for _ in 0..3000 {
            let p = in_box(&tree, &mut rng) * 0.999;
            let q = p + Vec3::new(1e-6, -1e-6, 1e-6);
            let (a, b) = (winding_at(&tree, p), winding_at(&tree, q));
            assert!((a - b).abs() < 1e-3, "{p}: {a} vs {b}");
        }
        // Across a voxel face exactly: the corner values are shared.
        let g = tree.winding_grid.as_ref().unwrap();
        let p = corner_point(&g.obb, g.voxels, g.voxels / 2) + Vec3::splat(1e-3);
        for axis in 0..3 {
            let step = g.obb.axes[axis] * 1e-6;
            let (a, b) = (winding_at(&tree, p - step), winding_at(&tree, p + step));
            assert!((a - b).abs() < 1e-3, "axis {axis}: {a} vs {b}");
        }
    }

    /// No trusted corner has the surface within its voxels: every corner
    /// with trust above 0 is more than a voxel diagonal from every triangle.
    #[test]
    fn trusted_corners_are_a_diagonal_off_the_surface() {
        let tree = bowl(0.3);
        let g = tree.winding_grid.as_ref().unwrap();
        let diagonal = (2.0 * g.obb.half / g.voxels.as_vec3()).length();
        let n = g.voxels + UVec3::ONE;
        let mut trusted = 0;
        for (k, c) in g.corners.iter().enumerate() {
            if c[1] <= 0.0 {
                continue;
            }
            trusted += 1;
            let k = k as u32;
            let p = corner_point(
                &g.obb,
                g.voxels,
                UVec3::new(k % n.x, (k / n.x) % n.y, k / (n.x * n.y)),
            );
            let d = tree
                .triangles
                .iter()
                .map(|t| {
                    crate::collision::closest_point::closest_point_on_triangle_region(p, t)
                        .0
                        .distance(p)
                })
                .fold(f32::INFINITY, f32::min);
            assert!(d > diagonal * TRUST_FROM, "corner {k} trusted at {d}");
        }
        assert!(trusted > 0);
    }

    /// A refitted (deforming) tree drops its grid; a closed or sheet-rule
    /// tree has none.
    #[test]
    fn only_a_winding_tree_has_a_grid() {
        let closed = ObbTree::build(&crate::object::shapes::sphere(1.0, 2), 12);
        assert!(closed.winding_grid.is_none());
        let tree = bowl(0.3);
        assert!(tree.winding_grid.is_some());
        assert!(WindingGrid::build(&closed).is_none());
    }
}
