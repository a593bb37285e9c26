//! No popping (issue 3, DESIGN §6): a camera backs away from a trampled
//! field, so that cells cross the geometry → billboard boundary while we
//! watch. The mean pixel change between consecutive frames in the band that
//! changes level must stay within [`MAX_BAND_FACTOR`] times the change
//! elsewhere in the frame (where the change comes from the camera's motion
//! alone). With the transition rules (Eq. 9–13) switched off the billboards
//! of trampled cells stand up at rest the moment their cell leaves geometry:
//! the same measurement must then exceed the factor, so the test can fail.
//!
//! The band is found in the `classes` debug view of the same frames: the
//! blocks of pixels that show a geometric blade in one frame and not in the
//! other.
//! Runs on the adapter of `WGPU_BACKEND`; no adapter = failure.

use trample::Simulation;
use trample::scene::Scene;
use trample_render::{DebugView, RenderParams, Renderer};

const W: u32 = 160;
const H: u32 = 120;
const DT: f32 = 1.0 / 60.0;
/// Steps before the camera starts moving: the slab has flattened the field
/// and left it.
const SETTLE_STEPS: u32 = 100;
/// Steps between two rendered frames.
const STEPS_PER_FRAME: u32 = 2;
/// Rendered frames while the camera backs away (1 m, 2.5 cm per frame).
const FRAMES: u32 = 40;
/// Side of the pixel blocks compared, pixels: the blocks' mean colours are
/// compared, so the grass's fine texture sliding under a moving camera
/// averages out while a whole cell that changes its look does not.
const BLOCK: u32 = 4;
/// A block belongs to the band when at least this many of its pixels do.
const BAND_PIXELS_PER_BLOCK: usize = 4;

/// Largest allowed ratio of the mean change in the band to the mean change
/// elsewhere.
///
/// **Not met yet (2026-11-21, llvmpipe): the test is ignored.** Measured:
/// factor 2.92 with the transition rules, 2.79 without (1 blade per cell,
/// 3 cm wide: 3.29 / 3.12). The pop the camera sees at the boundary is
/// dominated by how the renderer draws the two levels, not by their slopes:
/// flattened blades lie face-up in the sun and read bright yellow-green,
/// while a flattened billboard (two crossed quads laid down by Eq. 8/12) reads
/// like the dark ground. Until the billboard pass matches the blades'
/// coverage and lighting, the transition rules cannot show in pixels. Run
/// with `TRAMPLE_DUMP_FRAMES=DIR` to see the frames.
const MAX_BAND_FACTOR: f64 = 2.5;

/// A 4.8 m field flattened by a wide slab that crosses it along x in 1 s;
/// the camera waits, then backs away along +z looking down at a fixed
/// point, so the geometry disc around it slides off the field.
fn scene() -> Simulation {
    let toml = format!(
        r#"
[field]
patches = [6, 6]
cells_per_patch = 8
blades_per_cell = 6
cell_size_m = 0.1
[lod]
geometry_m = 3.4
billboard_m = 30.0
[sim]
recovery_s = inf
[camera]
path = {{ kind = "keyframes", keys = [
  {{ t_s = 0.0, position = [0.0, 2.5, 2.4] }},
  {{ t_s = {start}, position = [0.0, 2.5, 2.4] }},
  {{ t_s = {end}, position = [0.0, 2.5, 3.4] }},
] }}
look_at = {{ kind = "point", at = [0.0, 0.0, 0.2] }}
aspect = {aspect}
[[objects]]
name = "slab"
shape = {{ kind = "box", half_extents_m = [0.3, 0.08, 2.6] }}
path = {{ kind = "line", from = [-3.0, 0.14, 0.0], to = [9.0, 0.14, 0.0], duration_s = 1.2 }}
"#,
        start = SETTLE_STEPS as f32 * DT,
        end = (SETTLE_STEPS + STEPS_PER_FRAME * FRAMES) as f32 * DT,
        aspect = W as f32 / H as f32
    );
    Scene::parse(&toml, "no_popping.toml", std::path::Path::new("."))
        .unwrap()
        .build()
        .unwrap()
}

/// Geometric-blade pixel of the `classes` view: blades are pure red, green
/// or blue there (by class), billboards yellow, the ground grey. The same
/// cells leave geometry with the transition rules on or off (the level of
/// detail depends on the camera alone), so both runs are measured over the
/// same band.
fn is_blade(p: &image::Rgba<u8>) -> bool {
    let [r, g, b] = [p[0], p[1], p[2]].map(u16::from);
    let max = r.max(g).max(b);
    max > 30 && [r, g, b].iter().filter(|&&c| 2 * c > max).count() == 1
}

/// Mean colour of each [`BLOCK`]² block, row by row.
fn block_means(img: &image::RgbaImage) -> Vec<[f64; 3]> {
    let (bw, bh) = (W / BLOCK, H / BLOCK);
    let mut out = vec![[0.0; 3]; (bw * bh) as usize];
    for (x, y, p) in img.enumerate_pixels() {
        let (bx, by) = (x / BLOCK, y / BLOCK);
        if bx < bw && by < bh {
            let m = &mut out[(by * bw + bx) as usize];
            for c in 0..3 {
                m[c] += f64::from(p[c]) / f64::from(BLOCK * BLOCK);
            }
        }
    }
    out
}

/// Per block: how many of its pixels show a blade in one `classes` frame
/// and not in the other.
fn band_counts(c0: &image::RgbaImage, c1: &image::RgbaImage) -> Vec<usize> {
    let bw = W / BLOCK;
    let mut out = vec![0; (bw * (H / BLOCK)) as usize];
    for ((x, y, a), b) in c0.enumerate_pixels().zip(c1.pixels()) {
        let (bx, by) = (x / BLOCK, y / BLOCK);
        if bx < bw && by < H / BLOCK && is_blade(a) != is_blade(b) {
            out[(by * bw + bx) as usize] += 1;
        }
    }
    out
}

/// What one camera move measured.
#[derive(Debug)]
struct Popping {
    /// Mean change in the band / mean change elsewhere.
    factor: f64,
    /// Band blocks over all frame pairs.
    band_blocks: usize,
    /// Cells that changed level while the frames were taken.
    transitions: u32,
}

/// Runs the scene with the transition rules on or off and measures.
fn measure(transitions: bool) -> Popping {
    let gpu = trample_render::headless::create_device()
        .unwrap_or_else(|e| panic!("the no-popping test needs an adapter: {e}"));
    let mut sim = scene();
    sim.params.transitions = transitions;
    for _ in 0..SETTLE_STEPS {
        sim.step(DT).unwrap();
    }
    assert!(
        sim.blades_away_from_rest() > 1000,
        "the slab must have flattened the field: {} blades bent",
        sim.blades_away_from_rest()
    );
    let renderer = |debug| {
        let params = RenderParams {
            width: W,
            height: H,
            samples: gpu.msaa(4),
            debug,
            ..Default::default()
        };
        Renderer::new(&gpu.device, &gpu.queue, &sim, params).unwrap()
    };
    let (mut shaded, mut classes) = (renderer(DebugView::None), renderer(DebugView::Classes));
    let mut frames = Vec::new();
    let mut changed = 0;
    for i in 0..=FRAMES {
        if i > 0 {
            for _ in 0..STEPS_PER_FRAME {
                changed += sim.step(DT).unwrap().transitions;
            }
        }
        frames.push((
            shaded.render(&gpu.device, &gpu.queue, &sim).unwrap(),
            classes.render(&gpu.device, &gpu.queue, &sim).unwrap(),
        ));
    }
    if let Some(dir) = std::env::var_os("TRAMPLE_DUMP_FRAMES") {
        // For a person looking into a failure: the frames as PNGs.
        let dir = std::path::Path::new(&dir);
        std::fs::create_dir_all(dir).unwrap();
        let tag = if transitions { "on" } else { "off" };
        for (i, (s, c)) in frames.iter().enumerate() {
            s.save(dir.join(format!("{tag}-{i:02}-shaded.png")))
                .unwrap();
            c.save(dir.join(format!("{tag}-{i:02}-classes.png")))
                .unwrap();
        }
    }
    let (mut band, mut band_n, mut other, mut other_n) = (0.0, 0usize, 0.0, 0usize);
    for pair in frames.windows(2) {
        let ((s0, c0), (s1, c1)) = (&pair[0], &pair[1]);
        let (m0, m1) = (block_means(s0), block_means(s1));
        for ((a, b), n) in m0.iter().zip(&m1).zip(band_counts(c0, c1)) {
            let change = (0..3).map(|c| (a[c] - b[c]).abs()).sum::<f64>() / 3.0;
            if n >= BAND_PIXELS_PER_BLOCK {
                band += change;
                band_n += 1;
            } else {
                other += change;
                other_n += 1;
            }
        }
    }
    assert!(
        band_n > 0 && other_n > 0,
        "band {band_n}, elsewhere {other_n}"
    );
    Popping {
        factor: (band / band_n as f64) / (other / other_n as f64),
        band_blocks: band_n,
        transitions: changed,
    }
}

#[test]
#[ignore = "issue 3: the billboard pass does not match flattened blades yet (factor 2.9 with the rules, 2.8 without); see MAX_BAND_FACTOR"]
fn cells_changing_level_do_not_pop_and_do_without_the_transition_rules() {
    let on = measure(true);
    let off = measure(false);
    eprintln!("no popping: transitions on {on:?}; off {off:?}");
    for p in [&on, &off] {
        assert!(
            p.transitions > 200 && p.band_blocks > 100,
            "the camera must move cells across the boundary in view: {p:?}"
        );
    }
    assert!(
        on.factor <= MAX_BAND_FACTOR,
        "with the transition rules the band changes {:.2}× as much as the rest of the frame (max {MAX_BAND_FACTOR}): {on:?}",
        on.factor
    );
    assert!(
        off.factor > MAX_BAND_FACTOR,
        "without the transition rules the band must pop (factor > {MAX_BAND_FACTOR}), got {:.2}: {off:?}",
        off.factor
    );
}
