//! A centripetal Catmull-Rom spline through points, traversed by arc length.
//!
//! Catmull-Rom with the centripetal knot spacing (α = ½: knot intervals are
//! the square roots of the chord lengths; Yuksel, Schaefer & Keyser,
//! "Parameterization and applications of Catmull-Rom curves", CAD 2011) passes
//! through every point and, unlike the uniform spacing, never forms a cusp
//! or a loop inside a segment, so its tangent never vanishes. Each segment is
//! written as a cubic Hermite curve on u ∈ [0, 1]; the end segments use
//! mirrored phantom points, so a two-point spline is a straight line.
//! Arc length is tabulated ([`SAMPLES_PER_SEGMENT`] intervals of u per
//! segment, each integrated with 3-point Gauss-Legendre) and inverted with a
//! cubic Hermite interpolant of u(s) whose end slopes are the exact
//! du/ds = 1 / |dp/du|: the speed along the curve is then constant to about
//! 1e-4 (a linear inverse would leave ~1 % ripples where |dp/du| varies).

use glam::Vec3;

/// Intervals of u per segment in the arc-length table (12 bytes each).
pub const SAMPLES_PER_SEGMENT: usize = 64;

/// One segment as a cubic Hermite curve from `p1` (u = 0) to `p2` (u = 1)
/// with end derivatives `m1`, `m2` (per unit u).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Hermite {
    p1: Vec3,
    p2: Vec3,
    m1: Vec3,
    m2: Vec3,
}

impl Hermite {
    fn point(&self, u: f32) -> Vec3 {
        let (u2, u3) = (u * u, u * u * u);
        (2.0 * u3 - 3.0 * u2 + 1.0) * self.p1
            + (u3 - 2.0 * u2 + u) * self.m1
            + (-2.0 * u3 + 3.0 * u2) * self.p2
            + (u3 - u2) * self.m2
    }

    /// d point / du.
    fn first_derivative(&self, u: f32) -> Vec3 {
        let u2 = u * u;
        (6.0 * u2 - 6.0 * u) * self.p1
            + (3.0 * u2 - 4.0 * u + 1.0) * self.m1
            + (-6.0 * u2 + 6.0 * u) * self.p2
            + (3.0 * u2 - 2.0 * u) * self.m2
    }

    /// d² point / du².
    fn second_derivative(&self, u: f32) -> Vec3 {
        (12.0 * u - 6.0) * self.p1
            + (6.0 * u - 4.0) * self.m1
            + (-12.0 * u + 6.0) * self.p2
            + (6.0 * u - 2.0) * self.m2
    }
}

/// A centripetal Catmull-Rom spline parameterised by distance along it.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    segments: Vec<Hermite>,
    /// Distance along the curve at each table sample, metres: interval
    /// `k` (from sample k to k + 1) lies on segment `k / SAMPLES_PER_SEGMENT`;
    /// starts at 0.
    distances: Vec<f32>,
    /// |dp/du| at the start and end of each interval, metres per unit u.
    rates: Vec<[f32; 2]>,
}

impl Spline {
    /// The spline through `points`.
    ///
    /// Preconditions (checked by [`super::path::Path::new`]): at least two
    /// points, all finite, no two consecutive ones equal. Given fewer than
    /// two points it is the empty curve at the origin.
    #[must_use]
    pub fn new(points: &[Vec3]) -> Self {
        let n = points.len();
        if n < 2 {
            return Self {
                segments: Vec::new(),
                distances: vec![0.0],
                rates: Vec::new(),
            };
        }
        let at = |i: isize| -> Vec3 {
            match i {
                -1 => 2.0 * points[0] - points[1],
                i if i as usize == n => 2.0 * points[n - 1] - points[n - 2],
                i => points[i as usize],
            }
        };
        let segments: Vec<Hermite> = (0..n as isize - 1)
            .map(|i| centripetal_segment(at(i - 1), at(i), at(i + 1), at(i + 2)))
            .collect();
        let intervals = segments.len() * SAMPLES_PER_SEGMENT;
        let (mut distances, mut rates) = (
            Vec::with_capacity(intervals + 1),
            Vec::with_capacity(intervals),
        );
        distances.push(0.0);
        let mut total = 0.0_f64;
        let width = 1.0 / SAMPLES_PER_SEGMENT as f64;
        for segment in &segments {
            let rate = |u: f64| f64::from(segment.first_derivative(u as f32).length());
            for k in 0..SAMPLES_PER_SEGMENT {
                let (start, middle) = (k as f64 * width, (k as f64 + 0.5) * width);
                // 3-point Gauss-Legendre on [start, start + width].
                let offset = 0.5 * width * (3.0_f64 / 5.0).sqrt();
                total += 0.5
                    * width
                    * (5.0 * rate(middle - offset)
                        + 8.0 * rate(middle)
                        + 5.0 * rate(middle + offset))
                    / 9.0;
                distances.push(total as f32);
                rates.push([rate(start) as f32, rate(start + width) as f32]);
            }
        }
        Self {
            segments,
            distances,
            rates,
        }
    }

    /// Length of the curve, metres.
    #[must_use]
    pub fn length(&self) -> f32 {
        self.distances.last().copied().unwrap_or(0.0)
    }

    /// The point at distance `s` along the curve (clamped to the curve).
    #[must_use]
    pub fn point(&self, s: f32) -> Vec3 {
        self.locate(s)
            .map_or(Vec3::ZERO, |(segment, u)| segment.point(u))
    }

    /// Unit tangent at distance `s` (direction of travel).
    #[must_use]
    pub fn tangent(&self, s: f32) -> Vec3 {
        self.locate(s).map_or(Vec3::ZERO, |(segment, u)| {
            segment.first_derivative(u).normalize_or_zero()
        })
    }

    /// Curvature vector dT/ds at distance `s`, 1/metres: points to the centre
    /// of curvature, its length is the curvature. Times speed² it is the
    /// acceleration of a point moving along the curve at constant speed.
    #[must_use]
    pub fn curvature_vector(&self, s: f32) -> Vec3 {
        let Some((segment, u)) = self.locate(s) else {
            return Vec3::ZERO;
        };
        let d1 = segment.first_derivative(u);
        let speed2 = d1.length_squared();
        if speed2 <= f32::MIN_POSITIVE {
            return Vec3::ZERO;
        }
        let tangent = d1 / speed2.sqrt();
        let d2 = segment.second_derivative(u);
        (d2 - d2.dot(tangent) * tangent) / speed2
    }

    /// The horizontal direction (unit, y = 0) of segment `i`'s chord, or
    /// `None` for a vertical chord.
    #[must_use]
    pub fn chord_heading(&self, i: usize) -> Option<Vec3> {
        let segment = self.segments.get(i)?;
        let d = segment.p2 - segment.p1;
        Vec3::new(d.x, 0.0, d.z)
            .try_normalize()
            .filter(|_| d.x.hypot(d.z) > 1e-6 * d.length())
    }

    /// Number of segments (points − 1).
    #[must_use]
    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    /// The segment index at distance `s`.
    #[must_use]
    pub fn segment_at(&self, s: f32) -> usize {
        self.sample_at(s).0 / SAMPLES_PER_SEGMENT
    }

    /// (segment, u) at distance `s`, through the arc-length table.
    fn locate(&self, s: f32) -> Option<(&Hermite, f32)> {
        let (k, fraction) = self.sample_at(s);
        let segment = self.segments.get(k / SAMPLES_PER_SEGMENT)?;
        let u = ((k % SAMPLES_PER_SEGMENT) as f32 + fraction) / SAMPLES_PER_SEGMENT as f32;
        Some((segment, u))
    }

    /// Table interval `k` holding distance `s` (clamped), and the fraction of
    /// its u-width reached there.
    fn sample_at(&self, s: f32) -> (usize, f32) {
        let intervals = self.rates.len();
        if intervals == 0 {
            return (0, 0.0);
        }
        let s = s.clamp(0.0, self.length());
        let k = self
            .distances
            .partition_point(|&d| d <= s)
            .saturating_sub(1)
            .min(intervals - 1);
        let [rate0, rate1] = self.rates[k];
        let (a, b) = (self.distances[k], self.distances[k + 1]);
        if b <= a {
            return (k, 0.0);
        }
        // Cubic Hermite of the u-fraction over x = the distance fraction: its
        // slopes d(u-fraction)/dx at the ends are (b − a) / (|dp/du| × width).
        let width = 1.0 / SAMPLES_PER_SEGMENT as f32;
        let slope = |rate: f32| {
            if rate > 0.0 {
                (b - a) / (rate * width)
            } else {
                1.0
            }
        };
        let (m0, m1) = (slope(rate0), slope(rate1));
        let x = ((s - a) / (b - a)).clamp(0.0, 1.0);
        let (x2, x3) = (x * x, x * x * x);
        let fraction = (x3 - 2.0 * x2 + x) * m0 + (-2.0 * x3 + 3.0 * x2) + (x3 - x2) * m1;
        (k, fraction.clamp(0.0, 1.0))
    }
}

/// The Hermite form of the centripetal Catmull-Rom segment from `p1` to `p2`
/// with neighbours `p0` and `p3` (all consecutive points distinct).
fn centripetal_segment(p0: Vec3, p1: Vec3, p2: Vec3, p3: Vec3) -> Hermite {
    let knot = |a: Vec3, b: Vec3| a.distance(b).sqrt();
    let (t01, t12, t23) = (knot(p0, p1), knot(p1, p2), knot(p2, p3));
    let m1 = (p1 - p0) / t01 - (p2 - p0) / (t01 + t12) + (p2 - p1) / t12;
    let m2 = (p2 - p1) / t12 - (p3 - p1) / (t12 + t23) + (p3 - p2) / t23;
    Hermite {
        p1,
        p2,
        m1: m1 * t12,
        m2: m2 * t12,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_points_make_a_straight_line_at_exact_distances() {
        let spline = Spline::new(&[Vec3::ZERO, Vec3::new(4.0, 0.0, 3.0)]);
        assert!((spline.length() - 5.0).abs() < 1e-5);
        assert!(spline.point(2.5).distance(Vec3::new(2.0, 0.0, 1.5)) < 1e-4);
        assert!(spline.tangent(1.0).distance(Vec3::new(0.8, 0.0, 0.6)) < 1e-5);
        assert!(spline.curvature_vector(1.0).length() < 1e-4);
    }

    /// Points on a circle of radius 10, 1/32 of a turn apart, half a turn.
    fn half_circle() -> Spline {
        let points: Vec<Vec3> = (0..=16)
            .map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 32.0;
                Vec3::new(10.0 * a.cos(), 0.0, 10.0 * a.sin())
            })
            .collect();
        Spline::new(&points)
    }

    #[test]
    fn spline_through_circle_points_has_about_its_curvature_pointing_inwards() {
        let spline = half_circle();
        assert!(
            (spline.length() - 10.0 * std::f32::consts::PI).abs() < 0.05,
            "length {}",
            spline.length()
        );
        for s in [3.3, 10.0, 15.7, 22.1] {
            let k = spline.curvature_vector(s);
            // Catmull-Rom through a 32-gon bends within 5 % of the circle.
            assert!(
                (k.length() - 0.1).abs() < 0.005,
                "curvature {} at {s}",
                k.length()
            );
            assert!(
                k.normalize().dot(-spline.point(s).normalize()) > 0.999,
                "points to the centre"
            );
        }
    }

    #[test]
    fn tangent_and_curvature_match_finite_differences_of_the_point() {
        // Away from the end segments: their mirrored phantom points turn the
        // end tangents along the end chords, so their curvature changes fast.
        let spline = half_circle();
        let h = 0.1;
        for s in [5.1, 7.7, 12.4, 20.0, 26.0] {
            let (a, b, c) = (spline.point(s - h), spline.point(s), spline.point(s + h));
            let tangent = (c - a) / (2.0 * h);
            let curvature = (a - 2.0 * b + c) / (h * h);
            assert!(
                spline.tangent(s).distance(tangent) < 2e-3,
                "tangent at {s}: {} vs {tangent}",
                spline.tangent(s)
            );
            assert!(
                spline.curvature_vector(s).distance(curvature) < 2e-3,
                "curvature at {s}: {} vs {curvature}",
                spline.curvature_vector(s)
            );
        }
    }
}
