//! The viewpoint of the level of detail (the eye P of the paper's Fig. 1)
//! and of frustum culling: the scene's camera (an eye on a path, evaluated
//! at every sub-step) or the host's camera, a [`HostView`] handed in by the
//! program that embeds the simulation (issue 14: a game's own camera).
//!
//! While a host view is set, [`Simulation::step`] classifies cells by
//! distance to its `eye` and culls patches against its `view_proj`; the
//! scene's camera path is still evaluated into [`Simulation::view`] (cheap,
//! and what [`Simulation::clear_view`] returns to) but decides nothing.
//! Renderers draw with [`Simulation::view_proj`] and [`Simulation::eye`],
//! which follow whichever camera is in charge.

use super::simulation::Simulation;
use crate::field::{Frustum, cull_patches};
use glam::camera::rh::{proj::directx::perspective, view::look_at_mat4};
use glam::{Mat4, Vec3};

/// A camera the host hands in ([`Simulation::set_view`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostView {
    /// Eye position, world metres: the viewpoint of the level of detail
    /// (each cell's level is chosen by its centre's distance to it).
    pub eye: Vec3,
    /// World → clip matrix with clip z in [0, 1] (wgpu/D3D; for a
    /// [-1, 1] (OpenGL) projection the near plane culls a little too
    /// much). Patches wholly outside its frustum are marked invisible
    /// ([`Simulation::visible`]); they go on being simulated.
    pub view_proj: Mat4,
}

/// Why a [`HostView`] was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ViewError {
    /// The eye has a NaN or infinite coordinate.
    #[error("host view: eye = {eye}: every coordinate must be finite")]
    NonFiniteEye {
        /// The eye given.
        eye: Vec3,
    },
    /// The matrix has a NaN or infinite entry, or cannot be inverted
    /// (determinant 0: no frustum).
    #[error("host view: view_proj must be finite and invertible (determinant {determinant})")]
    BadMatrix {
        /// Its determinant.
        determinant: f32,
    },
    /// A lens value of [`HostView::look_at`] out of range.
    #[error("host view: {what}: need 0 < fov_y < π, aspect > 0 and 0 < near < far, all finite")]
    BadLens {
        /// The values given.
        what: String,
    },
}

impl HostView {
    /// A view from `eye` towards `target` (y up; z up when looking straight
    /// up or down) through a perspective lens: vertical field of view
    /// `fov_y` radians, `aspect` = width / height, near and far planes in
    /// metres. See also [`HostView::new`] for a matrix of the host's own.
    ///
    /// # Errors
    /// [`ViewError`] for a non-finite eye or target, a target at the eye, or
    /// a lens out of range.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        fov_y: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Result<Self, ViewError> {
        let lens_ok = fov_y > 0.0
            && fov_y < std::f32::consts::PI
            && aspect.is_finite()
            && aspect > 0.0
            && near.is_finite()
            && near > 0.0
            && far.is_finite()
            && far > near;
        if !lens_ok {
            return Err(ViewError::BadLens {
                what: format!("fov_y = {fov_y}, aspect = {aspect}, near = {near}, far = {far}"),
            });
        }
        let dir = (target - eye).normalize_or_zero();
        let up = if dir.abs().y > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let view = look_at_mat4(eye, target, up);
        Self::new(eye, perspective(fov_y, aspect, near, far) * view)
    }

    /// A view from the host's own eye and world → clip matrix, checked.
    ///
    /// # Errors
    /// [`ViewError`] for a non-finite eye or a matrix that is not finite
    /// and invertible.
    pub fn new(eye: Vec3, view_proj: Mat4) -> Result<Self, ViewError> {
        let view = Self { eye, view_proj };
        view.check()?;
        Ok(view)
    }

    /// Checks the values (the fields are public, so [`Simulation::set_view`]
    /// checks again).
    ///
    /// # Errors
    /// As [`HostView::new`].
    pub fn check(&self) -> Result<(), ViewError> {
        if !self.eye.is_finite() {
            return Err(ViewError::NonFiniteEye { eye: self.eye });
        }
        let determinant = self.view_proj.determinant();
        if !self.view_proj.is_finite() || determinant == 0.0 || !determinant.is_finite() {
            return Err(ViewError::BadMatrix { determinant });
        }
        Ok(())
    }

    /// The frustum of `view_proj`.
    #[must_use]
    pub fn frustum(&self) -> Frustum {
        Frustum::from_view_proj(self.view_proj)
    }
}

impl Simulation {
    /// From now on the level of detail and culling follow the host's camera
    /// `view` instead of the scene's camera path; call it every frame the
    /// camera moves, before [`Simulation::step`]. Culling
    /// ([`Simulation::visible`]) is redone at once, so a paused host draws
    /// the right patches; levels of detail change at the next step (which
    /// blends them, Eq. 9–13). See also [`Simulation::clear_view`].
    ///
    /// # Errors
    /// [`ViewError`] (and nothing changes) when `view` is not finite or its
    /// matrix cannot be inverted.
    pub fn set_view(&mut self, view: HostView) -> Result<(), ViewError> {
        view.check()?;
        self.host_view = Some(view);
        self.cull();
        Ok(())
    }

    /// Hands the level of detail and culling back to the scene's camera
    /// path (at the current time); culling is redone at once.
    pub fn clear_view(&mut self) {
        self.host_view = None;
        self.update_view(self.time as f32);
        self.cull();
    }

    /// The host's camera, when one is in charge ([`Simulation::set_view`]).
    #[must_use]
    pub fn host_view(&self) -> Option<&HostView> {
        self.host_view.as_ref()
    }

    /// The viewpoint of the level of detail now: the host's eye, or the
    /// scene camera's at the last sub-step.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.host_view.map_or(self.view.eye, |h| h.eye)
    }

    /// World → clip (z in [0, 1]) of the camera in charge: the host's
    /// matrix as given, or the scene camera's view with its lens drawn at
    /// `aspect` (width / height of the picture being drawn).
    #[must_use]
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        match self.host_view {
            Some(h) => h.view_proj,
            None => {
                let mut v = self.view;
                v.aspect = aspect;
                v.proj() * v.view()
            }
        }
    }

    /// The frustum that culls patches: the host's, or the scene camera's
    /// (with the scene's aspect).
    #[must_use]
    pub fn frustum(&self) -> Frustum {
        self.host_view
            .map_or_else(|| self.view.frustum(), |h| h.frustum())
    }

    /// Evaluates the scene's camera at time `t` (seconds) into
    /// [`Simulation::view`], with the bodies where they are now: the
    /// viewpoint of a sub-step ending at `t`. Both paths' steps call it
    /// once per sub-step. A host view, if set, stays in charge.
    pub fn update_view(&mut self, t: f32) {
        let positions: Vec<Vec3> = self.bodies.iter().map(|b| b.pose.position).collect();
        self.view = self.camera.view_at(t, &positions);
    }

    /// Levels of detail from the camera in charge now, without a step and
    /// without the transitions (Eq. 9–13): only for a field at rest (a
    /// simulation being built), where they have nothing to carry over.
    pub(crate) fn classify_at_rest(&mut self) {
        let (mut changes, eye) = (Vec::new(), self.eye());
        self.timings.lod = crate::field::classify_cells(
            &self.field.layout,
            &mut self.field.cells,
            eye,
            &self.lod,
            &mut changes,
        );
    }

    /// Frustum culling per patch for the camera in charge, into
    /// [`Simulation::visible`]; returns the number of visible patches (also
    /// kept in `timings.visible_patches`).
    pub fn cull(&mut self) -> u32 {
        let frustum = self.frustum();
        let n = cull_patches(&self.field.layout, &frustum, &mut self.visible);
        self.timings.visible_patches = n;
        n
    }
}
