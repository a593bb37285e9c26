//! The scene's camera: a path for the eye and a point or object to look at.
//! Its eye is the viewpoint P of the level of detail (paper Fig. 1).

use crate::field::Frustum;
use crate::object::path::{Path, PathParams};
use glam::camera::rh::{proj::directx::perspective, view::look_at_mat4};
use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

/// `[camera]` table of a scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraParams {
    /// Path of the eye. Default: a track-side camera moving along +x.
    pub path: PathParams,
    /// What the eye looks at. Default: the object named `ball`, falling back
    /// to the field centre when there is none.
    pub look_at: LookAt,
    /// Vertical field of view, degrees. Default 50.
    pub fov_y_deg: f32,
    /// Width / height of the picture, used for culling. Default 16/9.
    pub aspect: f32,
    /// Near plane, metres. Default 0.1.
    pub near_m: f32,
    /// Far plane, metres. Default 200.
    pub far_m: f32,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            path: PathParams::Line {
                from: [-21.0, 3.0, 7.5],
                to: [17.0, 3.0, 7.5],
                duration_s: 12.0,
            },
            look_at: LookAt::Object {
                name: "ball".into(),
            },
            fov_y_deg: 50.0,
            aspect: 16.0 / 9.0,
            near_m: 0.1,
            far_m: 200.0,
        }
    }
}

/// A `[camera]` value out of range. The message names the key.
#[derive(Debug, thiserror::Error)]
pub enum CameraError {
    /// `fov_y_deg` not in (0, 180).
    #[error("camera.fov_y_deg = {0}: must be in (0, 180) degrees")]
    FovY(f32),
    /// `aspect` not finite and positive.
    #[error("camera.aspect = {0}: must be a finite number > 0")]
    Aspect(f32),
    /// Near and far planes not `0 < near_m < far_m`, finite.
    #[error(
        "camera.near_m = {near_m}, camera.far_m = {far_m}: need 0 < near_m < far_m, both finite"
    )]
    Planes {
        /// Near plane given.
        near_m: f32,
        /// Far plane given.
        far_m: f32,
    },
    /// The eye's path is invalid.
    #[error("camera.{0}")]
    Path(crate::object::PathError),
}

impl CameraParams {
    /// Checks the lens and the eye's path (not `look_at`, which needs the
    /// objects: see [`crate::builder::SimulationBuilder::validate`]).
    ///
    /// # Errors
    /// [`CameraError`] naming the key.
    pub fn validate(&self) -> Result<(), CameraError> {
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(CameraError::FovY(self.fov_y_deg));
        }
        if !(self.aspect.is_finite() && self.aspect > 0.0) {
            return Err(CameraError::Aspect(self.aspect));
        }
        let (near_m, far_m) = (self.near_m, self.far_m);
        if !(near_m.is_finite() && near_m > 0.0 && far_m.is_finite() && far_m > near_m) {
            return Err(CameraError::Planes { near_m, far_m });
        }
        Path::new(self.path.clone())
            .map(|_| ())
            .map_err(CameraError::Path)
    }
}

/// What the camera looks at.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum LookAt {
    /// A fixed point, metres.
    Point {
        /// World position.
        at: [f32; 3],
    },
    /// The current position of an object, by name.
    Object {
        /// The object's `name`.
        name: String,
    },
}

/// A camera ready to evaluate.
#[derive(Clone, Debug)]
pub struct Camera {
    /// The eye's path.
    pub eye: Path,
    /// Index of the followed object, or a fixed target.
    pub target: CameraTarget,
    /// The parameters it was built from.
    pub params: CameraParams,
}

/// Resolved [`LookAt`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraTarget {
    /// A fixed point.
    Point(Vec3),
    /// The object with this index.
    Object(usize),
}

/// Where the camera is at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// Eye position: the viewpoint of the level of detail.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Width / height.
    pub aspect: f32,
    /// Near plane, metres.
    pub near: f32,
    /// Far plane, metres.
    pub far: f32,
}

impl CameraView {
    /// World → view matrix (right-handed, y up).
    #[must_use]
    pub fn view(&self) -> Mat4 {
        let up = if (self.target - self.eye).normalize_or_zero().abs().y > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        look_at_mat4(self.eye, self.target, up)
    }

    /// View → clip matrix (clip z in [0, 1], as wgpu wants).
    #[must_use]
    pub fn proj(&self) -> Mat4 {
        perspective(self.fov_y, self.aspect, self.near, self.far)
    }

    /// Frustum planes for culling.
    #[must_use]
    pub fn frustum(&self) -> Frustum {
        Frustum::from_view_proj(self.proj() * self.view())
    }
}

impl Camera {
    /// The view at time `t`, given the objects' current positions.
    #[must_use]
    pub fn view_at(&self, t: f32, object_positions: &[Vec3]) -> CameraView {
        let eye = self.eye.position(t);
        let target = match self.target {
            CameraTarget::Point(p) => p,
            CameraTarget::Object(i) => object_positions.get(i).copied().unwrap_or(Vec3::ZERO),
        };
        let target = if target.distance(eye) < 1e-3 {
            eye - Vec3::Z
        } else {
            target
        };
        CameraView {
            eye,
            target,
            fov_y: self.params.fov_y_deg.to_radians(),
            aspect: self.params.aspect,
            near: self.params.near_m,
            far: self.params.far_m,
        }
    }
}
