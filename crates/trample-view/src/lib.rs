//! `trample view`: an interactive window on a scene (issue 7).
//!
//! The window (winit + wgpu) shows the renderer's frame with an egui panel
//! over it; the simulation steps once a frame. What the viewer does lives in
//! window-free pieces that tests drive directly:
//! - [`input`]: keys → held axes and [`input::Action`]s;
//! - [`driver`]: the arrow-key driven object;
//! - [`camera`]: orbit and free-fly controllers;
//! - [`app`]: the state they act on ([`App`]);
//! - [`backend`]: the path that steps the simulation, CPU or GPU (on the
//!   window's device);
//! - [`panel`]: the egui panel; [`window`]: the event loop; [`blit`]: the
//!   copy of the frame onto the window surface.

pub mod app;
pub mod backend;
pub mod blit;
pub mod camera;
pub mod driver;
pub mod input;
pub mod panel;
pub mod window;

pub use app::App;
pub use backend::{BackendKind, GpuDevice, StartBackend};
pub use window::{ViewOptions, run};

/// Why the viewer could not run. Each message is one line.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// No display to open a window on.
    #[error(
        "cannot open a window ({0}); for output without a display use `trample run`, or run under Xvfb: xvfb-run -a trample view"
    )]
    NoDisplay(String),
    /// The scene does not build.
    #[error("{0}")]
    Scene(String),
    /// The window, surface or GPU device could not be made.
    #[error("graphics: {0}")]
    Graphics(String),
    /// A step refused the live parameters.
    #[error("simulation: {0}")]
    Step(String),
    /// A screenshot could not be written.
    #[error("screenshot {path}: {reason}")]
    Screenshot {
        /// The file.
        path: String,
        /// Why.
        reason: String,
    },
}
