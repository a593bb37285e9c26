//! Paths: where an object's origin is at time t (DESIGN §3).
//!
//! [`PathParams`] and [`Keyframe`] are the scene-file contract; [`Path`] is
//! a validated path that evaluates position, velocity (the analytic
//! derivative, which Eq. 2 scales the force by), acceleration and heading at
//! any time. Times are path times: seconds since the object's `start_s`.
//! Every evaluation is a pure function of t.

use super::piecewise::{Piecewise, fill_headings};
use super::pose::rotation_from_euler_deg;
use super::spline::Spline;
use glam::{Quat, Vec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// A path as written in a scene file (`path = { kind = "line", ... }`).
/// Before its start and after its end a path holds its end points (velocity 0).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum PathParams {
    /// Stays at `position`.
    Static {
        /// World position, metres.
        position: [f32; 3],
    },
    /// Straight from `from` to `to` at constant speed in `duration_s` seconds.
    Line {
        /// Start, metres.
        from: [f32; 3],
        /// End, metres.
        to: [f32; 3],
        /// Travel time, seconds (> 0).
        duration_s: f32,
    },
    /// Through `points` in order at constant speed.
    Polyline {
        /// At least two points, metres.
        points: Vec<[f32; 3]>,
        /// Speed along the path, m/s (> 0).
        speed_m_s: f32,
    },
    /// Around a horizontal circle, counter-clockwise seen from above, forever.
    /// Seen from above (looking down −y, with +x to the right) −z is up the
    /// page, so counter-clockwise runs from +x towards −z: a positive
    /// rotation about +y. Position at path time t:
    /// `center + radius_m (cos θ, 0, −sin θ)`, θ = `phase_rad` + 2π t / `period_s`.
    Circle {
        /// Centre, metres.
        center: [f32; 3],
        /// Radius, metres (> 0).
        radius_m: f32,
        /// Time for one turn, seconds (> 0).
        period_s: f32,
        /// Start angle θ at t = 0, radians from +x towards −z (the direction
        /// of travel). Default 0.
        #[serde(default)]
        phase_rad: f32,
    },
    /// A Catmull-Rom spline through `points` at (nearly) constant speed.
    Spline {
        /// At least two points, metres.
        points: Vec<[f32; 3]>,
        /// Speed along the path, m/s (> 0).
        speed_m_s: f32,
    },
    /// Positions (and optional orientations) at given times, linearly
    /// interpolated (orientations slerped). Before the first key and after
    /// the last one the path holds that key.
    Keyframes {
        /// At least one key, times strictly increasing. `rotation_deg` on
        /// every key or on none.
        keys: Vec<Keyframe>,
    },
}

/// One key of a [`PathParams::Keyframes`] path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Path time, seconds since the object's `start_s`.
    pub t_s: f32,
    /// World position, metres.
    pub position: [f32; 3],
    /// Orientation as Euler angles (yaw about y, pitch about x, roll about z;
    /// applied y, x, z: R = R_y(yaw) R_x(pitch) R_z(roll)), degrees. Only
    /// used with `orientation = "keyframes"`.
    #[serde(default)]
    pub rotation_deg: Option<[f32; 3]>,
}

impl PathParams {
    /// The scene-file name of the kind (`"line"`, `"circle"`, ...).
    #[must_use]
    pub fn kind_name(&self) -> &'static str {
        match self {
            PathParams::Static { .. } => "static",
            PathParams::Line { .. } => "line",
            PathParams::Polyline { .. } => "polyline",
            PathParams::Circle { .. } => "circle",
            PathParams::Spline { .. } => "spline",
            PathParams::Keyframes { .. } => "keyframes",
        }
    }
}

/// Why a path was refused. Every message starts with the scene key
/// (`path.…`) and says what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PathError {
    /// A number (or one coordinate of a point) is NaN or infinite.
    #[error("path.{key} = {value}: must be finite")]
    NonFinite {
        /// The key, e.g. `points[2]`.
        key: String,
        /// The value as written.
        value: String,
    },
    /// A duration, speed, radius or period is zero or negative.
    #[error("path.{key} = {value}: must be > 0")]
    NotPositive {
        /// The key, e.g. `duration_s`.
        key: &'static str,
        /// The value.
        value: f32,
    },
    /// A speed so low that the path would take longer than [`MAX_DURATION_S`].
    #[error(
        "path.{key} = {value}: the path would take {duration_s:.1e} s; at most 1e9 s is allowed"
    )]
    TooSlow {
        /// The key (`speed_m_s`).
        key: &'static str,
        /// The speed, m/s.
        value: f32,
        /// The time the path would take, seconds.
        duration_s: f64,
    },
    /// A polyline or spline with fewer than two points.
    #[error("path.points: {given} point{} given; at least 2 are needed", if *.given == 1 { "" } else { "s" })]
    TooFewPoints {
        /// How many were given.
        given: usize,
    },
    /// Every point of a polyline or spline is the same.
    #[error("path.points: all points are the same; the path must have a length > 0")]
    ZeroLength,
    /// Two consecutive spline points are equal (the curve would have no
    /// direction there).
    #[error("path.points[{index}] repeats points[{}]; consecutive spline points must differ", .index - 1)]
    RepeatedSplinePoint {
        /// The index of the repeated point (≥ 1).
        index: usize,
    },
    /// A keyframes path with no key.
    #[error("path.keys: 0 keys given; at least 1 is needed")]
    NoKeys,
    /// Key times are not strictly increasing.
    #[error("path.keys[{index}].t_s = {t_s} is not after keys[{}].t_s = {previous_t_s}", .index - 1)]
    KeysNotIncreasing {
        /// The key (≥ 1).
        index: usize,
        /// Its time, seconds.
        t_s: f32,
        /// The time of the key before it, seconds.
        previous_t_s: f32,
    },
    /// Some keys have `rotation_deg` and some do not.
    #[error("path.keys[{index}] {}; give rotation_deg on every key or on none",
        if *.first_has_rotation { "has no rotation_deg but keys[0] has one" } else { "has rotation_deg but keys[0] has none" })]
    MixedRotations {
        /// The first key that differs from key 0.
        index: usize,
        /// Whether key 0 has a rotation.
        first_has_rotation: bool,
    },
}

/// Longest accepted path duration, seconds (32 years): a longer one comes
/// from a mistyped speed, and f32 times could not resolve its steps.
pub const MAX_DURATION_S: f64 = 1e9;

/// A validated path, ready to evaluate at any path time `t` (seconds since
/// the object's start). Before the path's start and after its end the
/// position is held and the velocity is 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    params: PathParams,
    curve: Curve,
}

/// The evaluable form of each kind.
#[derive(Clone, Debug, PartialEq)]
enum Curve {
    /// `static`, `line`, `polyline` and `keyframes`: straight segments
    /// between timed points.
    Piecewise(Piecewise),
    /// `circle`: θ(t) = phase + 2π t / period.
    Circle {
        center: Vec3,
        radius: f32,
        period: f32,
        phase: f32,
    },
    /// `spline`: distance s = speed · t along the curve.
    Spline {
        spline: Spline,
        speed: f32,
        chord_headings: Vec<Option<Vec3>>,
    },
}

impl Path {
    /// Validates `params`.
    ///
    /// # Errors
    /// A [`PathError`] naming the first bad key: non-finite numbers,
    /// non-positive durations, speeds, radii and periods, too few points or
    /// keys, key times not increasing, a zero-length polyline or spline,
    /// repeated consecutive spline points, rotations on only some keys.
    pub fn new(params: PathParams) -> Result<Self, PathError> {
        let curve = match &params {
            PathParams::Static { position } => Curve::Piecewise(Piecewise::new(
                vec![0.0],
                vec![finite3("position".into(), position)?],
                None,
            )),
            PathParams::Line {
                from,
                to,
                duration_s,
            } => {
                let (from, to) = (finite3("from".into(), from)?, finite3("to".into(), to)?);
                let duration = positive("duration_s", *duration_s)?;
                Curve::Piecewise(Piecewise::new(vec![0.0, duration], vec![from, to], None))
            }
            PathParams::Polyline { points, speed_m_s } => {
                let points = point_list(points)?;
                let speed = positive("speed_m_s", *speed_m_s)?;
                Curve::Piecewise(polyline(&points, speed)?)
            }
            PathParams::Circle {
                center,
                radius_m,
                period_s,
                phase_rad,
            } => Curve::Circle {
                center: finite3("center".into(), center)?,
                radius: positive("radius_m", *radius_m)?,
                period: positive("period_s", *period_s)?,
                phase: finite("phase_rad", *phase_rad)?,
            },
            PathParams::Spline { points, speed_m_s } => {
                let points = point_list(points)?;
                let speed = positive("speed_m_s", *speed_m_s)?;
                if let Some(index) = (1..points.len()).find(|&i| points[i] == points[i - 1]) {
                    return Err(PathError::RepeatedSplinePoint { index });
                }
                let spline = Spline::new(&points);
                check_duration(f64::from(spline.length()) / f64::from(speed), speed)?;
                let chord_headings = fill_headings(
                    (0..spline.segment_count())
                        .map(|i| spline.chord_heading(i))
                        .collect(),
                );
                Curve::Spline {
                    spline,
                    speed,
                    chord_headings,
                }
            }
            PathParams::Keyframes { keys } => Curve::Piecewise(keyframes(keys)?),
        };
        Ok(Self { params, curve })
    }

    /// What the path was built from.
    #[must_use]
    pub fn params(&self) -> &PathParams {
        &self.params
    }

    /// Path time at which the motion starts, seconds: 0, or the first key's
    /// time for `keyframes`.
    #[must_use]
    pub fn start_time(&self) -> f32 {
        match &self.curve {
            Curve::Piecewise(p) => p.times[0],
            _ => 0.0,
        }
    }

    /// Path time at which the motion ends, seconds; `None` for a circle,
    /// which never ends. A `static` path ends at 0.
    #[must_use]
    pub fn end_time(&self) -> Option<f32> {
        match &self.curve {
            Curve::Piecewise(p) => p.times.last().copied(),
            Curve::Circle { .. } => None,
            Curve::Spline { spline, speed, .. } => Some(spline.length() / speed),
        }
    }

    /// Length of the path, metres; `None` for a circle (endless).
    #[must_use]
    pub fn length(&self) -> Option<f32> {
        match &self.curve {
            Curve::Piecewise(p) => Some(p.length()),
            Curve::Circle { .. } => None,
            Curve::Spline { spline, .. } => Some(spline.length()),
        }
    }

    /// For a path of straight segments (static, line, polyline, keyframes):
    /// the times of its points, seconds, strictly increasing; the velocity
    /// is constant between two of them. `None` for a circle or a spline.
    #[must_use]
    pub fn breakpoints(&self) -> Option<&[f32]> {
        match &self.curve {
            Curve::Piecewise(p) => Some(&p.times),
            _ => None,
        }
    }

    /// Position of the object's origin at path time `t`, metres.
    /// See also [`Self::velocity`].
    #[must_use]
    pub fn position(&self, t: f32) -> Vec3 {
        match &self.curve {
            Curve::Piecewise(p) => p.position(t),
            &Curve::Circle {
                center,
                radius,
                period,
                phase,
            } => center + radius * circle_direction(circle_angle(phase, period, t.max(0.0))),
            Curve::Spline { spline, speed, .. } => spline.point(speed * t.max(0.0)),
        }
    }

    /// Velocity at path time `t`, m/s: the analytic derivative of
    /// [`Self::position`] (for a spline: the requested speed along the
    /// tangent). 0 before the start and from the end on.
    #[must_use]
    pub fn velocity(&self, t: f32) -> Vec3 {
        if !self.is_moving(t) {
            return Vec3::ZERO;
        }
        match &self.curve {
            Curve::Piecewise(p) => p.velocity(t),
            &Curve::Circle {
                radius,
                period,
                phase,
                ..
            } => {
                let theta = circle_angle(phase, period, t);
                radius
                    * (std::f32::consts::TAU / period)
                    * Vec3::new(-theta.sin(), 0.0, -theta.cos())
            }
            Curve::Spline { spline, speed, .. } => speed * spline.tangent(speed * t),
        }
    }

    /// Acceleration at path time `t`, m/s²: centripetal on a circle and a
    /// spline, 0 on straight segments (the turns at polyline corners and
    /// keys are instantaneous and not represented).
    #[must_use]
    pub fn acceleration(&self, t: f32) -> Vec3 {
        if !self.is_moving(t) {
            return Vec3::ZERO;
        }
        match &self.curve {
            Curve::Piecewise(_) => Vec3::ZERO,
            &Curve::Circle {
                radius,
                period,
                phase,
                ..
            } => {
                let omega = std::f32::consts::TAU / period;
                -radius * omega * omega * circle_direction(circle_angle(phase, period, t))
            }
            Curve::Spline { spline, speed, .. } => {
                speed * speed * spline.curvature_vector(speed * t)
            }
        }
    }

    /// Horizontal direction of travel at path time `t` (unit, y = 0): while
    /// moving horizontally, the direction of the velocity; while stopped or
    /// moving vertically, the last such direction before `t`, or before the
    /// path starts the first one. `None` when the path never moves
    /// horizontally (a static or vertical path).
    #[must_use]
    pub fn heading(&self, t: f32) -> Option<Vec3> {
        match &self.curve {
            Curve::Piecewise(p) => p.heading(t),
            &Curve::Circle { period, phase, .. } => {
                let theta = circle_angle(phase, period, t.max(0.0));
                Some(Vec3::new(-theta.sin(), 0.0, -theta.cos()))
            }
            Curve::Spline {
                spline,
                speed,
                chord_headings,
            } => {
                let s = (speed * t).clamp(0.0, spline.length());
                let tangent = spline.tangent(s);
                let horizontal = Vec3::new(tangent.x, 0.0, tangent.z);
                if horizontal.length() > 1e-4 {
                    Some(horizontal.normalize())
                } else {
                    chord_headings.get(spline.segment_at(s)).copied().flatten()
                }
            }
        }
    }

    /// Orientation from a `keyframes` path's `rotation_deg` at path time `t`
    /// (slerped between keys, held outside them); `None` for other paths and
    /// for keys without rotations. See also [`Self::keyframe_angular_velocity`].
    #[must_use]
    pub fn keyframe_rotation(&self, t: f32) -> Option<Quat> {
        match &self.curve {
            Curve::Piecewise(p) => p.rotation(t),
            _ => None,
        }
    }

    /// World angular velocity of [`Self::keyframe_rotation`] at path time
    /// `t`, rad/s (constant between two keys, 0 outside them); `None` when
    /// there is no keyframe rotation.
    #[must_use]
    pub fn keyframe_angular_velocity(&self, t: f32) -> Option<Vec3> {
        match &self.curve {
            Curve::Piecewise(p) => p.angular_velocity(t),
            _ => None,
        }
    }

    /// Whether the object moves at path time `t`: from the start (included)
    /// to the end (excluded).
    fn is_moving(&self, t: f32) -> bool {
        t >= self.start_time() && self.end_time().is_none_or(|end| t < end)
    }
}

/// Angle θ on a circle at time `t` ≥ 0, radians, computed in f64 over the
/// fraction of the current turn so that late times keep their precision.
fn circle_angle(phase: f32, period: f32, t: f32) -> f32 {
    let turns = (f64::from(t) / f64::from(period)).fract();
    (f64::from(phase) + TAU * turns) as f32
}

/// Unit vector at angle θ from +x towards −z (counter-clockwise from above).
fn circle_direction(theta: f32) -> Vec3 {
    Vec3::new(theta.cos(), 0.0, -theta.sin())
}

/// A polyline at constant `speed`: time of each point = distance along / speed.
/// Points that add no length (repeats) are skipped.
fn polyline(points: &[Vec3], speed: f32) -> Result<Piecewise, PathError> {
    let mut times = vec![0.0];
    let mut kept = vec![points[0]];
    let mut distance = 0.0_f64;
    for &p in &points[1..] {
        let previous = *kept.last().unwrap_or(&p);
        distance += f64::from(p.distance(previous));
        let t = (distance / f64::from(speed)) as f32;
        if t > *times.last().unwrap_or(&0.0) {
            times.push(t);
            kept.push(p);
        }
    }
    if kept.len() < 2 {
        return Err(PathError::ZeroLength);
    }
    check_duration(distance / f64::from(speed), speed)?;
    Ok(Piecewise::new(times, kept, None))
}

/// A keyframes path, validated.
fn keyframes(keys: &[Keyframe]) -> Result<Piecewise, PathError> {
    let first = keys.first().ok_or(PathError::NoKeys)?;
    let first_has_rotation = first.rotation_deg.is_some();
    let (mut times, mut points, mut rotations) = (Vec::new(), Vec::new(), Vec::new());
    for (index, key) in keys.iter().enumerate() {
        let t_s = finite(&format!("keys[{index}].t_s"), key.t_s)?;
        if let Some(&previous_t_s) = times.last()
            && t_s <= previous_t_s
        {
            return Err(PathError::KeysNotIncreasing {
                index,
                t_s,
                previous_t_s,
            });
        }
        if key.rotation_deg.is_some() != first_has_rotation {
            return Err(PathError::MixedRotations {
                index,
                first_has_rotation,
            });
        }
        times.push(t_s);
        points.push(finite3(format!("keys[{index}].position"), &key.position)?);
        if let Some(degrees) = &key.rotation_deg {
            finite3(format!("keys[{index}].rotation_deg"), degrees)?;
            rotations.push(rotation_from_euler_deg(*degrees));
        }
    }
    Ok(Piecewise::new(
        times,
        points,
        first_has_rotation.then_some(rotations),
    ))
}

/// At least two finite points.
fn point_list(points: &[[f32; 3]]) -> Result<Vec<Vec3>, PathError> {
    if points.len() < 2 {
        return Err(PathError::TooFewPoints {
            given: points.len(),
        });
    }
    let points = points
        .iter()
        .enumerate()
        .map(|(i, p)| finite3(format!("points[{i}]"), p))
        .collect::<Result<Vec<_>, _>>()?;
    if points.iter().all(|&p| p == points[0]) {
        return Err(PathError::ZeroLength);
    }
    Ok(points)
}

fn finite3(key: String, value: &[f32; 3]) -> Result<Vec3, PathError> {
    if value.iter().all(|c| c.is_finite()) {
        Ok(Vec3::from_array(*value))
    } else {
        Err(PathError::NonFinite {
            key,
            value: format!("[{}, {}, {}]", value[0], value[1], value[2]),
        })
    }
}

fn finite(key: &str, value: f32) -> Result<f32, PathError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(PathError::NonFinite {
            key: key.to_owned(),
            value: value.to_string(),
        })
    }
}

fn positive(key: &'static str, value: f32) -> Result<f32, PathError> {
    let value = finite(key, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(PathError::NotPositive { key, value })
    }
}

fn check_duration(duration_s: f64, speed: f32) -> Result<(), PathError> {
    if duration_s <= MAX_DURATION_S {
        Ok(())
    } else {
        Err(PathError::TooSlow {
            key: "speed_m_s",
            value: speed,
            duration_s,
        })
    }
}
