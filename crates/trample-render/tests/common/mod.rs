//! Scenes and settings shared by the renderer's tests (each test file
//! that uses them declares `mod common;`).

// Each test binary compiles this module and uses only part of it.
#![allow(dead_code)]

use glam::Vec3;
use trample_render::{DebugView, RenderParams};

/// The tests' render settings: a `width` × `height` frame with 4× MSAA
/// where the device has it, the view `debug`, the rest the defaults.
pub fn test_params(
    gpu: &trample_render::headless::Gpu,
    width: u32,
    height: u32,
    debug: DebugView,
) -> RenderParams {
    RenderParams {
        width,
        height,
        samples: gpu.msaa(4),
        debug,
        ..Default::default()
    }
}

/// The light tests' field: 3.2 m square (4 × 4 patches of 8 × 8 cells of
/// 10 cm), blades 0.45 m tall and 3 cm wide, every cell geometric, with
/// `camera` (the body of a `[camera]` table) and `rest` (more TOML, e.g.
/// `[[objects]]`) appended.
pub fn light_field(camera: &str, rest: &str) -> String {
    format!(
        r#"
[field]
patches = [4, 4]
cells_per_patch = 8
cell_size_m = 0.1
blade_height_m = 0.45
blade_width_m = 0.03
[lod]
geometry_m = 50.0
billboard_m = 60.0
[camera]
{camera}
{rest}
"#
    )
}

/// [`light_field`] with a still ball of radius `radius` at `ball`, seen
/// from the side of the sun's ray with the sun behind the camera's
/// shoulder, looking down at the middle of the field.
pub fn ball_above_grass(ball: Vec3, radius: f32) -> String {
    light_field(
        r#"path = { kind = "static", position = [0.95, 1.6, 1.67] }
look_at = { kind = "point", at = [0.0, 0.1, 0.0] }"#,
        &format!(
            r#"[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = {radius}, subdivisions = 3 }}
path = {{ kind = "static", position = [{}, {}, {}] }}"#,
            ball.x, ball.y, ball.z
        ),
    )
}
