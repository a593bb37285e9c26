//! The camera a frame is drawn with: the host's matrices (issue 14), or the
//! simulation's own camera for tools that have none.

use glam::{Mat4, Vec3};
use trample::Simulation;

/// The camera of one frame: what the host draws its own geometry with, so
/// that the grass lines up with it in the shared depth buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCamera {
    /// World → clip, clip z in [0, 1] (wgpu's convention), metres.
    pub view_proj: Mat4,
    /// Eye position, world metres: lighting, fog and the blades' facing
    /// are computed from it.
    pub eye: Vec3,
}

impl FrameCamera {
    /// The camera in charge of `sim` ([`Simulation::view_proj`],
    /// [`Simulation::eye`]: the host's view set with
    /// [`Simulation::set_view`], else the scene's camera path) drawn at
    /// `aspect` = width / height (used only for the scene's camera).
    #[must_use]
    pub fn of(sim: &Simulation, aspect: f32) -> Self {
        Self {
            view_proj: sim.view_proj(aspect),
            eye: sim.eye(),
        }
    }
}

impl From<trample::step::HostView> for FrameCamera {
    fn from(v: trample::step::HostView) -> Self {
        Self {
            view_proj: v.view_proj,
            eye: v.eye,
        }
    }
}
