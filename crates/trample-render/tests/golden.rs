//! Golden images: tiny scenes rendered offscreen on the adapter of
//! `WGPU_BACKEND` (GL on llvmpipe in CI) and compared with the references in
//! tests/golden/ within a tolerance. A failure writes NAME-actual.png and
//! NAME-difference.png next to the reference. A missing reference is a
//! failure too (it writes NAME-actual.png). References are made only on
//! request: `TRAMPLE_BLESS=1` writes the frame as the reference of every
//! golden test whose reference is missing or differs (then look at it,
//! then commit it; CONTRIBUTING.md). No adapter = failure, not a skip.

mod common;

use std::path::PathBuf;
use trample::Simulation;
use trample::scene::Scene;
use trample_render::{DebugView, RenderParams, Renderer};

/// Mean absolute difference per channel (0–255) allowed.
const MAX_MEAN_DIFF: f64 = 2.0;
/// Share of pixels allowed to differ by more than [`PIXEL_TOLERANCE`] in some channel.
const MAX_DIFFERING: f64 = 0.02;
/// A channel difference above this makes a pixel "differing".
const PIXEL_TOLERANCE: u8 = 24;

const W: u32 = 160;
const H: u32 = 90;

fn gpu() -> &'static trample_render::headless::Gpu {
    use std::sync::OnceLock;
    static GPU: OnceLock<trample_render::headless::Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        let gpu = trample_render::headless::create_device()
            .unwrap_or_else(|e| panic!("golden tests need an adapter: {e}"));
        eprintln!("golden: adapter {}", gpu.adapter_name());
        gpu
    })
}

fn scene(toml: &str) -> Simulation {
    Scene::parse(toml, "golden.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

fn render(sim: &Simulation, debug: DebugView) -> image::RgbaImage {
    let gpu = gpu();
    let params = common::test_params(gpu, W, H, debug);
    let mut r = Renderer::new(&gpu.device, &gpu.queue, sim, params).unwrap();
    r.render(&gpu.device, &gpu.queue, sim).unwrap()
}

/// (mean absolute difference, share of differing pixels, difference image).
fn compare(a: &image::RgbaImage, b: &image::RgbaImage) -> (f64, f64, image::RgbaImage) {
    let mut diff = image::RgbaImage::new(a.width(), a.height());
    let (mut sum, mut differing) = (0u64, 0usize);
    for ((pa, pb), pd) in a.pixels().zip(b.pixels()).zip(diff.pixels_mut()) {
        let mut worst = 0u8;
        for c in 0..3 {
            let d = pa[c].abs_diff(pb[c]);
            sum += u64::from(d);
            worst = worst.max(d);
        }
        if worst > PIXEL_TOLERANCE {
            differing += 1;
        }
        let v = worst.saturating_mul(4);
        *pd = image::Rgba([v, v, v, 255]);
    }
    let n = (a.width() * a.height()) as f64;
    (sum as f64 / (3.0 * n), differing as f64 / n, diff)
}

/// The environment variable that makes [`check`] write references.
const BLESS: &str = "TRAMPLE_BLESS";

fn check(name: &str, actual: &image::RgbaImage) {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden"));
    let reference = dir.join(format!("{name}.png"));
    let actual_path = dir.join(format!("{name}-actual.png"));
    let diff_path = dir.join(format!("{name}-difference.png"));
    let bless = std::env::var_os(BLESS).is_some_and(|v| v == "1");
    if !reference.exists() {
        if bless {
            actual.save(&reference).unwrap();
            eprintln!(
                "golden: {BLESS}=1 wrote {} — look at it, then commit it",
                reference.display()
            );
            return;
        }
        actual.save(&actual_path).unwrap();
        panic!(
            "{}: missing reference; wrote {}. To make it the reference: {BLESS}=1 cargo test -p trample-render --test golden (CONTRIBUTING.md)",
            reference.display(),
            actual_path.display()
        );
    }
    let expected = image::open(&reference).unwrap().to_rgba8();
    assert_eq!(
        expected.dimensions(),
        actual.dimensions(),
        "{name}: size differs from the reference"
    );
    let (mean, share, diff) = compare(&expected, actual);
    if mean > MAX_MEAN_DIFF || share > MAX_DIFFERING {
        if bless {
            actual.save(&reference).unwrap();
            eprintln!(
                "golden: {name} differed (mean {mean:.2}, {:.2} % pixels); {BLESS}=1 wrote {} — look at it, then commit it",
                share * 100.0,
                reference.display()
            );
            return;
        }
        actual.save(&actual_path).unwrap();
        diff.save(&diff_path).unwrap();
        panic!(
            "{name}: mean abs difference {mean:.2} (max {MAX_MEAN_DIFF}), {:.2} % pixels differ (max {:.2} %); wrote {} and {}",
            share * 100.0,
            MAX_DIFFERING * 100.0,
            actual_path.display(),
            diff_path.display()
        );
    }
    let _ = std::fs::remove_file(&actual_path);
    let _ = std::fs::remove_file(&diff_path);
}

/// A small field (8×8 cells per patch, 2×2 patches = 1.6 m square) and a
/// ball that rolls into it; the camera looks from `eye` at `target`.
fn small_scene(
    eye: [f32; 3],
    target: [f32; 3],
    lod: (f32, f32),
    cell: f32,
    patches: u32,
) -> String {
    format!(
        r#"
[field]
patches = [{patches}, {patches}]
cells_per_patch = 8
cell_size_m = {cell}
blade_height_m = 0.45
blade_width_m = 0.03
[lod]
geometry_m = {g}
billboard_m = {b}
[camera]
path = {{ kind = "static", position = [{ex}, {ey}, {ez}] }}
look_at = {{ kind = "point", at = [{tx}, {ty}, {tz}] }}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.3, subdivisions = 2 }}
orientation = "rolling"
path = {{ kind = "line", from = [-1.5, 0.3, 0.0], to = [0.0, 0.3, 0.0], duration_s = 1.0 }}
"#,
        g = lod.0,
        b = lod.1,
        ex = eye[0],
        ey = eye[1],
        ez = eye[2],
        tx = target[0],
        ty = target[1],
        tz = target[2],
    )
}

fn stepped(toml: &str, frames: u32) -> Simulation {
    let mut sim = scene(toml);
    for _ in 0..frames {
        sim.step(1.0 / 60.0).unwrap();
    }
    sim
}

#[test]
fn golden_bent_blades_close_up() {
    let toml = small_scene([0.4, 0.6, 1.6], [-0.3, 0.2, 0.0], (50.0, 60.0), 0.1, 2);
    let sim = stepped(&toml, 50);
    // The picture must show bent grass: tips lowered by 10 cm or more
    // (measured 2026-11-23: 52 blades, 37 by 20 cm or more, the deepest by
    // 34 cm).
    let pressed = sim.field.blades.tips_lowered_by(0.1);
    assert!(
        pressed >= 20,
        "the ball must have bent blades: {pressed} tips lowered by 10 cm"
    );
    check("bent_blades", &render(&sim, DebugView::None));
}

#[test]
fn golden_billboards() {
    let toml = small_scene([0.0, 1.0, 3.0], [0.0, 0.2, 0.0], (0.5, 60.0), 0.1, 4);
    let sim = stepped(&toml, 1);
    assert_eq!(
        sim.timings.lod.geometry, 0,
        "every cell must be a billboard"
    );
    check("billboards", &render(&sim, DebugView::None));
}

#[test]
fn golden_three_levels() {
    let toml = small_scene([0.0, 1.2, 4.5], [0.0, 0.0, -2.0], (4.0, 6.0), 0.2, 4);
    let sim = stepped(&toml, 30);
    let lod = sim.timings.lod;
    assert!(
        lod.geometry > 0 && lod.billboard > 0 && lod.texture > 0,
        "{lod:?}"
    );
    check("three_levels", &render(&sim, DebugView::None));
}

#[test]
fn golden_debug_classes() {
    let toml = small_scene([0.0, 1.2, 4.5], [0.0, 0.0, -2.0], (4.0, 6.0), 0.2, 4);
    let sim = stepped(&toml, 30);
    check("debug_classes", &render(&sim, DebugView::Classes));
}

#[test]
fn golden_debug_obb_nodes() {
    // The ball close up at precision 3: its depth-3 boxes over it.
    let toml = small_scene([0.4, 0.6, 1.6], [-0.3, 0.2, 0.0], (50.0, 60.0), 0.1, 2)
        .replace("[camera]", "[sim]\nprecision = 3\n[camera]");
    let sim = stepped(&toml, 50);
    check("debug_obb", &render(&sim, DebugView::Obb));
}

#[test]
fn golden_debug_patch_grid() {
    let toml = small_scene([0.0, 1.2, 4.5], [0.0, 0.0, -2.0], (4.0, 6.0), 0.2, 4);
    let sim = stepped(&toml, 30);
    check("debug_patches", &render(&sim, DebugView::Patches));
}

#[test]
fn a_changed_frame_fails_the_comparison() {
    // The tolerance is not so loose that a visibly different frame passes.
    let toml = small_scene([0.4, 0.6, 1.6], [-0.3, 0.2, 0.0], (50.0, 60.0), 0.1, 2);
    let before = render(&stepped(&toml, 0), DebugView::None);
    let after = render(&stepped(&toml, 50), DebugView::None);
    let (mean, share, _) = compare(&before, &after);
    assert!(
        mean > MAX_MEAN_DIFF || share > MAX_DIFFERING,
        "mean {mean}, share {share}"
    );
}

/// The host of the `embed_headless` and `embed_window` examples.
#[path = "../examples/embed/mod.rs"]
mod embed;

/// Whether `p` is the host cube's unlit pure magenta (255, 0, 255).
fn is_magenta(p: &image::Rgba<u8>) -> bool {
    p.0[..3] == [255, 0, 255]
}

/// Whether `p` reads as grass: green above red and blue.
fn is_grass(p: &image::Rgba<u8>) -> bool {
    let [r, g, b, _] = p.0;
    g > r && g > b
}

#[test]
fn golden_embed_headless_host_cube_in_the_grass() {
    // The frame `embed_headless` writes (at a smaller size): the host's
    // magenta cube and trample's grass in one pass with one depth buffer.
    let gpu = gpu();
    let (size, steps) = ([320, 180], 30);
    let frame =
        embed::render_headless(&gpu.device, &gpu.queue, &gpu.adapter, size, steps, true).unwrap();
    let alone =
        embed::render_headless(&gpu.device, &gpu.queue, &gpu.adapter, size, steps, false).unwrap();
    let pixels = f64::from(size[0] * size[1]);
    let cube_alone = alone.pixels().filter(|p| is_magenta(p)).count();
    let cube = frame.pixels().filter(|p| is_magenta(p)).count();
    let grass = frame.pixels().filter(|p| is_grass(p)).count();
    // Cube pixels of the frame without grass that the grass covers (fully
    // or partly: blades thinner than a pixel blend with the cube under MSAA).
    let hidden = alone
        .pixels()
        .zip(frame.pixels())
        .filter(|(a, f)| is_magenta(a) && !is_magenta(f))
        .count();
    eprintln!(
        "embed: cube {cube_alone} px alone, {cube} px in the grass ({hidden} hidden by grass); grass {grass} px of {pixels}"
    );
    assert!(
        cube_alone as f64 > 0.03 * pixels,
        "the cube covers {cube_alone} px alone"
    );
    // Depth shared both ways: the cube hides the grass (and the sky)
    // behind it, and grass in front of it hides part of it.
    assert!(
        cube as f64 > 0.5 * cube_alone as f64,
        "the cube shows {cube} px of {cube_alone}: the grass or sky covers it"
    );
    assert!(
        hidden as f64 > 0.03 * cube_alone as f64,
        "grass in front hides only {hidden} px of the cube's {cube_alone}"
    );
    assert!(
        grass as f64 > 0.2 * pixels,
        "grass covers only {grass} px of {pixels}"
    );
    check("embed_headless", &frame);
}

#[test]
fn golden_ball_shadow() {
    // Light (issue 15 item 3): a still ball above the grass between it and
    // the sun; its shadow on the grass below right, the blades darker to
    // their roots (tests/shadows.rs measures both).
    let sun = RenderParams::default().sun_dir.normalize();
    let ball = glam::Vec3::new(0.0, 0.25, 0.0) + sun * 1.3;
    let toml = common::ball_above_grass(ball, 0.3);
    let sim = stepped(&toml, 1);
    check("ball_shadow", &render(&sim, DebugView::None));
}
