//! Wind (DESIGN §6, ours) is drawn at draw time: a steady wind along +x
//! leans the blades towards +x on screen (the green of the `classes` view
//! moves right), gusts make the picture change with time, and the
//! simulation state is not touched. Runs on the adapter of `WGPU_BACKEND`;
//! no adapter = failure.

use trample::Simulation;
use trample::scene::Scene;
use trample::wind::WindParams;
use trample_render::{DebugView, RenderParams, Renderer};

const W: u32 = 200;
const H: u32 = 120;

/// A 1.6 m field of blades, all geometry, seen from the side (+z, looking
/// towards −z): +x is to the right of the picture.
fn scene() -> Simulation {
    let toml = format!(
        r#"
[field]
patches = [2, 2]
cells_per_patch = 8
blades_per_cell = 4
cell_size_m = 0.1
[lod]
geometry_m = 50.0
billboard_m = 60.0
[camera]
path = {{ kind = "static", position = [0.0, 0.45, 1.6] }}
look_at = {{ kind = "point", at = [0.0, 0.15, 0.0] }}
aspect = {aspect}
"#,
        aspect = W as f32 / H as f32
    );
    Scene::parse(&toml, "wind.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

fn render(sim: &Simulation, debug: DebugView) -> image::RgbaImage {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the wind test needs an adapter: {e}"));
    let params = RenderParams {
        width: W,
        height: H,
        samples: gpu.msaa(4),
        debug,
        ..Default::default()
    };
    Renderer::new(&gpu.device, &gpu.queue, sim, params)
        .unwrap()
        .render(&gpu.device, &gpu.queue, sim)
        .unwrap()
}

/// Mean x of the untouched-blade green of the `classes` view, and how many
/// such pixels there are.
fn green_centroid(img: &image::RgbaImage) -> (f64, usize) {
    let (mut sum, mut n) = (0.0, 0usize);
    for (x, _, p) in img.enumerate_pixels() {
        let [r, g, b] = [p[0], p[1], p[2]].map(u16::from);
        if g > 40 && g > 2 * r && g > 2 * b {
            sum += f64::from(x);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

fn differing_pixels(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 24))
        .count()
}

#[test]
fn steady_wind_leans_the_drawn_blades_downwind_and_leaves_the_state_alone() {
    let calm = scene();
    let mut windy = scene();
    windy.wind = WindParams {
        strength_m: 0.3,
        ..WindParams::default()
    };
    let (c0, n0) = green_centroid(&render(&calm, DebugView::Classes));
    let (c1, n1) = green_centroid(&render(&windy, DebugView::Classes));
    assert!(n0 > 1000 && n1 > 1000, "blade pixels: {n0}, {n1}");
    assert!(
        c1 - c0 > 3.0,
        "green centroid x: calm {c0:.1}, wind +x {c1:.1}"
    );
    // Blowing the other way leans them the other way.
    windy.wind.direction_deg = 180.0;
    let (c2, _) = green_centroid(&render(&windy, DebugView::Classes));
    assert!(
        c0 - c2 > 3.0,
        "green centroid x: calm {c0:.1}, wind −x {c2:.1}"
    );
    // Draw time only: the blades the simulation holds are at rest.
    assert_eq!(windy.blade_vertices(), calm.blade_vertices());
}

#[test]
fn gusts_change_the_picture_with_time_and_calm_does_not() {
    let mut sim = scene();
    let a = render(&sim, DebugView::None);
    sim.time = 0.75;
    let b = render(&sim, DebugView::None);
    assert_eq!(
        differing_pixels(&a, &b),
        0,
        "calm: time alone changed the picture"
    );
    sim.wind = WindParams {
        gust_m: 0.2,
        gust_period_s: 3.0,
        ..WindParams::default()
    };
    sim.time = 0.0;
    let c = render(&sim, DebugView::None);
    sim.time = 0.75;
    let d = render(&sim, DebugView::None);
    let changed = differing_pixels(&c, &d);
    assert!(changed > 500, "a gust moved only {changed} pixels");
}
