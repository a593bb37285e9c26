//! The generalized winding number of an open mesh (ours, DESIGN §5
//! "Contact"): how much a point is inside a mesh with holes.
//!
//! A closed mesh has an inside (ray parity, `exact.rs`); a mesh with holes
//! — a car body with no floor, open wheel arches, a window left out, the
//! way game meshes are made — has none, and the rule before this one
//! ("behind the closest sheet, within a blade segment of it") left grass
//! standing in the hollow of such a body, which the camera sees through
//! its windows. The generalized winding number (Jacobson, Kavan and
//! Sorkine-Hornung, *Robust inside-outside segmentation using generalized
//! winding numbers*, SIGGRAPH 2013) is
//!
//! `w(p) = Σ_t Ω_t(p) / 4π`,
//!
//! the solid angles `Ω_t` the triangles subtend at `p`, signed by their
//! winding: 1 inside a closed mesh, 0 outside, and in between across a
//! hole (½ in the plane of a flat hole, at its middle), smooth
//! (harmonic) everywhere off the surface. The contact response takes
//! [`inside_factor`]`(w)` of the push a closed mesh would give: 1 where
//! `w ≥` [`WINDING_INSIDE_HI`], 0 where `w ≤` [`WINDING_INSIDE_LO`],
//! linear between — continuous in `p`, since `w` is continuous off the
//! surface and the push is zero on it. The full push starts at ½, not 1:
//! a hole is closed at its plane (½ at its middle) and lets go beyond it,
//! as `w` falls to 0.3. The factor is faded in from the faces of the
//! mesh's root box ([`root_fade`]), where the narrow phase's walk starts;
//! so a flat lone sheet (a flat root box) has no inside by this rule.
//!
//! `w` is summed down the OBB tree (after Barill et al., *Fast winding
//! numbers for soups and clouds*, SIGGRAPH 2018): a node whose triangles'
//! area-weighted centroid `c` lies `r ≥` [`FAR_HI`]` · R` from `p` (`R`
//! the distance from `c` to its farthest corner) counts as a dipole,
//! `A · (c − p) / (4π r³)` with `A` the node's area vector
//! (`Σ ½ (b − a) × (c − a)`; all three kept per node: [`Dipole`]); one
//! nearer than [`FAR_LO`]` · R` is opened (a leaf: its triangles' exact
//! solid angles, Van Oosterom and Strackee 1983); between, both, blended
//! linearly in `r / R`. The blend keeps the sum continuous in `p` (a hard
//! switch between the dipole and the exact sum would jump by the dipole's
//! error); the dipole is within a few per cent of the node's exact sum at
//! `r ≥ 2R`, which moves `w` by far less than the ramp's width.

use glam::Vec3;

use super::exact::STACK_SIZE;
use crate::obb::ObbTree;

/// Below this winding number a point is outside an open mesh
/// ([`inside_factor`] 0).
pub const WINDING_INSIDE_LO: f32 = 0.3;

/// From this winding number on a point is inside an open mesh
/// ([`inside_factor`] 1).
pub const WINDING_INSIDE_HI: f32 = 0.5;

/// A node whose centre is nearer than `FAR_LO` times its half diagonal is
/// opened (its children's, or its triangles', exact sum).
pub const FAR_LO: f32 = 2.0;

/// A node whose centre is at least `FAR_HI` times its half diagonal away
/// counts as its dipole alone.
pub const FAR_HI: f32 = 3.0;

/// A node of at most this many triangles that is opened counts as its
/// triangles' exact solid angles, not as its subtree: the same or a truer
/// sum (exact where the subtree had dipoles), and cheaper than walking
/// the subtree's nodes (the beetle, points within 10 cm of its surface:
/// 7.0 → 5.8 µs a query with 1 → 4; 8 and 16 cost more again:
/// BENCHMARKS.md, "Session 39").
pub const EXACT_TRIANGLES: u32 = 4;

/// `1 / 4π`.
const INV_4PI: f32 = 0.079_577_47;

/// Over how far inside the root box, metres, a winding mesh's inside fades
/// in from 0 at the box's faces ([`root_fade`]): 1 cm.
pub const ROOT_FADE_M: f32 = 0.01;

/// How far inside `tree`'s root box `p` lies, over [`ROOT_FADE_M`],
/// clamped to [0, 1] (0 outside; 0 for NaN): what a winding mesh's inside
/// factor is multiplied by. Above a hole the winding number stays near ½
/// past the mesh's box, where the narrow phase finds no segment (it starts
/// from the root's box): the fade brings the push to 0 before the box's
/// faces, continuously.
#[must_use]
pub fn root_fade(tree: &ObbTree, p: Vec3) -> f32 {
    let Some(root) = tree.nodes.first() else {
        return 0.0;
    };
    let q = root.obb.to_box(p).abs();
    let depth = (root.obb.half - q).min_element();
    let f = depth / ROOT_FADE_M;
    if f.is_nan() { 0.0 } else { f.clamp(0.0, 1.0) }
}

/// How much of a closed mesh's push a point of winding number `w` gets:
/// `clamp((w − LO) / (HI − LO), 0, 1)` with [`WINDING_INSIDE_LO`] and
/// [`WINDING_INSIDE_HI`]; 0 for NaN.
#[must_use]
#[inline]
pub fn inside_factor(w: f32) -> f32 {
    let s = (w - WINDING_INSIDE_LO) / (WINDING_INSIDE_HI - WINDING_INSIDE_LO);
    if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) }
}

/// The signed solid angle, steradians, that triangle `t` subtends at `p`
/// (Van Oosterom and Strackee): `2 atan2(a · (b × c), den)`, with
/// `den = |a||b||c| + (a · b)|c| + (a · c)|b| + (b · c)|a|` and `a, b, c`
/// its corners minus `p`.
/// Positive where `p` lies behind the triangle (against its
/// counter-clockwise normal), so a closed outward mesh sums to 4π inside.
/// Continuous off the triangle (the denominator is positive wherever the
/// numerator vanishes off it); ±2π on it.
#[must_use]
#[inline]
pub fn solid_angle(t: &[Vec3; 3], p: Vec3) -> f32 {
    let (a, b, c) = (t[0] - p, t[1] - p, t[2] - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * atan2(num, den)
}

/// The odd polynomial of [`atan2`] on [0, 1], coefficients of `a`, `a³`,
/// …, `a¹¹`: a classic minimax fit (max error 1.7e-6 rad) scaled by
/// 1.0000021 so that it gives π/4 at 1 within float rounding (max error
/// 3.4e-6 rad), and the two octants meet without a jump.
pub const ATAN_POLY: [f32; 6] = [
    0.999_979_4,
    -0.332_624_17,
    0.193_543_87,
    -0.116_433_11,
    0.052_653_43,
    -0.011_721_225,
];

/// `atan2(y, x)` within 4e-6 rad (the fit and the rounding), the same
/// formula as its WGSL twin (`object.wgsl`'s `atan2_poly`) instead of the
/// platform's: WGSL lets a GPU's `atan2` stray by thousands of ulps, and
/// the winding number sums tens of them. The octant's ratio `min / max` of `|x|`, `|y|` goes
/// through [`ATAN_POLY`], then is reflected: `π/2 − r` where `|y| > |x|`,
/// `π − r` where `x < 0`, negated where `y < 0`. Continuous wherever
/// `atan2` is (the reflections meet within an ulp); the cut is where `y`
/// changes sign with `x < 0` (on the triangle, for [`solid_angle`]).
/// `(0, 0)` gives 0; NaN in, NaN or a finite angle out, never a panic.
#[must_use]
#[inline]
pub fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    let a = if hi > 0.0 { lo / hi } else { 0.0 };
    let s = a * a;
    let [c1, c3, c5, c7, c9, c11] = ATAN_POLY;
    let mut r = a * (c1 + s * (c3 + s * (c5 + s * (c7 + s * (c9 + s * c11)))));
    if ay > ax {
        r = std::f32::consts::FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = std::f32::consts::PI - r;
    }
    if y < 0.0 { -r } else { r }
}

/// The generalized winding number of `tree`'s mesh at `p` (object-local
/// frame), summed down the tree with the blended dipoles of the module
/// docs. Needs the tree's dipoles ([`ObbTree::enable_winding`]; without
/// them every node is opened: the exact sum). 0 for an empty tree
/// or a non-finite `p`. No allocation.
#[must_use]
pub fn winding_number(tree: &ObbTree, p: Vec3) -> f32 {
    if tree.is_empty() || !p.is_finite() {
        return 0.0;
    }
    let mut stack = [(0u32, 0.0f32); STACK_SIZE];
    stack[0] = (0, 1.0);
    let mut len = 1usize;
    let mut sum = 0.0f32;
    while len > 0 {
        len -= 1;
        let (i, weight) = stack[len];
        let Some(node) = tree.nodes.get(i as usize) else {
            continue;
        };
        let dipole = tree.dipoles.get(i as usize);
        let (centre, radius) = dipole.map_or((node.obb.center, node.obb.half_diagonal()), |d| {
            (d.centre, d.radius)
        });
        let to_centre = centre - p;
        let r = to_centre.length();
        // Dipole weight: 0 nearer than FAR_LO · R, 1 from FAR_HI · R.
        let far = match dipole {
            Some(_) if r > 0.0 && r >= FAR_HI * radius => 1.0,
            Some(_) if r > FAR_LO * radius => (r / radius - FAR_LO) / (FAR_HI - FAR_LO),
            _ => 0.0,
        };
        if let Some(d) = dipole.filter(|_| far > 0.0) {
            sum += weight * far * (d.area.dot(to_centre) / (r * r * r)) * INV_4PI;
        }
        let near = weight * (1.0 - far);
        if near <= 0.0 {
            continue;
        }
        let [l, rr] = node.children;
        if node.is_leaf()
            || node.tri_count <= EXACT_TRIANGLES
            || l <= i
            || rr <= i
            || len + 2 > STACK_SIZE
        {
            let first = node.first_tri as usize;
            let tris = tree
                .triangles
                .get(first..first + node.tri_count as usize)
                .unwrap_or(&[]);
            let exact: f32 = tris.iter().map(|t| solid_angle(t, p)).sum();
            sum += near * exact * INV_4PI;
        } else {
            // Left first (popped first).
            stack[len] = (rr, near);
            stack[len + 1] = (l, near);
            len += 2;
        }
    }
    sum
}

/// What stands for a node of an open mesh's tree in [`winding_number`]
/// when the node is far from the point: the first term (the dipole) of the
/// expansion of its triangles' solid angles about `centre`. (A second term,
/// the triangles' second moment, was tried: BENCHMARKS.md, "Session 38".)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dipole {
    /// The node's area vector `A = Σ a_t n_t` (`a_t n_t = ½ (b − a) ×
    /// (c − a)`): the dipole.
    pub area: Vec3,
    /// The area-weighted centroid of its triangles: where the dipole sits.
    pub centre: Vec3,
    /// The distance from `centre` to the farthest of its triangles'
    /// corners (grown by a few ulp): how near the point may come.
    pub radius: f32,
}

/// Per node of `tree`, its [`Dipole`], from its triangles (f64 sums).
#[must_use]
pub fn dipoles(tree: &ObbTree) -> Vec<Dipole> {
    use glam::DVec3;
    tree.nodes
        .iter()
        .map(|node| {
            let first = node.first_tri as usize;
            let tris = tree
                .triangles
                .get(first..first + node.tri_count as usize)
                .unwrap_or(&[]);
            let (mut sum, mut area, mut vector) = (DVec3::ZERO, 0.0f64, DVec3::ZERO);
            for t in tris {
                let [a, b, c] = t.map(|v| v.as_dvec3());
                let an = (b - a).cross(c - a) * 0.5;
                let w = an.length();
                sum += (a + b + c) / 3.0 * w;
                area += w;
                vector += an;
            }
            let centre = if area > 0.0 {
                (sum / area).as_vec3()
            } else {
                node.obb.center
            };
            let radius = tris
                .iter()
                .flatten()
                .map(|v| v.distance(centre))
                .fold(0.0f32, f32::max);
            Dipole {
                area: vector.as_vec3(),
                centre,
                radius: radius * (1.0 + 4.0 * f32::EPSILON),
            }
        })
        .collect()
}

/// How far the tree sum may stray from the exact winding number in
/// [`box_may_be_inside`]'s bound: twice the 0.05 the tests hold it to.
pub const WINDING_SLACK: f32 = 0.1;

/// An edge of an open mesh's rim: triangle `tri`'s edge `edge` (0: `ab`,
/// 1: `bc`, 2: `ca`), which `count` more triangles run along one way than
/// the other (the boundary of the mesh as a chain: a hole's border counts
/// 1, an edge shared by two faces wound alike 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rim {
    /// The triangle (index into `ObbTree::triangles`).
    pub tri: u32,
    /// Its edge: 0 `ab`, 1 `bc`, 2 `ca`.
    pub edge: u8,
    /// How many times the chain's boundary runs along it.
    pub count: u32,
}

/// Whether the box `lo ..= hi` (object frame), which crosses no triangle
/// of `tree`'s open mesh, may hold a point of winding number above
/// [`WINDING_INSIDE_LO`] (a point the contact response would push): false
/// only when `w(c) + ρ G +` [`WINDING_SLACK`] `≤` [`WINDING_INSIDE_LO`],
/// with `c` the box's centre, `ρ` its half diagonal and `G` a bound of
/// `|∇w|` over the box. Off the surface `∇w` is the Biot–Savart field of
/// the mesh's rim (the gradient of a solid angle depends on the boundary
/// alone), so `|∇w(x)| ≤ Σ count · length / (4π dist(x, edge)²)` over
/// [`ObbTree::rims`], and `dist(x, edge) ≥ dist(c, edge) − ρ`. True when
/// an edge is within `ρ` of `c`, or for bad input.
#[must_use]
pub fn box_may_be_inside(tree: &ObbTree, lo: Vec3, hi: Vec3) -> bool {
    let (c, rho) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    if !(c.is_finite() && rho.is_finite()) {
        return true;
    }
    let mut gradient = 0.0f32;
    for rim in &tree.rims {
        let Some(t) = tree.triangles.get(rim.tri as usize) else {
            return true;
        };
        let (a, b) = (t[rim.edge as usize % 3], t[(rim.edge as usize + 1) % 3]);
        let q = crate::obb::build::closest_point_on_segment(a, b, c);
        let gap = q.distance(c) - rho;
        if gap.is_nan() || gap <= 0.0 {
            return true;
        }
        gradient += rim.count as f32 * a.distance(b) / (gap * gap);
    }
    let bound = winding_number(tree, c) + rho * gradient * INV_4PI + WINDING_SLACK;
    bound.is_nan() || bound > WINDING_INSIDE_LO
}

/// What the winding tests share (here and in `winding_grid.rs`).
#[cfg(test)]
pub(crate) mod test_support {
    use super::{INV_4PI, solid_angle};
    use crate::obb::ObbTree;
    use glam::Vec3;

    /// The winding number of `tree`'s mesh at `p` summed over every
    /// triangle: the reference.
    pub(crate) fn exact_sum(tree: &ObbTree, p: Vec3) -> f32 {
        tree.triangles
            .iter()
            .map(|t| solid_angle(t, p))
            .sum::<f32>()
            * INV_4PI
    }

    /// A unit sphere with its cap above `y = cut` left out: a bowl (the
    /// open mesh of the winding, contact and narrow-phase tests).
    pub(crate) fn bowl_mesh(cut: f32) -> crate::object::TriMesh {
        let mut mesh = crate::object::shapes::sphere(1.0, 3);
        let positions = mesh.positions.clone();
        mesh.indices
            .retain(|t| t.iter().all(|&i| positions[i as usize].y <= cut));
        mesh
    }

    /// [`bowl_mesh`]'s tree, with the winding data.
    pub(crate) fn bowl(cut: f32) -> ObbTree {
        let mut tree = ObbTree::build(&bowl_mesh(cut), 12);
        tree.enable_winding();
        tree
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::{bowl, exact_sum};
    use super::*;
    use crate::object::mesh::TriMesh;
    use crate::test_rng::XorShift;

    fn sphere() -> TriMesh {
        crate::object::shapes::sphere(1.0, 3)
    }

    /// The polynomial `atan2` is within 4e-6 rad of the platform's
    /// everywhere (all four quadrants, both octants, magnitudes from 1e-30
    /// to 1e30), exact at the axes, and continuous across the octants'
    /// diagonal: a point an ulp off it moves the angle by about an ulp.
    #[test]
    fn the_polynomial_atan2_follows_the_platforms_and_is_continuous() {
        let mut rng = XorShift(0x6a09_e667_f3bc_c908);
        let mut worst = 0.0f64;
        for _ in 0..200_000 {
            let scale = 10f32.powf(rng.range(-30.0, 30.0));
            let (y, x) = (rng.range(-1.0, 1.0) * scale, rng.range(-1.0, 1.0) * scale);
            let e = (f64::from(atan2(y, x)) - f64::from(y).atan2(f64::from(x))).abs();
            worst = worst.max(e);
        }
        assert!(worst < 4e-6, "{worst} rad");
        use std::f32::consts::{FRAC_PI_2, PI};
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert_eq!(atan2(0.0, 2.0), 0.0);
        assert_eq!(atan2(2.0, 0.0), FRAC_PI_2);
        assert_eq!(atan2(-2.0, 0.0), -FRAC_PI_2);
        assert_eq!(atan2(0.0, -2.0), PI);
        // Across |y| = |x| in every quadrant, and across x = 0.
        for (y, x) in [(1.0f32, 1.0f32), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)] {
            for m in [1e-3f32, 1.0, 1e3] {
                let (y, x) = (y * m, x * m);
                let step = x.abs() * 4.0 * f32::EPSILON;
                let (a, b) = (atan2(y, x - step), atan2(y, x + step));
                assert!((a - b).abs() < 1e-6, "({y}, {x}): {a} vs {b}");
            }
        }
        let (a, b) = (atan2(1.0, -1e-7), atan2(1.0, 1e-7));
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        assert!(!atan2(f32::NAN, 1.0).is_infinite());
    }

    #[test]
    fn a_closed_sphere_winds_once_inside_and_not_outside() {
        let mut tree = ObbTree::build(&sphere(), 12);
        tree.dipoles = dipoles(&tree);
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        for _ in 0..500 {
            let d = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let Some(d) = d.try_normalize() else { continue };
            let inside = d * rng.range(0.0, 0.9);
            let outside = d * rng.range(1.1, 6.0);
            // The dipoles stand for their nodes within a few per cent.
            assert!(
                (winding_number(&tree, inside) - 1.0).abs() < 0.05,
                "{inside}"
            );
            assert!(winding_number(&tree, outside).abs() < 0.05, "{outside}");
        }
    }

    #[test]
    fn the_tree_sum_follows_the_exact_sum_on_an_open_bowl() {
        let tree = bowl(0.3);
        assert!(!tree.closed && tree.winds());
        assert_eq!(tree.dipoles.len(), tree.nodes.len());
        let mut rng = XorShift(0x2545_f491_4f6c_dd1d);
        let mut worst = 0.0f32;
        for _ in 0..2000 {
            let p = Vec3::new(
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
            );
            let (a, b) = (winding_number(&tree, p), exact_sum(&tree, p));
            worst = worst.max((a - b).abs());
        }
        assert!(worst < 0.05, "tree sum {worst} from the exact sum");
        // Half in the plane of the hole at its middle; deep in the bowl,
        // one less the hole's solid angle (0.12 of the sphere at 1.1 below
        // a hole of radius 0.95); above the hole, little.
        assert!((winding_number(&tree, Vec3::new(0.0, 0.3, 0.0)) - 0.5).abs() < 0.05);
        assert!((winding_number(&tree, Vec3::new(0.0, -0.8, 0.0)) - 0.88).abs() < 0.05);
        assert!(winding_number(&tree, Vec3::new(0.0, 1.2, 0.0)) < 0.2);
    }

    /// Continuous: points a few ulp apart get sums a few ulp apart, here
    /// where the blend between dipole and exact sum is at work (every
    /// distance) and across the plane of the hole.
    #[test]
    fn the_sum_is_continuous_in_the_point() {
        let tree = bowl(0.3);
        let mut rng = XorShift(0x1234_5678_9abc_def1);
        for _ in 0..2000 {
            let p = Vec3::new(
                rng.range(-3.0, 3.0),
                rng.range(-0.6, 3.0),
                rng.range(-3.0, 3.0),
            );
            let q = p + Vec3::new(1e-6, -1e-6, 1e-6);
            let (a, b) = (winding_number(&tree, p), winding_number(&tree, q));
            // Off the surface the gradient is bounded by the distance.
            assert!((a - b).abs() < 1e-3, "{p}: {a} vs {b}");
        }
    }

    /// The bound of [`box_may_be_inside`] holds: no box it clears has a
    /// point above the ramp's foot, on the bowl, among random boxes that
    /// cross no triangle; and it clears boxes well outside.
    #[test]
    fn a_cleared_box_holds_no_point_inside() {
        let tree = bowl(0.3);
        assert!(!tree.rims.is_empty());
        let mut rng = XorShift(0x0bad_cafe_f00d_d00d);
        let (mut cleared, mut checked) = (0, 0);
        for _ in 0..3000 {
            let c = Vec3::new(
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
            );
            let h = Vec3::splat(rng.range(0.01, 0.3));
            // Crossing no triangle: wholly inside or outside the sphere.
            let (near, far) = ((c.length() - h.length()), (c.length() + h.length()));
            if !(far < 0.999 || near > 1.001) {
                continue;
            }
            checked += 1;
            if box_may_be_inside(&tree, c - h, c + h) {
                continue;
            }
            cleared += 1;
            for k in 0..27 {
                let f = Vec3::new((k % 3) as f32, ((k / 3) % 3) as f32, (k / 9) as f32) - 1.0;
                let w = exact_sum(&tree, c + h * f);
                assert!(w <= WINDING_INSIDE_LO, "box at {c} cleared, w {w}");
            }
        }
        assert!(cleared > checked / 4, "{cleared} of {checked} cleared");
    }

    #[test]
    fn the_factor_ramps_between_its_bounds() {
        assert_eq!(inside_factor(0.0), 0.0);
        assert_eq!(inside_factor(WINDING_INSIDE_LO), 0.0);
        assert!((inside_factor(0.4) - 0.5).abs() < 1e-6);
        assert_eq!(inside_factor(WINDING_INSIDE_HI), 1.0);
        assert_eq!(inside_factor(2.0), 1.0);
        assert_eq!(inside_factor(f32::NAN), 0.0);
    }
}
