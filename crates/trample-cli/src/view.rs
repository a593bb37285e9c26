//! `trample view`: the interactive viewer (crate `trample-view`) on a scene.

use crate::backend::Backend;
use crate::common::{SimOverrides, load_scene};
use anyhow::Result;
use std::path::PathBuf;
use trample_view::{StartBackend, ViewOptions, run as view};

/// Arguments of `trample view`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML); none = the embedded default scene.
    pub scene: Option<PathBuf>,
    /// Window size, WIDTHxHEIGHT. Default 960x540: a software driver
    /// renders the default scene at 1280x720 in seconds per frame.
    #[arg(long, default_value = "960x540", value_parser = crate::common::parse_size)]
    pub size: (u32, u32),
    /// Close after N frames (for tests and scripts).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write the last frame, panel included, to this PNG on closing
    /// (with --frames: after N frames).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Collision precision, OBB-tree depth 1..=32 (overrides `[sim] precision`).
    #[arg(long)]
    pub precision: Option<u32>,
    /// Simulation path to start on (the panel switches it live): auto (the
    /// default, as for `run`) = the GPU on a hardware adapter, else the
    /// CPU; gpu = the GPU path, also on a software adapter; cpu = the
    /// reference. The GPU path runs on the window's device and is drawn
    /// straight from its buffers; a scene it refuses (a field too large for
    /// the device) runs on the CPU, and stderr says why.
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    pub backend: Backend,
}

/// Runs the viewer until its window closes.
pub fn run(a: &Args) -> Result<()> {
    let scene = load_scene(
        a.scene.as_deref(),
        SimOverrides {
            precision: a.precision,
            ..SimOverrides::default()
        },
    )?;
    view(ViewOptions {
        scene,
        size: [a.size.0, a.size.1],
        frames: a.frames,
        screenshot: a.screenshot.clone(),
        samples: 4,
        backend: match a.backend {
            Backend::Cpu => StartBackend::Cpu,
            Backend::Gpu => StartBackend::Gpu,
            Backend::Auto => StartBackend::Auto,
        },
    })?;
    Ok(())
}
