//! Per-frame values every pass reads: camera, sun, sky, fog, debug view.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec4};

/// WGSL of [`Globals`] and the helpers every shader shares (lighting, fog,
/// hash); prepended to each pass's own WGSL by [`shader_source`].
pub const GLOBALS_WGSL: &str = include_str!("globals.wgsl");

/// Per-frame uniform block. Layout-compatible with the struct `Globals` in globals.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Globals {
    /// World → clip.
    pub view_proj: Mat4,
    /// Clip → world (the sky reconstructs view rays from it).
    pub inv_view_proj: Mat4,
    /// xyz eye position, w time in seconds.
    pub eye: Vec4,
    /// xyz unit direction towards the sun, w ambient strength.
    pub sun_dir: Vec4,
    /// rgb sun colour (linear).
    pub sun_color: Vec4,
    /// rgb sky overhead (linear).
    pub sky_zenith: Vec4,
    /// rgb sky at the horizon (linear): also the fog colour.
    pub sky_horizon: Vec4,
    /// x fog start, y fog end, z `geometry_m`, w `billboard_m` (metres).
    pub fog: Vec4,
    /// x debug view (0 none, 1 classes), y segments per blade, z blade
    /// count, w 1 when the shaders encode sRGB (a non-sRGB target), else 0.
    pub params: UVec4,
    /// Wind ([`trample::wind`]): xz unit direction, y steady tip
    /// displacement (m), w gust amplitude (m).
    pub wind: Vec4,
    /// Wind gusts: x period (s), y wavelength (m); z drawn copies per
    /// simulated blade, w their reach (m) (render density).
    pub gusts: Vec4,
    /// Blend bands between levels of detail (issue 15 item 1), metres: x
    /// past `geometry_m`, where the blades of billboard cells thin out as
    /// the billboards fade in; y before `billboard_m`, where the billboards
    /// thin out over the ground. zw unused.
    pub blend: Vec4,
    /// World → the sun's shadow-map clip space ([`crate::shadows::light_view_proj`]).
    pub light_view_proj: Mat4,
    /// x shadow strength (0 = no shadows: the map is not sampled), y
    /// ambient-occlusion strength, z depth bias of the shadow test (clip
    /// depth), w unused.
    pub shadow: Vec4,
}

const _: () = assert!(std::mem::size_of::<Globals>() == 368);

/// The full source of a pass: the blade shape every renderer shares
/// ([`trample::blade_shape::WGSL`]: hash, wind bend, strip, colour), the
/// globals, then `own`.
#[must_use]
pub fn shader_source(own: &str) -> String {
    format!("{}\n{GLOBALS_WGSL}\n{own}", trample::blade_shape::WGSL)
}

/// Compiles a pass's WGSL (with the shared globals prepended).
#[must_use]
pub fn shader_module(device: &wgpu::Device, label: &str, own: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(shader_source(own).into()),
    })
}
