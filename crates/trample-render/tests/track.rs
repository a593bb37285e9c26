//! The track is visible (issue 3): a frame after the ball has passed differs
//! from the same frame of a field the ball never touched along the ball's
//! path, and hardly anywhere far from it. Runs on the adapter of
//! `WGPU_BACKEND`; no adapter = failure.

use glam::Vec3;
use trample::Simulation;
use trample::scene::Scene;
use trample_render::{RenderParams, Renderer};

const W: u32 = 160;
const H: u32 = 120;

/// A 3.2 m field seen from above; the ball rolls along x at `ball_z`, from
/// out of view to out of view; `lod` = (geometry_m, billboard_m).
fn scene(ball_z: f32, (geometry_m, billboard_m): (f32, f32)) -> Simulation {
    let toml = format!(
        r#"
[field]
patches = [4, 4]
cells_per_patch = 8
cell_size_m = 0.1
blade_width_m = 0.03
[lod]
geometry_m = {geometry_m}
billboard_m = {billboard_m}
[sim]
recovery_s = inf
[camera]
path = {{ kind = "static", position = [0.0, 3.0, 0.8] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.0] }}
aspect = {aspect}
[[objects]]
name = "ball"
shape = {{ kind = "sphere", radius_m = 0.3, subdivisions = 2 }}
orientation = "rolling"
path = {{ kind = "line", from = [-6.0, 0.3, {ball_z}], to = [6.0, 0.3, {ball_z}], duration_s = 1.5 }}
"#,
        aspect = W as f32 / H as f32
    );
    let mut sim = Scene::parse(&toml, "track.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap();
    for _ in 0..100 {
        sim.step(1.0 / 60.0).unwrap();
    }
    sim
}

/// Image row of world point `p` in `sim`'s view.
fn row(sim: &Simulation, p: Vec3) -> f32 {
    let clip = sim.view.proj() * sim.view.view() * p.extend(1.0);
    (1.0 - clip.y / clip.w) * 0.5 * H as f32
}

#[test]
fn track_is_visible_along_the_path_and_not_far_from_it() {
    let (in_band, far) = track_contrast((50.0, 60.0), None);
    assert!(
        in_band > 4.0,
        "the track does not show: mean difference {in_band:.2} along the path"
    );
    assert!(
        far < in_band / 4.0,
        "the frames differ far from the path: {far:.2} vs {in_band:.2} along it"
    );
}

#[test]
fn track_is_visible_at_ground_texture_level() {
    // Every cell is drawn as ground texture (no blade, no billboard): the
    // track shows through the cells' flatness (issue 12 item 4, issue 15
    // item 4).
    let (in_band, far) = track_contrast((0.2, 0.4), Some(trample::field::Lod::Texture));
    assert!(
        in_band > 3.0,
        "the track does not show on ground-texture cells: mean difference {in_band:.2} along the path"
    );
    assert!(
        far < in_band / 4.0,
        "the frames differ far from the path: {far:.2} vs {in_band:.2} along it"
    );
}

/// Mean colour difference (0–255 per channel) between a frame after the
/// ball passed and one of an untouched field, along the path and far from
/// it; every cell must be at `level` when one is given.
fn track_contrast(lod: (f32, f32), level: Option<trample::field::Lod>) -> (f64, f64) {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the track test needs an adapter: {e}"));
    let render = |sim: &Simulation| {
        let params = RenderParams {
            width: W,
            height: H,
            samples: gpu.msaa(4),
            ..Default::default()
        };
        Renderer::new(&gpu.device, &gpu.queue, sim, params)
            .unwrap()
            .render(&gpu.device, &gpu.queue, sim)
            .unwrap()
    };
    let passed = scene(0.0, lod);
    // The same field with the ball rolling far outside it: never touched.
    let untouched = scene(40.0, lod);
    if let Some(level) = level {
        assert!(passed.field.cells.lod.iter().all(|&l| l == level));
    }
    assert!(passed.blades_away_from_rest() > 100);
    assert_eq!(untouched.blades_away_from_rest(), 0);
    let (a, b) = (render(&passed), render(&untouched));

    // Rows of the path band (|z| < 0.45 m: ball radius + bent neighbours) and
    // rows far from it (|z| > 1.0 m, inside the field).
    let band = row(&passed, Vec3::new(0.0, 0.0, 0.45))..row(&passed, Vec3::new(0.0, 0.0, -0.45));
    let far_near = row(&passed, Vec3::new(0.0, 0.0, 1.0));
    let far_back = row(&passed, Vec3::new(0.0, 0.0, -1.0));
    let (mut in_band, mut n_band, mut far, mut n_far) = (0.0f64, 0usize, 0.0f64, 0usize);
    for y in 0..H {
        let yf = y as f32 + 0.5;
        let is_band = yf > band.end && yf < band.start;
        let is_far =
            yf > far_near || (yf < far_back && yf > row(&passed, Vec3::new(0.0, 0.0, -1.5)));
        for x in W / 8..W - W / 8 {
            let (pa, pb) = (a.get_pixel(x, y), b.get_pixel(x, y));
            let d: f64 = (0..3)
                .map(|c| f64::from(pa[c].abs_diff(pb[c])))
                .sum::<f64>()
                / 3.0;
            if is_band {
                in_band += d;
                n_band += 1;
            } else if is_far {
                far += d;
                n_far += 1;
            }
        }
    }
    assert!(
        n_band > 0 && n_far > 0,
        "band rows {band:?}, far rows > {far_near} or < {far_back}"
    );
    let (in_band, far) = (in_band / n_band as f64, far / n_far as f64);
    eprintln!(
        "track (lod {lod:?}): mean difference {in_band:.2} along the path, {far:.2} far from it"
    );
    (in_band, far)
}
