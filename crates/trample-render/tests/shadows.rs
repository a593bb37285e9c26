//! Light (issue 15 item 3): the sun's shadow map and the grass's ambient
//! occlusion. "Shadows": a still ball between the sun and the grass darkens
//! the grass in its shadow's footprint (found by casting the ball's centre
//! along the sun onto the grass and projecting it into the frame) against
//! the grass beside it, and does not with shadows off. "Ambient occlusion":
//! the roots of blades seen side-on darken more than their tips. Runs on
//! the adapter of `WGPU_BACKEND`; no adapter = failure.

mod common;

use glam::{Vec2, Vec3};
use trample::Simulation;
use trample::scene::Scene;
use trample_render::{RenderParams, Renderer};

const W: u32 = 320;
const H: u32 = 180;

/// Height on the blades (m, 0.45 tall) where the footprint is measured.
const GRASS_Y: f32 = 0.25;
/// The ball's radius (m).
const BALL_R: f32 = 0.3;

fn gpu() -> &'static trample_render::headless::Gpu {
    use std::sync::OnceLock;
    static GPU: OnceLock<trample_render::headless::Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        trample_render::headless::create_device()
            .unwrap_or_else(|e| panic!("the shadow tests need an adapter: {e}"))
    })
}

fn sun() -> Vec3 {
    RenderParams::default().sun_dir.normalize()
}

/// The centre of the ball's shadow on the grass: below the ball along the
/// sun, at [`GRASS_Y`].
fn footprint() -> Vec3 {
    Vec3::new(0.0, GRASS_Y, 0.0)
}

/// A 3.2 m field, a still ball 1.3 m up the sun's ray from the
/// [`footprint`] (well above the grass: nothing bends), the camera to the
/// side of the sun's ray with the sun behind its shoulder (the blades it
/// sees are lit, not back-lit), looking down at the footprint.
fn scene_with_ball() -> Simulation {
    let ball = footprint() + sun() * 1.3;
    let toml = common::ball_above_grass(ball, BALL_R);
    let mut sim = Scene::parse(&toml, "shadows.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap();
    sim.step(1.0 / 60.0).unwrap();
    sim
}

fn render(sim: &Simulation, params: RenderParams) -> image::RgbaImage {
    let gpu = gpu();
    let params = RenderParams {
        width: W,
        height: H,
        samples: gpu.msaa(4),
        ..params
    };
    Renderer::new(&gpu.device, &gpu.queue, sim, params)
        .unwrap()
        .render(&gpu.device, &gpu.queue, sim)
        .unwrap()
}

/// Pixel of world point `p` in `sim`'s frame (`None` behind the eye).
fn pixel(sim: &Simulation, p: Vec3) -> Option<Vec2> {
    let clip = sim.view_proj(W as f32 / H as f32) * p.extend(1.0);
    (clip.w > 0.0).then(|| {
        Vec2::new(
            (clip.x / clip.w * 0.5 + 0.5) * W as f32,
            (0.5 - clip.y / clip.w * 0.5) * H as f32,
        )
    })
}

/// Luminance (0–255, of the sRGB bytes) of a pixel.
fn luminance(p: &image::Rgba<u8>) -> f64 {
    0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2])
}

/// Mean luminance of the pixels of the points of a disc of radius `r_m`
/// around `centre` in the horizontal plane (a grid of points 2 cm apart).
fn disc_luminance(sim: &Simulation, frame: &image::RgbaImage, centre: Vec3, r_m: f32) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    let steps = (r_m / 0.02) as i32;
    for i in -steps..=steps {
        for j in -steps..=steps {
            let d = Vec3::new(i as f32, 0.0, j as f32) * 0.02;
            if d.length() > r_m {
                continue;
            }
            let Some(px) = pixel(sim, centre + d) else {
                continue;
            };
            let (x, y) = (px.x as i64, px.y as i64);
            if (0..i64::from(W)).contains(&x) && (0..i64::from(H)).contains(&y) {
                sum += luminance(frame.get_pixel(x as u32, y as u32));
                n += 1;
            }
        }
    }
    assert!(n > 20, "the disc at {centre} is not in the frame ({n} px)");
    sum / n as f64
}

/// (footprint, beside) mean luminance: the ball's shadow on the grass and
/// two discs as large either side of it, across the sun (three ball radii
/// away), where the ball casts nothing.
fn footprint_and_beside(sim: &Simulation, frame: &image::RgbaImage) -> (f64, f64) {
    let r = 0.5 * BALL_R;
    let across = Vec3::Y.cross(sun()).normalize() * 3.0 * BALL_R;
    let f = footprint();
    let shadow = disc_luminance(sim, frame, f, r);
    let beside = 0.5
        * (disc_luminance(sim, frame, f + across, r) + disc_luminance(sim, frame, f - across, r));
    (shadow, beside)
}

#[test]
fn the_ball_shadows_the_grass_in_its_footprint() {
    let sim = scene_with_ball();
    let on = render(&sim, RenderParams::default());
    let off = render(
        &sim,
        RenderParams {
            shadow_strength: 0.0,
            ..RenderParams::default()
        },
    );
    let dir = std::env::temp_dir();
    let _ = on.save(dir.join("trample-shadows-on.png"));
    let _ = off.save(dir.join("trample-shadows-off.png"));
    let (shadow_on, beside_on) = footprint_and_beside(&sim, &on);
    let (shadow_off, beside_off) = footprint_and_beside(&sim, &off);
    eprintln!(
        "footprint / beside luminance: shadows on {shadow_on:.1} / {beside_on:.1} ({:.2}), off {shadow_off:.1} / {beside_off:.1} ({:.2})",
        shadow_on / beside_on,
        shadow_off / beside_off
    );
    assert!(
        shadow_on < 0.7 * beside_on,
        "the footprint ({shadow_on:.1}) must be clearly darker than beside it ({beside_on:.1})"
    );
    assert!(
        shadow_off > 0.9 * beside_off,
        "without shadows the footprint ({shadow_off:.1}) is as light as beside it ({beside_off:.1})"
    );
    // Only the footprint changes: beside it the light is the same.
    assert!(
        (beside_on - beside_off).abs() < 0.05 * beside_off,
        "beside: {beside_on:.1} with shadows, {beside_off:.1} without"
    );
}

#[test]
fn the_gpu_path_draws_the_shadow_too() {
    // The same frame drawn from the GPU path's buffers (`prepare_gpu`
    // records the shadow pass too).
    let gpu = gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let cpu = scene_with_ball();
    let mut g = trample_gpu::GpuSimulation::new(device, queue, cpu.clone()).unwrap();
    g.step(device, queue, 1.0 / 60.0).unwrap();
    let frame = |shadow_strength: f32, g: &mut trample_gpu::GpuSimulation| {
        let params = RenderParams {
            width: W,
            height: H,
            samples: gpu.msaa(4),
            shadow_strength,
            ..RenderParams::default()
        };
        Renderer::new_gpu(device, queue, g, params)
            .unwrap()
            .render_gpu(device, queue, g)
            .unwrap()
    };
    let (on, off) = (frame(1.0, &mut g), frame(0.0, &mut g));
    let _ = on.save(std::env::temp_dir().join("trample-shadows-gpu-on.png"));
    let (shadow_on, beside_on) = footprint_and_beside(&cpu, &on);
    let (shadow_off, beside_off) = footprint_and_beside(&cpu, &off);
    eprintln!(
        "GPU path: footprint / beside {:.2} with shadows, {:.2} without",
        shadow_on / beside_on,
        shadow_off / beside_off
    );
    assert!(
        shadow_on < 0.7 * beside_on,
        "{shadow_on:.1} / {beside_on:.1}"
    );
    assert!(
        shadow_off > 0.9 * beside_off,
        "{shadow_off:.1} / {beside_off:.1}"
    );
}

/// Whether `p` reads as grass: green above red and blue (not the sky).
fn is_grass(p: &image::Rgba<u8>) -> bool {
    let [r, g, b, _] = p.0;
    g > r && g > b
}

/// Eye height (m) of the side view of [`blades_side_on`].
const EYE_Y: f32 = 0.06;

/// A 3.2 m field of standing blades (0.45 m) seen side-on from just above
/// the ground, 0.6 m outside its near edge (z = 1.6), looking along -z.
fn blades_side_on() -> Simulation {
    let toml = common::light_field(
        &format!(
            r#"path = {{ kind = "static", position = [0.0, {EYE_Y}, 2.2] }}
look_at = {{ kind = "point", at = [0.0, {EYE_Y}, 0.0] }}"#
        ),
        "",
    );
    let mut sim = Scene::parse(&toml, "ao.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap();
    sim.step(1.0 / 60.0).unwrap();
    sim
}

/// Mean luminance with ambient occlusion over without, over the grass
/// pixels (of the frame without) of image rows `rows`.
fn darkening(
    with: &image::RgbaImage,
    without: &image::RgbaImage,
    rows: std::ops::Range<u32>,
) -> (f64, usize) {
    let (mut on, mut off, mut n) = (0.0, 0.0, 0usize);
    for y in rows {
        for x in 0..W {
            let p = without.get_pixel(x, y);
            if is_grass(p) {
                off += luminance(p);
                on += luminance(with.get_pixel(x, y));
                n += 1;
            }
        }
    }
    (on / off.max(1e-9), n)
}

#[test]
fn ambient_occlusion_darkens_the_roots_more_than_the_tips() {
    let sim = blades_side_on();
    let no_shadows = RenderParams {
        shadow_strength: 0.0,
        ..RenderParams::default()
    };
    let with = render(&sim, no_shadows);
    let without = render(
        &sim,
        RenderParams {
            ambient_occlusion: 0.0,
            ..no_shadows
        },
    );
    let dir = std::env::temp_dir();
    let _ = with.save(dir.join("trample-ao-on.png"));
    let _ = without.save(dir.join("trample-ao-off.png"));
    let row = |p: Vec3| pixel(&sim, p).unwrap().y.round() as u32;
    // At eye height every blade is seen near its root (the horizon row,
    // whatever its distance); 0.3-0.4 m up on the nearest blades, only the
    // upper thirds of blades show.
    let horizon = row(Vec3::new(0.0, EYE_Y, 0.0));
    let (roots, n_roots) = darkening(&with, &without, horizon - 3..horizon + 4);
    let (lo, hi) = (row(Vec3::new(0.0, 0.4, 1.6)), row(Vec3::new(0.0, 0.3, 1.6)));
    let (tips, n_tips) = darkening(&with, &without, lo..hi);
    eprintln!(
        "ambient occlusion: luminance with / without {roots:.2} at the roots ({n_roots} px, rows about {horizon}), {tips:.2} at the tips ({n_tips} px, rows {lo}..{hi})"
    );
    assert!(n_roots > 200 && n_tips > 200, "{n_roots} {n_tips}");
    assert!(roots < 0.8, "roots darken to {roots:.2} of their light");
    assert!(tips > 0.9, "tips keep {tips:.2} of their light");
}
