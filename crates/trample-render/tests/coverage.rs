//! Render density beyond the simulation's (issue 15 item 2, "Coverage"): in
//! the nearest fifth of the default scene's frame 0 (640×360, the classes
//! view, where the ground between blades is its own dark grey), ground
//! shows on at most 10 % of the pixels with the default render density;
//! with the simulated blades alone (`near_density = 1`) it showed on about
//! 40 %. The simulation is the same in both. Runs on the adapter of
//! `WGPU_BACKEND`; no adapter = failure.

mod common;

use trample::scene::Scene;
use trample_render::{DebugView, RenderParams, Renderer};

const W: u32 = 640;
const H: u32 = 360;

/// The classes view's near ground, as the sRGB target stores it:
/// `terrain.wgsl`'s linear (0.05, 0.06, 0.04).
const GROUND: [u8; 3] = [63, 69, 56];

/// Fraction of the nearest fifth's pixels (the bottom rows) that show the
/// ground (within 24 per channel of [`GROUND`]: MSAA edges blend).
fn ground_fraction(near_density: u32) -> f64 {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the coverage test needs an adapter: {e}"));
    let mut sim = Scene::default_scene().unwrap().build().unwrap();
    sim.step(sim.params.dt_s).unwrap();
    let params = RenderParams {
        near_density,
        ..common::test_params(&gpu, W, H, DebugView::Classes)
    };
    let frame = Renderer::new(&gpu.device, &gpu.queue, &sim, params)
        .unwrap()
        .render(&gpu.device, &gpu.queue, &sim)
        .unwrap();
    let rows = H - H / 5..H;
    let mut ground = 0usize;
    for y in rows.clone() {
        for x in 0..W {
            let p = frame.get_pixel(x, y);
            if (0..3).all(|c| p[c].abs_diff(GROUND[c]) <= 24) {
                ground += 1;
            }
        }
    }
    ground as f64 / (rows.len() as f64 * f64::from(W))
}

#[test]
fn near_grass_is_dense_with_the_default_render_density() {
    let alone = ground_fraction(1);
    let dense = ground_fraction(RenderParams::default().near_density);
    eprintln!(
        "ground in the nearest fifth: {:.1} % with the simulated blades alone, {:.1} % with {} drawn per simulated blade",
        100.0 * alone,
        100.0 * dense,
        RenderParams::default().near_density
    );
    assert!(
        alone > 0.2,
        "the measure must see the bare ground between simulated blades ({alone})"
    );
    assert!(
        dense <= 0.10,
        "ground shows on {:.1} % of the nearest fifth (at most 10 %)",
        100.0 * dense
    );
}
