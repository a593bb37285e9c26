//! Paths: where an object's origin is at time t (DESIGN §3).
//!
//! PARAMS ARE THE SCENE-FILE CONTRACT (fixed). Evaluation: object helper.

use glam::Vec3;
use serde::{Deserialize, Serialize};

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
    Circle {
        /// Centre, metres.
        center: [f32; 3],
        /// Radius, metres (> 0).
        radius_m: f32,
        /// Time for one turn, seconds (> 0).
        period_s: f32,
        /// Start angle, radians from +x towards +z. Default 0.
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
    /// interpolated (orientations slerped).
    Keyframes {
        /// At least one key, times strictly increasing.
        keys: Vec<Keyframe>,
    },
}

/// One key of a [`PathParams::Keyframes`] path.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    /// Time, seconds.
    pub t_s: f32,
    /// World position, metres.
    pub position: [f32; 3],
    /// Orientation as Euler angles (yaw about y, pitch about x, roll about z;
    /// applied y, x, z), degrees. Only used with `orientation = "keyframes"`.
    #[serde(default)]
    pub rotation_deg: Option<[f32; 3]>,
}

/// A validated path, ready to evaluate.
#[derive(Clone, Debug)]
pub struct Path {
    /// What it was built from.
    pub params: PathParams,
}

impl Path {
    /// STUB
    pub fn new(p: PathParams) -> Result<Path, String> {
        Ok(Path { params: p })
    }
    /// Position at time `t`, metres.
    #[must_use]
    pub fn position(&self, _t: f32) -> Vec3 {
        todo!("object helper")
    }
}
