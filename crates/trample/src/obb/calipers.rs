//! The box axes, around a given first axis, that give the box of smallest
//! surface (issue 16, item 5: a better orientation search than covariance
//! axes alone).
//!
//! With the first axis `u` fixed, the box's extent along `u` is fixed and
//! the other two axes turn in the plane ⊥ `u`: the problem is a rectangle
//! around the points projected on that plane. The rectangle of smallest
//! area has a side flush with an edge of the projected points' convex hull
//! (H. Freeman, R. Shapira, *Determining the minimum-area encasing
//! rectangle for an arbitrary closed curve*, CACM 1975; the rotating
//! calipers of G. Toussaint, 1983, visit those orientations). Here the cost
//! is the box's surface `w·v + h·(w + v)` (rectangle sides `w`, `v`, extent
//! `h` along `u`), and every hull edge's orientation is evaluated.
//!
//! [`super::fit::fit_obb`] calls it around the covariance axes and keeps
//! the smallest of all the boxes it gets; the extents are then
//! computed exactly from every corner, so the search only proposes axes and
//! may work on a subsample.

use glam::Vec3;

/// Points used at most for the hull: more are subsampled evenly (the hull
/// only proposes an orientation; the box around all points is computed
/// afterwards), which bounds the cost on nodes of huge meshes.
const MAX_POINTS: usize = 4096;

/// Hull edges evaluated at most, evenly spread when the hull has more.
const MAX_EDGES: usize = 256;

/// The axes `[u, e, u × e]`, `e` ⊥ `u`, whose box around `points` has the
/// smallest surface among those with `e` along an edge of the convex hull
/// of `points` projected on the plane ⊥ `u`. `None` when `u` is not a
/// finite non-zero vector, the points are not finite, or their projection
/// is a single point. Deterministic.
#[must_use]
pub fn min_surface_axes(points: &[Vec3], u: Vec3) -> Option<[Vec3; 3]> {
    let u = u.try_normalize()?;
    let (a, b) = u.any_orthonormal_pair();
    let step = points.len().div_ceil(MAX_POINTS).max(1);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut flat: Vec<[f64; 2]> = Vec::with_capacity(points.len() / step + 1);
    for p in points.iter().step_by(step) {
        let h = f64::from(p.dot(u));
        lo = lo.min(h);
        hi = hi.max(h);
        flat.push([f64::from(p.dot(a)), f64::from(p.dot(b))]);
    }
    let height = hi - lo;
    if !height.is_finite() || flat.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let hull = convex_hull(&mut flat);
    if hull.len() < 2 {
        return None;
    }
    let mut best: Option<(f64, [f64; 2])> = None;
    for i in (0..hull.len()).step_by(hull.len().div_ceil(MAX_EDGES)) {
        let (p, q) = (hull[i], hull[(i + 1) % hull.len()]);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        if len <= 0.0 {
            continue;
        }
        let (ex, ey) = (dx / len, dy / len);
        let (mut w0, mut w1, mut v0, mut v1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for h in &hull {
            let (s, t) = (h[0] * ex + h[1] * ey, h[1] * ex - h[0] * ey);
            (w0, w1, v0, v1) = (w0.min(s), w1.max(s), v0.min(t), v1.max(t));
        }
        let (w, v) = (w1 - w0, v1 - v0);
        let cost = w * v + height * (w + v);
        if best.is_none_or(|(c, _)| cost < c) {
            best = Some((cost, [ex, ey]));
        }
    }
    let [ex, ey] = best?.1;
    let e = (a * ex as f32 + b * ey as f32).try_normalize()?;
    let e = (e - u * u.dot(e)).try_normalize()?;
    Some([u, e, u.cross(e)])
}

/// The convex hull of `points` (sorted in place), counter-clockwise,
/// without repeated or collinear points: Andrew's monotone chain (A. M.
/// Andrew, *Another efficient algorithm for convex hulls in two
/// dimensions*, 1979). Fewer than two distinct points give those points.
fn convex_hull(points: &mut [[f64; 2]]) -> Vec<[f64; 2]> {
    points.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::new();
    for lower in [true, false] {
        let start = hull.len();
        let mut add = |p: [f64; 2]| {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        };
        if lower {
            points.iter().for_each(|&p| add(p));
        } else {
            points.iter().rev().for_each(|&p| add(p));
        }
        // The last point of each chain starts the other.
        hull.pop();
    }
    hull.dedup();
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_inner_and_edge_points() {
        let mut pts = vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.5, 0.5],
            [0.5, 0.0],
            [1.0, 1.0],
        ];
        let hull = convex_hull(&mut pts);
        assert_eq!(hull, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(convex_hull(&mut [[2.0, 3.0], [2.0, 3.0]]), vec![[2.0, 3.0]]);
    }

    #[test]
    fn finds_a_rectangle_turned_in_the_plane() {
        // A 4 × 1 rectangle turned 0.3 rad about y, at two heights.
        let (c, s) = (0.3f32.cos(), 0.3f32.sin());
        let mut pts = Vec::new();
        for (x, z) in [
            (-2.0, -0.5),
            (2.0, -0.5),
            (2.0, 0.5),
            (-2.0, 0.5),
            (0.7, 0.1),
        ] {
            for y in [0.0, 0.2] {
                pts.push(Vec3::new(c * x + s * z, y, -s * x + c * z));
            }
        }
        let [u, e, w] = min_surface_axes(&pts, Vec3::Y).unwrap();
        assert_eq!(u, Vec3::Y);
        // e lies along the long or the short side: |e · (c, 0, -s)| is 1 or 0.
        let along = e.dot(Vec3::new(c, 0.0, -s)).abs();
        assert!((along - 1.0).abs() < 1e-5 || along < 1e-5, "{e}");
        assert!(w.dot(u).abs() < 1e-6 && w.dot(e).abs() < 1e-6);
        assert!(min_surface_axes(&[Vec3::ONE; 3], Vec3::X).is_none());
        assert!(min_surface_axes(&pts, Vec3::ZERO).is_none());
    }
}
