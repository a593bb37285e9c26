//! Fitting one oriented bounding box to a set of triangles (paper §4.2: a
//! node is "a centre point C, an orthonormal system [u, v, w] and three values
//! (hu, hv, hw)"; DESIGN §3: "covariance axes, then exact extents").
//!
//! Method: S. Gottschalk, M. C. Lin, D. Manocha, *OBBTree: a hierarchical
//! structure for rapid interference detection*, SIGGRAPH 1996, and
//! D. Eberly, *Dynamic collision detection using oriented bounding boxes*
//! (Geometric Tools, 2002). The axes are the eigenvectors of the
//! **continuous** covariance of the triangles (each triangle taken as a
//! uniformly dense surface, so a finely tessellated region does not pull the
//! axes towards itself as it would with vertex covariance). The extents are
//! then exact: every triangle corner is projected on the axes.
//!
//! Three additions (ours):
//! - the world-axis box of the same corners is fitted too and the one with
//!   the smaller surface area is kept. By Cauchy–Crofton, the probability
//!   that a random line meets a convex body is proportional to its surface
//!   area, so this is the box that fewer blade segments hit; it also fixes
//!   the classic failure of covariance fitting on shapes whose covariance is
//!   isotropic (a cube, a sphere), where any basis is an eigenbasis.
//! - around each covariance axis, the other two axes that give the
//!   smallest surface ([`super::calipers`]: the rectangle flush with a hull
//!   edge of the corners projected on the plane ⊥ that axis) are tried too
//!   (issue 16). Measured on the knot at depth 7: 23.5 % false positives
//!   without, 18.1 % with (18.4 % also around the world axes, at twice the
//!   cost).
//! - a tiny padding, see [`padding`].
//!
//! The covariance and its eigen-decomposition are computed in `f64` (this is
//! the off-line stage); the result is `f32`.

use glam::{DVec3, Vec3};

use super::calipers::min_surface_axes;
use super::node::Obb;

/// Relative padding of every half extent, as a fraction of the box's largest
/// half extent. Projecting a corner on an axis in `f32` rounds by a few ulps
/// of the corner's distance to the centre (≤ √3 × the largest half extent),
/// about 1e-6 relative in the worst case; 1e-5 is ten times that, and at
/// 1e-5 of the object's size (0.01 mm on a 1 m object) it is invisible.
pub const REL_PADDING: f32 = 1e-5;

/// Absolute padding of every half extent, metres: keeps a box around a
/// single flat triangle (or a point) from having a zero extent, so that the
/// slab test in [`crate::collision::segment_obb`] is never asked to decide a
/// tie it could round either way.
pub const ABS_PADDING: f32 = 1e-6;

/// Padding added to every half extent of a box whose largest unpadded half
/// extent is `max_half` and whose centre is `center`.
///
/// Float rounding (in the fit, in [`Obb::to_box`], in the segment test) must
/// never let a triangle poke out of its box: the collision properties of
/// DESIGN §4 ("no segment that crosses a triangle is ever missed") rest on
/// the boxes containing their triangles. Three terms: [`REL_PADDING`] of the
/// box size, [`ABS_PADDING`], and 16 ulps of the centre's largest
/// coordinate (the rounding of `p − center` for a box far from the origin).
#[must_use]
#[inline]
pub fn padding(max_half: f32, center: Vec3) -> f32 {
    REL_PADDING * max_half + ABS_PADDING + 16.0 * f32::EPSILON * center.abs().max_element()
}

/// Fits an oriented bounding box to `triangles` (object-local frame).
///
/// Axes: of the boxes with the eigenvectors of the area-weighted continuous
/// covariance of the triangles (Gottschalk et al. 1996; ordered by
/// decreasing variance, orthonormalised, right-handed `w = u × v`), with
/// the world axes, and with [`super::calipers::min_surface_axes`] around
/// each covariance axis, the one of smallest surface area (the first of
/// them on a tie). The world axes alone when all triangles have zero area
/// and the corners do not define a covariance, or when the decomposition is
/// not finite. Extents: exact projection of all corners, plus [`padding`].
///
/// Every corner of every triangle lies inside the returned box, as measured
/// by [`Obb::to_box`]. An empty slice gives a zero box at the origin.
/// A non-finite corner cannot be contained: it is ignored by the extents
/// (never a panic), and [`super::ObbTree::validate`] reports the tree as
/// malformed; meshes with NaN coordinates are rejected upstream (DESIGN §9).
#[must_use]
pub fn fit_obb(triangles: &[[Vec3; 3]]) -> Obb {
    fit_obb_searched(triangles, true)
}

/// [`fit_obb`] without the orientation search around the covariance axes
/// when `search` is false: the covariance box or the world-axis box,
/// whichever has the smaller surface (the fit before issue 16). About
/// three times cheaper; [`super::ObbTree::build`] uses it below
/// [`super::build::SEARCH_DEPTH`].
#[must_use]
pub fn fit_obb_searched(triangles: &[[Vec3; 3]], search: bool) -> Obb {
    if triangles.is_empty() {
        return Obb {
            center: Vec3::ZERO,
            axes: WORLD_AXES,
            half: Vec3::ZERO,
        };
    }
    let reference = corner_bounds_centre(triangles);
    let Some(axes) = covariance_axes(triangles, reference) else {
        return extents_along(triangles, WORLD_AXES, reference).padded();
    };
    let covariance = extents_along(triangles, axes, reference);
    // A flat node (its covariance box as thin as rounding) keeps its
    // covariance rectangle: the search would only turn it in its plane,
    // flush with a hull edge, which puts box edges exactly on the
    // neighbouring boxes' and makes ties of grazing segments common
    // (measured, GPU against CPU on the busy scene, 200 frames on
    // llvmpipe: worst vertex 3.6e-3 m with flat nodes searched, 3.5e-5 m
    // without; the accuracy goals hold either way).
    let flat = covariance.half.min_element() <= FLAT * covariance.half.max_element();
    let turned: Vec<[Vec3; 3]> = if search && !flat {
        let points: Vec<Vec3> = triangles.iter().flatten().map(|p| *p - reference).collect();
        axes.into_iter()
            .filter_map(|u| min_surface_axes(&points, u))
            .collect()
    } else {
        Vec::new()
    };
    // Strictly smaller only: on a tie the earlier box (covariance first) is kept.
    let mut best = covariance;
    for candidate in std::iter::once(WORLD_AXES).chain(turned) {
        let b = extents_along(triangles, candidate, reference);
        if b.surface_area() < best.surface_area() {
            best = b;
        }
    }
    best.padded()
}

/// Thickness, relative to the largest extent, below which a covariance box
/// counts as flat in [`fit_obb_searched`] (a few ulps of the projections).
const FLAT: f32 = 1e-5;

/// The world axes x, y, z.
const WORLD_AXES: [Vec3; 3] = [Vec3::X, Vec3::Y, Vec3::Z];

/// A box before padding: axes, centre and exact half extents.
struct Unpadded {
    axes: [Vec3; 3],
    center: Vec3,
    half: Vec3,
}

impl Unpadded {
    /// Surface area over 8 (`hu hv + hv hw + hw hu`), enough to compare boxes.
    fn surface_area(&self) -> f32 {
        let h = self.half;
        h.x * h.y + h.y * h.z + h.z * h.x
    }

    fn padded(self) -> Obb {
        let pad = padding(self.half.max_element(), self.center);
        Obb {
            center: self.center,
            axes: self.axes,
            half: self.half + Vec3::splat(pad),
        }
    }
}

/// Centre of the axis-aligned bounds of all corners: the origin of the
/// projections, which keeps the numbers small for meshes far from the origin.
fn corner_bounds_centre(triangles: &[[Vec3; 3]]) -> Vec3 {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in triangles.iter().flatten() {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo + hi) * 0.5
}

/// Exact extents of all corners along orthonormal `axes`, projections taken
/// relative to `reference`.
fn extents_along(triangles: &[[Vec3; 3]], axes: [Vec3; 3], reference: Vec3) -> Unpadded {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for p in triangles.iter().flatten() {
        let d = *p - reference;
        let q = Vec3::new(d.dot(axes[0]), d.dot(axes[1]), d.dot(axes[2]));
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let mid = (lo + hi) * 0.5;
    let center = reference + axes[0] * mid.x + axes[1] * mid.y + axes[2] * mid.z;
    Unpadded {
        axes,
        center,
        half: (hi - lo) * 0.5,
    }
}

/// Principal axes of the triangles, `None` when they are not defined (no
/// area and all corners equal) or not finite.
fn covariance_axes(triangles: &[[Vec3; 3]], reference: Vec3) -> Option<[Vec3; 3]> {
    let cov = triangle_covariance(triangles, reference.as_dvec3())
        .or_else(|| corner_covariance(triangles, reference.as_dvec3()))?;
    let (values, vectors) = symmetric_eigen(cov);
    // Decreasing variance: u is the direction of largest spread.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    let column = |k: usize| DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]).as_vec3();
    orthonormal_right_handed(column(order[0]), column(order[1]))
}

/// Continuous covariance of the triangles as uniformly dense surfaces
/// (Gottschalk 1996, Eq. for `C_jk`): with `A_i` the area and `m_i` the
/// centroid of triangle `(p, q, r)`, `A = Σ A_i`, `m = Σ A_i m_i / A`,
/// `C_jk = Σ A_i / 12 (9 m_ij m_ik + p_j p_k + q_j q_k + r_j r_k) / A − m_j m_k`.
/// `None` when the total area is zero (or not finite).
fn triangle_covariance(triangles: &[[Vec3; 3]], reference: DVec3) -> Option<[[f64; 3]; 3]> {
    let mut area = 0.0f64;
    let mut mean = DVec3::ZERO;
    let mut second = [[0.0f64; 3]; 3];
    for tri in triangles {
        let [p, q, r] = tri.map(|c| c.as_dvec3() - reference);
        let a = 0.5 * (q - p).cross(r - p).length();
        let m = (p + q + r) / 3.0;
        area += a;
        mean += a * m;
        for j in 0..3 {
            for k in j..3 {
                second[j][k] +=
                    a / 12.0 * (9.0 * m[j] * m[k] + p[j] * p[k] + q[j] * q[k] + r[j] * r[k]);
            }
        }
    }
    if !(area > f64::MIN_POSITIVE && area.is_finite()) {
        return None;
    }
    let mean = mean / area;
    Some(symmetric_from_upper(|j, k| {
        second[j][k] / area - mean[j] * mean[k]
    }))
}

/// Covariance of the corners as points (the fallback when every triangle has
/// zero area). `None` when all corners coincide or are not finite.
fn corner_covariance(triangles: &[[Vec3; 3]], reference: DVec3) -> Option<[[f64; 3]; 3]> {
    let n = (triangles.len() * 3) as f64;
    let mean = triangles
        .iter()
        .flatten()
        .map(|c| c.as_dvec3() - reference)
        .sum::<DVec3>()
        / n;
    let mut second = [[0.0f64; 3]; 3];
    for c in triangles.iter().flatten() {
        let d = c.as_dvec3() - reference - mean;
        for j in 0..3 {
            for k in j..3 {
                second[j][k] += d[j] * d[k];
            }
        }
    }
    let cov = symmetric_from_upper(|j, k| second[j][k] / n);
    let trace = cov[0][0] + cov[1][1] + cov[2][2];
    (trace > 0.0 && trace.is_finite()).then_some(cov)
}

/// A symmetric matrix whose upper triangle entry `(j, k)`, `j ≤ k`, is `f(j, k)`.
#[allow(clippy::needless_range_loop)] // matrix indices read best as indices
fn symmetric_from_upper(f: impl Fn(usize, usize) -> f64) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for j in 0..3 {
        for k in j..3 {
            out[j][k] = f(j, k);
            out[k][j] = out[j][k];
        }
    }
    out
}

/// Off-diagonal entries below this fraction of the matrix's Frobenius norm
/// are treated as zero by [`symmetric_eigen`]. The covariance comes from
/// `f32` corners, so it is only known to ~1e-7 relative: below 1e-6, an
/// off-diagonal entry is noise, and rotating by it would turn a cube's
/// exactly world-aligned (isotropic) covariance by an arbitrary angle.
const JACOBI_TOLERANCE: f64 = 1e-6;

/// Most Jacobi sweeps; a 3×3 matrix converges quadratically in 4–6.
pub const JACOBI_MAX_SWEEPS: usize = 32;

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations
/// (Golub & Van Loan, *Matrix Computations*, §8.5). Returns the eigenvalues
/// and the matrix whose **columns** are the matching unit eigenvectors (an
/// orthogonal matrix). A non-finite or zero matrix gives its diagonal and the
/// identity. Never loops more than `JACOBI_MAX_SWEEPS` (32) sweeps.
#[must_use]
#[allow(clippy::needless_range_loop)] // matrix indices read best as indices
pub fn symmetric_eigen(m: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut a = m;
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let norm = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return ([a[0][0], a[1][1], a[2][2]], v);
    }
    let tiny = JACOBI_TOLERANCE * norm;
    for _ in 0..JACOBI_MAX_SWEEPS {
        let mut rotated = false;
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            let apq = a[p][q];
            if apq.abs() <= tiny {
                continue;
            }
            rotated = true;
            // Rotation angle that zeroes a[p][q]: tan(2φ) = 2 a_pq / (a_qq − a_pp);
            // t = tan φ, the smaller root, for stability.
            let theta = (a[q][q] - a[p][p]) / (2.0 * apq);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J, with J the rotation in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            // V ← V J.
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
        if !rotated {
            break;
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// An orthonormal right-handed basis `[u, v, u × v]` from two directions:
/// `u` normalised, `v` made orthogonal to `u` (Gram–Schmidt) and normalised.
/// `None` when either is zero, parallel to the other, or not finite.
fn orthonormal_right_handed(u: Vec3, v: Vec3) -> Option<[Vec3; 3]> {
    let u = u.try_normalize()?;
    let v = (v - u * u.dot(v)).try_normalize()?;
    let w = u.cross(v).try_normalize()?;
    // Re-derive v from w and u so the basis is orthogonal to f32 precision.
    let v = w.cross(u);
    Some([u, v, w])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mat_vec(m: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|k| m[i][k] * x[k]).sum())
    }

    #[test]
    fn jacobi_diagonalises_a_full_symmetric_matrix() {
        let m = [[4.0, 1.0, -2.0], [1.0, 2.0, 0.5], [-2.0, 0.5, 3.0]];
        let (values, vectors) = symmetric_eigen(m);
        for k in 0..3 {
            let x = [vectors[0][k], vectors[1][k], vectors[2][k]];
            let mx = mat_vec(&m, x);
            for i in 0..3 {
                assert!(
                    (mx[i] - values[k] * x[i]).abs() < 1e-5,
                    "column {k}: {mx:?} vs {values:?}"
                );
            }
        }
        // Orthogonal eigenvectors.
        for a in 0..3 {
            for b in 0..3 {
                let dot: f64 = (0..3).map(|i| vectors[i][a] * vectors[i][b]).sum();
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < 1e-9);
            }
        }
        // Trace is preserved.
        assert!((values.iter().sum::<f64>() - 9.0).abs() < 1e-9);
    }

    #[test]
    fn jacobi_keeps_the_basis_of_an_isotropic_matrix() {
        let m = [[1.0, 1e-9, 0.0], [1e-9, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let (_, vectors) = symmetric_eigen(m);
        assert_eq!(vectors, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    }

    #[test]
    fn jacobi_survives_nan_and_zero() {
        let (_, v) = symmetric_eigen([[f64::NAN; 3]; 3]);
        assert_eq!(v[0], [1.0, 0.0, 0.0]);
        let (values, _) = symmetric_eigen([[0.0; 3]; 3]);
        assert_eq!(values, [0.0; 3]);
    }

    #[test]
    fn basis_is_right_handed() {
        let [u, v, w] = orthonormal_right_handed(Vec3::new(1.0, 1.0, 0.0), Vec3::Z).unwrap();
        assert!((u.cross(v) - w).length() < 1e-6);
        assert!(u.dot(v).abs() < 1e-6 && w.is_normalized());
        assert!(orthonormal_right_handed(Vec3::X, Vec3::X * 2.0).is_none());
    }
}
