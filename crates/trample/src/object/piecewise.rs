//! Paths made of straight segments between timed points: `static`, `line`,
//! `polyline` and `keyframes` (see [`super::path::Path`]).

use glam::{Quat, Vec3};

/// Straight segments between points at strictly increasing times.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Piecewise {
    /// Path times of the points, seconds, strictly increasing, at least one.
    pub(super) times: Vec<f32>,
    points: Vec<Vec3>,
    /// One per point, or none.
    rotations: Option<Vec<Quat>>,
    /// Horizontal direction of each segment, filled over the segments that
    /// do not move horizontally; empty when none does.
    headings: Vec<Vec3>,
}

/// Where a time falls on a [`Piecewise`] path.
enum Place {
    /// Held at point k (before the first key or from the last one on).
    Held(usize),
    /// On segment i, fraction u ∈ [0, 1).
    On(usize, f32),
}

impl Piecewise {
    pub(super) fn new(times: Vec<f32>, points: Vec<Vec3>, rotations: Option<Vec<Quat>>) -> Self {
        let raw = points
            .windows(2)
            .map(|w| {
                let d = w[1] - w[0];
                Vec3::new(d.x, 0.0, d.z)
                    .try_normalize()
                    .filter(|_| d.x.hypot(d.z) > 1e-6 * d.length())
            })
            .collect();
        let filled = fill_headings(raw);
        let headings = if filled.iter().all(Option::is_some) {
            filled.into_iter().flatten().collect()
        } else {
            Vec::new()
        };
        Self {
            times,
            points,
            rotations,
            headings,
        }
    }

    fn place(&self, t: f32) -> Place {
        let last = self.times.len() - 1;
        if last == 0 || t < self.times[0] || t.is_nan() {
            return Place::Held(0);
        }
        if t >= self.times[last] {
            return Place::Held(last);
        }
        let i = self
            .times
            .partition_point(|&k| k <= t)
            .saturating_sub(1)
            .min(last - 1);
        let u = (t - self.times[i]) / (self.times[i + 1] - self.times[i]);
        Place::On(i, u.clamp(0.0, 1.0))
    }

    /// Sum of the segment lengths, metres.
    pub(super) fn length(&self) -> f32 {
        self.points.windows(2).map(|w| w[0].distance(w[1])).sum()
    }

    pub(super) fn position(&self, t: f32) -> Vec3 {
        match self.place(t) {
            Place::Held(k) => self.points[k],
            Place::On(i, u) => self.points[i].lerp(self.points[i + 1], u),
        }
    }

    pub(super) fn velocity(&self, t: f32) -> Vec3 {
        match self.place(t) {
            Place::Held(_) => Vec3::ZERO,
            Place::On(i, _) => {
                (self.points[i + 1] - self.points[i]) / (self.times[i + 1] - self.times[i])
            }
        }
    }

    pub(super) fn heading(&self, t: f32) -> Option<Vec3> {
        let segment = match self.place(t) {
            Place::Held(k) => k.min(self.points.len().saturating_sub(2)),
            Place::On(i, _) => i,
        };
        self.headings.get(segment).copied()
    }

    pub(super) fn rotation(&self, t: f32) -> Option<Quat> {
        let rotations = self.rotations.as_ref()?;
        Some(match self.place(t) {
            Place::Held(k) => rotations[k],
            Place::On(i, u) => rotations[i].slerp(rotations[i + 1], u),
        })
    }

    pub(super) fn angular_velocity(&self, t: f32) -> Option<Vec3> {
        let rotations = self.rotations.as_ref()?;
        Some(match self.place(t) {
            Place::Held(_) => Vec3::ZERO,
            Place::On(i, _) => {
                // slerp takes the short way: so does this world-frame delta.
                let mut delta = rotations[i + 1] * rotations[i].inverse();
                if delta.w < 0.0 {
                    delta = -delta;
                }
                let (axis, angle) = delta.to_axis_angle();
                axis * angle / (self.times[i + 1] - self.times[i])
            }
        })
    }
}

/// Segment headings with the gaps (segments without horizontal motion)
/// taking the heading before them, and leading gaps the first heading.
pub(super) fn fill_headings(mut headings: Vec<Option<Vec3>>) -> Vec<Option<Vec3>> {
    let mut last = None;
    for h in &mut headings {
        if h.is_none() {
            *h = last;
        }
        last = *h;
    }
    let first = headings.iter().flatten().next().copied();
    for h in &mut headings {
        if h.is_none() {
            *h = first;
        }
    }
    headings
}
